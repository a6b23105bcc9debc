"""The attentional map M (docs/model.md §7): courses, kernels and the closed-form gain map.

- ``rise_decay_kernel``: the phase kernel ``h_T``, a difference of exponentials with peak 1.
- ``lateral_spread``: ``G(i, j) = exp(−(i − j)² / (2σ²))``.
- ``bottom_up_gain``: a bottom-up course's signed contribution at its centre.
- ``top_down_components``: a held top-down course's enhancement and vigilance adaptation.
- ``top_down_gain``: a top-down course's signed contribution at its centre.
- ``attentional_map``: ``M = max(0, 1 + G @ centre gains)``.
- ``CourseBook``: the active courses (state, plain arrays), started by the winner selection.
- ``course_gains``, ``release_courses``, ``bottom_up_running``, ``top_down_holding``,
  ``add_course``: the compiled kernels over a ``CourseBook``'s arrays (``CourseBook.arrays``),
  for compiled callers such as the model's step.

M is a closed-form function of the course start (and release) times and the current
time ``t`` (s): it does not depend on the step size, only on when courses started.

Small kernels that the model's step calls in its loops are compiled ``inline="always"``:
inlined into their caller, the views of per-track rows (or the arrays) they take need no
reference counting, two atomic operations per array and call otherwise.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

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
    "course_gains",
    "release_courses",
    "bottom_up_running",
    "top_down_holding",
    "add_course",
]

#: Phase boundaries are compared with this slack (s). Timestamps built as ``k · dt`` land
#: a few 1e-16 s either side of a boundary such as 0.3 s; 1 ns absorbs that while staying
#: far below any sensor period, so a step exactly on a boundary is classified the same
#: way for every ``dt``.
TIME_TOLERANCE_S = 1e-9
#: A released top-down course is dropped once all its contributions fall below this (gain
#: units, i.e. a millionth of M's baseline): invisible in L, and it bounds the book's size.
NEGLIGIBLE_GAIN = 1e-6
# the course parameters of the kernels (``course_parameters``), one vector per configuration
(
    _PRE,
    _EXC,
    _IOR,
    _COURSE,
    _A_EXC,
    _A_IOR,
    _RISE,
    _DECAY,
    _A_TD,
    _TD_ONSET,
    _TD_TAU_ON,
    _TD_TAU_OFF,
    _VIG_AFTER,
    _VIG_REL,
    _VIG_TAU,
    _VIG_RECOVERY,
    _N_COURSE_PARAMS,
) = range(17)
#: Columns of a top-down course's times (s): start, release (NaN while held), drop time.
_START, _RELEASE, _DROP = 0, 1, 2


@njit(cache=True)
def _kernel_peak(rise_fraction, decay_fraction):
    """Peak of ``exp(−x/decay) − exp(−x/rise)`` over x (lengths in units of T)."""
    x_peak = (
        math.log(decay_fraction / rise_fraction) * rise_fraction * decay_fraction / (decay_fraction - rise_fraction)
    )
    return math.exp(-x_peak / decay_fraction) - math.exp(-x_peak / rise_fraction)


@njit(cache=True)
def rise_decay_kernel(tau_s, length_s, rise_fraction, decay_fraction):
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


def course_parameters(config: AttentionConfig) -> np.ndarray:
    """The course parameters of ``config`` as the kernels read them: ``(16,)`` float64."""
    params = np.empty(_N_COURSE_PARAMS)
    params[_PRE], params[_EXC], params[_IOR] = config.preactivation_s, config.excitation_s, config.ior_s
    params[_COURSE], params[_A_EXC], params[_A_IOR] = config.course_s, config.A_exc, config.A_ior
    params[_RISE], params[_DECAY] = config.kernel_rise_fraction, config.kernel_decay_fraction
    params[_A_TD], params[_TD_ONSET] = config.A_td, config.td_onset_s
    params[_TD_TAU_ON], params[_TD_TAU_OFF] = config.td_tau_on_s, config.td_tau_off_s
    params[_VIG_AFTER], params[_VIG_REL] = config.vigilance_after_s, config.vigilance_amplitude_rel
    params[_VIG_TAU], params[_VIG_RECOVERY] = config.vigilance_tau_s, config.vigilance_recovery_s
    return params


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
    return _bottom_up_gain(float(tau_s), course_parameters(config))


def top_down_components(held_s: float, config: AttentionConfig) -> tuple[float, float]:
    """Enhancement and vigilance adaptation of a top-down course held ``held_s`` seconds (§7).

    ``E(τ) = A_td (1 − exp(−(τ − onset)/τ_on))`` after the onset and
    ``V(τ) = A_vig (1 − exp(−(τ − after)/τ_vig))`` after ``vigilance_after_s``, with
    ``A_vig = vigilance_amplitude_rel · A_td``; both 0 before their start.

    Returns:
        ``(E, V)`` (gain units, >= 0).
    """
    return _top_down_components(float(held_s), course_parameters(config))


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
    return _top_down_gain(float(held_s), float(since_release_s), course_parameters(config))


@njit(cache=True, inline="always")
def _bottom_up_gain(tau_s, params):
    """``bottom_up_gain`` with the configuration as ``course_parameters``."""
    pre, exc = params[_PRE], params[_EXC]
    if tau_s <= pre + TIME_TOLERANCE_S:
        return 0.0
    if tau_s <= pre + exc + TIME_TOLERANCE_S:
        return params[_A_EXC] * rise_decay_kernel(tau_s - pre, exc, params[_RISE], params[_DECAY])
    if tau_s <= params[_COURSE] + TIME_TOLERANCE_S:
        return -params[_A_IOR] * rise_decay_kernel(tau_s - pre - exc, params[_IOR], params[_RISE], params[_DECAY])
    return 0.0


@njit(cache=True, inline="always")
def _top_down_components(held_s, params):
    """``top_down_components`` with the configuration as ``course_parameters``."""
    enhancement = adaptation = 0.0
    if held_s > params[_TD_ONSET]:
        enhancement = -params[_A_TD] * math.expm1(-(held_s - params[_TD_ONSET]) / params[_TD_TAU_ON])
    if held_s > params[_VIG_AFTER]:
        adaptation = -params[_VIG_REL] * params[_A_TD] * math.expm1(-(held_s - params[_VIG_AFTER]) / params[_VIG_TAU])
    return enhancement, adaptation


@njit(cache=True, inline="always")
def _top_down_gain(held_s, since_release_s, params):
    """``top_down_gain`` with the configuration as ``course_parameters``."""
    enhancement, adaptation = _top_down_components(held_s, params)
    if since_release_s > 0.0:
        enhancement *= math.exp(-since_release_s / params[_TD_TAU_OFF])
        adaptation *= math.exp(-since_release_s / params[_VIG_RECOVERY])
    return enhancement - adaptation


@njit(cache=True)
def _decay_horizon(held_s, params):
    """Time after release (s) when a course held ``held_s`` has decayed below ``NEGLIGIBLE_GAIN``."""
    enhancement, adaptation = _top_down_components(held_s, params)
    horizon = 0.0
    if enhancement > NEGLIGIBLE_GAIN:
        horizon = params[_TD_TAU_OFF] * math.log(enhancement / NEGLIGIBLE_GAIN)
    if adaptation > NEGLIGIBLE_GAIN:
        horizon = max(horizon, params[_VIG_RECOVERY] * math.log(adaptation / NEGLIGIBLE_GAIN))
    return horizon


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

    The state is plain arrays (``arrays``), courses in the order they started; they grow
    when full (``reserve``).

    Args:
        config: the model's parameters.
        n_regions: J.
    """

    def __init__(self, config: AttentionConfig, n_regions: int) -> None:
        self.config = config
        self.n_regions = n_regions
        self.params = course_parameters(config)
        capacity = 2 * n_regions
        self._bu_regions = np.zeros(capacity, np.int64)
        self._bu_starts = np.zeros(capacity)  # (s)
        self._td_regions = np.zeros(capacity, np.int64)
        self._td_times = np.zeros((capacity, 3))  # start, release (NaN while held), drop time (s)
        self._counts = np.zeros(2, np.int64)  # bottom-up, top-down courses

    @property
    def arrays(self) -> tuple[np.ndarray, ...]:
        """``(params, bu_regions, bu_starts, td_regions, td_times, counts)`` for the kernels
        (the arrays themselves, updated in place): ``params`` ``(16,)`` (``course_parameters``);
        the bottom-up courses' regions and start times (s) and the top-down courses'
        regions and ``(start, release, drop)`` times (s), ``(capacity,)`` and ``(capacity, 3)``,
        the first ``counts[0]`` and ``counts[1]`` rows in use."""
        return self.params, self._bu_regions, self._bu_starts, self._td_regions, self._td_times, self._counts

    def reserve(self) -> None:
        """Make room for one more course of each kind (the kernels cannot grow the arrays)."""
        if self._counts[0] == self._bu_starts.shape[0] or self._counts[1] == self._td_times.shape[0]:
            grown = 2 * max(self._bu_starts.shape[0], self._td_times.shape[0])
            self._bu_regions = np.resize(self._bu_regions, grown)
            self._bu_starts = np.resize(self._bu_starts, grown)
            self._td_regions = np.resize(self._td_regions, grown)
            self._td_times = np.resize(self._td_times, (grown, 3))

    def reset(self) -> None:
        """Drop every course."""
        self._counts[:] = 0

    @property
    def empty(self) -> bool:
        """True when no course is active."""
        return not (self._counts[0] or self._counts[1])

    def bottom_up_active(self, region: int, t_s: float) -> bool:
        """Whether a bottom-up course at ``region`` is still running at ``t_s``."""
        return bottom_up_running(region, float(t_s), *self.arrays)

    def top_down_held(self, region: int) -> bool:
        """Whether a top-down course at ``region`` is currently held."""
        return top_down_holding(region, *self.arrays)

    def start_bottom_up(self, region: int, t_s: float) -> None:
        """Start a bottom-up (exogenous) course at ``region`` at time ``t_s``."""
        self.reserve()
        add_course(False, region, float(t_s), *self.arrays)

    def start_top_down(self, region: int, t_s: float) -> None:
        """Start (and hold) a top-down (endogenous) course at ``region`` at time ``t_s``."""
        self.reserve()
        add_course(True, region, float(t_s), *self.arrays)

    def update_holds(self, t_s: float, fulfilled: np.ndarray) -> None:
        """Release every held top-down course whose region's goal is no longer fulfilled.

        Args:
            t_s: current time (s): the release time of the courses released now.
            fulfilled: ``(J,)`` bool, the top-down goal holds at each region.
        """
        release_courses(float(t_s), np.asarray(fulfilled, np.bool_), *self.arrays)

    def centre_gains(self, t_s: float) -> list[float] | None:
        """Summed course gains per region at ``t_s`` (J floats), or None when no course is active.

        Finished courses are dropped first (time only moves forward).
        """
        gains = np.zeros(self.n_regions)
        return gains.tolist() if course_gains(float(t_s), *self.arrays, gains) else None


