"""The world's step for many worlds in one compiled call, with a pure-Python fallback.

- ``step_worlds``: check every world's command, then advance all worlds by ``dt_s`` in one
  call; ``World.step`` is the same call with one world.
- ``engine`` / ``select_engine``: which implementation runs (``"compiled"`` or
  ``"python"``), chosen at import.

The compiled step does, for each world in turn, what the pure-Python step
(``World._step_python``) does, with the same arithmetic in the same order, so the two
give the same numbers bit for bit: clip the command, drive the movers once (their laws of
``world.behaviours``, from the numbers ``world.state`` holds), then per physics sub-step
ramp the robot's command, set its control body's velocity and call Chipmunk's
``cpSpaceStep``; finally read back the robot's and the movers' poses and velocities. It
reaches pymunk through Chipmunk's C functions called by address
(``_pymunk_access.chipmunk_functions``; the addresses are arguments, so the kernel stays in
numba's cache). The robot's contact callbacks stay Python: Chipmunk calls them from
inside ``cpSpaceStep``, which is why the kernel holds the GIL and runs the worlds one
after another.

At import, ``_pymunk_access.probe_batch_layout`` checks pymunk's version, its batch
layout and the private ``Space`` attributes the step relies on. If that fails, or if the
environment variable ``ATTENTIVE_GYM_PURE_PYTHON_WORLD`` is ``1``, every step runs the
pure-Python path (after one warning naming why, when the probe failed).
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numba
import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from attentive_gym import _pymunk_access
from attentive_gym.world.state import LAW_PATH, LAW_PURSUE, LAW_STILL, MOVER_DTYPE, WORLD_DTYPE

if TYPE_CHECKING:
    from attentive_gym.world.world import World

__all__ = ["step_worlds", "engine", "select_engine", "PURE_PYTHON_VARIABLE", "ENGINES"]

#: Set to ``1`` to run every world step in pure Python (read at import).
PURE_PYTHON_VARIABLE = "ATTENTIVE_GYM_PURE_PYTHON_WORLD"
#: The implementations of the world step.
ENGINES = ("compiled", "python")

# A world's row of addresses and counts for the kernel (``World.kernel_row``).
ROW_WORLD = 0  # its (1,) WORLD_DTYPE record
ROW_MOVERS = 1  # its (M,) MOVER_DTYPE records
ROW_NUM_MOVERS = 2
ROW_KNOTS = 3  # its (K, 3) float64 knots
ROW_NUM_KNOTS = 4
ROW_SPACE = 5  # its cpSpace
ROW_ROBOT = 6  # the robot's cpBody
ROW_CONTROL = 7  # the robot's control cpBody
ROW_MOVER_BODIES = 8  # its (M,) int64 mover cpBody addresses
ROW_SIZE = 9

# ``_pymunk_access.ChipmunkFunctions.as_array`` indices
_GET_BODY, _SET_BODY, _SPACE_STEP, _POSITION, _ANGLE, _VELOCITY, _ANGULAR_VELOCITY = range(7)

# The kernel's scratch, int64 words: a pmFloatArray (words 0-1), an empty pmIntArray
# (2-3), the pmBatchedData pointing at both (4-6) and the numbers (8-15: 8 doubles, two
# more than a body's largest read, so a push never finds the array full and reallocates
# numpy's memory).
_SCRATCH_WORDS = 16
_INTS_WORD = 2
_DATA_WORD = 4
_NUMBERS_WORD = 8
_NUMBERS = 8


@intrinsic
def _call_body_function(typingctx, function, body, data):
    """Call ``void function(cpBody *body, void *data)``; all three are addresses (int64)."""
    if not all(isinstance(arg, types.Integer) for arg in (function, body, data)):
        return None
    signature = types.void(function, body, data)

    def codegen(context, builder, sig, args):
        fn_type = ir.FunctionType(ir.VoidType(), [cgutils.voidptr_t, cgutils.voidptr_t])
        fn = builder.inttoptr(args[0], fn_type.as_pointer())
        builder.call(fn, [builder.inttoptr(args[1], cgutils.voidptr_t), builder.inttoptr(args[2], cgutils.voidptr_t)])
        return context.get_dummy_value()

    return signature, codegen


@intrinsic
def _call_space_step(typingctx, function, space, dt):
    """Call ``void function(cpSpace *space, double dt)``; ``function`` and ``space`` are
    addresses (int64)."""
    if not (isinstance(function, types.Integer) and isinstance(space, types.Integer) and dt == types.float64):
        return None
    signature = types.void(function, space, dt)

    def codegen(context, builder, sig, args):
        fn_type = ir.FunctionType(ir.VoidType(), [cgutils.voidptr_t, ir.DoubleType()])
        fn = builder.inttoptr(args[0], fn_type.as_pointer())
        builder.call(fn, [builder.inttoptr(args[1], cgutils.voidptr_t), args[2]])
        return context.get_dummy_value()

    return signature, codegen


@intrinsic
def _pointer(typingctx, address):
    """The ``void *`` at an address (int64)."""
    if not isinstance(address, types.Integer):
        return None

    def codegen(context, builder, sig, args):
        return builder.inttoptr(args[0], cgutils.voidptr_t)

    return types.voidptr(address), codegen


@njit(cache=True)
def _py_min(a, b):
    """Python's ``min(a, b)``: ``b`` only if it is smaller (the first of equals, as ``-0.0``)."""
    return b if b < a else a


