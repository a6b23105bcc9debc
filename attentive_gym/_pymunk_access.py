"""Fast reads and writes of pymunk body state for the per-step hot path (private).

pymunk's ``Body`` properties build a ``Vec2d`` per read and pass through a Python
``__setattr__`` per write: about 0.4 µs each, several times per body per environment
step. These helpers call the same Chipmunk functions the properties call
(``cpBodyGetPosition`` …) directly, on the body's ``_body`` handle, and return plain
floats: the values are the same, bit for bit. If this pymunk does not expose them (a
future version), they fall back to the public properties.

Nothing here caches a Chipmunk handle, so bodies stay picklable and copyable.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pymunk

__all__ = [
    "FAST",
    "position",
    "velocity",
    "pose",
    "poses",
    "set_velocity",
    "set_angle",
    "set_angular_velocity",
    "contact_count",
    "TESTED_PYMUNK",
    "ChipmunkFunctions",
    "chipmunk_functions",
    "handle",
    "probe_batch_layout",
    "stepping",
]


def _probe() -> bool:
    try:
        from pymunk._chipmunk import lib

        body = pymunk.Body(1.0, 1.0)
        body.position = (1.5, -2.0)
        body.velocity = (0.25, 4.0)
        body.angle = 0.75
        p, v = lib.cpBodyGetPosition(body._body), lib.cpBodyGetVelocity(body._body)
        lib.cpBodySetVelocity(body._body, (3.0, -1.0))
        lib.cpBodySetAngle(body._body, -0.5)
        lib.cpBodySetAngularVelocity(body._body, 2.0)
        return (
            (p.x, p.y, v.x, v.y, lib.cpBodyGetAngle(body._body)) == (1.5, -2.0, 0.25, 4.0, -0.5)
            and tuple(body.velocity) == (3.0, -1.0)
            and body.angular_velocity == 2.0
            and callable(lib.cpArbiterGetCount)
        )
    except Exception:  # an internal layout we do not know: use the public properties
        return False


FAST = _probe()

if FAST:
    from pymunk._chipmunk import lib as _lib

    _get_position = _lib.cpBodyGetPosition
    _get_velocity = _lib.cpBodyGetVelocity
    _get_angle = _lib.cpBodyGetAngle
    _set_velocity = _lib.cpBodySetVelocity
    _set_angle = _lib.cpBodySetAngle
    _set_angular_velocity = _lib.cpBodySetAngularVelocity
    _arbiter_count = _lib.cpArbiterGetCount

    def position(body: pymunk.Body) -> tuple[float, float]:
        """``body.position`` as a tuple of floats."""
        p = _get_position(body._body)
        return p.x, p.y

    def velocity(body: pymunk.Body) -> tuple[float, float]:
        """``body.velocity`` as a tuple of floats."""
        v = _get_velocity(body._body)
        return v.x, v.y

    def pose(body: pymunk.Body) -> tuple[float, float, float]:
        """``(x, y, angle)`` of ``body``."""
        handle = body._body
        p = _get_position(handle)
        return p.x, p.y, _get_angle(handle)

    def poses(bodies) -> list[float]:
        """``[x0, y0, angle0, x1, ...]`` of ``bodies``."""
        out: list[float] = []
        for body in bodies:
            handle = body._body
            p = _get_position(handle)
            out += (p.x, p.y, _get_angle(handle))
        return out

    def set_velocity(body: pymunk.Body, vx: float, vy: float) -> None:
        """``body.velocity = (vx, vy)``."""
        _set_velocity(body._body, (vx, vy))

    def set_angle(body: pymunk.Body, angle: float) -> None:
        """``body.angle = angle``."""
        _set_angle(body._body, angle)

    def set_angular_velocity(body: pymunk.Body, omega: float) -> None:
        """``body.angular_velocity = omega``."""
        _set_angular_velocity(body._body, omega)

    def contact_count(arbiter: pymunk.Arbiter) -> int:
        """``len(arbiter.contact_point_set.points)``."""
        return _arbiter_count(arbiter._arbiter)

else:  # pragma: no cover - depends on the pymunk build

    def position(body: pymunk.Body) -> tuple[float, float]:
        x, y = body.position
        return x, y

    def velocity(body: pymunk.Body) -> tuple[float, float]:
        x, y = body.velocity
        return x, y

    def pose(body: pymunk.Body) -> tuple[float, float, float]:
        x, y = body.position
        return x, y, body.angle

    def poses(bodies) -> list[float]:
        out: list[float] = []
        for body in bodies:
            x, y = body.position
            out += (x, y, body.angle)
        return out

    def set_velocity(body: pymunk.Body, vx: float, vy: float) -> None:
        body.velocity = (vx, vy)

    def set_angle(body: pymunk.Body, angle: float) -> None:
        body.angle = angle

    def set_angular_velocity(body: pymunk.Body, omega: float) -> None:
        body.angular_velocity = omega

    def contact_count(arbiter: pymunk.Arbiter) -> int:
        return len(arbiter.contact_point_set.points)


# --- Chipmunk's C functions for compiled callers ---------------------------------------
#
# A compiled kernel drives pymunk through three C functions called by address: pymunk's
# batch iterators ``pmSpaceBodyGetIteratorFuncBatched`` / ``pmSpaceBodySetIteratorFuncBatched``
# (``void f(cpBody *, void *data)``; ``data`` is a ``pmBatchedData`` pointing at a
# ``pmFloatArray`` whose numbers they push or pop: position x, y, angle, velocity x, y,
# angular velocity, as the fields ask) and ``cpSpaceStep`` (``void f(cpSpace *, double)``).
# Only pointers and doubles cross the boundary, so no struct is passed by value.

#: The pymunk releases whose batch layout this module has been checked against.
TESTED_PYMUNK = ((7, 3), (7, 4))  # [low, high): 7.3.x
#: Byte offsets the compiled callers assume: ``pmFloatArray`` (num, max, arr) and
#: ``pmBatchedData`` (intArray, floatArray, fields), and their sizes.
FLOAT_ARRAY_LAYOUT = {"num": 0, "max": 4, "arr": 8, "size": 16}
BATCHED_DATA_LAYOUT = {"intArray": 0, "floatArray": 8, "fields": 16, "size": 24}


@dataclass(frozen=True)
class ChipmunkFunctions:
    """The C addresses and batch field flags a compiled caller needs (plain ints).

    Attributes:
        get_body: address of ``pmSpaceBodyGetIteratorFuncBatched``.
        set_body: address of ``pmSpaceBodySetIteratorFuncBatched``.
        space_step: address of ``cpSpaceStep``.
        position, angle, velocity, angular_velocity: the batch field flags.
    """

    get_body: int
    set_body: int
    space_step: int
    position: int
    angle: int
    velocity: int
    angular_velocity: int

    def as_array(self) -> np.ndarray:
        """``(7,)`` int64 of the fields in declaration order."""
        return np.array(
            [
                self.get_body,
                self.set_body,
                self.space_step,
                self.position,
                self.angle,
                self.velocity,
                self.angular_velocity,
            ],
            dtype=np.int64,
        )


def chipmunk_functions() -> ChipmunkFunctions:
    """The C addresses of the functions compiled callers use (see ``probe_batch_layout``)."""
    from pymunk._chipmunk import ffi, lib

    def address(name: str) -> int:
        return int(ffi.cast("uintptr_t", ffi.addressof(lib, name)))

    return ChipmunkFunctions(
        get_body=address("pmSpaceBodyGetIteratorFuncBatched"),
        set_body=address("pmSpaceBodySetIteratorFuncBatched"),
        space_step=address("cpSpaceStep"),
        position=int(lib.POSITION),
        angle=int(lib.ANGLE),
        velocity=int(lib.VELOCITY),
        angular_velocity=int(lib.ANGULAR_VELOCITY),
    )


def handle(obj: pymunk.Body | pymunk.Space) -> int:
    """The address of the Chipmunk object behind a pymunk ``Body`` or ``Space``. Valid while
    ``obj`` lives; a copy or an unpickled object has its own."""
    from pymunk._chipmunk import ffi

    native = obj._body if isinstance(obj, pymunk.Body) else obj._space
    return int(ffi.cast("uintptr_t", native))


def probe_batch_layout() -> str | None:
    """Why compiled callers cannot drive this pymunk, or ``None`` when they can.

    Checks the version against ``TESTED_PYMUNK``, the struct layouts against
    ``FLOAT_ARRAY_LAYOUT`` / ``BATCHED_DATA_LAYOUT``, the private ``Space`` attributes
    ``stepping`` relies on, and makes a round trip on a tiny space: the get iterator reads
    a body's known state into a numpy buffer in the expected order, the set iterator writes
    it back from one, and ``cpSpaceStep`` called by address moves the body as ``Space.step``
    would.
    """
    try:
        release = tuple(int(part) for part in pymunk.version.split(".")[:2])
    except ValueError:
        return f"pymunk version {pymunk.version!r} is not a release number"
    low, high = TESTED_PYMUNK
    if not low <= release < high:
        return f"pymunk {pymunk.version} is outside the tested range >={low[0]}.{low[1]},<{high[0]}.{high[1]}"
    try:
        return _round_trip()
    except Exception as error:  # an internal layout we do not know
        return f"pymunk's batch API is not as expected ({type(error).__name__}: {error})"


def _round_trip() -> str | None:
    from pymunk._chipmunk import ffi

    for struct, layout in (("pmFloatArray", FLOAT_ARRAY_LAYOUT), ("pmBatchedData", BATCHED_DATA_LAYOUT)):
        found = {name: ffi.offsetof(struct, name) for name in layout if name != "size"}
        found["size"] = ffi.sizeof(struct)
        if found != layout:
            return f"{struct} has the layout {found}, expected {layout}"
    space = pymunk.Space()
    for name in ("_bodies_to_check", "_locked", "_removed_shapes", "_add_later", "threaded"):
        if not hasattr(space, name):
            return f"pymunk.Space has no attribute {name}"
    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    space.add(body)
    body.position, body.angle, body.velocity, body.angular_velocity = (1.5, -2.0), 0.75, (0.25, 4.0), -3.0
    functions = chipmunk_functions()
    every = functions.position | functions.angle | functions.velocity | functions.angular_velocity
    numbers = np.full(8, np.nan)  # two spare slots: a push into a full array reallocates it
    floats = ffi.new("pmFloatArray *")
    floats.arr, floats.max, floats.num = ffi.cast("double *", numbers.ctypes.data), len(numbers), 0
    data = ffi.new("pmBatchedData *")
    data.floatArray, data.intArray, data.fields = floats, ffi.NULL, every
    get_body = ffi.cast("void (*)(cpBody *, void *)", functions.get_body)
    set_body = ffi.cast("void (*)(cpBody *, void *)", functions.set_body)
    get_body(body._body, data)
    if numbers[:6].tolist() != [1.5, -2.0, 0.75, 0.25, 4.0, -3.0] or floats.num != 6:
        return f"the batch get iterator wrote {numbers[:6].tolist()} ({floats.num} numbers)"
    numbers[:6] = [0.5, 1.0, -0.25, 2.0, -1.0, 0.125]
    floats.num = 0
    set_body(body._body, data)
    if (*body.position, body.angle, *body.velocity, body.angular_velocity) != (0.5, 1.0, -0.25, 2.0, -1.0, 0.125):
        return "the batch set iterator did not set position, angle, velocity and angular velocity in that order"
    space_step = ffi.cast("void (*)(cpSpace *, double)", functions.space_step)
    space_step(space._space, 0.5)
    if tuple(body.position) != (1.5, 0.5):
        return f"cpSpaceStep called by address moved the body to {tuple(body.position)}, expected (1.5, 0.5)"
    return None


class stepping:
    """Context manager around stepping ``spaces`` by calling ``cpSpaceStep`` directly: the
    Python bookkeeping ``pymunk.Space.step`` does around Chipmunk's step (it checks newly
    added dynamic bodies, locks the spaces so that callbacks defer adding and removing, then
    adds what was deferred).

    Raises:
        ValueError: for a threaded space (its step is another C function).
    """

    def __init__(self, spaces: Sequence[pymunk.Space]) -> None:
        self._spaces = spaces

    def __enter__(self) -> None:
        for space in self._spaces:
            if space.threaded:
                raise ValueError("a threaded pymunk.Space cannot be stepped by the compiled world step")
            if space._bodies_to_check:
                space.step(0.0)  # only the checks: Chipmunk returns at once from a zero-length step
            space._locked = True

    def __exit__(self, *exc) -> None:
        for space in self._spaces:
            space._locked = False
            if space._removed_shapes:
                space._removed_shapes.clear()
            if space._add_later:
                space.add(*space._add_later)
                space._add_later.clear()
