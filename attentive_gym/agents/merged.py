"""Many comparisons' results in one tidy table, and the figures read from it.

Batches of runs trained at different times add up to one table when each row carries the
training setting it came from:

- ``COMPARISON_COLUMNS`` / ``CLUTTER_COLUMNS``: the columns of a merged comparison and of a
  merged clutter sweep (``EVAL_COLUMNS`` with ``algo``, ``obs_scaling`` and, for a sweep,
  ``num_distractors``).
- ``algo_tag(run, variant)``: the setting tag of a comparison's rows (its algorithm, its
  learning rate unless SB3's constant default, its rollout, its model version unless 0 for
  the variants that run the model); ``default_tag(variant)``: the tag of today's default
  setting (``RunSpec``'s, on ``HEADLINE_MODEL_VERSION``); ``tagged_rate(tag)``: the rate a
  tag names.
- ``merge_rows(existing, new, algo, keys, obs_scaling)``: ``new`` rows, tagged, replace the
  rows of the same runs.
- ``labelled(rows)`` / ``ordered(rows)``: variant names that say their setting
  (``"focus (recurrent-ppo, unscaled)"``), and the tables' row order.
- ``budgets(rows)``: the rows at each training budget (runs trained on are cut there).
- ``summarise_by_setting(rows)``: ``summarise`` with each variant's probability of
  improvement taken over raw of its own training setting.
- ``targets(rows, summary)`` / ``clutter_targets(summary)``: attention against its bound and
  control: how soon an attended variant reaches raw's final success, whether its interval
  lies above raw's, and the share of the raw → oracle gap it closes.
- ``learning_curve_figures(rows)``: one learning-curve figure per training setting.

Example:
    >>> from attentive_gym.agents.merged import labelled
    >>> [row["variant"] for row in labelled([{"variant": "focus", "algo": "ppo", "obs_scaling": "none"}])]
    ['focus (unscaled)']
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

from attentive_gym.agents.config import SB3_LEARNING_RATE, RunSpec, canonical_rate
from attentive_gym.agents.plots import curve_stats, split_label
from attentive_gym.agents.results import EVAL_COLUMNS, summarise
from attentive_gym.registration import MODEL_VARIANTS
from attentive_gym.wrappers.variants import VARIANTS

__all__ = [
    "COMPARISON_COLUMNS",
    "CLUTTER_COLUMNS",
    "SCALED",
    "BASELINE",
    "ORACLE",
    "NOT_ATTENDED",
    "algo_tag",
    "default_tag",
    "HEADLINE_MODEL_VERSION",
    "HEADLINE_STEPS",
    "UNNOTED_MODEL_VERSION",
    "UNNOTED_TASK_VERSION",
    "row_tag",
    "without_model_note",
    "tagged_rate",
    "merge_rows",
    "labelled",
    "ordered",
    "budgets",
    "summarise_by_setting",
    "targets",
    "clutter_targets",
    "learning_curve_figures",
]

COMPARISON_COLUMNS = ("algo", "obs_scaling", *EVAL_COLUMNS)
CLUTTER_COLUMNS = ("algo", "obs_scaling", "num_distractors", *EVAL_COLUMNS)
#: The scaling of the runs whose learning curves the figures show (``RunSpec``'s default).
SCALED = "running"
#: The baseline and the bound of attention.
BASELINE, ORACLE = "raw", "oracle"
#: Variants that bound or control attention, and the baselines; the rest are "attended".
NOT_ATTENDED = frozenset({"raw", "raw-stack", "oracle", "random-focus"})


#: PPO's rollout before ``algo_defaults`` 3 (envs, steps per env, minibatch, epochs): rows
#: trained with it carry no rollout note in their tag.
EARLIER_ROLLOUT = (4, 256, 256, 5)
#: The model version (``RunSpec.env_version``) whose rows carry no model note in their tag:
#: every row trained before version 1 existed was trained on it.
UNNOTED_MODEL_VERSION = 0
#: The model version of the headline's attended variants (raw and the oracle run no model).
HEADLINE_MODEL_VERSION = 2
#: The budget (env steps) of the headline's runs, whose default settings ``default_tag`` names.
HEADLINE_STEPS = 1_000_000
#: The task version (``RunSpec.task_version``) whose rows carry no task note in their tag:
#: every row trained before version 1 existed was trained on it.
UNNOTED_TASK_VERSION = 0
_MODEL_NOTE = re.compile(r", model v\d+")


def row_tag(tag: str, variant: str) -> str:
    """The tag of a ``variant`` row of a comparison tagged ``tag``: ``tag`` without its
    ``", model v<N>"`` note when the variant runs no attention model (``raw``, ``raw-stack``,
    ``oracle``: their observations are the same under every model version), so that their
    rows of one training setting share one tag whatever the model."""
    return tag if variant in MODEL_VARIANTS else _MODEL_NOTE.sub("", tag)


def algo_tag(run: Mapping[str, Any], variant: str | None = None) -> str:
    """The tag of the rows of a comparison whose run settings (``compare.json``'s ``"run"``)
    are ``run``: its algorithm, followed by ``", lr <rate>"`` unless its learning rate is
    SB3's constant ``SB3_LEARNING_RATE`` (a schedule, the default since ``algo_defaults`` 2,
    or another number given in ``algo_kwargs``), and for PPO and RecurrentPPO by the rollout
    (``", 32 envs × 64 steps, batch 512"``, with ``", N epochs"`` when not 5) unless it is
    ``EARLIER_ROLLOUT``, by ``", warm start <teacher>"`` for a warm-started run, and by
    ``", task v<N>"`` for a task version other than ``UNNOTED_TASK_VERSION`` and by
    ``", model v<N>"`` for a model version other than ``UNNOTED_MODEL_VERSION``, so that runs
    at different rates, rollouts, starts, tasks or models never share a tag. Given a ``variant``,
    the tag of its rows (``row_tag``), with its own warm start where ``run`` leaves it to each
    variant's default (``compare.json``)."""
    spec = RunSpec.from_dict(run if variant is None else {**run, "variant": variant})
    parts = [spec.algo]
    if spec.learning_rate() != SB3_LEARNING_RATE:
        parts.append(f"lr {spec.hyper_parameters()['learning_rate']}")
    if spec.algo != "sac":
        hyper = spec.hyper_parameters()
        rollout = (spec.n_envs, hyper["n_steps"], hyper["batch_size"], hyper["n_epochs"])
        if rollout != EARLIER_ROLLOUT:
            parts.append(f"{rollout[0]} envs × {rollout[1]} steps, batch {rollout[2]}")
            parts += [f"{rollout[3]} epochs"] if rollout[3] != EARLIER_ROLLOUT[3] else []
    if spec.warm_start is not None:
        parts.append(f"warm start {spec.warm_start}")
    if spec.task_version != UNNOTED_TASK_VERSION:
        parts.append(f"task v{spec.task_version}")
    if spec.env_version != UNNOTED_MODEL_VERSION:
        parts.append(f"model v{spec.env_version}")
    tag = ", ".join(parts)
    return tag if variant is None else row_tag(tag, variant)


