"""Scripted policies of the attended environments: the baselines of the perception benchmark.

A policy maps an observation and the step's ``info`` to an action (linear, angular), each
a fraction in [−1, 1] of the robot's top speeds (0.7 m/s and 140°/s).

- ``steer``: turn towards a bearing and drive forward; spin in place without one.
- ``FocusController``: steer towards the model's latest top-down focus (``info["attention"]``).
- ``memory_controller``: steer towards the first row of a ``focus`` observation's working
  memory when that body matched the goal: it reads nothing but the observation a policy gets.
- ``true_bearing_controller``: steer towards the target's true bearing (a privileged oracle).
- ``clearance_controller``: steer towards the first working-memory row's bearing through the
  free heading nearest to it, from the ``proximity`` entry alone (a reactive avoider);
  ``privileged_clearance_controller``: the same towards the target's true bearing (a
  privileged teacher, for any variant); ``clearance_action``: what both do.
- ``RandomController``: seeded random actions.
- ``Wander``: a seeded scripted exploration; ``stand_still``: the zero action.
- ``control_success``: how often a policy reaches the target, over seeded episodes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from attentive_gym.attention import ORIGIN_TOP_DOWN
from attentive_gym.attention.regions import Grid
from attentive_gym.attention.working_memory import MEMORY_FIELDS
from attentive_gym.perception.geometry import bearing_of, true_target_bearing, true_target_xy, wrap_angle

__all__ = [
    "Policy",
    "steer",
    "focus_bearing",
    "FocusController",
    "memory_controller",
    "true_bearing_controller",
    "clearance_controller",
    "privileged_clearance_controller",
    "clearance_action",
    "free_heading",
    "RandomController",
    "Wander",
    "stand_still",
    "control_success",
    "WANDER_LINEAR",
    "WANDER_ANGULAR",
    "WANDER_PERIOD_S",
    "WANDER_FRONT_BEAMS",
    "WANDER_CLEARANCE_M",
    "STEER_LINEAR",
    "STEER_GAIN_PER_RAD",
    "SEARCH_SPIN",
]

#: ``policy(observation, info) -> action`` (linear, angular; float32 fractions in [−1, 1]).
Policy = Callable[[Mapping[str, np.ndarray], Mapping[str, Any]], np.ndarray]

#: ``Wander``'s forward command.
WANDER_LINEAR = 0.6
#: Amplitude of ``Wander``'s sinusoidal turn (angular command).
WANDER_ANGULAR = 0.3
#: Period (s) of ``Wander``'s sinusoidal turn.
WANDER_PERIOD_S = 8.0
#: The laser beams ``Wander`` keeps clear: bearings −30° .. +30°.
WANDER_FRONT_BEAMS = slice(60, 120)
#: ``Wander`` turns in place while those beams see closer than this (m).
WANDER_CLEARANCE_M = 0.8
#: ``steer``'s forward command when facing the bearing.
STEER_LINEAR = 1.0
#: ``steer``'s angular command per radian of bearing error.
STEER_GAIN_PER_RAD = 2.0
#: ``steer``'s angular command while there is no bearing to steer to.
SEARCH_SPIN = 0.5
#: ``free_heading``: a reading closer than this to a heading's line blocks it (m; the
#: robot's half width, 0.25 m, and a margin).
CLEARANCE_HALF_WIDTH_M = 0.35
#: ``free_heading``: how far ahead (m) a heading must be free, or up to the target if nearer.
CLEARANCE_AHEAD_M = 0.9
#: ``clearance_controller`` stops when the front regions read this close (m) and drives at
#: full speed from this plus 1 m.
CLEARANCE_STOP_M = 0.25
#: ``clearance_controller``'s front: the regions within this bearing (rad) of straight ahead.
CLEARANCE_FRONT_RAD = math.radians(35.0)
#: Columns of a working-memory row that ``memory_controller`` reads.
_COS, _SIN, _MATCH = (MEMORY_FIELDS.index(f) for f in ("cos_bearing", "sin_bearing", "goal_match"))
_DISTANCE = MEMORY_FIELDS.index("distance_m")
_GRID = Grid.make("sonar")
#: (180,) bearing (rad) of each laser beam's centre, −89.5° .. +89.5°.
_BEAM_RAD = np.radians(np.arange(len(_GRID.beam_region)) - 0.5 * (len(_GRID.beam_region) - 1))


def steer(bearing_rad: float | None) -> np.ndarray:
    """The action (linear, angular; fractions in [−1, 1]) that turns towards ``bearing_rad``
    (robot frame) and drives forward in proportion to max(0, cos(bearing)); spinning in
    place when there is no bearing."""
    if bearing_rad is None:
        return np.array([0.0, SEARCH_SPIN], np.float32)
    linear = STEER_LINEAR * max(0.0, math.cos(bearing_rad))
    angular = float(np.clip(STEER_GAIN_PER_RAD * bearing_rad, -1.0, 1.0))
    return np.array([linear, angular], np.float32)


def focus_bearing(output) -> float:
    """Bearing (rad) of an ``AttentionOutput``'s focus: the focused track's bearing when the
    view carries one, else the centre bearing of the focused region."""
    view = output.view
    track_xy = getattr(view, "track_position_m", None)
    if track_xy is not None:
        return float(bearing_of(np.asarray(track_xy, float)))
    return view.bearing_rad


class FocusController:
    """Steers towards the latest top-down focus (``steer``).

    The focus's bearing is kept in the robot frame as the robot turns: each step it drops
    by the odometry's angular velocity × ``dt_s`` until the next top-down focus replaces it.
    Before the first top-down focus the robot spins in place.
    """

    def __init__(self, dt_s: float) -> None:
        self.dt_s = dt_s
        self.bearing_rad: float | None = None

    def __call__(self, obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
        if self.bearing_rad is not None:
            self.bearing_rad = float(wrap_angle(self.bearing_rad - float(obs["odometry"][1]) * self.dt_s))
        output = info["attention"]
        if output.origin == ORIGIN_TOP_DOWN:
            self.bearing_rad = focus_bearing(output)
        return steer(self.bearing_rad)


def memory_controller(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """``steer`` towards the first row of a ``focus`` observation's working memory when that
    body matched the goal (the rows hold the goal matches first), else spin: a reactive
    policy that reads nothing but the observation (``info`` is not used)."""
    rows = np.asarray(obs["memory"]).reshape(-1, len(MEMORY_FIELDS))
    cos_bearing, sin_bearing, goal_match = rows[0, _COS], rows[0, _SIN], rows[0, _MATCH]
    return steer(math.atan2(sin_bearing, cos_bearing) if goal_match > 0.5 else None)


def true_bearing_controller(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """``steer`` towards the target's true bearing (a privileged oracle)."""
    return steer(true_target_bearing(info))


