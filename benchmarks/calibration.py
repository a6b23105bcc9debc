"""Is the tracker's judgement of a speed goal calibrated? Reliability tables against the truth.

For every confirmed track at every step of the perception benchmark's arena (10 m, 3
distractors, 5 % Gaussian noise, the tracker; the robot still, then wandering), the model's
judgement that the body's speed lies in the fast goal's band [0.5, 0.9] m/s
(``track_regions.speed_goal_probability``: the track's probability of moving × P(speed in
the band), the speed normal along the velocity estimate with its covariance; what
``AttentionConfig.track_speed_goal_probability`` judges the goal by) is set against the truth
of the mover the track lies on (``perception.calibration.judged_track_steps``).

A judgement is calibrated when, of the track-steps judged in band with probability p, about
p are. The script prints, per robot mode, the reliability table of the judgement (bins of p:
count, mean p, the share truly in band), that of ``moving_probability`` against the truth of
moving (> 0.1 m/s), and the Brier scores of the judgement and of the point rule it can
replace (the track's speed weighted by its probability of moving, inside the band; 0 or 1)::

    python benchmarks/calibration.py --episodes 4 --seconds 20   # a few seconds

Seeds 8 onwards (the perception benchmark's phantom-motion seeds).
"""

from __future__ import annotations

import argparse

from attentive_gym.perception.calibration import brier, judged_track_steps, reliability
from attentive_gym.perception.controllers import Wander, stand_still
from attentive_gym.perception.settings import PERCEPTION_ARENA, make_attentive_env

#: The fast goal's band (m/s), the first seed and the range noise (relative σ).
BAND, FIRST_SEED, NOISE = (0.5, 0.9), 8, 0.05


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
    args = parser.parse_args(argv)
    if args.episodes < 1 or not args.seconds > 0:
        parser.error(f"--episodes must be >= 1 and --seconds > 0, got {args.episodes} and {args.seconds}")
    env = make_attentive_env("tracker", NOISE, "saliency", sensor_noise=NOISE, **PERCEPTION_ARENA)
    seeds = range(FIRST_SEED, FIRST_SEED + args.episodes)
    for robot, policy_of in (("still", lambda seed: stand_still), ("driving", Wander)):
        steps = judged_track_steps(env, BAND, seeds, args.seconds, policy_of)
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
    env.close()


if __name__ == "__main__":
    main()
