"""The paper's five experimental set-ups as scenarios (docs/model.md §9).

The attentive robot stands still at the origin facing +x (it receives zero commands in
the experiments); targets are P2AT-sized robots. Bearings follow docs/model.md §1: front
sonar s1..s8 (indices 0..7) at +90, +50, +30, +10, −10, −30, −50, −90°, each a ±15°
cone, so a body at +10° and 3 m lies in s4's cone only. Distances and speeds are those the
paper states; the timings the paper leaves open are chosen so that every phase it
describes happens within the run and are listed in each docstring.

``builtin_scenario(name)`` returns one by name; ``BUILTIN_SCENARIOS`` lists them.
"""

from __future__ import annotations

import math

from attentive_gym.world.scenario import BoxRubble, Leg, MoverSpec, PathBehaviour, Pose, Scenario, WallSpec

__all__ = ["BUILTIN_SCENARIOS", "builtin_scenario", "polar"]


def polar(range_m: float, bearing_deg: float) -> tuple[float, float]:
    """The world point at ``range_m`` and ``bearing_deg`` from the origin (robot at rest)."""
    angle = math.radians(bearing_deg)
    return (round(range_m * math.cos(angle), 6), round(range_m * math.sin(angle), 6))


def _robot(name: str, range_m: float, bearing_deg: float, legs, delay_s: float) -> MoverSpec:
    """A P2AT-sized robot facing the attentive robot, following straight ``legs``."""
    x, y = polar(range_m, bearing_deg)
    return MoverSpec(
        name=name,
        kind="robot",
        start=Pose(x, y, bearing_deg + 180.0),
        behaviour=PathBehaviour(legs=tuple(legs), start_delay_s=delay_s),
    )


def exp01() -> Scenario:
    """Exp01, motion (F1): a robot 3 m ahead at +10° (s4) approaches 0.4 m, then backs
    away out of sonar range (to 6 m), at 0.5 m/s after 0.5 s; then the scene is static."""
    legs = [Leg(polar(2.6, 10.0), 0.5), Leg(polar(6.0, 10.0), 0.5)]
    return Scenario(
        name="exp01",
        bounds=(-2.0, -8.0, 10.0, 8.0),
        movers=(_robot("target", 3.0, 10.0, legs, delay_s=0.5),),
        duration_s=10.0,
    )


def exp02() -> Scenario:
    """Exp02, distance (F3, sonar + laser): a room 16 × 12 m whose walls lie beyond sonar
    range (> 5 m) but within laser range; a robot 3 m away at +135° — behind-left, outside
    every front sonar cone and the laser's field of view — starts after 1.5 s at 0.5 m/s
    and drives forward past the robot's left side (2.1 m abeam), entering sonar s1's cone
    at about 4.3 s and s2's at about 7.2 s."""
    x, y = polar(3.0, 135.0)
    target = MoverSpec(
        name="target",
        kind="robot",
        start=Pose(x, y, 0.0),
        behaviour=PathBehaviour(legs=(Leg((6.0, y), 0.5),), start_delay_s=1.5),
    )
    return Scenario(
        name="exp02",
        bounds=(-4.0, -6.0, 12.0, 6.0),
        enclosed=True,
        movers=(target,),
        duration_s=12.0,
    )


def exp03() -> Scenario:
    """Exp03, motion + distance (F1 + F3): a wall 2 m to the left, two boxes 11–12 m ahead,
    and two robots 8 m away at +10° and −30° that approach to 2.5 m and return at
    0.6 m/s, the first after 1 s, the second after 5 s."""

    def there_and_back(bearing):
        return [Leg(polar(2.5, bearing), 0.6), Leg(polar(8.0, bearing), 0.6)]

    return Scenario(
        name="exp03",
        bounds=(-2.0, -10.0, 14.0, 10.0),
        walls=(WallSpec((-1.0, 2.0), (9.0, 2.0)),),
        rubble=(BoxRubble(11.5, 3.5, 0.8, 0.8), BoxRubble(12.0, -3.0, 0.8, 0.8)),
        movers=(
            _robot("first", 8.0, 10.0, there_and_back(10.0), delay_s=1.0),
            _robot("second", 8.0, -30.0, there_and_back(-30.0), delay_s=5.0),
        ),
        duration_s=24.0,
    )


def exp04() -> Scenario:
    """Exp04, motion + goal speed (F1 + F4, BETWEEN(0.5, 0.9) m/s): a robot 7 m away at
    +10° (out of sonar range) approaches to 2 m at 0.7 m/s after 0.5 s, waits 1 s, and
    backs away to 7 m at 0.7 m/s."""
    legs = [Leg(polar(2.0, 10.0), 0.7, pause_s=1.0), Leg(polar(7.0, 10.0), 0.7)]
    return Scenario(
        name="exp04",
        bounds=(-2.0, -8.0, 10.0, 8.0),
        movers=(_robot("target", 7.0, 10.0, legs, delay_s=0.5),),
        duration_s=17.0,
    )


def exp05() -> Scenario:
    """Exp05, motion + goal speed (F1 + F4, GREATER(0.6) m/s): two robots 7 m away, out of
    sonar range: the faster (0.7 m/s) at +10° from 0 s, the slower (0.55 m/s: the paper's
    "~0.6", below the goal's threshold) at −30° from 2 s; each approaches to 2.5 m and
    backs away to 7 m, the faster leaving range first."""

    def there_and_back(bearing, speed):
        return [Leg(polar(2.5, bearing), speed), Leg(polar(7.0, bearing), speed)]

    return Scenario(
        name="exp05",
        bounds=(-2.0, -8.0, 10.0, 8.0),
        movers=(
            _robot("fast", 7.0, 10.0, there_and_back(10.0, 0.7), delay_s=0.0),
            _robot("slow", 7.0, -30.0, there_and_back(-30.0, 0.55), delay_s=2.0),
        ),
        duration_s=19.0,
    )


BUILTIN_SCENARIOS = {"exp01": exp01, "exp02": exp02, "exp03": exp03, "exp04": exp04, "exp05": exp05}


def builtin_scenario(name: str) -> Scenario:
    """The built-in scenario called ``name`` (one of ``BUILTIN_SCENARIOS``)."""
    try:
        return BUILTIN_SCENARIOS[name]()
    except KeyError:
        raise ValueError(f"unknown built-in scenario {name!r}; allowed: {sorted(BUILTIN_SCENARIOS)}") from None
