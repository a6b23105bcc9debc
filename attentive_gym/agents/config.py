"""The run specification: one training run = one ``RunSpec`` (variant, algorithm, budget, seed).

A ``RunSpec`` is a frozen dataclass that validates itself on construction (``ValueError``
with the allowed values), round-trips through JSON (``to_dict`` / ``from_dict``) and names
its run folder (``run_name``). Budgets are in **environment steps** (one step = one
``env.step`` of one environment = ``dt`` = 0.05 s of simulated time by default).
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from attentive_gym._checks import check_int
from attentive_gym.attention.config import MODEL_VERSIONS, check_model_version
from attentive_gym.envs.config_mappings import config_as_mapping, env_kwargs_as_mappings
from attentive_gym.envs.tasks import TASK_VERSIONS, check_task_version, task_reward
from attentive_gym.wrappers.variants import FOCUS_LAYOUT, VARIANTS, has_proximity

__all__ = [
    "ALGOS",
    "VEC_ENVS",
    "OBS_SCALINGS",
    "ALGO_DEFAULTS",
    "N_ENVS",
    "PPO_N_ENVS",
    "QUICK",
    "SCHEDULE_KEYS",
    "SB3_LEARNING_RATE",
    "STEPS_PER_EVAL_EPISODE",
    "DEFAULT_WARM_START",
    "WARM_START_MIN_STEPS",
    "RunSpec",
    "canonical_rate",
    "default_eval_episodes",
    "parse_schedule",
    "parse_variants",
    "parse_seeds",
]

#: Algorithms ``train`` knows: SB3 ``PPO`` (default) and ``SAC``, and sb3-contrib's
#: ``RecurrentPPO`` (an LSTM policy; the ``agents`` extra installs sb3-contrib).
ALGOS = ("ppo", "sac", "recurrent-ppo")
#: Vectorisation of the training environments: the project's ``NativeVecEnv`` (one process,
#: all sensors in one call; the default), SB3's ``DummyVecEnv`` or ``SubprocVecEnv``. All
#: three give the same numbers.
VEC_ENVS = ("native", "dummy", "subproc")
#: What the policy sees of the observation: ``"running"`` (the default) normalises every
#: entry with running statistics (SB3's ``VecNormalize``, ``agents.normalization``; saved
#: with the model, frozen in evaluation); ``"none"`` passes the observation on in its own
#: units (metres, seconds, flags), as runs did before normalisation existed (their
#: ``spec.json`` has no ``obs_scaling`` and reads as ``"none"``).
OBS_SCALINGS = ("running", "none")

#: Versions of ``RunSpec.default_algo_kwargs`` (``RunSpec.algo_defaults``), so that a run
#: folder keeps the hyper-parameters it was trained with: 1, PPO's and RecurrentPPO's
#: learning rate constant at 3e-4 (SB3's default; runs written before 2026-12-03, whose
#: ``spec.json`` has no ``algo_defaults``); 2 (the current one), the rate decayed linearly
#: from 3e-4 to 0 over the budget (``"lin_3e-4"``), which keeps the focus policies from
#: falling back late in long runs (docs/notes/2026-12-03-learning-rate.md), with 4 envs ×
#: 256-step rollouts and minibatches of 256; 3 (the current one), PPO with 32 envs × 64-step
#: rollouts and minibatches of 512 (2048 steps and 20 gradient steps per update), which trains
#: more than twice as fast on 2 cores (docs/notes/2026-12-06-faster-ppo.md).
ALGO_DEFAULTS = (1, 2, 3)
#: ``RunSpec.n_envs`` when none is given: PPO's under ``algo_defaults`` 3, and every other case.
PPO_N_ENVS, N_ENVS = 32, 4

#: ``algo_kwargs`` that take a schedule: a number, or ``"lin_<number>"`` (as in rl-zoo's
#: hyper-parameter files), a linear decay from that number to 0 over the run's budget.
SCHEDULE_KEYS = ("learning_rate", "clip_range", "clip_range_vf")
_LINEAR_PREFIX = "lin_"
#: The learning rate of PPO, RecurrentPPO and SAC when none is given (SB3's).
SB3_LEARNING_RATE = 3e-4

#: ``RunSpec.warm_start`` when none is given: ``RunSpec.default_warm_start`` picks the teacher.
DEFAULT_WARM_START = "default"
#: The smallest budget (env steps) that warm-starts by default: the demonstrations take
#: 64,000 env steps of it (``agents.warm_start.DEMO_STEPS``), a quarter of this.
WARM_START_MIN_STEPS = 256_000
#: The variants whose observation the privileged teacher can read as ``make_env`` builds it
#: (raw and saliency: their sonar and laser; the focus layout: its ``proximity`` entry; in
#: ``goal-action`` it also sets the task's goal, ``agents.warm_start.goal_action_label``).
_PRIVILEGED_READABLE = ("raw", "saliency", "focus", "goal-action", "random-focus", "oracle")

#: ``compare --quick``: the raw sensors, the attended focus and its privileged bound (the
#: oracle) × 3 seeds × 300 000 PPO steps, 10 eval episodes every 50 000 steps, in the main
#: comparison's smaller arena (8 m, 2 distractors, 3 rubble per 100 m²). With today's PPO
#: rollout 150 000 steps were too few to tell raw from focus (0.53 each on 3 seeds); 300 000,
#: the first 64 000 cloning the privileged teacher (the default warm start), take about 9
#: minutes on 2 cores.
QUICK: dict[str, Any] = {
    "variants": ("raw", "focus", "oracle"),
    "seeds": (0, 1, 2),
    "total_steps": 300_000,
    "eval_every": 50_000,
    "eval_episodes": 10,
    "checkpoint_every": 50_000,
    "env_kwargs": {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0},
}


@dataclass(frozen=True)
class RunSpec:
    """Everything that determines one training run (and nothing about where it is written).

    Attributes:
        variant: observation variant, one of ``attentive_gym.wrappers.VARIANTS``.
        algo: one of ``ALGOS`` (``"ppo"``, ``"sac"``, ``"recurrent-ppo"``).
        total_steps: training budget in environment steps (summed over the ``n_envs``).
        seed: seeds SB3 (``seed=``), the training environments and, offset by 10 000,
            the evaluation episodes.
        n_envs: parallel training environments; None (the default) takes ``default_n_envs``
            (32 for PPO under ``algo_defaults`` 3, else 4).
        vec_env: ``"native"`` (one process, the fleet stepped as one), ``"dummy"`` (one
            process, one env after another) or ``"subproc"`` (one process per env).
        eval_every: environment steps between evaluations (plus one at 0 and at the end).
        eval_episodes: episodes per evaluation (the same episode seeds every time).
        checkpoint_every: environment steps between checkpoints (an interrupted run loses
            at most this many steps).
        env_kwargs: keyword arguments of ``make_env`` (``arena_size_m``, ``num_distractors``, ...);
            ``reward``, ``robot``, ``sonar`` and ``laser`` (a dataclass or a mapping of some
            of its fields) are stored as the mapping of every field, so ``to_dict`` is plain
            JSON and ``from_dict`` rebuilds the same settings.
        algo_kwargs: keyword arguments of the SB3 algorithm (override ``default_algo_kwargs``).
        algo_defaults: which version of ``default_algo_kwargs`` (one of ``ALGO_DEFAULTS``;
            the latest unless a stored spec says otherwise).
        torch_threads: threads of torch and of the compiled sensor sweep (numba) in the
            training process (1 suits a pool of runs).
        obs_scaling: one of ``OBS_SCALINGS``: how the observation reaches the policy.
        warm_start: None, or a teacher of ``agents.warm_start.WARM_STARTS`` (``"clearance"``,
            ``"privileged"``)
            whose demonstrations PPO clones before it trains; their env steps count in
            ``total_steps``. Not given (``DEFAULT_WARM_START``): ``default_warm_start``'s.
        env_version: the version of the attentional model's defaults the environments are
            built with (``attention.MODEL_VERSIONS``; the latest unless a stored spec says
            otherwise: one without it was trained with version 0).
        task_version: the version of the task the environments are built with
            (``envs.tasks.TASK_VERSIONS``: its reward and ``proximity`` defaults; the latest
            unless a stored spec says otherwise: one without it was trained on version 0).
    """

    variant: str = "focus"
    algo: str = "ppo"
    total_steps: int = 100_000
    seed: int = 0
    n_envs: int | None = None
    vec_env: str = "native"
    eval_every: int = 10_000
    eval_episodes: int = 20
    checkpoint_every: int = 20_000
    env_kwargs: Mapping[str, Any] = field(default_factory=dict)
    algo_kwargs: Mapping[str, Any] = field(default_factory=dict)
    algo_defaults: int = ALGO_DEFAULTS[-1]
    torch_threads: int = 1
    obs_scaling: str = "running"
    warm_start: str | None = DEFAULT_WARM_START
    env_version: int = MODEL_VERSIONS[-1]
    task_version: int = TASK_VERSIONS[-1]

    def __post_init__(self) -> None:
        if self.variant not in VARIANTS:
            raise ValueError(f"unknown variant {self.variant!r}; allowed: {list(VARIANTS)}")
        if self.algo not in ALGOS:
            raise ValueError(f"unknown algo {self.algo!r}; allowed: {list(ALGOS)}")
        if self.vec_env not in VEC_ENVS:
            raise ValueError(f"unknown vec_env {self.vec_env!r}; allowed: {list(VEC_ENVS)}")
        if self.obs_scaling not in OBS_SCALINGS:
            raise ValueError(f"unknown obs_scaling {self.obs_scaling!r}; allowed: {list(OBS_SCALINGS)}")
        check_int("total_steps", self.total_steps, 1)
        check_int("seed", self.seed, 0)
        check_model_version(self.env_version, "env_version")
        check_task_version(self.task_version, "task_version")
        for name, what in (
            ("version", "the model's version is the spec's env_version"),
            ("task", "the task's version is the spec's task_version"),
        ):
            if name in self.env_kwargs:
                raise ValueError(f"env_kwargs cannot hold {name!r}: {what}")
        if type(self.algo_defaults) is not int or self.algo_defaults not in ALGO_DEFAULTS:
            raise ValueError(f"unknown algo_defaults {self.algo_defaults!r}; allowed: {list(ALGO_DEFAULTS)}")
        if self.n_envs is None:
            object.__setattr__(self, "n_envs", self.default_n_envs())
        check_int("n_envs", self.n_envs, 1)
        check_int("eval_every", self.eval_every, 1)
        check_int("eval_episodes", self.eval_episodes, 1)
        check_int("checkpoint_every", self.checkpoint_every, 1)
        check_int("torch_threads", self.torch_threads, 1)
        for name in ("env_kwargs", "algo_kwargs"):
            value = getattr(self, name)
            if not isinstance(value, Mapping):
                raise ValueError(f"{name} must be a mapping, got {type(value).__name__}")
            object.__setattr__(self, name, dict(value))
        object.__setattr__(self, "env_kwargs", _resolved_env_kwargs(self.env_kwargs, self.task_version))
        if self.warm_start == DEFAULT_WARM_START:
            object.__setattr__(self, "warm_start", self.default_warm_start())
        if self.warm_start is not None and self.algo != "ppo":
            raise ValueError(f"warm_start applies to ppo only, got algo {self.algo!r}")
        _check_finite("algo_kwargs", self.algo_kwargs)
        for key in SCHEDULE_KEYS:
            if isinstance(self.algo_kwargs.get(key), str):
                parse_schedule(key, self.algo_kwargs[key])

    @property
    def run_name(self) -> str:
        """The run's folder name, e.g. ``"focus-seed3"``."""
        return f"{self.variant}-seed{self.seed}"

    def default_n_envs(self) -> int:
        """The training envs when ``n_envs`` is not given: ``PPO_N_ENVS`` (32) for PPO under
        ``algo_defaults`` 3, ``N_ENVS`` (4) otherwise (RecurrentPPO and SAC, and earlier defaults)."""
        return PPO_N_ENVS if self.algo == "ppo" and self.algo_defaults >= 3 else N_ENVS

    def default_warm_start(self) -> str | None:
        """The teacher PPO clones when ``warm_start`` is not given: ``"privileged"`` (the
        clearance avoider steering for the target's true bearing) wherever it can read the
        observation, so that every variant starts from one behaviour, cloned from its own
        observation (docs/results/safe_rescue.md; in ``goal-action`` with the task's goal and
        the default weights); None for the other algorithms, for stacked or masked readings,
        for a focus layout without the ``proximity`` entry, and for a budget under
        ``WARM_START_MIN_STEPS``, which the demonstrations would take too much of."""
        if self.algo != "ppo" or self.variant not in _PRIVILEGED_READABLE or self.total_steps < WARM_START_MIN_STEPS:
            return None
        if self.variant in FOCUS_LAYOUT and not self.proximity:
            return None
        return "privileged"

    @property
    def proximity(self) -> bool:
        """Whether the run's observation carries the ``proximity`` entry: a variant with the
        focus layout, with ``env_kwargs``' ``proximity`` or, where it is not given, the task's
        default, as ``make_env`` resolves it (``wrappers.variants.has_proximity``)."""
        return has_proximity(self.variant, self.task_version, self.env_kwargs.get("proximity"))

    def default_algo_kwargs(self) -> dict[str, Any]:
        """Hyper-parameters used unless ``algo_kwargs`` overrides them.

        PPO: rollouts of 64 steps per env and minibatches of 512 (with ``n_envs`` 32, 2048
        steps and 4 minibatches per epoch; rollouts of 256 and minibatches of 256 with
        ``algo_defaults`` 1 and 2), 5 epochs; RecurrentPPO: rollouts of 256, minibatches of 256,
        5 epochs. Both: lr 3e-4 decayed linearly to 0 over the budget (``"lin_3e-4"``; constant 3e-4 with
        ``algo_defaults`` 1), gamma 0.99, a small ent_coef for exploration. RecurrentPPO's LSTM has
        one layer of 64 units (sb3-contrib's default is 256): the observations hold at
        most a few hundred numbers, and 64 units train ≈ 3× faster on a CPU. SAC: SB3's
        defaults with a 100 000-step buffer and 1 000 warm-up steps.
        """
        if self.algo in ("ppo", "recurrent-ppo"):
            learning_rate = SB3_LEARNING_RATE if self.algo_defaults == 1 else "lin_3e-4"
            fast = self.algo == "ppo" and self.algo_defaults >= 3
            ppo = {
                "n_steps": 64 if fast else 256,
                "batch_size": 512 if fast else 256,
                "n_epochs": 5,
                "learning_rate": learning_rate,
                "gamma": 0.99,
                "ent_coef": 0.005,
            }
            return ppo if self.algo == "ppo" else {**ppo, "policy_kwargs": {"lstm_hidden_size": 64}}
        return {"buffer_size": 100_000, "learning_starts": 1_000, "batch_size": 256}

    def hyper_parameters(self) -> dict[str, Any]:
        """``default_algo_kwargs`` updated with ``algo_kwargs``, schedules still as their
        ``"lin_<number>"`` text; ``policy_kwargs`` are merged key by key
        (``{"policy_kwargs": {"net_arch": [32]}}`` keeps the LSTM's size)."""
        defaults = self.default_algo_kwargs()
        merged = {**defaults, **self.algo_kwargs}
        if "policy_kwargs" in defaults and isinstance(self.algo_kwargs.get("policy_kwargs"), Mapping):
            merged["policy_kwargs"] = {**defaults["policy_kwargs"], **self.algo_kwargs["policy_kwargs"]}
        return merged

    def merged_algo_kwargs(self) -> dict[str, Any]:
        """``hyper_parameters`` with the ``"lin_<number>"`` schedules (``SCHEDULE_KEYS``) as
        SB3 ``LinearSchedule`` objects: the algorithm's keyword arguments."""
        merged = self.hyper_parameters()
        for key in SCHEDULE_KEYS:
            if isinstance(merged.get(key), str):
                merged[key] = parse_schedule(key, merged[key])
        return merged

    def learning_rate(self) -> float | str:
        """The run's learning rate as ``canonical_rate`` writes it (``SB3_LEARNING_RATE`` when
        neither the defaults nor ``algo_kwargs`` give one)."""
        return canonical_rate("learning_rate", self.hyper_parameters().get("learning_rate", SB3_LEARNING_RATE))

    def settings(self) -> dict[str, Any]:
        """What the run's numbers depend on, for telling runs apart: ``to_dict`` with
        ``algo_kwargs`` replaced by ``hyper_parameters`` (schedules as ``canonical_rate``
        writes them) and without ``algo_defaults``, so that a folder trained with earlier
        defaults and a command asking for the same hyper-parameters agree."""
        data = self.to_dict()
        del data["algo_defaults"]
        data["algo_kwargs"] = {
            key: canonical_rate(key, value) if key in SCHEDULE_KEYS else value
            for key, value in self.hyper_parameters().items()
        }
        return data

    def to_dict(self) -> dict[str, Any]:
        """A JSON-serialisable dict (``from_dict`` inverts it)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> RunSpec:
        """Build from ``to_dict``'s output; unknown keys raise ``ValueError``. A spec without
        ``obs_scaling`` was written before observations were scaled: it reads as ``"none"``;
        one without ``algo_defaults`` before the learning rate decayed by default: it reads as 1;
        one without ``env_version`` before the model's defaults had versions, or without
        ``task_version`` before the task had versions: it reads as 0; one without
        ``warm_start`` before warm starts existed: it reads as None."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(data) - names)
        if unknown:
            raise ValueError(f"unknown RunSpec field(s) {unknown}; allowed: {sorted(names)}")
        return cls(
            **{
                "obs_scaling": "none",
                "algo_defaults": 1,
                "env_version": 0,
                "task_version": 0,
                "warm_start": None,
                **data,
            }
        )

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2, sort_keys=True)

    def replace(self, **changes: Any) -> RunSpec:
        """A copy with ``changes`` applied (validated again)."""
        return dataclasses.replace(self, **changes)

    def for_variant(self, variant: str, **changes: Any) -> RunSpec:
        """A copy for ``variant`` (with ``changes``): a comparison's run of each variant. Where
        this spec's warm start is its variant's default, the copy takes its own variant's
        default (``default_warm_start``: the privileged teacher for raw, none for
        ``raw-stack``), so that one command trains every variant with the start it can have."""
        warm_start = DEFAULT_WARM_START if self.warm_start == self.default_warm_start() else self.warm_start
        return self.replace(variant=variant, warm_start=warm_start, **changes)

    def same_settings(self, other: RunSpec) -> bool:
        """Whether ``other`` has the same ``settings``."""
        return self.settings() == other.settings()

    def differences(self, other: RunSpec) -> str:
        """The ``settings`` where ``other`` differs, as ``"eval_every 25 → 51, total_steps 256 → 512"``;
        within ``algo_kwargs`` the entries that differ (``"algo_kwargs.n_epochs 1 → 2"``)."""
        mine, theirs = self.settings(), other.settings()
        hyper = (mine.pop("algo_kwargs"), theirs.pop("algo_kwargs"))
        changed = [(key, mine[key], theirs[key]) for key in mine if mine[key] != theirs[key]]
        changed += [
            (f"algo_kwargs.{key}", hyper[0].get(key), hyper[1].get(key))
            for key in dict.fromkeys([*hyper[0], *hyper[1]])
            if hyper[0].get(key) != hyper[1].get(key)
        ]
        return ", ".join(f"{key} {json.dumps(old)} → {json.dumps(new)}" for key, old, new in changed)