def default_tag(variant: str | None = None) -> str:
    """``algo_tag`` of today's default training setting for a run of ``HEADLINE_STEPS`` (the
    latest task, and the privileged warm start where the variant can have it) on the model
    version of the headline (``HEADLINE_MODEL_VERSION``): the tag of the rows a
    ``RunSpec(variant=variant, total_steps=HEADLINE_STEPS, env_version=HEADLINE_MODEL_VERSION)``
    with no other field given would give (``variant``'s rows; None: ``focus``'s setting)."""
    spec = RunSpec(variant=variant or "focus", total_steps=HEADLINE_STEPS, env_version=HEADLINE_MODEL_VERSION)
    return algo_tag(spec.to_dict(), variant)


def without_model_note(setting: str) -> str:
    """A label's setting (``split_label``; ``labelled`` writes it) without its ``", model v<N>"``
    note: the setting of the raw and oracle rows an attended variant's rows are compared with
    (``" (ppo, lr lin_3e-4, model v1)"`` → ``" (ppo, lr lin_3e-4)"``; ``" (ppo, model v1)"`` →
    ``""``, as ``labelled`` leaves plain PPO unnamed)."""
    stripped = _MODEL_NOTE.sub("", setting)
    return {" (ppo)": "", " (ppo, unscaled)": " (unscaled)"}.get(stripped, stripped)


