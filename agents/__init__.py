"""Training and evaluation of helm agents with Stable-Baselines3 against the classical baselines.

* ``python agents/train.py --env ID --algo ppo --seed 0``: train with ``agents/hyperparams/<algo>.yml``.
* ``python agents/evaluate.py --env ID --agent PATH|pid|scripted --episodes 20 --seed 0 --json``: evaluate
  (``--render DIR``, ``--video FILE``, ``--plot FILE``: frames, video, trajectory plot).
* ``python agents/results.py``: train every env x algorithm over several seeds, evaluate, plot the learning
  curves, write the results table ``docs/results.md`` and ship the agents to ``agents/trained/``.
* ``python agents/tune_ray.py``: hyperparameter sweeps with Ray Tune and ASHA (local or on a cluster).

The library part is :mod:`agents.common` (hyperparameters, vector environments, training, evaluation),
:mod:`agents.shipped` (the shipped-agent convention) and :mod:`agents.visual` (pictures).
See ``docs/agents.md``.
"""
