"""Is the tracker's judgement of a speed goal calibrated? Reliability tables against the truth.

For every confirmed track at every step of the perception benchmark's arena (10 m, 3
distractors, 5 % Gaussian noise, the tracker; the robot still, then wandering), the model's
judgement that the body's speed lies in a task goal's band (``--band``: the fast goal's
[0.5, 0.9] m/s by default, or the slow goal's 0.15,0.45)
(``track_regions.speed_goal_probability``: the track's probability of moving × P(speed in
the band), the speed normal along the velocity estimate with its covariance; what
``AttentionConfig.track_speed_goal_probability`` judges the goal by) is set against the truth
of the mover the track lies on (``perception.calibration.judged_track_steps``).

A judgement is calibrated when, of the track-steps judged in band with probability p, about
p are. The script prints, per robot mode, the reliability table of the judgement (bins of p:
count, mean p, the share truly in band), that of ``moving_probability`` against the truth of
moving (> 0.1 m/s), and the Brier scores of the judgement and of the point rule it can
replace (the track's speed weighted by its probability of moving, inside the band; 0 or 1).
Then, of the track-steps judged in band (p ≥ ½), the share whose body truly stands, moves
below the band, inside it, just above it (within 0.2 m/s) or faster: where the judgement's
errors lie::

    python benchmarks/calibration.py --episodes 4 --seconds 20   # a few seconds
    python benchmarks/calibration.py --band 0.15,0.45 --episodes 8

Seeds 8 onwards (the perception benchmark's phantom-motion seeds).
"""

from __future__ import annotations

import argparse

from attentive_gym.perception.calibration import brier, judged_track_steps, reliability
from attentive_gym.perception.controllers import Wander, stand_still
from attentive_gym.perception.settings import PERCEPTION_ARENA, make_attentive_env

#: The fast goal's band (m/s), the first seed and the range noise (relative σ).
BAND, FIRST_SEED, NOISE = (0.5, 0.9), 8, 0.05
#: Above the band by at most this (m/s): "just above" in the breakdown of the judged steps.
NEAR_ABOVE_MPS = 0.2


def parse_band(text: str) -> tuple[float, float]:
    """``"lo,hi"`` (m/s) as a band with ``0 <= lo < hi``; ``argparse.ArgumentTypeError`` otherwise."""
    try:
        lo, hi = (float(part) for part in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--band must be two speeds 'lo,hi' in m/s, got {text!r}") from None
    if not 0.0 <= lo < hi:
        raise argparse.ArgumentTypeError(f"--band must have 0 <= lo < hi (m/s), got {text!r}")
    return lo, hi


def judged_breakdown(judged, true_speed, band: tuple[float, float]) -> dict[str, float]:
    """Of the track-steps ``judged`` in band (bool ``(n,)``), the share per truth of their body's
    ``true_speed`` ``(n,)`` (m/s): standing (≤ 0.1), below the band, in it, just above it (by at
    most ``NEAR_ABOVE_MPS``), faster; NaN shares where none is judged in band."""
    lo, hi = band
    speed = true_speed[judged]
    groups = {
        "standing": speed <= 0.1,
        "below the band": (speed > 0.1) & (speed < lo),
        "in the band": (speed >= lo) & (speed <= hi),
        "just above": (speed > hi) & (speed <= hi + NEAR_ABOVE_MPS),
        "faster": speed > hi + NEAR_ABOVE_MPS,
    }
    return {name: float(group.mean()) if speed.size else float("nan") for name, group in groups.items()}


def table(judged, truth) -> list[str]:
    """The markdown rows of ``reliability(judged, truth)``."""
    header = ["| bin of p | track-steps | mean p | share true |", "|---|---|---|---|"]
    return header + [
        f"| [{low:.2f}, {high:.2f}] | {count} | {mean:.3f} | {share:.3f} |"
        for low, high, count, mean, share in reliability(judged, truth)
    ]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--episodes", type=int, default=4, help="episodes per robot mode (default 4)")
    parser.add_argument("--seconds", type=float, default=20.0, help="seconds per episode (default 20)")
    parser.add_argument(
        "--band", type=parse_band, default=BAND, help="the speed goal's band 'lo,hi' in m/s (default 0.5,0.9)"
    )
    args = parser.parse_args(argv)
    if args.episodes < 1 or not args.seconds > 0:
        parser.error(f"--episodes must be >= 1 and --seconds > 0, got {args.episodes} and {args.seconds}")
    env = make_attentive_env("tracker", NOISE, "saliency", sensor_noise=NOISE, **PERCEPTION_ARENA)
    seeds = range(FIRST_SEED, FIRST_SEED + args.episodes)
    for robot, policy_of in (("still", lambda seed: stand_still), ("driving", Wander)):
        steps = judged_track_steps(env, args.band, seeds, args.seconds, policy_of)
        truth = steps["in_band"]
        print(f"\n## Robot {robot}: {truth.size} track-steps, {truth.mean():.3f} of them truly in band\n")
        print("P(speed in band), as the model judges it:\n", *table(steps["probability"], truth), "", sep="\n")
        print("moving_probability against moving:\n", *table(steps["moving"], steps["truly_moving"]), sep="\n")
        point = steps["point"] > 0.5
        print(
            f"\npoint rule: {point.sum()} in band, {truth[point].mean():.3f} of them truly; "
            f"{point[truth > 0.5].mean():.3f} of the truly in band judged so"
        )
        judged = steps["probability"] >= 0.5
        print(
            f"judged (p ≥ ½): {judged.sum()} in band, {truth[judged].mean():.3f} of them truly; "
            f"{judged[truth > 0.5].mean():.3f} of the truly in band judged so"
        )
        print(f"Brier score: point {brier(steps['point'], truth):.4f}, judged {brier(steps['probability'], truth):.4f}")
        shares = judged_breakdown(judged, steps["true_speed"], args.band)
        print("judged in band, by the body's true speed: " + ", ".join(f"{k} {v:.3f}" for k, v in shares.items()))
    env.close()


if __name__ == "__main__":
    main()