def tagged_rate(tag: str) -> float | str:
    """The learning rate a tag names (its ``"lr <rate>"`` part, as ``canonical_rate`` writes
    it), ``SB3_LEARNING_RATE`` for none.

    Raises:
        ValueError: the ``lr`` part names no number or schedule.
    """
    note = next((part.strip() for part in tag.split(",")[1:] if part.strip().startswith("lr ")), None)
    if note is None:
        return SB3_LEARNING_RATE
    text = note[len("lr ") :].strip()
    try:
        return canonical_rate("learning_rate", text if text.startswith("lin_") else float(text))
    except ValueError:
        raise ValueError(
            f"--algo {tag!r}: {note!r} names no learning rate; write e.g. 'lr lin_3e-4' or 'lr 1e-4'"
        ) from None


def merge_rows(
    existing: Sequence[Mapping[str, Any]],
    new: Sequence[Mapping[str, Any]],
    algo: str,
    keys: Sequence[str],
    obs_scaling: str = SCALED,
) -> list[dict[str, Any]]:
    """``existing`` rows with every run of ``new`` (tagged with ``algo`` and ``obs_scaling``)
    replacing the rows of the same run; a run is identified by ``keys`` (with ``algo`` and
    ``obs_scaling``; an existing row without ``obs_scaling`` has ``"none"``). A row of a
    variant that runs no model is tagged without ``algo``'s model note (``row_tag``)."""
    tagged = [{"algo": row_tag(algo, row["variant"]), "obs_scaling": obs_scaling, **row} for row in new]
    run = lambda row: tuple(row[k] for k in ("algo", "obs_scaling", *keys))  # noqa: E731
    replaced = {run(row) for row in tagged}
    kept = [{"obs_scaling": "none", **row} for row in existing]
    return [row for row in kept if run(row) not in replaced] + tagged


