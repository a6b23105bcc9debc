"""Perception metrics of recorded episodes (``records.EpisodeRecord``): does the model see
motion, and does it attend to the goal's target?

- ``speed_metrics``: the error (m/s) of the speed estimate of the region a mover lies in,
  and of its matched track, against the mover's true speed, over (mover, step) pairs
  where the mover has been in view for ``SETTLE_S`` (steady, and within ``TRANSIENT_S``
  after a turn apart); the speed the regions that see static structure only report; and
  how often "the goal holds" judged from the estimate agrees with the truth.
- ``focus_on_target``: per goal, the fraction of the steps with the target in view (or,
  told so, in sight of the laser) at which the focus is the target's region (chance: 1/8),
  with a 95 % bootstrap interval over the episodes (``attentive_gym.statistics.ratio_ci``).
- ``target_cases``: the same steps split by why the focus is or is not on the target
  (``records.TARGET_CASES``).
- ``focus_by_track_age``, ``focus_after_turns``: the focus on target by the age of the
  target's track, and right after the target turned.
- Their parts: ``pair_masks``, ``turns``, ``time_since``, ``region_estimates``, ``error_stats``.

Arrays: T steps, M movers, J = 8 regions; speeds in m/s, times in seconds.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from attentive_gym.attention.goals import Feature
from attentive_gym.perception.geometry import in_sight, in_view, region_of
from attentive_gym.perception.records import SETTLE_S, TARGET_CASES, EpisodeRecord
from attentive_gym.statistics import ratio_ci

__all__ = [
    "speed_metrics",
    "focus_on_target",
    "FocusRate",
    "target_cases",
    "focus_by_track_age",
    "focus_after_turns",
    "case_key",
    "pair_masks",
    "turns",
    "time_since",
    "region_estimates",
    "error_stats",
    "Pairs",
    "TURN_ANGLE_RAD",
    "TRANSIENT_S",
    "MOVING_MPS",
    "TRACK_AGE_BINS_S",
]

#: A change of a mover's velocity direction above this (rad) is a turn.
TURN_ANGLE_RAD = math.radians(30.0)
#: Pairs within this (s) after a turn are reported apart (transient).
TRANSIENT_S = 1.0
#: Below this speed (m/s) a mover is still, its direction undefined (movers go in 0.05 m/s steps).
MOVING_MPS = 0.02
#: Bins (s) of the age of the target's track in ``focus_by_track_age``: how long a track
#: must have lasted before its goal can be judged.
TRACK_AGE_BINS_S = (0.0, 1.0, 2.0, 4.0, math.inf)


def time_since(t_s: np.ndarray, event: np.ndarray) -> np.ndarray:
    """``(T, M)`` seconds since the latest ``event`` (T, M) at or before each step, inf
    before the first."""
    last = np.full(event.shape[1], -np.inf)
    since = np.empty(event.shape)
    for k, t in enumerate(t_s):
        last = np.where(event[k], t, last)
        since[k] = t - last
    return since


def turns(velocity: np.ndarray) -> np.ndarray:
    """``(T, M)`` bool: the mover's velocity ``(T, M, 2)`` (m/s) changed direction by more
    than ``TURN_ANGLE_RAD`` since the previous step, or it started or stopped (a direction
    appeared or vanished); False at the first step."""
    before, after = velocity[:-1], velocity[1:]
    speed_before, speed_after = np.linalg.norm(before, axis=-1), np.linalg.norm(after, axis=-1)
    moving_before, moving_after = speed_before > MOVING_MPS, speed_after > MOVING_MPS
    both = moving_before & moving_after
    cosine = np.sum(before * after, axis=-1) / np.where(both, speed_before * speed_after, 1.0)
    turned = (both & (cosine < math.cos(TURN_ANGLE_RAD))) | (moving_before != moving_after)
    return np.vstack([np.zeros((1, velocity.shape[1]), bool), turned])


def pair_masks(record: EpisodeRecord) -> tuple[np.ndarray, np.ndarray]:
    """``(T, M)`` bool masks of the steady and the transient (mover, step) pairs.

    Both hold movers in view (``in_view``) continuously for at least ``SETTLE_S``; the
    transient ones are within ``TRANSIENT_S`` after a turn (``turns``), the steady ones not.
    """
    visible = in_view(record.mover_xy)
    entered = visible & ~np.vstack([np.zeros((1, visible.shape[1]), bool), visible[:-1]])
    settled = visible & (time_since(record.t_s, entered) >= SETTLE_S - 1e-9)
    transient = settled & (time_since(record.t_s, turns(record.mover_velocity)) <= TRANSIENT_S + 1e-9)
    return settled & ~transient, transient


def region_estimates(record: EpisodeRecord) -> np.ndarray:
    """``(T, M)`` each mover's speed estimate (m/s): the speed of the region it lies in."""
    regions = region_of(record.mover_xy)
    return np.take_along_axis(record.region_speed, regions, axis=1)


