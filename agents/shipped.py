"""Shipped agents: small SB3 zips under ``agents/trained/`` with a JSON sidecar saying how they were made.

Convention: ``agents/trained/<algo>_<env>_seed<N>.zip`` (e.g. ``ppo_ZigZag-v1_seed0.zip``): the algorithm
first (:func:`vessel_gym.policy.load_policy` reads it from the part before the first underscore), then the
short env id with its version, then the training seed. Next to it ``<same stem>.json``:

* ``env_id``, ``env_version`` (the ``-vN`` of the id), ``env_kwargs`` / ``eval_env_kwargs`` (what the agent
  was trained and is evaluated with), ``action_filter`` (wrappers of :mod:`agents.wrappers` between the
  network and the helm, e.g. a rudder rate limit, that evaluation applies too; ``null``: none), ``algo``, ``hyperparams`` (the block as trained);
* ``seed`` (training seed; copies ``seed .. seed + n_envs - 1``), ``n_timesteps`` (budget),
  ``num_timesteps`` (steps trained), ``n_envs``;
* ``validation_seeds`` / ``test_seeds`` (the episode seed ranges of :mod:`agents.seeds` used for model
  selection and for the final numbers), ``test`` (the test-set summary, when evaluated);
* ``vessel_gym_version``, ``stable_baselines3``, ``torch``, ``created`` (UTC date);
* ``train_time_s`` / ``cpu_time_s`` (wall-clock and CPU time of training), ``selected_at_timesteps`` (a
  model chosen as the best of the periodic validation evaluations: the step it was saved at), and for a model made by another
  method than training with its algorithm (shipped in a subdirectory named after it, e.g. ``bc/``):
  ``method``, ``method_detail`` and the method's settings and log (``bc``, ``bc_rounds``);
* ``test_episodes`` (written by ``results.py``): the per-episode test figures, so a re-evaluation of a few
  episodes can be compared with what was recorded.

``<stem>_vecnormalize.pkl`` is shipped too when training normalised observations. :func:`read_sidecar`
is what ``evaluate.py`` uses to find the environment arguments of a shipped agent.
"""

from __future__ import annotations

import datetime as dt
import json
import re
import shutil
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from agents import seeds
from agents.common import UsageError, check_algo, env_short_name, json_safe, load_json_sidecar, sidecar

TRAINED_DIR = Path(__file__).resolve().parent / "trained"
#: ``<algo>_<Env>-v<N>_seed<S>``
NAME_RE = re.compile(r"^(?P<algo>[a-z0-9]+)_(?P<env>[A-Za-z0-9]+-v\d+)_seed(?P<seed>\d+)$")
#: sidecar keys every shipped agent has
REQUIRED_KEYS = (
    "env_id",
    "env_version",
    "algo",
    "seed",
    "n_timesteps",
    "hyperparams",
    "validation_seeds",
    "test_seeds",
    "vessel_gym_version",
)


def shipped_stem(algo: str, env_id: str, seed: int) -> str:
    """``ppo``, ``vessel_gym/ZigZag-v1``, 3 -> ``ppo_ZigZag-v1_seed3``."""
    return f"{check_algo(algo)}_{env_short_name(env_id)}_seed{int(seed)}"


def env_version(env_id: str) -> int:
    """The ``N`` of an id ending in ``-vN``."""
    m = re.search(r"-v(\d+)$", env_id)
    if m is None:
        raise UsageError(f"env id {env_id!r} has no -vN version suffix")
    return int(m.group(1))


def seed_range(split: str, n: int) -> str:
    """``"2000000..2000019"``: the first ``n`` episode seeds of ``split``, as the sidecar writes them."""
    s = seeds.episode_seeds(split, n)
    return f"{s[0]}..{s[-1]}" if s else ""