@njit(cache=True)
def _py_max(a, b):
    """Python's ``max(a, b)``: ``b`` only if it is larger."""
    return b if b > a else a


@njit(cache=True)
def _approach(value, target, max_change):
    """``robot._approach``: ``value`` moved towards ``target`` by at most ``max_change``."""
    return value + _py_min(_py_max(target - value, -max_change), max_change)


@njit(cache=True)
def _new_scratch():
    """The scratch (``_SCRATCH_WORDS`` int64) wired up: the batch data points at the float
    array, the float array at the numbers (capacity ``_NUMBERS``)."""
    scratch = np.zeros(_SCRATCH_WORDS, np.int64)
    base = scratch.ctypes.data
    halves = scratch.view(np.int32)
    halves[1] = _NUMBERS  # pmFloatArray.max; .num (halves[0]) is set before every call
    scratch[1] = base + 8 * _NUMBERS_WORD  # pmFloatArray.arr
    scratch[_DATA_WORD] = base + 8 * _INTS_WORD  # pmBatchedData.intArray: empty, never used
    scratch[_DATA_WORD + 1] = base  # pmBatchedData.floatArray
    return scratch


@njit(cache=True)
def _read_body(functions, scratch, body, fields):
    """Push ``fields`` of the cpBody at ``body`` into the scratch's numbers; returns them
    (``(_NUMBERS,)`` float64 view; position x, y, angle, velocity x, y, angular velocity,
    in that order, of the fields asked)."""
    halves = scratch.view(np.int32)
    halves[0] = 0
    halves[2 * _DATA_WORD + 4] = fields  # pmBatchedData.fields
    _call_body_function(functions[_GET_BODY], body, scratch.ctypes.data + 8 * _DATA_WORD)
    return scratch.view(np.float64)[_NUMBERS_WORD:]


@njit(cache=True)
def _write_body(functions, scratch, body, fields):
    """Set ``fields`` of the cpBody at ``body`` from the scratch's numbers (filled by the
    caller, in ``_read_body``'s order)."""
    halves = scratch.view(np.int32)
    halves[0] = 0
    halves[2 * _DATA_WORD + 4] = fields
    _call_body_function(functions[_SET_BODY], body, scratch.ctypes.data + 8 * _DATA_WORD)


