"""Training and evaluation of helm agents with Stable-Baselines3 against the classical baselines.

* ``vessel-gym train --env ID --algo ppo --seed 0`` (or ``python agents/train.py ...`` in a checkout): train
  with ``agents/hyperparams/<algo>.yml``.
* ``vessel-gym evaluate --env ID --agent PATH|pid|scripted --episodes 20 --seed 0 --json`` (or
  ``python agents/evaluate.py ...``): evaluate (``--render DIR``, ``--video FILE``, ``--plot FILE``: frames,
  video, trajectory plot).
* ``python agents/results.py``: train every env x algorithm over several seeds, evaluate, plot the learning
  curves and write the results table (``--doc docs/results.md`` and ``--ship-dir agents/trained`` replace the
  committed table and shipped agents).
* ``python agents/tune_ray.py``: hyperparameter sweeps with Ray Tune and ASHA (local or on a cluster).

The library part is :mod:`agents.common` (hyperparameters, vector environments, training, evaluation),
:mod:`agents.shipped` (the shipped-agent convention) and :mod:`agents.visual` (pictures).
See ``docs/agents.md``.
"""