def error_stats(estimate: np.ndarray, truth: np.ndarray) -> dict[str, float]:
    """Median, 90th percentile and root mean square of ``|estimate − truth|`` (m/s), and
    the number of pairs; NaN statistics for no pairs."""
    error = np.abs(np.asarray(estimate, float) - np.asarray(truth, float))
    if error.size == 0:
        return {"pairs": 0, "median_mps": math.nan, "p90_mps": math.nan, "rmse_mps": math.nan}
    return {
        "pairs": int(error.size),
        "median_mps": float(np.median(error)),
        "p90_mps": float(np.percentile(error, 90)),
        "rmse_mps": float(np.sqrt(np.mean(error**2))),
    }


@dataclass
class Pairs:
    """(mover, step) pairs pooled over episodes, one entry per pair (speeds in m/s)."""

    true: list[np.ndarray] = field(default_factory=list)
    region: list[np.ndarray] = field(default_factory=list)
    track: list[np.ndarray] = field(default_factory=list)
    goal_true: list[np.ndarray] = field(default_factory=list)
    goal_region: list[np.ndarray] = field(default_factory=list)
    goal_track: list[np.ndarray] = field(default_factory=list)

    def add(self, record: EpisodeRecord, mask: np.ndarray) -> None:
        """Add the pairs of ``record`` selected by ``mask`` (T, M); goal judgements only for
        a speed goal."""
        true = np.linalg.norm(record.mover_velocity, axis=-1)[mask]
        region = region_estimates(record)[mask]
        track = np.full(true.shape, np.nan) if record.track_speed is None else record.track_speed[mask]
        self.true.append(true)
        self.region.append(region)
        self.track.append(track)
        if record.goal.feature is Feature.SPEED:
            matched = ~np.isnan(track)
            self.goal_true.append(record.goal.is_fulfilled(true))
            self.goal_region.append(record.goal.is_fulfilled(region))
            self.goal_track.append(np.where(matched, record.goal.is_fulfilled(np.nan_to_num(track)), np.nan))

    def array(self, name: str) -> np.ndarray:
        """The pooled entries of ``name`` (float)."""
        parts = getattr(self, name)
        return np.concatenate(parts).astype(float) if parts else np.zeros(0)


def _prefixed(prefix: str, stats: Mapping[str, float]) -> dict[str, float]:
    """``stats`` with each key prefixed by ``prefix_``."""
    return {f"{prefix}_{name}": value for name, value in stats.items()}


def _agreement(judged: np.ndarray, truth: np.ndarray) -> float:
    """Fraction of the pairs where ``judged`` (1/0, NaN = no judgement) equals ``truth``."""
    keep = ~np.isnan(judged)
    return float(np.mean(judged[keep] == truth[keep])) if keep.any() else math.nan


