"""Is the tracker's judgement calibrated? Reliability tables of three judgements of a speed goal.

For every confirmed track at every step of the perception benchmark's arena (10 m, 3
distractors, 5 % Gaussian noise, the tracker; the robot still, then wandering), three
judgements that the body's speed lies in the fast goal's band [0.5, 0.9] m/s are set against
the truth of the mover the track lies on (within ``TRACK_MATCH_M``; a track on no mover is on
structure: speed 0):

- ``point``: the track's point speed in the band (what F4's table reads today), 0 or 1;
- ``covariance``: P(|v| in band) for v ~ N(the track's velocity, its velocity covariance),
  by Monte Carlo (``DRAWS`` draws, a fixed seed);
- ``mixed``: the track's ``moving_probability`` × ``covariance``: a static body has no speed;
- ``closed``: ``mixed`` with a closed form in place of the Monte Carlo: the speed taken as
  normal along the velocity, mean |v| and variance vᵀΣv / |v|² (the variance projected on the
  velocity's direction; Σ's mean eigenvalue where |v| is near 0), its probability in the band
  from ``math.erf``: what a compiled step could compute.

A judgement is calibrated when, of the track-steps judged in band with probability p, about
p are. The script prints, per robot mode, the reliability table of each probability (bins of
p: count, mean p, the share truly in band), that of ``moving_probability`` against the truth
of moving (> 0.1 m/s), and the Brier score of each judgement (lower is better)::

    python benchmarks/calibration.py --episodes 4 --seconds 20   # about 6 minutes on 2 cores

Seeds 8 onwards (the benchmark's phantom-motion seeds), each episode's goal the fast band.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from attentive_gym.attention import Goal
from attentive_gym.perception.controllers import Wander, stand_still
from attentive_gym.perception.geometry import to_robot_frame
from attentive_gym.perception.records import TRACK_MATCH_M
from attentive_gym.perception.settings import PERCEPTION_ARENA, make_attentive_env

#: The fast goal's band (m/s), the speed a moving body must have to count as moving (m/s).
BAND, MOVING_MPS = (0.5, 0.9), 0.1
#: Monte Carlo draws of a track's velocity; the bins of the reliability tables.
DRAWS, BINS = 400, (0.0, 0.05, 0.2, 0.4, 0.6, 0.8, 0.95, 1.0001)
FIRST_SEED, NOISE = 8, 0.05


def track_steps(robot: str, episodes: int, seconds: float) -> dict[str, np.ndarray]:
    """Per confirmed track and step: ``point``, ``covariance``, ``mixed`` and ``moving``
    (the track's own probabilities), ``in_band`` and ``truly_moving`` (the truth)."""
    env = make_attentive_env("tracker", NOISE, "saliency", sensor_noise=NOISE, **PERCEPTION_ARENA)
    draws = np.random.default_rng(0).standard_normal((DRAWS, 2))
    out: dict[str, list] = {key: [] for key in ("point", "covariance", "closed", "moving", "in_band", "truly_moving")}
    for seed in range(FIRST_SEED, FIRST_SEED + episodes):
        policy = stand_still if robot == "still" else Wander(seed)
        obs, info = env.reset(seed=seed, options={"goal": Goal.between("speed", *BAND)})
        while info["time_s"] < seconds:
            obs, _, terminated, truncated, info = env.step(policy(obs, info))
            tracks = info["attention"].tracks
            movers = to_robot_frame(info["mover_positions"], info["robot_pose"])
            speeds = np.linalg.norm(info["mover_velocities"], axis=1)
            for k in np.flatnonzero(tracks.confirmed) if tracks is not None else ():
                gaps = np.linalg.norm(movers - tracks.position_m[k], axis=1)
                true_speed = speeds[gaps.argmin()] if gaps.size and gaps.min() < TRACK_MATCH_M else 0.0
                spread = tracks.covariance[k][2:, 2:]
                values, vectors = np.linalg.eigh(0.5 * (spread + spread.T))
                samples = tracks.velocity_mps[k] + draws @ (vectors * np.sqrt(np.clip(values, 0.0, None))).T
                drawn = np.linalg.norm(samples, axis=1)
                out["point"].append(float(BAND[0] <= tracks.speed_mps[k] <= BAND[1]))
                out["covariance"].append(float(np.mean((drawn >= BAND[0]) & (drawn <= BAND[1]))))
                out["closed"].append(speed_in_band(tracks.velocity_mps[k], spread))
                out["moving"].append(float(tracks.moving_probability[k]))
                out["in_band"].append(float(BAND[0] <= true_speed <= BAND[1]))
                out["truly_moving"].append(float(true_speed > MOVING_MPS))
            if terminated or truncated:
                break
    env.close()
    steps = {key: np.array(values) for key, values in out.items()}
    steps["mixed"] = steps["moving"] * steps["covariance"]
    steps["closed"] = steps["moving"] * steps["closed"]
    return steps


def speed_in_band(velocity: np.ndarray, spread: np.ndarray) -> float:
    """P(speed in ``BAND``) with the speed normal along ``velocity`` (m/s): mean its norm,
    variance ``spread`` (the 2 × 2 velocity covariance, m²/s²) projected on its direction, or
    the mean of its diagonal where the speed is under 1e-6 m/s."""
    speed = float(np.hypot(*velocity))
    variance = float(velocity @ spread @ velocity) / speed**2 if speed > 1e-6 else 0.5 * float(np.trace(spread))
    sigma = math.sqrt(max(variance, 1e-12))
    cdf = lambda x: 0.5 * (1.0 + math.erf((x - speed) / (sigma * math.sqrt(2.0))))  # noqa: E731
    return cdf(BAND[1]) - cdf(BAND[0])


def reliability(judged: np.ndarray, truth: np.ndarray) -> list[str]:
    """Markdown rows: a bin of the judged probability, its count, its mean, the share true."""
    rows = []
    for low, high in zip(BINS[:-1], BINS[1:]):
        inside = (judged >= low) & (judged < high)
        if inside.any():
            rows.append(
                f"| [{low:.2f}, {min(high, 1.0):.2f}] | {inside.sum()} | {judged[inside].mean():.3f} | "
                f"{truth[inside].mean():.3f} |"
            )
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--episodes", type=int, default=4, help="episodes per robot mode (default 4)")
    parser.add_argument("--seconds", type=float, default=20.0, help="seconds per episode (default 20)")
    args = parser.parse_args(argv)
    if args.episodes < 1 or not args.seconds > 0:
        parser.error(f"--episodes must be >= 1 and --seconds > 0, got {args.episodes} and {args.seconds}")
    header = ["| bin of p | track-steps | mean p | share true |", "|---|---|---|---|"]
    for robot in ("still", "driving"):
        steps = track_steps(robot, args.episodes, args.seconds)
        truth = steps["in_band"]
        print(f"\n## Robot {robot}: {truth.size} track-steps, {truth.mean():.3f} of them truly in band\n")
        for name in ("covariance", "mixed", "closed"):
            print(f"P(speed in band), {name}:\n", *header, *reliability(steps[name], truth), "", sep="\n")
        print(
            "moving_probability against moving:\n",
            *header,
            *reliability(steps["moving"], steps["truly_moving"]),
            sep="\n",
        )
        point = steps["point"] > 0.5
        print(
            f"\npoint judgement: {point.sum()} in band, {truth[point].mean():.3f} of them truly; "
            f"{point[truth > 0.5].mean():.3f} of the truly in band judged so"
        )
        brier = {
            name: float(np.mean((steps[name] - truth) ** 2)) for name in ("point", "covariance", "mixed", "closed")
        }
        print("Brier score: " + ", ".join(f"{name} {value:.4f}" for name, value in brier.items()))


if __name__ == "__main__":
    main()