#: Training env steps per evaluation episode in ``default_eval_episodes``: a budget of
#: 100 000 steps or more gets ``RunSpec.eval_episodes`` (20) episodes per evaluation.
STEPS_PER_EVAL_EPISODE = 5_000


def default_eval_episodes(total_steps: int) -> int:
    """Episodes per evaluation when the command line does not say (``--eval-episodes``): one
    per ``STEPS_PER_EVAL_EPISODE`` training env steps of ``total_steps``, at least 1 and at
    most ``RunSpec.eval_episodes`` (20, reached at 100 000 steps).

    An evaluation episode lasts up to the episode's time limit (hundreds of env steps for an
    untrained policy), so 20 of them at the start and at the end of a smoke run of a few
    hundred steps cost many times its training; 1 each keeps the learning curve's points.
    """
    check_int("total_steps", total_steps, 1)
    return max(1, min(RunSpec.eval_episodes, total_steps // STEPS_PER_EVAL_EPISODE))


def _resolved_env_kwargs(env_kwargs: dict[str, Any], task_version: int) -> dict[str, Any]:
    """``env_kwargs`` with the env's settings objects (``reward``, ``robot``, ``sonar``,
    ``laser``; a dataclass or a mapping of some fields) as the mapping of every field
    (``env_kwargs_as_mappings``; a ``reward`` mapping's missing fields are those of task
    ``task_version``'s reward): plain JSON, equal however the same settings were given;
    ``ValueError`` for a field or value their dataclass refuses."""
    try:
        if "reward" in env_kwargs:
            env_kwargs = {**env_kwargs, "reward": config_as_mapping(task_reward(task_version, env_kwargs["reward"]))}
        return env_kwargs_as_mappings(env_kwargs)
    except TypeError as err:
        raise ValueError(f"env_kwargs: {err}") from None


def _check_finite(name: str, value: Any) -> None:
    """``ValueError`` naming the entry when a float in ``value`` (nested mappings and lists
    included) is NaN or infinite: SB3 would take it and train on NaN."""
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{name} must hold finite numbers, got {value}")
    items = (
        value.items() if isinstance(value, Mapping) else enumerate(value) if isinstance(value, (list, tuple)) else ()
    )
    for key, item in items:
        _check_finite(f"{name}[{key!r}]", item)


def canonical_rate(key: str, value: Any) -> Any:
    """A schedule setting (``algo_kwargs[key]``, ``key`` in ``SCHEDULE_KEYS``) in one spelling
    per value, so that ``"lin_3e-4"`` and ``"lin_0.0003"`` (or ``3e-4`` and ``0.0003``) compare
    equal: ``"lin_" + repr(start)`` for a schedule, a float for a number, anything else as
    given; ``ValueError`` for text that is no schedule (``parse_schedule``)."""
    if isinstance(value, str):
        return _LINEAR_PREFIX + repr(parse_schedule(key, value).start)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    return value


def parse_schedule(key: str, text: str):
    """``"lin_<number>"`` (``algo_kwargs[key]``) as SB3's ``LinearSchedule`` from that number
    (> 0, finite) down to 0 at the end of the run's budget: SB3 passes it the fraction of
    the budget that remains, so a run resumed from a checkpoint continues the same decay,
    and ``--extend`` stretches it over the new budget (the value rises again where the
    extension starts). ``ValueError`` for any other string."""
    number = text[len(_LINEAR_PREFIX) :] if text.startswith(_LINEAR_PREFIX) else ""
    try:
        start = float(number)
    except ValueError:
        start = math.nan
    if not (math.isfinite(start) and start > 0.0):
        raise ValueError(
            f"algo_kwargs[{key!r}] = {text!r}: a schedule is a number or "
            f"'{_LINEAR_PREFIX}<number > 0>' (a linear decay to 0 over the budget), e.g. 'lin_3e-4'"
        )
    from stable_baselines3.common.utils import LinearSchedule

    return LinearSchedule(start, 0.0, 1.0)


def _split_list(text: str, what: str) -> list[str]:
    """``"a, b"`` → ``["a", "b"]``; an empty item (``"a,"``, ``"a,,b"``) raises ``ValueError``."""
    parts = [part.strip() for part in text.split(",")]
    if "" in parts:
        raise ValueError(f"empty item in the {what} list {text!r}; separate the items by single commas")
    return parts


def _check_distinct(items: Sequence[Any], what: str, text: str) -> None:
    twice = next((item for i, item in enumerate(items) if item in items[:i]), None)
    if twice is not None:
        raise ValueError(f"{what} {twice!r} is listed twice in {text!r}; each may appear once")


def parse_variants(text: str) -> tuple[str, ...]:
    """``"raw,raw-stack,focus"`` → ``("raw", "raw-stack", "focus")``.

    Unknown, empty (``"raw,"``) or repeated items raise ``ValueError`` naming the item.
    """
    if not text.strip():
        raise ValueError(f"no variant given; allowed: {list(VARIANTS)}")
    names = tuple(_split_list(text, "variant"))
    for name in names:
        if name not in VARIANTS:
            raise ValueError(f"unknown variant {name!r}; allowed: {list(VARIANTS)}")
    _check_distinct(names, "variant", text)
    return names


_SEEDS_FORMAT = "a count (e.g. 5) or a comma list of distinct integers >= 0 (e.g. 0,3,7)"


def _seed_number(part: str, text: str) -> int:
    try:
        return int(part)
    except ValueError:
        raise ValueError(f"seeds must be {_SEEDS_FORMAT}, got {text!r}") from None


def parse_seeds(text: str | int) -> tuple[int, ...]:
    """Seeds from a count (``"5"`` → 0..4) or a list (``"0,3,7"``).

    A count < 1, a non-integer, or a negative, empty (``"0,1,"``) or repeated item in a list
    raises ``ValueError`` naming what was wrong.
    """
    text = str(text).strip()
    if "," not in text:
        count = _seed_number(text, text)
        if count < 1:
            raise ValueError(f"seeds must be {_SEEDS_FORMAT}; a count must be >= 1, got {text!r}")
        return tuple(range(count))
    seeds = tuple(_seed_number(part, text) for part in _split_list(text, "seed"))
    if min(seeds) < 0:
        raise ValueError(f"seeds must be {_SEEDS_FORMAT}, got {text!r}")
    _check_distinct(seeds, "seed", text)
    return seeds
