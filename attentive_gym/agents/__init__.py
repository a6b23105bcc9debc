"""Train SB3 agents on the observation variants and compare them.

- ``RunSpec`` (``config``): one run — variant, algorithm, budget in env steps, seed, ...
- ``train`` (``training``): one run with periodic evaluation, TensorBoard logs,
  checkpoints/resume, ``final_model.zip``, ``metrics.json`` and a ``done`` marker.
- ``evaluate_policy`` (``evaluation``): success rate, return, collisions, episode length.
- ``pretrained``: the small ``raw`` and ``focus`` policies shipped with the package
  (``attentive-gym evaluate --pretrained focus``).
- ``goal_choice``: what a ``goal-action`` agent chooses at each evaluation (its goal against
  the task's, its map weights): a run's ``goal_choice.csv``.
- ``compare.compare``: every (variant, seed) pair in parallel processes or on Ray, then
  ``results.csv``, ``learning_curves.png`` and ``summary.md``/``summary.csv``.
- ``backends.run_many``: the runs in spawned processes or Ray tasks; ``stopping``: Ctrl-C and
  SIGTERM (``Interrupted``), which both ``backends`` and ``training`` stop on.
- ``results``: atomic writes and summaries, with the statistics of
  ``attentive_gym.statistics`` (IQM, bootstrap CIs, probability of improvement, as
  ``rliable``); ``plots``: the figures; ``sweep``: the clutter sweep;
  ``merged``: many comparisons' rows in one table, tagged with their training setting, and
  attention against its bound and control (the repository's ``tools/report.py`` renders the
  docs' results pages from them; ``report`` is its deprecated former home).

Importing this package does not import torch or SB3 (the ``agents`` extra); the functions do.
SB3's vector env over a fleet, ``NativeVecEnv``, moved to ``attentive_gym.vector.sb3``, and the
statistics to ``attentive_gym.statistics`` (the perception metrics use them too); the old paths
``attentive_gym.agents.native_vec`` and ``attentive_gym.agents.statistics`` still import, with a
``DeprecationWarning``.
"""

from attentive_gym import _moved
from attentive_gym.agents.config import ALGOS, RunSpec, parse_seeds, parse_variants
from attentive_gym.agents.results import summarise
from attentive_gym.statistics import bootstrap_ci, iqm, probability_of_improvement

__all__ = [
    "ALGOS",
    "RunSpec",
    "parse_seeds",
    "parse_variants",
    "summarise",
    "bootstrap_ci",
    "iqm",
    "probability_of_improvement",
    "train",
    "evaluate_policy",
    "load_model",
]

_moved.install(
    {f"{__name__}.native_vec": "attentive_gym.vector.sb3", f"{__name__}.statistics": "attentive_gym.statistics"}
)


def __getattr__(name):
    if name in ("train", "load_model"):
        from attentive_gym.agents import training

        return getattr(training, name)
    if name == "evaluate_policy":
        from attentive_gym.agents.evaluation import evaluate_policy

        return evaluate_policy
    return _moved.attribute(__name__, name)  # an old module path, or AttributeError