def free_heading(proximity: np.ndarray, bearing_rad: float, distance_m: float) -> float | None:
    """The beam bearing nearest ``bearing_rad`` along which the robot's corridor is free, from
    the ``proximity`` entry ``(J,)`` (each region's nearest reading, m, spread over its beams);
    None when every heading is blocked.

    A heading is blocked when some beam's reading lies ahead along it, nearer than
    min(``CLEARANCE_AHEAD_M``, the target's distance − 0.3 m, at least 0.3 m), and within
    ``CLEARANCE_HALF_WIDTH_M`` of its line.
    """
    ranges = np.asarray(proximity, float)[_GRID.beam_region]
    need = min(CLEARANCE_AHEAD_M, max(distance_m - 0.3, 0.3))
    offsets = _BEAM_RAD[None, :] - _BEAM_RAD[:, None]  # (heading, beam)
    ahead, lateral = ranges * np.cos(offsets), np.abs(ranges * np.sin(offsets))
    free = ~((ahead > 0.0) & (ahead < need) & (lateral < CLEARANCE_HALF_WIDTH_M)).any(axis=1)
    if not free.any():
        return None
    candidates = _BEAM_RAD[free]
    return float(candidates[np.argmin(np.abs(candidates - bearing_rad))])


def clearance_controller(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """A reactive avoider on a focus-layout observation with ``proximity`` (the oracle's, where
    the first memory row is the target): ``clearance_action`` towards the first memory row's
    bearing and distance; it reads nothing but the observation."""
    row = np.asarray(obs["memory"]).reshape(-1, len(MEMORY_FIELDS))[0]
    return clearance_action(math.atan2(row[_SIN], row[_COS]), float(row[_DISTANCE]), obs["proximity"])


def privileged_clearance_controller(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """``clearance_action`` towards the target's true bearing and distance (``info``, the
    world's truth: a privileged teacher), clear of each region's nearest reading: the
    observation's ``"proximity"`` entry, or its ``"sonar"`` and ``"laser"`` ranges where it has
    none (``raw``); straight ahead while the episode has no target."""
    proximity = obs["proximity"] if "proximity" in obs else _GRID.nearest_reading(obs["sonar"], obs["laser"])
    if info["target_index"] < 0:
        return clearance_action(0.0, 0.0, proximity)
    target = true_target_xy(info)
    return clearance_action(float(bearing_of(target)), float(np.hypot(*target)), proximity)


def clearance_action(bearing_rad: float, distance_m: float, proximity: np.ndarray) -> np.ndarray:
    """Head for ``bearing_rad`` (robot frame) through ``free_heading`` given the target's
    ``distance_m`` and each region's nearest reading ``proximity`` ``(J,)`` (m), slowing as the
    front regions close in, turning towards the most open region when every heading is
    blocked; a target behind is turned to directly."""
    proximity = np.asarray(proximity, float)
    heading = bearing_rad
    if abs(bearing_rad) <= 0.5 * math.pi:
        free = free_heading(proximity, bearing_rad, distance_m)
        heading = float(_GRID.bearings_rad[np.argmax(proximity)]) if free is None else free
    front = proximity[np.abs(_GRID.bearings_rad) < CLEARANCE_FRONT_RAD].min()
    linear = float(np.clip(front - CLEARANCE_STOP_M, 0.0, 1.0)) * max(0.0, math.cos(heading))
    angular = float(np.clip(STEER_GAIN_PER_RAD * heading, -1.0, 1.0))
    return np.array([linear, angular], np.float32)


class RandomController:
    """Random actions from ``action_space``, seeded with ``seed``."""

    def __init__(self, action_space, seed: int) -> None:
        self.action_space = action_space
        self.action_space.seed(seed)

    def __call__(self, obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
        return self.action_space.sample()


class Wander:
    """Scripted exploration, deterministic given ``seed``: forward at ``WANDER_LINEAR`` with
    a slow sinusoidal turn (phase drawn from the seed), turning in place (direction drawn
    from the seed) while the front laser beams see something closer than
    ``WANDER_CLEARANCE_M``."""

    def __init__(self, seed: int) -> None:
        rng = np.random.default_rng(seed)
        self.phase_rad = float(rng.uniform(0.0, 2.0 * math.pi))
        self.turn_sign = float(rng.choice((-1.0, 1.0)))

    def __call__(self, obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
        if float(np.min(obs["laser"][WANDER_FRONT_BEAMS])) < WANDER_CLEARANCE_M:
            return np.array([0.0, self.turn_sign], np.float32)
        angular = WANDER_ANGULAR * math.sin(2.0 * math.pi * info["time_s"] / WANDER_PERIOD_S + self.phase_rad)
        return np.array([WANDER_LINEAR, angular], np.float32)


def stand_still(obs: Mapping[str, np.ndarray], info: Mapping[str, Any]) -> np.ndarray:
    """The zero action."""
    return np.zeros(2, np.float32)


def control_success(env, make_policy: Callable[[Any, int], Policy], seeds: Iterable[int]) -> float:
    """Fraction of the episodes (one per seed) that end in ``info["success"]`` before
    truncation; ``make_policy(env, seed)`` gives each episode's policy.

    Raises:
        ValueError: for no seed.
    """
    seeds = list(seeds)
    if not seeds:
        raise ValueError("control_success needs at least one seed, got none")
    successes = 0
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        policy = make_policy(env, seed)
        terminated = truncated = False
        while not (terminated or truncated):
            obs, _, terminated, truncated, info = env.step(policy(obs, info))
        successes += bool(info["success"])
    return successes / len(seeds)