@njit(cache=True)
def _path_position(mover, knots, t_s):
    """``PathMotion.position``: where a path mover is at ``t_s`` (s)."""
    start = mover.start_delay_s
    period = mover.period_s
    if period > 0.0 and t_s > start:  # NaN (no loop) compares false
        t_s = start + np.fmod(t_s - start, period)  # exact, as C fmod
    first = mover.first_knot
    count = mover.num_knots
    low = 0  # bisect_right over the knot times
    high = count
    while low < high:
        middle = (low + high) // 2
        if t_s < knots[first + middle, 0]:
            high = middle
        else:
            low = middle + 1
    if low == 0:
        return knots[first, 1], knots[first, 2]
    if low == count:
        return knots[first + count - 1, 1], knots[first + count - 1, 2]
    k = first + low
    u = (t_s - knots[k - 1, 0]) / (knots[k, 0] - knots[k - 1, 0])
    x0 = knots[k - 1, 1]
    y0 = knots[k - 1, 2]
    return x0 + u * (knots[k, 1] - x0), y0 + u * (knots[k, 2] - y0)


@njit(cache=True)
def _law_velocity(mover, knots, t_s, h_s, x, y, robot_x, robot_y):
    """The velocity (m/s) of a mover at ``(x, y)`` under its law over ``[t_s, t_s + h_s]``
    (``PathMotion`` / ``PursueMotion`` / ``EvadeMotion.velocity``)."""
    law = mover.law
    if law == LAW_PATH:
        px, py = _path_position(mover, knots, t_s + h_s)
        return (px - x) / h_s, (py - y) / h_s
    if law == LAW_PURSUE:
        dx = robot_x - x
        dy = robot_y - y
        distance = math.sqrt(dx * dx + dy * dy)
        if t_s < mover.start_delay_s or distance <= mover.stop_distance_m:
            return 0.0, 0.0
        gain = _py_min(mover.speed_mps, (distance - mover.stop_distance_m) / h_s) / distance
        return dx * gain, dy * gain
    # evade (LAW_EVADE)
    dx = x - robot_x
    dy = y - robot_y
    distance = math.sqrt(dx * dx + dy * dy)
    if t_s < mover.start_delay_s or distance == 0.0:
        return 0.0, 0.0
    gain = mover.speed_mps * h_s / distance
    wanted_x = _py_min(_py_max(x + dx * gain, mover.low[0]), mover.high[0])
    wanted_y = _py_min(_py_max(y + dy * gain, mover.low[1]), mover.high[1])
    return (wanted_x - x) / h_s, (wanted_y - y) / h_s


@njit(cache=True)
def _drive_mover(functions, scratch, body, mover, knots, t_s, h_s, robot_x, robot_y):
    """``Mover.drive``: set the velocity (and heading) that follows the mover's law over
    the step, or stop it where it touches the robot and would not move away."""
    if mover.law == LAW_STILL:
        return
    if mover.blocked != 0 and mover.follows_clock != 0:
        mover.script_delay_s += h_s
    mover.blocked = 0
    numbers = _read_body(functions, scratch, body, functions[_POSITION])
    x = numbers[0]
    y = numbers[1]
    vx, vy = _law_velocity(mover, knots, t_s - mover.script_delay_s, h_s, x, y, robot_x, robot_y)
    if mover.touching != 0:
        mover.touching = 0
        if (vx != 0.0 or vy != 0.0) and vx * mover.towards_robot[0] + vy * mover.towards_robot[1] >= 0.0:
            vx = 0.0
            vy = 0.0
            if mover.follows_clock != 0:
                mover.script_delay_s += h_s
    numbers = scratch.view(np.float64)[_NUMBERS_WORD:]
    if mover.face_motion != 0 and (vx != 0.0 or vy != 0.0):
        numbers[0] = math.atan2(vy, vx)
        numbers[1] = vx
        numbers[2] = vy
        _write_body(functions, scratch, body, functions[_ANGLE] | functions[_VELOCITY])
    else:
        numbers[0] = vx
        numbers[1] = vy
        _write_body(functions, scratch, body, functions[_VELOCITY])