def labelled(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Rows whose variant names their algorithm when it is not PPO and says "unscaled" when
    the policy saw the observation in its own units (``obs_scaling`` ``"none"``, or absent)."""
    out = []
    for row in rows:
        notes = [row["algo"]] if row["algo"] != "ppo" else []
        notes += ["unscaled"] if row.get("obs_scaling", "none") == "none" else []
        out.append({**row, "variant": f"{row['variant']} ({', '.join(notes)})" if notes else row["variant"]})
    return out


def ordered(rows: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """``rows`` in the tables' order: the runs on normalised observations first, then PPO's
    before other algorithms', then by variant in ``VARIANTS``' order (raw first, the bound and
    the control last); rows of one variant and setting keep their order."""
    rank = {variant: k for k, variant in enumerate(VARIANTS)}
    return sorted(
        rows,
        key=lambda row: (
            row.get("obs_scaling", "none") != SCALED,
            row["algo"] != "ppo",
            rank.get(row["variant"], len(rank)),
        ),
    )


def budgets(
    rows: Sequence[Mapping[str, Any]], keys: Sequence[str] = ("variant", "seed")
) -> list[tuple[int, list[Mapping[str, Any]]]]:
    """``(budget, rows)`` for each distinct final env-step count of the runs in ``rows``
    (a run: the values of ``keys``; a sweep's runs also differ in ``num_distractors``),
    smallest first: the rows of every run trained at least that far, up to that budget."""
    run = lambda row: tuple(row[k] for k in keys)  # noqa: E731
    finals: dict[tuple[Any, ...], int] = {}
    for row in rows:
        finals[run(row)] = max(finals.get(run(row), 0), row["env_steps"])
    return [
        (budget, [row for row in rows if finals[run(row)] >= budget and row["env_steps"] <= budget])
        for budget in sorted(set(finals.values()))
    ]


def summarise_by_setting(rows: Sequence[Mapping[str, Any]], threshold: float = 0.5) -> list[dict[str, Any]]:
    """``summarise(rows)`` for labelled rows of several training settings (``labelled``): the
    summary rows in the variants' first-seen order, each variant's ``prob_improvement`` and
    ``prob_safe_improvement`` taken over raw of the same setting (``"raw (recurrent-ppo)"``
    for ``"focus (recurrent-ppo)"``), NaN where that setting has no raw."""
    settings = list(dict.fromkeys(split_label(row["variant"])[1] for row in rows))
    by_variant = {}
    for setting in settings:
        group = [row for row in rows if split_label(row["variant"])[1] == setting]
        own = {row["variant"] for row in group}
        baseline = BASELINE + without_model_note(setting)
        if baseline not in own:
            group += [row for row in rows if row["variant"] == baseline]
        for row in summarise(group, threshold=threshold, baseline=baseline):
            if row["variant"] not in own:
                continue
            if not any(r["variant"] == baseline for r in group):
                row.update({key: math.nan for key in row if key.startswith("prob_")}, improvement_over=baseline)
            by_variant[row["variant"]] = row
    return [by_variant[variant] for variant in dict.fromkeys(row["variant"] for row in rows)]


def targets(rows: Sequence[Mapping[str, Any]], summary: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """For every attended variant of ``summary`` (``summarise(rows)``), how it compares with
    ``raw`` and ``oracle`` of the same setting (``without_model_note``; NaN where they are
    missing):

    - ``steps_fraction``: the env steps at which its mean curve first reaches raw's final
      mean success, as a fraction of raw's budget;
    - ``above_raw``: its final-success CI lies wholly above raw's;
    - ``gap_closed``: (its final success − raw's) / (oracle's − raw's).
    """
    by_variant = {row["variant"]: row for row in summary}
    out = []
    for row in summary:
        if split_label(row["variant"])[0] in NOT_ATTENDED:
            continue
        setting = without_model_note(split_label(row["variant"])[1])
        raw, oracle = by_variant.get(BASELINE + setting), by_variant.get(ORACLE + setting)
        steps_fraction = gap = math.nan
        above = False
        if raw is not None:
            steps, mean_curve, _, _ = curve_stats(rows, row["variant"], "success_rate")
            reached = [s for s, m in zip(steps, mean_curve) if m >= raw["final_success_mean"]]
            steps_fraction = reached[0] / raw["final_env_steps"] if reached else math.nan
            above = row["final_success_ci_low"] > raw["final_success_ci_high"]
            if oracle is not None and oracle["final_success_mean"] > raw["final_success_mean"]:
                gap = (row["final_success_mean"] - raw["final_success_mean"]) / (
                    oracle["final_success_mean"] - raw["final_success_mean"]
                )
        out.append({"variant": row["variant"], "steps_fraction": steps_fraction, "above_raw": above, "gap_closed": gap})
    return out


def clutter_targets(summary: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """For every attended variant of a clutter sweep's ``summary`` and every distractor count,
    its margin over ``raw`` of the same algorithm and scaling (final success minus raw's) and
    the gap between raw and ``oracle`` it closes (NaN where raw or the oracle is missing,
    or the oracle is not above raw), in ``summary``'s order."""
    cell = {(row["variant"], row["num_distractors"]): row for row in summary}
    out = []
    for row in summary:
        if split_label(row["variant"])[0] in NOT_ATTENDED:
            continue
        n, setting = row["num_distractors"], without_model_note(split_label(row["variant"])[1])
        raw, oracle = cell.get((BASELINE + setting, n)), cell.get((ORACLE + setting, n))
        margin = gap = math.nan
        if raw is not None:
            margin = row["final_success_mean"] - raw["final_success_mean"]
            if oracle is not None and oracle["final_success_mean"] > raw["final_success_mean"]:
                gap = margin / (oracle["final_success_mean"] - raw["final_success_mean"])
        out.append({"variant": row["variant"], "num_distractors": n, "margin": margin, "gap_closed": gap})
    return out


def learning_curve_figures(rows: Sequence[Mapping[str, Any]]) -> list[tuple[str, str, list[Mapping[str, Any]]]]:
    """One learning-curve figure per training setting of the ``labelled`` ``rows``, so that no
    figure mixes more curves than a reader can tell apart: ``(file name, setting, rows)``.
    The first, in ``rl_learning_curves.png``, holds today's default setting (each variant's
    ``default_tag(variant)``: the attended ones on ``HEADLINE_MODEL_VERSION``), labelled by
    their variant alone (the page says what today's defaults are); then one per ``algo`` tag, in
    ``rl_learning_curves_<tag>.png``, but for a tag whose rows are all in the first. The first
    tag present takes the plain name when the default's rows are absent."""

    def in_headline(row: Mapping[str, Any]) -> bool:
        return row["algo"] == default_tag(split_label(row["variant"])[0])

    headline = [{**row, "variant": split_label(row["variant"])[0]} for row in filter(in_headline, rows)]
    figures = [("rl_learning_curves.png", "today's defaults", headline)] if headline else []
    for tag in dict.fromkeys(row["algo"] for row in rows):
        tagged = [row for row in rows if row["algo"] == tag]
        if all(in_headline(row) for row in tagged):
            continue
        suffix = "_" + re.sub(r"[^0-9A-Za-z]+", "-", tag).strip("-") if figures else ""
        figures.append((f"rl_learning_curves{suffix}.png", tag, tagged))
    return figures