def speed_metrics(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """Speed-error, static-structure and goal-classification figures of a configuration.

    Keys: ``region_*`` / ``transient_region_*`` (``error_stats`` of the region estimate on
    steady / transient pairs), ``track_*`` / ``transient_track_*`` and
    ``track_unmatched_frac`` (steady pairs without a matched track) when tracks exist,
    ``static_regions``, ``static_median_mps``, ``static_p90_mps`` (speed of the regions
    that see static structure only), ``goal_agreement_region`` / ``goal_agreement_track``
    (fraction of steady pairs, speed goals only; NaN otherwise); with tracks,
    ``false_label_steps``, ``false_label_near_steps`` and ``false_in_band_steps``: the share of
    the steps with phantom motion (``records.false_moving_tracks``) anywhere, within
    ``VIEW_RANGE_M`` of the robot, and at a speed inside the goal's range, each with its 95 %
    interval over the episodes (``<name>_low``, ``<name>_high``; ``attentive_gym.statistics.ratio_ci``).
    """
    records = list(records)
    steady, transient = Pairs(), Pairs()
    for record in records:
        steady_mask, transient_mask = pair_masks(record)
        steady.add(record, steady_mask)
        transient.add(record, transient_mask)
    metrics: dict[str, float] = {}
    for prefix, pairs in (("region", steady), ("transient_region", transient)):
        metrics |= _prefixed(prefix, error_stats(pairs.array("region"), pairs.array("true")))
    if any(record.track_speed is not None for record in records):
        for prefix, pairs in (("track", steady), ("transient_track", transient)):
            track, true = pairs.array("track"), pairs.array("true")
            matched = ~np.isnan(track)
            metrics |= _prefixed(prefix, error_stats(track[matched], true[matched]))
        unmatched = np.isnan(steady.array("track"))
        metrics["track_unmatched_frac"] = float(unmatched.mean()) if unmatched.size else math.nan
    static = np.concatenate([r.region_speed[r.static_region] for r in records])
    metrics["static_regions"] = int(static.size)
    metrics["static_median_mps"] = float(np.median(static)) if static.size else math.nan
    metrics["static_p90_mps"] = float(np.percentile(static, 90)) if static.size else math.nan
    tracked = any(record.track_speed is not None for record in records)
    if tracked and all(record.false_label is not None for record in records):
        steps = [len(record.false_label) for record in records]
        for column, name in enumerate(("false_label_steps", "false_label_near_steps", "false_in_band_steps")):
            share, low, high = ratio_ci([int(record.false_label[:, column].sum()) for record in records], steps)
            metrics |= {name: share, f"{name}_low": low, f"{name}_high": high}
    goal_true = steady.array("goal_true")
    metrics["goal_agreement_region"] = _agreement(steady.array("goal_region"), goal_true)
    metrics["goal_agreement_track"] = _agreement(steady.array("goal_track"), goal_true)
    return metrics


@dataclass(frozen=True)
class FocusRate:
    """Focus on target under one goal: the pooled rate ``rate`` (on-target steps over
    ``steps``, the steps counted; NaN for none), its 95 % interval ``low``–``high`` over
    the ``episodes`` episodes that had such steps (the episodes resampled; NaN with fewer
    than 2)."""

    rate: float
    low: float
    high: float
    steps: int
    episodes: int


def focus_on_target(records: Iterable[EpisodeRecord], in_sight_only: bool = False) -> dict[str, FocusRate]:
    """Per goal (``str(goal)``): the fraction of the steps with the target in view
    (``in_view``; with ``in_sight_only``, in sight of the laser: ``in_sight``) at which the
    focus is the target's region, pooled over the records, with its interval over them.

    Raises:
        ValueError: ``in_sight_only`` for a record without ``target_beams``.
    """
    counts: dict[str, tuple[list[int], list[int]]] = {}
    for record in records:
        target_xy = record.mover_xy[:, record.target]
        if in_sight_only and record.target_beams is None:
            raise ValueError("focus on target in sight needs records with target_beams (record_episode's)")
        visible = in_sight(target_xy, record.target_beams) if in_sight_only else in_view(target_xy)
        on_target = record.focus[visible] == region_of(target_xy[visible])
        hits, totals = counts.setdefault(str(record.goal), ([], []))
        hits.append(int(on_target.sum()))
        totals.append(int(visible.sum()))
    rates = {}
    for goal, (hits, totals) in counts.items():
        rate, low, high = ratio_ci(hits, totals)
        rates[goal] = FocusRate(rate, low, high, sum(totals), sum(1 for n in totals if n))
    return rates


def target_cases(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """The fraction of the steps with the target in view (``in_view``) that falls in each of
    ``TARGET_CASES`` (keys ``case_...``), over the records that have cases."""
    counts = np.zeros(len(TARGET_CASES))
    for record in records:
        if record.target_case is not None:
            visible = in_view(record.mover_xy[:, record.target])
            counts += np.bincount(record.target_case[visible], minlength=len(TARGET_CASES))
    total = counts.sum()
    return {case_key(case): (n / total if total else math.nan) for case, n in zip(TARGET_CASES, counts)}


def _age_bin_key(low: float, high: float) -> str:
    """The metric key of the track-age bin [``low``, ``high``) s."""
    if math.isfinite(high):
        return f"focus_on_target_track_{low:g}_to_{high:g}_s"
    return f"focus_on_target_track_over_{low:g}_s"


def focus_by_track_age(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """Focus on target (as ``focus_on_target``, both goals) over the in-view steps at which
    the target has no track (``focus_on_target_no_track``) or a track whose age falls in
    each bin of ``TRACK_AGE_BINS_S``, with each group's share of the steps (``steps_...``);
    NaN rates for empty groups, {} without recorded ages."""
    bins = zip(TRACK_AGE_BINS_S, TRACK_AGE_BINS_S[1:])
    keys = ["focus_on_target_no_track"] + [_age_bin_key(lo, hi) for lo, hi in bins]
    hits = np.zeros((len(keys), 2))  # [group] × [on target, steps]
    for record in records:
        if record.target_track_age is None:
            continue
        target_xy = record.mover_xy[:, record.target]
        visible = in_view(target_xy)
        age = record.target_track_age
        group = np.where(np.isnan(age), 0, np.searchsorted(TRACK_AGE_BINS_S, np.nan_to_num(age), side="right"))
        on_target = record.focus == region_of(target_xy)
        for index in range(len(keys)):
            mask = visible & (group == index)
            hits[index] += on_target[mask].sum(), mask.sum()
    total = hits[:, 1].sum()
    if not total:
        return {}
    rates = {key: (on / n if n else math.nan) for key, (on, n) in zip(keys, hits)}
    shares = {"steps_" + key[len("focus_on_target_") :]: n / total for key, (_, n) in zip(keys, hits)}
    return {**rates, **shares}


def focus_after_turns(records: Iterable[EpisodeRecord]) -> dict[str, float]:
    """Focus on target (as ``focus_on_target``, both goals) over the in-view steps within
    ``TRANSIENT_S`` after the target turned (``turns``), and over the others."""
    hits = np.zeros((2, 2))  # [after a turn, otherwise] × [on target, steps]
    for record in records:
        target_xy = record.mover_xy[:, record.target]
        visible = in_view(target_xy)
        after = time_since(record.t_s, turns(record.mover_velocity))[:, record.target] <= TRANSIENT_S
        on_target = record.focus == region_of(target_xy)
        for row, mask in enumerate((visible & after, visible & ~after)):
            hits[row] += on_target[mask].sum(), mask.sum()
    rates = [on / n if n else math.nan for on, n in hits]
    return {"focus_on_target_after_turn": rates[0], "focus_on_target_otherwise": rates[1]}


def case_key(case: str) -> str:
    """The metric key of an entry of ``TARGET_CASES``: ``"seen, no track"`` → ``"case_seen_no_track"``."""
    return "case_" + case.replace(",", "").replace(" ", "_")