@njit(cache=True)
def _step_world(functions, scratch, row, dt_s, linear, angular):
    """``World._step_python`` for the world of ``row`` (``ROW_*``); the command is finite.
    Returns whether the robot touched anything."""
    world = numba.carray(_pointer(row[ROW_WORLD]), (1,), WORLD_DTYPE)[0]
    movers = numba.carray(_pointer(row[ROW_MOVERS]), (row[ROW_NUM_MOVERS],), MOVER_DTYPE)
    knots = numba.carray(_pointer(row[ROW_KNOTS]), (row[ROW_NUM_KNOTS], 3), np.float64)
    mover_bodies = numba.carray(_pointer(row[ROW_MOVER_BODIES]), (row[ROW_NUM_MOVERS],), np.int64)
    robot = row[ROW_ROBOT]
    # the clock restarts when the step length changes
    if dt_s != world.clock_dt_s:
        world.clock_start_s = world.time_s
        world.clock_dt_s = dt_s
        world.steps_taken = 0
    substeps = max(1, math.ceil(dt_s / world.physics_dt_s - 1e-9))
    h = dt_s / substeps
    # Robot.command
    world.target[0] = _py_min(_py_max(linear, -world.max_linear_mps), world.max_linear_mps)
    world.target[1] = _py_min(_py_max(angular, -world.max_angular_rps), world.max_angular_rps)
    if movers.shape[0] > 0:
        numbers = _read_body(functions, scratch, robot, functions[_POSITION])
        robot_x = numbers[0]
        robot_y = numbers[1]
        t_s = world.time_s
        for i in range(movers.shape[0]):
            _drive_mover(functions, scratch, mover_bodies[i], movers[i], knots, t_s, dt_s, robot_x, robot_y)
    world.touched = 0
    control = row[ROW_CONTROL]
    for _ in range(substeps):
        # Robot.drive
        command_linear = _approach(world.command[0], world.target[0], world.linear_accel_mps2 * h)
        command_angular = _approach(world.command[1], world.target[1], world.angular_accel_rps2 * h)
        world.command[0] = command_linear
        world.command[1] = command_angular
        numbers = _read_body(functions, scratch, robot, functions[_ANGLE])
        heading = numbers[0] + 0.5 * command_angular * h
        numbers[0] = command_linear * math.cos(heading)
        numbers[1] = command_linear * math.sin(heading)
        numbers[2] = command_angular
        _write_body(functions, scratch, control, functions[_VELOCITY] | functions[_ANGULAR_VELOCITY])
        _call_space_step(functions[_SPACE_STEP], row[ROW_SPACE], h)
    world.steps_taken += 1
    world.time_s = world.clock_start_s + world.steps_taken * dt_s
    _read_back(functions, scratch, world, movers, mover_bodies, robot)
    return world.touched != 0


@njit(cache=True)
def _read_back(functions, scratch, world, movers, mover_bodies, robot):
    """Copy the robot's pose and velocity and the movers' poses and velocities into the
    records (``World.read_back``)."""
    every = functions[_POSITION] | functions[_ANGLE] | functions[_VELOCITY] | functions[_ANGULAR_VELOCITY]
    numbers = _read_body(functions, scratch, robot, every)
    for k in range(3):
        world.robot_pose[k] = numbers[k]
        world.robot_velocity[k] = numbers[3 + k]
    for i in range(movers.shape[0]):
        numbers = _read_body(functions, scratch, mover_bodies[i], every)
        mover = movers[i]
        for k in range(3):
            mover.pose[k] = numbers[k]
        mover.velocity[0] = numbers[3]
        mover.velocity[1] = numbers[4]


