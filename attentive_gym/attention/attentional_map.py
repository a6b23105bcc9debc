"""The attentional map M (docs/model.md §7): courses, kernels and the closed-form gain map.

- ``rise_decay_kernel``: the phase kernel ``h_T``, a difference of exponentials with peak 1.
- ``lateral_spread``: ``G(i, j) = exp(−(i − j)² / (2σ²))``.
- ``bottom_up_gain``: a bottom-up course's signed contribution at its centre.
- ``top_down_components``: a held top-down course's enhancement and vigilance adaptation.
- ``top_down_gain``: a top-down course's signed contribution at its centre.
- ``attentional_map``: ``M = max(0, 1 + G @ centre gains)``.
- ``CourseBook``: the active courses (state), started by the winner selection.

M is a closed-form function of the course start (and release) times and the current
time ``t`` (s): it does not depend on the step size, only on when courses started.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from attentive_gym.attention.config import AttentionConfig

__all__ = [
    "TIME_TOLERANCE_S",
    "NEGLIGIBLE_GAIN",
    "rise_decay_kernel",
    "lateral_spread",
    "bottom_up_gain",
    "top_down_components",
    "top_down_gain",
    "attentional_map",
    "CourseBook",
]

#: Phase boundaries are compared with this slack (s). Timestamps built as ``k · dt`` land
#: a few 1e-16 s either side of a boundary such as 0.3 s; 1 ns absorbs that while staying
#: far below any sensor period, so a step exactly on a boundary is classified the same
#: way for every ``dt``.
TIME_TOLERANCE_S = 1e-9
#: A released top-down course is dropped once all its contributions fall below this (gain
#: units, i.e. a millionth of M's baseline): invisible in L, and it bounds the book's size.
NEGLIGIBLE_GAIN = 1e-6


@functools.lru_cache(maxsize=None)
def _kernel_peak(rise_fraction: float, decay_fraction: float) -> float:
    """Peak of ``exp(−x/decay) − exp(−x/rise)`` over x (lengths in units of T)."""
    x_peak = math.log(decay_fraction / rise_fraction) * rise_fraction * decay_fraction / (decay_fraction - rise_fraction)
    return math.exp(-x_peak / decay_fraction) - math.exp(-x_peak / rise_fraction)


def rise_decay_kernel(tau_s: float, length_s: float, rise_fraction: float, decay_fraction: float) -> float:
    """The phase kernel ``h_T(τ)``: a rise-and-decay curve with peak 1 (§7).

    ``h_T(τ) = (exp(−τ/τ_d) − exp(−τ/τ_r)) / peak`` for ``τ > 0`` (0 otherwise), with
    ``τ_r = rise_fraction · T`` and ``τ_d = decay_fraction · T`` (default T/20 and T/2:
    a neuronal-integration curve peaking at ≈ 0.128 T and down to ≈ 0.19 at τ = T).

    Args:
        tau_s: time since the phase started (s).
        length_s: the phase length T (s).
        rise_fraction, decay_fraction: time constants as fractions of T (rise < decay).

    Returns:
        ``h`` in [0, 1].
    """
    if tau_s <= 0.0:
        return 0.0
    x = tau_s / length_s
    return (math.exp(-x / decay_fraction) - math.exp(-x / rise_fraction)) / _kernel_peak(rise_fraction, decay_fraction)


def lateral_spread(n_regions: int, sigma_regions: float) -> np.ndarray:
    """``G(i, j) = exp(−(i − j)² / (2σ²))``, shape ``(J, J)``; σ = 0.5 gives neighbours e⁻²."""
    idx = np.arange(n_regions, dtype=float)
    return np.exp(-((idx[:, None] - idx[None, :]) ** 2) / (2.0 * sigma_regions**2))


def bottom_up_gain(tau_s: float, config: AttentionConfig) -> float:
    """Centre contribution of a bottom-up course ``τ`` seconds after it started (§7).

    ============================  ===============================================
    phase                          contribution
    ============================  ===============================================
    pre-activation  0 < τ ≤ P      0
    excitation      P < τ ≤ P+E    ``+A_exc · h_E(τ − P)``
    IOR             P+E < τ ≤ end  ``−A_ior · h_I(τ − P − E)``
    over            τ > end        0
    ============================  ===============================================

    with P, E, I = ``preactivation_s``, ``excitation_s``, ``ior_s``; boundaries are
    compared with ``TIME_TOLERANCE_S`` of slack.

    Args:
        tau_s: time since the course started (s).
        config: the model's parameters.

    Returns:
        The signed gain (gain units).
    """
    pre, exc = config.preactivation_s, config.excitation_s
    if tau_s <= pre + TIME_TOLERANCE_S:
        return 0.0
    if tau_s <= pre + exc + TIME_TOLERANCE_S:
        return config.A_exc * rise_decay_kernel(tau_s - pre, exc, config.kernel_rise_fraction,
                                                config.kernel_decay_fraction)
    if tau_s <= config.course_s + TIME_TOLERANCE_S:
        return -config.A_ior * rise_decay_kernel(tau_s - pre - exc, config.ior_s, config.kernel_rise_fraction,
                                                 config.kernel_decay_fraction)
    return 0.0


def top_down_components(held_s: float, config: AttentionConfig) -> tuple[float, float]:
    """Enhancement and vigilance adaptation of a top-down course held ``held_s`` seconds (§7).

    ``E(τ) = A_td (1 − exp(−(τ − onset)/τ_on))`` after the onset and
    ``V(τ) = A_vig (1 − exp(−(τ − after)/τ_vig))`` after ``vigilance_after_s``, with
    ``A_vig = vigilance_amplitude_rel · A_td``; both 0 before their start.

    Returns:
        ``(E, V)`` (gain units, >= 0).
    """
    enhancement = adaptation = 0.0
    if held_s > config.td_onset_s:
        enhancement = -config.A_td * math.expm1(-(held_s - config.td_onset_s) / config.td_tau_on_s)
    if held_s > config.vigilance_after_s:
        adaptation = (-config.vigilance_amplitude_rel * config.A_td
                      * math.expm1(-(held_s - config.vigilance_after_s) / config.vigilance_tau_s))
    return enhancement, adaptation


def top_down_gain(held_s: float, since_release_s: float, config: AttentionConfig) -> float:
    """Centre contribution of a top-down course (§7): ``E − V`` while held, decaying after release.

    While held for ``τ`` seconds the gain is ``E(τ) − V(τ)`` (``top_down_components``);
    ``r`` seconds after a release it is ``E·exp(−r/τ_off) − V·exp(−r/τ_recovery)`` with E
    and V frozen at their values at the release. No IOR.

    Args:
        held_s: how long the course was (or has been) held (s).
        since_release_s: time since release (s); 0 while held.
        config: the model's parameters.

    Returns:
        The signed gain (gain units); >= 0 until vigilance sets in.
    """
    enhancement, adaptation = top_down_components(held_s, config)
    if since_release_s > 0.0:
        enhancement *= math.exp(-since_release_s / config.td_tau_off_s)
        adaptation *= math.exp(-since_release_s / config.vigilance_recovery_s)
    return enhancement - adaptation


def attentional_map(centre_gains, spread: np.ndarray) -> np.ndarray:
    """``M = max(0, 1 + G @ g)``: baseline 1 plus laterally spread course gains, floored at 0.

    Args:
        centre_gains: ``(..., J)`` summed course gains at each course's region (array or list).
        spread: ``(J, J)`` lateral spread ``G`` (symmetric).

    Returns:
        ``(..., J)`` gains >= 0.
    """
    return np.maximum(1.0 + np.dot(centre_gains, spread), 0.0)


class CourseBook:
    """The active attentional courses; ``centre_gains(t)`` evaluates them in closed form.

    A bottom-up course at region ``j`` lives for ``config.course_s`` seconds; a new one
    at ``j`` starts only when none is active there. A top-down course is held until the
    goal stops being fulfilled at ``j`` (``update_holds``), then decays; it is dropped once
    its contributions are below ``NEGLIGIBLE_GAIN``.

    Args:
        config: the model's parameters.
        n_regions: J.
    """

    def __init__(self, config: AttentionConfig, n_regions: int) -> None:
        self.config = config
        self.n_regions = n_regions
        self._bu_regions: list[int] = []
        self._bu_starts: list[float] = []
        # top-down courses: [region, start (s), release (s) or None, drop time (s) or inf]
        self._td: list[list] = []

    def reset(self) -> None:
        """Drop every course."""
        self._bu_regions.clear()
        self._bu_starts.clear()
        self._td.clear()

    @property
    def empty(self) -> bool:
        """True when no course is active."""
        return not (self._bu_regions or self._td)

    def bottom_up_active(self, region: int, t_s: float) -> bool:
        """Whether a bottom-up course at ``region`` is still running at ``t_s``."""
        limit = self.config.course_s + TIME_TOLERANCE_S
        return any(j == region and t_s - s <= limit for j, s in zip(self._bu_regions, self._bu_starts))

    def top_down_held(self, region: int) -> bool:
        """Whether a top-down course at ``region`` is currently held."""
        return any(c[0] == region and c[2] is None for c in self._td)

    def start_bottom_up(self, region: int, t_s: float) -> None:
        """Start a bottom-up (exogenous) course at ``region`` at time ``t_s``."""
        self._bu_regions.append(region)
        self._bu_starts.append(t_s)

    def start_top_down(self, region: int, t_s: float) -> None:
        """Start (and hold) a top-down (endogenous) course at ``region`` at time ``t_s``."""
        self._td.append([region, t_s, None, math.inf])

    def update_holds(self, t_s: float, fulfilled: np.ndarray) -> None:
        """Release every held top-down course whose region's goal is no longer fulfilled.

        Args:
            t_s: current time (s): the release time of the courses released now.
            fulfilled: ``(J,)`` bool, the top-down goal holds at each region.
        """
        for course in self._td:
            if course[2] is None and not fulfilled[course[0]]:
                course[2] = t_s
                course[3] = t_s + self._decay_horizon(t_s - course[1])

    def _decay_horizon(self, held_s: float) -> float:
        """Time after release when a course held ``held_s`` has decayed below ``NEGLIGIBLE_GAIN``."""
        enhancement, adaptation = top_down_components(held_s, self.config)
        horizon = 0.0
        if enhancement > NEGLIGIBLE_GAIN:
            horizon = self.config.td_tau_off_s * math.log(enhancement / NEGLIGIBLE_GAIN)
        if adaptation > NEGLIGIBLE_GAIN:
            horizon = max(horizon, self.config.vigilance_recovery_s * math.log(adaptation / NEGLIGIBLE_GAIN))
        return horizon

    def centre_gains(self, t_s: float) -> list[float] | None:
        """Summed course gains per region at ``t_s`` (J floats), or None when no course is active.

        Finished courses are dropped first (time only moves forward).
        """
        cfg = self.config
        if self._bu_regions:
            limit = cfg.course_s + TIME_TOLERANCE_S
            keep = [k for k, s in enumerate(self._bu_starts) if t_s - s <= limit]
            if len(keep) != len(self._bu_starts):
                self._bu_regions[:] = [self._bu_regions[k] for k in keep]
                self._bu_starts[:] = [self._bu_starts[k] for k in keep]
        if self._td:
            self._td[:] = [c for c in self._td if t_s <= c[3]]
        if not (self._bu_regions or self._td):
            return None
        gains = [0.0] * self.n_regions
        for region, start in zip(self._bu_regions, self._bu_starts):
            gains[region] += bottom_up_gain(t_s - start, cfg)
        for region, start, release, _ in self._td:
            if release is None:
                gains[region] += top_down_gain(t_s - start, 0.0, cfg)
            else:
                gains[region] += top_down_gain(release - start, t_s - release, cfg)
        return gains
