"""Invariants of ``AttentiveRescue-v0`` checked after every step (soak tests, fuzzing).

- ``check_invariants(env, obs, output=None)``: the list of violated invariants (empty = fine)
  of an unwrapped env right after ``reset``/``step``, its observation, and optionally the
  ``AttentionOutput`` of a model fed that observation.
- ``InvariantChecker``: the same, remembering when the robot last touched something (the
  speed bounds are wider for a while after a contact, see below). Call ``reset()`` per
  episode.
- ``PENETRATION_TOL_M``, ``CONTACT_MEMORY_S``, …: the tolerances, documented.

What is checked:

1. **Nothing inside a wall or static shape**: the robot's penetration into any wall or
   rubble (pymunk ``shape_query`` contact depth) is at most ``PENETRATION_TOL_M``. Path movers
   (victims and robots on scripted legs) must not penetrate static shapes by more than
   ``PENETRATION_TOL_M`` either; pursuers and
   evaders steer straight at/away from the robot and, being scripted kinematic bodies, are
   allowed to pass through rubble (a documented property of ``World``), so they are
   exempt. Every body's position must be finite.
2. **Readings within sensor limits and finite**: sonar in ``[min_range, max_range]``,
   laser in ``[0, max_range]``, odometry and goal finite and inside the observation space,
   every array float32 with the space's shape.
3. **Robot speed within its limits**: ``|v| <= max_linear_mps`` and
   ``|w| <= max_angular_rps`` (relative tolerance ``SPEED_REL_TOL``). Movers never push
   the robot (``World`` stops a mover that touches it), so no allowance is made for
   them. While the robot touches (or touched within ``CONTACT_MEMORY_S``) a wall, rubble
   or a mover, contact impulses may add ``CONTACT_SPEED_REL`` to the linear bound and
   ``max_linear_mps`` over half the robot's width to the angular one (hitting a corner at
   full speed turns forward motion into spin, measured up to 2.50 rad/s against the
   drive's 2.44, and spinning against one turns rotation into translation).
4. **Attention output** (optional): ``M`` and ``L`` finite and ``>= 0``, ``F`` finite; the
   track table (``output.tracks``) finite, speeds ``>= 0`` and motion probabilities in
   [0, 1] (speeds in the table are not clipped, so no upper bound).
5. **Tracker state** (optional, ``check_tracker``; pass the model and it runs when the
   model has a tracker, ``kinematics="tracker"``), over every live track slot: the state
   (constant-velocity and static filters, motion probability) finite; both covariances
   (4×4 and 2×2) symmetric to ``COVARIANCE_SYMMETRY_REL`` and positive definite (their
   Cholesky factorisation succeeds); the motion probability in [0, 1]; ids unique and below the next
   id; at most ``max_tracks`` live tracks, and at most as many tentative (unconfirmed)
   tracks as the last scan had segments: a scan gives each candidate segment at most one
   birth or one match and deletes tentative tracks at their first miss, so every live
   tentative track holds a segment of the last scan. With an output, its track table has
   one row per live track.

Tolerances — measured, not guessed: the world's pymunk space keeps the default
``collision_slop`` of 0.1 (pymunk's unit is the metre here, so contacts are allowed to
overlap up to 10 cm before the solver pushes the shapes apart). Over a 1,000,000-step soak
(``benchmarks/soak.py``, see ``docs/reliability.md``) the deepest robot-in-static overlap
was 0.092 m (the robot driving and turning into a wall at full speed). The tolerance sits
above that with margin but far below any real tunnelling (a wall is 0.2 m thick, the robot
0.505 m wide).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "check_invariants",
    "InvariantChecker",
    "PENETRATION_TOL_M",
    "CONTACT_MEMORY_S",
    "SPEED_REL_TOL",
    "CONTACT_SPEED_REL",
    "COVARIANCE_SYMMETRY_REL",
    "check_tracker",
]

#: Largest robot/mover overlap with a wall or rubble accepted (m): pymunk's collision
#: slop (0.1) plus 2 cm.
PENETRATION_TOL_M = 0.12
#: How long after its last contact the robot keeps the contact speed bounds (s): the
#: solver removes overlap beyond the slop at ``collision_bias`` = 0.9 per 1/60 s, so the
#: separation impulses are over in ~1 s.
CONTACT_MEMORY_S = 1.5
#: Extra linear speed (fraction of ``max_linear_mps``) a contact may add: a robot driving
#: and spinning against a corner turns part of its rotation into translation. Measured up
#: to +11.1 % (0.778 m/s, reversing and spinning against a stopped mover's corner) over a
#: 3,000,000-step soak; the first tolerance, 10 %, came from a 1,000,000-step soak.
CONTACT_SPEED_REL = 0.15
#: Relative tolerance on the speed limits (floating-point slack of the joint solver).
SPEED_REL_TOL = 1e-3
#: Largest asymmetry of a track's covariance, relative to its largest entry: the Kalman
#: kernels (predictions and Joseph-form updates) keep both triangles equal up to rounding
#: (~1e-16 relative per operation); 1e-9 leaves room for accumulated rounding and still
#: catches a real fault.
COVARIANCE_SYMMETRY_REL = 1e-9


def _penetration(space, shape, others: set) -> float:
    """Deepest overlap (m, >= 0) of ``shape`` with any shape of ``others``."""
    worst = 0.0
    centre = shape.body.position
    for hit in space.shape_query(shape):
        if hit.shape in others:
            for point in hit.contact_point_set.points:
                if -point.distance > worst:
                    worst = -point.distance
            # pymunk reports a depth of 0 for some deep, symmetric overlaps (a box centred on
            # a wall): with the centre inside the other shape, the overlap is at least that
            # depth plus the shape's own inner radius (centre to its nearest edge)
            inside = -hit.shape.point_query(centre).distance
            if inside > 0.0:
                worst = max(worst, inside - shape.point_query(centre).distance)
    return worst


def _check_array(violations: list[str], name: str, value, space) -> np.ndarray | None:
    if not isinstance(value, np.ndarray):
        violations.append(f"obs[{name!r}] is a {type(value).__name__}, not an ndarray")
        return None
    if value.dtype != space.dtype or value.shape != space.shape:
        violations.append(
            f"obs[{name!r}] has dtype {value.dtype} shape {value.shape}, space wants {space.dtype} {space.shape}"
        )
        return None
    if not np.all(np.isfinite(value)):
        violations.append(f"obs[{name!r}] is not finite at indices {np.flatnonzero(~np.isfinite(value))[:10].tolist()}")
        return None
    if not space.contains(value):
        violations.append(f"obs[{name!r}] leaves its space: min {value.min()}, max {value.max()}")
    return value


def check_invariants(
    env, obs: dict[str, np.ndarray], output=None, *, model=None, contact: bool | None = None, _depth: list | None = None
) -> list[str]:
    """The violated invariants (messages) of ``env`` after a step; empty when all hold.

    Args:
        env: an unwrapped ``AttentiveRescueEnv`` after ``reset`` or ``step``.
        obs: the observation that call returned.
        output: an ``AttentionOutput`` computed from ``obs``, or None.
        model: the ``AttentionModel`` that computed ``output``, or None; its tracker's
            state is checked when it has one (``check_tracker``).
        contact: whether the robot touches (or recently touched) anything; None: whether
            it touches something now.
    """
    violations: list[str] = []
    world = env.world
    if world is None:
        return ["env has no world: reset() was not called"]
    if contact is None:
        contact = world.robot.in_contact()

    # --- 1. bodies finite and not inside static shapes ----------------------------------
    static = {shape for _, shape in world.static}
    body = world.robot.body
    pose = (body.position.x, body.position.y, body.angle)
    if not all(math.isfinite(v) for v in pose):
        violations.append(f"robot pose is not finite: {pose}")
    positions = world.mover_positions()
    if not np.all(np.isfinite(positions)):
        violations.append(f"mover positions are not finite: {positions.tolist()}")
    if static:
        depth = _penetration(world.space, world.robot.shape, static)
        if _depth is not None:
            _depth.append(depth)
        if depth > PENETRATION_TOL_M:
            violations.append(f"robot is {depth:.3f} m inside a wall/rubble (tolerance {PENETRATION_TOL_M} m)")
        from attentive_gym.world.scenario import PathBehaviour  # deferred: keeps this module light

        for mover in world.movers:
            if mover.spec.behaviour is None or isinstance(mover.spec.behaviour, PathBehaviour):
                depth = _penetration(world.space, mover.shape, static)
                if depth > PENETRATION_TOL_M:
                    violations.append(f"mover {mover.entity.name!r} is {depth:.3f} m inside a wall/rubble")

    # --- 2. readings -------------------------------------------------------------------
    space = env.observation_space
    if not isinstance(obs, dict) or set(obs) != set(space.spaces):
        return violations + [
            f"observation keys {sorted(obs) if isinstance(obs, dict) else type(obs)} are not {sorted(space.spaces)}"
        ]
    checked = {name: _check_array(violations, name, obs[name], space[name]) for name in space.spaces}
    sonar = checked["sonar"]
    if sonar is not None:
        low, high = env.sensors.sonar_ring.config.min_range_m, env.sensors.sonar_ring.config.max_range_m
        if sonar.min() < np.float32(low) or sonar.max() > np.float32(high):
            violations.append(f"sonar outside [{low}, {high}] m: min {sonar.min()}, max {sonar.max()}")
    laser = checked["laser"]
    if laser is not None:
        high = env.sensors.laser_scanner.config.max_range_m
        if laser.min() < 0.0 or laser.max() > np.float32(high):
            violations.append(f"laser outside [0, {high}] m: min {laser.min()}, max {laser.max()}")

    # --- 3. robot speed ----------------------------------------------------------------
    config = env.robot_config
    speed = math.hypot(body.velocity.x, body.velocity.y)
    spin = abs(body.angular_velocity)
    linear_limit, angular_limit = config.max_linear_mps, config.max_angular_rps
    if contact:
        linear_limit *= 1.0 + CONTACT_SPEED_REL
        angular_limit += config.max_linear_mps / (0.5 * min(config.length_m, config.width_m))
    if not math.isfinite(speed) or speed > linear_limit * (1.0 + SPEED_REL_TOL) + 1e-9:
        violations.append(f"robot speed {speed:.4f} m/s exceeds {linear_limit:.4f} m/s (contact={contact})")
    if not math.isfinite(spin) or spin > angular_limit * (1.0 + SPEED_REL_TOL) + 1e-9:
        violations.append(f"robot turn rate {spin:.4f} rad/s exceeds {angular_limit:.4f} rad/s (contact={contact})")

    # --- 4. attention ------------------------------------------------------------------
    if output is not None:
        for name in ("M", "L"):
            values = np.asarray(getattr(output, name))
            if not np.all(np.isfinite(values)):
                violations.append(f"attention {name} is not finite: {values.tolist()}")
            elif np.any(values < 0.0):
                violations.append(f"attention {name} is negative: min {values.min()}")
        if not np.all(np.isfinite(output.F)):
            violations.append("attention F is not finite")
        violations.extend(_check_track_table(output.tracks))

    # --- 5. tracker --------------------------------------------------------------------
    tracker = None if model is None else model.tracker
    if tracker is not None:
        violations.extend(check_tracker(tracker, None if output is None else output.tracks))
    return violations


def _slots(tracker, slots: np.ndarray) -> str:
    """``slots`` (array of slot indices) with their track ids, the first 5."""
    shown = ", ".join(f"{int(k)} (id {int(tracker.ids[k])})" for k in slots[:5])
    return f"slot{'s' if slots.size > 1 else ''} {shown}{', …' if slots.size > 5 else ''}"


def check_tracker(tracker, tracks=None) -> list[str]:
    """The violated invariants (messages) of a ``Tracker``'s live tracks (item 5 of the
    module docstring); empty when all hold.

    Args:
        tracker: an ``attentive_gym.attention.tracking.tracker.Tracker`` (``AttentionModel._tracker``).
        tracks: the ``TrackTable`` the model output with the tracker in this state, or None.

    Each check first tests all live tracks at once and only looks for the offending slots
    when it fails (the soak runs this after every step).
    """
    violations: list[str] = []
    live = np.flatnonzero(tracker.alive)
    n = live.size
    config = tracker.config
    state = {name: getattr(tracker, name)[live] for name in _TRACKER_STATE}
    if not math.isfinite(sum(float(array.sum()) for array in state.values())):  # NaN or inf somewhere (or overflow)
        finite = np.ones(n, bool)
        for name, array in state.items():
            ok = np.isfinite(array).reshape(n, math.prod(array.shape[1:])).all(axis=1)
            if not ok.all():
                violations.append(f"tracker {name} is not finite at live {_slots(tracker, live[~ok])}")
            finite &= ok
        live = live[finite]
        state = {name: array[finite] for name, array in state.items()}
    for name in ("cv_P", "static_P"):
        P = state[name]
        if not P.size:
            continue
        asymmetry = np.abs(P - P.transpose(0, 2, 1)).max(axis=(1, 2))
        bad = asymmetry > COVARIANCE_SYMMETRY_REL * np.abs(P).max(axis=(1, 2))
        if bad.any():
            violations.append(
                f"tracker covariance {name} is not symmetric at {_slots(tracker, live[bad])}: "
                f"largest |P - Pᵀ| {asymmetry[bad].max():.3g}"
            )
        try:
            np.linalg.cholesky(P)  # every matrix at once; reads the lower triangle
        except np.linalg.LinAlgError:
            smallest = np.linalg.eigvalsh(P)[:, 0]  # ascending
            bad = ~(smallest > 0.0)
            violations.append(
                f"tracker covariance {name} is not positive definite at {_slots(tracker, live[bad])}: "
                f"smallest eigenvalue {smallest[bad].min():.3g}"
            )
    p_moving = state["p_moving"]
    if p_moving.size and not (p_moving.min() >= 0.0 and p_moving.max() <= 1.0):
        bad = ~((p_moving >= 0.0) & (p_moving <= 1.0))
        violations.append(
            f"tracker motion probability outside [0, 1] at {_slots(tracker, live[bad])}: {p_moving[bad][:5].tolist()}"
        )
    ids = tracker.ids[tracker.alive]
    if ids.size and (ids.max() >= tracker.counters[0] or np.unique(ids).size != ids.size):
        violations.append(
            f"tracker ids {sorted(ids.tolist())} are not unique or not below the next id {int(tracker.counters[0])}"
        )
    if n > config.max_tracks:
        violations.append(f"tracker has {n} live tracks, more than max_tracks={config.max_tracks}")
    tentative = int(np.count_nonzero(tracker.hits[tracker.alive] < config.track_confirm_hits))
    segments = int(tracker.counters[1])
    if tentative > segments:
        violations.append(
            f"tracker has {tentative} tentative tracks but the last scan had {segments} segments "
            f"(each tentative track holds one of them)"
        )
    if tracks is not None and len(tracks) != n:
        violations.append(f"tracks table has {len(tracks)} rows but the tracker has {n} live tracks")
    return violations


#: The per-track state arrays of ``Tracker`` that must be finite.
_TRACKER_STATE = ("cv_x", "cv_P", "static_x", "static_P", "p_moving")
#: The float columns of a ``TrackTable`` that must be finite.
_TABLE_FLOATS = ("position_m", "velocity_mps", "speed_mps", "moving_probability", "covariance", "age_s")


def _check_track_table(tracks) -> list[str]:
    """The violated invariants of an ``AttentionOutput.tracks`` table (item 4)."""
    n = len(tracks)
    if not n:
        return []
    violations = []
    if not math.isfinite(sum(float(getattr(tracks, name).sum()) for name in _TABLE_FLOATS)):
        for name in _TABLE_FLOATS:
            values = getattr(tracks, name)
            bad = ~np.isfinite(values).reshape(n, math.prod(values.shape[1:])).all(axis=1)
            if bad.any():
                violations.append(f"tracks {name} is not finite for ids {tracks.id[bad][:5].tolist()}")
    speed = tracks.speed_mps
    if speed.min() < 0.0:
        violations.append(f"tracks speed_mps is negative: min {speed.min()}")
    p = tracks.moving_probability
    if p.min() < 0.0 or p.max() > 1.0:
        violations.append(f"tracks moving_probability outside [0, 1]: {p[(p < 0.0) | (p > 1.0)][:5].tolist()}")
    return violations


class InvariantChecker:
    """``check_invariants`` over an episode, remembering the robot's last contact.

    Example:
        >>> checker = InvariantChecker()
        >>> obs, info = env.reset(seed=0); checker.reset()
        >>> problems = checker.check(env.unwrapped, obs)
    """

    def __init__(self) -> None:
        self.reset()
        #: Deepest robot overlap with a wall/rubble seen (m).
        self.max_penetration_m = 0.0

    def reset(self) -> None:
        """Start a new episode (forget the last contact)."""
        self._last_contact_s = -math.inf

    def check(self, env, obs: dict[str, np.ndarray], output=None, info: dict | None = None, *, model=None) -> list[str]:
        """The violated invariants after this step (see ``check_invariants``; ``model``:
        the model that computed ``output``, for its tracker).

        Pass the step's ``info``: its ``collision`` flag covers every physics sub-step,
        while the contacts still present after the step may already have ended.
        """
        world = env.world
        if world is not None and ((info is not None and info.get("collision")) or world.robot.in_contact()):
            self._last_contact_s = world.time_s
        contact = world is not None and world.time_s - self._last_contact_s <= CONTACT_MEMORY_S
        depth: list[float] = []
        violations = check_invariants(env, obs, output, model=model, contact=contact, _depth=depth)
        if depth:
            self.max_penetration_m = max(self.max_penetration_m, depth[0])
        return violations