@njit(cache=True)
def bottom_up_running(region, t_s, params, bu_regions, bu_starts, td_regions, td_times, counts):
    """Whether a bottom-up course at ``region`` is still running at ``t_s`` (s)."""
    limit = params[_COURSE] + TIME_TOLERANCE_S
    for k in range(counts[0]):
        if bu_regions[k] == region and t_s - bu_starts[k] <= limit:
            return True
    return False


@njit(cache=True)
def top_down_holding(region, params, bu_regions, bu_starts, td_regions, td_times, counts):
    """Whether a top-down course at ``region`` is currently held."""
    for k in range(counts[1]):
        if td_regions[k] == region and math.isnan(td_times[k, _RELEASE]):
            return True
    return False


@njit(cache=True)
def add_course(top_down, region, t_s, params, bu_regions, bu_starts, td_regions, td_times, counts):
    """Append a course at ``region`` started at ``t_s`` (s), top-down (held) or bottom-up;
    the arrays must have room (``CourseBook.reserve``)."""
    if top_down:
        k = counts[1]
        td_regions[k] = region
        td_times[k, _START], td_times[k, _RELEASE], td_times[k, _DROP] = t_s, np.nan, np.inf
        counts[1] = k + 1
    else:
        k = counts[0]
        bu_regions[k], bu_starts[k] = region, t_s
        counts[0] = k + 1


