"""The paper's five experiments (docs/model.md §9): registry, runner, checks and figures.

- ``EXPERIMENTS`` / ``get_experiment``: what each experiment attends to (maps, weights,
  goals, goal changes, duration) on top of its built-in scenario.
- ``run_experiment(name, noise, seed, out_dir, *, kinematics, profile, config)``: the
  immobile robot in the scenario, the model attending (kinematics "tracker" by default,
  or "window", "literal", or "truth": the perfect-perception bound; sensor profile None or
  "usarsim"); returns an
  ``ExperimentResult`` (trace + ground truth) and can write ``NAME.npz`` and ``NAME.png``.
- ``check_experiment(result)``: docs/model.md §9's criteria as named ``Check`` outcomes;
  ``pass_rates(name, noise, seeds, ...)`` over several seeds.
- ``experiment_figure(result)`` / ``plot_experiment(result, path)``: the paper-like
  figure (every panel on one time axis), as a ``Figure`` or saved as a PNG.
- ``attentive_gym.experiments.table``: the table of checks per kinematics mode
  (``measure``, ``markdown``) and its tidy rows (``to_rows``, ``from_rows``); the
  repository's ``tools/experiments_table.py`` measures it into
  ``docs/results/experiment_checks.csv``.

Modules import in one direction: ``registry`` → ``result`` → ``figures`` → ``runner`` →
``checks`` → ``cli`` / ``table``.

Example:
    >>> from attentive_gym.experiments import run_experiment, check_experiment
    >>> result = run_experiment("exp01", kinematics="window")
    >>> [c.name for c in check_experiment(result) if not c.passed]
    []
    >>> [c.name for c in check_experiment(run_experiment("exp05", kinematics="truth")) if not c.passed]
    ['faster_holds_focus', 'top_down_never_below_1', 'goal_change_moves_focus']
"""

from attentive_gym.experiments.checks import CHECKS, Check, check_experiment, pass_rates
from attentive_gym.experiments.figures import experiment_figure, plot_experiment
from attentive_gym.experiments.registry import EXPERIMENT_NAMES, EXPERIMENTS, Experiment, GoalChange, get_experiment
from attentive_gym.experiments.result import ExperimentResult
from attentive_gym.experiments.runner import DT_S, experiment_config, run_experiment

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
    "experiment_config",
    "experiment_figure",
    "get_experiment",
    "pass_rates",
    "plot_experiment",
    "run_experiment",
]
