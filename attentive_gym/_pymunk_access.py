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