@njit(cache=True)
def release_courses(t_s, fulfilled, params, bu_regions, bu_starts, td_regions, td_times, counts):
    """``CourseBook.update_holds``: release, at ``t_s`` (s), each held top-down course whose
    region's goal is not fulfilled (``fulfilled`` ``(J,)`` bool), and set its drop time."""
    for k in range(counts[1]):
        if math.isnan(td_times[k, _RELEASE]) and not fulfilled[td_regions[k]]:
            td_times[k, _RELEASE] = t_s
            td_times[k, _DROP] = t_s + _decay_horizon(t_s - td_times[k, _START], params)


@njit(cache=True)
def course_gains(t_s, params, bu_regions, bu_starts, td_regions, td_times, counts, gains):
    """``CourseBook.centre_gains`` into ``gains`` ``(J,)`` (zeros on entry): drop the finished
    courses (keeping the others' order), then add each course's gain at its region, the
    bottom-up courses first, in the order they started; False when no course is active."""
    limit = params[_COURSE] + TIME_TOLERANCE_S
    kept = 0
    for k in range(counts[0]):
        if t_s - bu_starts[k] <= limit:
            bu_regions[kept], bu_starts[kept] = bu_regions[k], bu_starts[k]
            kept += 1
    counts[0] = kept
    kept = 0
    for k in range(counts[1]):
        if t_s <= td_times[k, _DROP]:
            td_regions[kept] = td_regions[k]
            td_times[kept, _START], td_times[kept, _RELEASE] = td_times[k, _START], td_times[k, _RELEASE]
            td_times[kept, _DROP] = td_times[k, _DROP]
            kept += 1
    counts[1] = kept
    for k in range(counts[0]):
        gains[bu_regions[k]] += _bottom_up_gain(t_s - bu_starts[k], params)
    for k in range(counts[1]):
        start, release = td_times[k, _START], td_times[k, _RELEASE]
        if math.isnan(release):
            gains[td_regions[k]] += _top_down_gain(t_s - start, 0.0, params)
        else:
            gains[td_regions[k]] += _top_down_gain(release - start, t_s - release, params)
    return counts[0] > 0 or counts[1] > 0