def make_sidecar(record: Mapping[str, Any], validation_episodes: int, test_episodes: int) -> dict[str, Any]:
    """The JSON sidecar of a model from its run record (``<stem>.yml`` written by :func:`agents.common.train`)."""
    import stable_baselines3 as sb3
    import torch

    import vessel_gym

    env_id = str(record["env_id"])
    out = {
        "env_id": env_id,
        "env_version": env_version(env_id),
        "env_kwargs": record.get("env_kwargs") or {},
        "eval_env_kwargs": record.get("eval_env_kwargs") or {},
        "action_filter": record.get("action_filter"),
        "algo": record["algo"],
        "hyperparams": record.get("hyperparams") or {},
        "seed": int(record["seed"]),
        "n_envs": record.get("n_envs"),
        "n_timesteps": record.get("n_timesteps"),
        "num_timesteps": record.get("num_timesteps"),
        "validation_seeds": seed_range("validation", validation_episodes),
        "test_seeds": seed_range("test", test_episodes),
        "vessel_gym_version": vessel_gym.__version__,
        "stable_baselines3": str(sb3.__version__),
        "torch": str(torch.__version__),
        "created": dt.datetime.now(dt.timezone.utc).date().isoformat(),
    }
    keys = ("train_time_s", "cpu_time_s", "selected_at_timesteps", "method", "method_detail", "bc", "bc_rounds")
    for key in keys:
        if record.get(key) is not None:  # training times; how a model not trained by its algo was made
            out[key] = record[key]
    if record.get("test") is not None:
        out["test"] = record["test"]
    return out


def ship(
    model_path: str | Path,
    meta: Mapping[str, Any],
    dest: str | Path = TRAINED_DIR,
    *,
    overwrite: bool = True,
) -> Path:
    """Copy a trained model (and its ``_vecnormalize.pkl``) to ``dest/<algo>_<env>_seed<N>.zip`` with its
    JSON sidecar ``meta``; returns the new zip's path. ``overwrite=False`` refuses to replace a file."""
    missing = [k for k in REQUIRED_KEYS if k not in meta]
    if missing:
        raise UsageError(f"sidecar of {model_path} lacks {', '.join(missing)}")
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    target = dest / f"{shipped_stem(meta['algo'], meta['env_id'], meta['seed'])}.zip"
    if target.exists() and not overwrite:
        raise UsageError(f"{target} exists (not overwritten)")
    without_optimizer_state(model_path, target)
    vn = sidecar(model_path, "_vecnormalize.pkl")
    if vn.is_file():
        shutil.copyfile(vn, sidecar(target, "_vecnormalize.pkl"))
    sidecar(target, ".json").write_text(json.dumps(json_safe(dict(meta)), indent=1, sort_keys=False) + "\n")
    return target


def without_optimizer_state(src: str | Path, dst: str | Path) -> Path:
    """Copy the SB3 zip ``src`` to ``dst`` with the optimiser's running state (Adam's moment estimates, twice
    the size of the network) left out: the policy is unchanged, the file about a third of the size, and
    continued training starts with fresh moments. The optimiser entry itself stays (SB3 loads a model only
    with all its parts), with its hyperparameters (``param_groups``)."""
    import io
    import zipfile

    import torch

    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename.endswith("optimizer.pth"):
                state = torch.load(io.BytesIO(data), map_location="cpu", weights_only=False)
                state["state"] = {}
                buf = io.BytesIO()
                torch.save(state, buf)
                data = buf.getvalue()
            zout.writestr(item, data)
    return Path(dst)


def read_sidecar(model_path: str | Path) -> dict[str, Any]:
    """The JSON sidecar of a shipped agent (empty if there is none); a broken one is a :class:`UsageError`."""
    path = sidecar(model_path, ".json")
    if not path.is_file():
        return {}
    data = load_json_sidecar(path)
    if not isinstance(data, dict):
        raise UsageError(f"{path}: expected a JSON object")
    return data


def list_shipped(directory: str | Path = TRAINED_DIR) -> list[Path]:
    """The shipped agent zips of ``directory`` and its subdirectories (one per method that is not plain
    training by the algorithm, e.g. ``bc/``) that follow the naming convention and have a sidecar."""
    d = Path(directory)
    if not d.is_dir():
        return []
    return sorted(p for p in d.rglob("*.zip") if NAME_RE.match(p.stem) and sidecar(p, ".json").is_file())


__all__ = [
    "NAME_RE",
    "REQUIRED_KEYS",
    "TRAINED_DIR",
    "env_version",
    "list_shipped",
    "make_sidecar",
    "read_sidecar",
    "ship",
    "shipped_stem",
    "without_optimizer_state",
]
