"""Training and evaluation of helm agents with Stable-Baselines3 against the classical baselines.

* ``python agents/train.py --env ID --algo ppo --seed 0``: train with ``agents/hyperparams/<algo>.yml``.
* ``python agents/evaluate.py --env ID --agent PATH|pid|scripted --episodes 20 --seed 0``: evaluate.
* ``python agents/results.py``: train, evaluate and write the results table ``docs/results.md``.
* ``python agents/tune_ray.py``: hyperparameter sweeps with Ray Tune (local or on a cluster).

The library part is :mod:`agents.common` (hyperparameters, vector environments, training, evaluation).
See ``docs/agents.md``.
"""
