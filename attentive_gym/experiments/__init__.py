"""The paper's five experiments (MODEL.md §9): registry, runner, checks and figures.

- ``EXPERIMENTS`` / ``get_experiment``: what each experiment attends to (maps, weights,
  goals, goal changes, duration) on top of its built-in scenario.
- ``run_experiment(name, noise, seed, out_dir)``: the immobile robot in the scenario,
  the model attending; returns an ``ExperimentResult`` (trace + ground truth) and can
  write ``NAME.npz`` and ``NAME.png``.
- ``check_experiment(result)``: MODEL.md §9's criteria as named ``Check`` outcomes;
  ``pass_rates(name, noise, seeds)`` over several seeds.
- ``plot_experiment(result, path)``: the paper-like figure.

Example:
    >>> from attentive_gym.experiments import run_experiment, check_experiment
    >>> result = run_experiment("exp01")
    >>> [c.name for c in check_experiment(result) if not c.passed]
    []
"""

from attentive_gym.experiments.checks import CHECKS, Check, check_experiment, pass_rates
from attentive_gym.experiments.figures import plot_experiment
from attentive_gym.experiments.registry import EXPERIMENT_NAMES, EXPERIMENTS, Experiment, GoalChange, get_experiment
from attentive_gym.experiments.runner import DT_S, ExperimentResult, run_experiment

__all__ = [
    "CHECKS",
    "Check",
    "DT_S",
    "EXPERIMENTS",
    "EXPERIMENT_NAMES",
    "Experiment",
    "ExperimentResult",
    "GoalChange",
    "check_experiment",
    "get_experiment",
    "pass_rates",
    "plot_experiment",
    "run_experiment",
]