@njit(cache=True, nogil=False)
def _step_worlds_kernel(functions, table, dt_s, commands, touched):
    """Step the worlds of ``table`` (``(N, ROW_SIZE)`` int64 rows) by ``dt_s`` with
    ``commands`` (``(N, 2)`` float64), one after another, writing ``touched`` (N,).

    Returns -1, or the first world whose command is not finite (then no world moved).
    Holds the GIL: the contact callbacks Chipmunk calls are Python.
    """
    for w in range(table.shape[0]):
        if not (math.isfinite(commands[w, 0]) and math.isfinite(commands[w, 1])):
            return w
    scratch = _new_scratch()
    for w in range(table.shape[0]):
        touched[w] = _step_world(functions, scratch, table[w], dt_s, commands[w, 0], commands[w, 1])
    return -1


def step_worlds(worlds: Sequence[World], dt_s: float, commands: np.ndarray) -> np.ndarray:
    """Advance every world by ``dt_s`` seconds with its robot commanded to ``commands``.

    Args:
        worlds: the N worlds (distinct).
        dt_s: the step (s), the same for all; a finite number > 0.
        commands: ``(N, 2)`` (linear m/s, angular rad/s) per world; values beyond the
            robot's limits are clipped to them.

    Returns:
        ``(N,)`` bool: whether each robot touched another body during the step.

    Raises:
        ValueError: ``dt_s`` is not a finite number > 0, ``commands`` does not have shape
            ``(N, 2)``, a command is not finite, or a world is listed twice; raised before
            any world moves.
    """
    if not (isinstance(dt_s, (int, float)) and math.isfinite(dt_s) and dt_s > 0.0):
        raise ValueError(f"dt_s must be a finite number of seconds > 0, got {dt_s!r}")
    commands = np.ascontiguousarray(commands, dtype=np.float64)
    n = len(worlds)
    if commands.shape != (n, 2):
        raise ValueError(
            f"commands must have shape (N, 2) = (linear m/s, angular rad/s) per world, with N = {n} "
            f"worlds; got shape {commands.shape}"
        )
    if n > 1 and len({id(world) for world in worlds}) < n:
        raise ValueError("worlds must be distinct: a world listed twice would step twice")
    if _engine == "python":
        if not np.isfinite(commands).all():
            _refuse(commands, int(np.flatnonzero(~np.isfinite(commands).all(axis=1))[0]))
        pairs = commands.tolist()
        return np.array([world._step_python(float(dt_s), *pair) for world, pair in zip(worlds, pairs)], dtype=np.bool_)
    touched = np.empty(n, dtype=np.bool_)
    table = worlds[0].kernel_row() if n == 1 else np.concatenate([world.kernel_row() for world in worlds])
    with _pymunk_access.stepping([world.space for world in worlds]):
        bad = _step_worlds_kernel(_functions, table, float(dt_s), commands, touched)
    if bad >= 0:
        _refuse(commands, bad)
    return touched


def _refuse(commands: np.ndarray, i: int) -> None:
    """Raise the ``ValueError`` for world ``i``'s command, which is not finite."""
    linear, angular = commands[i].tolist()
    raise ValueError(
        f"robot commands must be finite numbers, got linear {linear!r} m/s, angular {angular!r} rad/s for world {i}"
    )


def engine() -> str:
    """The implementation ``step_worlds`` runs now: ``"compiled"`` or ``"python"``."""
    return _engine


def select_engine(pure_python: bool = False) -> str:
    """Choose the implementation of the world step and return it.

    ``pure_python=True`` always chooses ``"python"``. Otherwise the probe
    (``_pymunk_access.probe_batch_layout``) runs: when it passes, ``"compiled"``; when it
    fails, ``"python"`` after a ``RuntimeWarning`` naming why.
    """
    global _engine, _functions
    if pure_python:
        _engine = "python"
        return _engine
    problem = _pymunk_access.probe_batch_layout()
    if problem is not None:
        warnings.warn(f"the world steps in pure Python (slower): {problem}", RuntimeWarning, stacklevel=2)
        _engine = "python"
        return _engine
    _functions = _pymunk_access.chipmunk_functions().as_array()
    _engine = "compiled"
    return _engine


_engine = "python"
_functions = np.zeros(7, np.int64)
select_engine(os.environ.get(PURE_PYTHON_VARIABLE, "") == "1")
