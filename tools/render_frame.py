"""Render the README's picture: one frame of the ``focus`` variant with the attention overlay.

The robot stands still in a procedural arena while the attentional model runs; the frame
is taken at the first step, from ``--min-time-s`` on, whose focus is top-down (a body that
meets the episode's goal) and holds the task's target (outlined in yellow), so the picture
shows the model attending the mover it should. The overlay shades each region by its
saliency and outlines the focus (see ``attentive_gym.wrappers.overlay``).

Run from the repository root (needs the ``render`` extra, pygame)::

    SDL_VIDEODRIVER=dummy python tools/render_frame.py            # writes docs/figures/frame.png
    python tools/render_frame.py --seed 3 --out /tmp/frame.png
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from attentive_gym.attention import ORIGIN_TOP_DOWN
from attentive_gym.attention.regions import laser_bearings_rad
from attentive_gym.perception.geometry import true_target_bearing
from attentive_gym.wrappers import make_env

#: Where the README expects its picture.
DEFAULT_OUT = Path("docs/figures/frame.png")
#: The arena of the picture: the RL comparison's (8 m, 2 distractors, 3 rubble pieces per 100 m²).
ARENA = {"arena_size_m": 8.0, "num_distractors": 2, "rubble_per_100m2": 3.0}
#: The robot's command while the frame is sought: stand still, so only the movers move.
STILL = np.zeros(2, dtype=np.float32)
#: Half the angular width of one of the laser's 180 beams over its 180° (rad).
HALF_BEAM_RAD = np.pi / 360


def render_frame(seed: int = 0, min_time_s: float = 2.0, max_steps: int = 800) -> tuple[np.ndarray, float]:
    """The ``(H, W, 3)`` uint8 frame of the first step at or after ``min_time_s`` (s of
    simulated time) whose focus is top-down and holds the target, and that step's time (s).

    Raises:
        ValueError: ``min_time_s`` is negative or ``max_steps`` is not a positive integer.
        RuntimeError: no such step within ``max_steps`` steps (or before the episode ended);
            the message suggests another seed.
    """
    if min_time_s < 0:
        raise ValueError(f"min_time_s must be >= 0 s, got {min_time_s}")
    if not isinstance(max_steps, int) or max_steps < 1:
        raise ValueError(f"max_steps must be a positive integer, got {max_steps!r}")
    env = make_env("focus", render_mode="rgb_array", **ARENA)
    try:
        env.reset(seed=seed)
        grid = env.get_wrapper_attr("model").grid
        for _ in range(max_steps):
            _, _, terminated, truncated, info = env.step(STILL)
            output = info["attention"]
            if (
                info["time_s"] >= min_time_s
                and output.origin == ORIGIN_TOP_DOWN
                and target_in_region(info, grid.beam_slices[output.focus])
            ):
                return env.render(), float(info["time_s"])
            if terminated or truncated:
                break
        raise RuntimeError(
            f"seed {seed}: no top-down focus on the target from {min_time_s} s within {max_steps} steps; "
            "try another --seed"
        )
    finally:
        env.close()


def target_in_region(info: dict, beams: slice) -> bool:
    """Whether the task's target lies within the laser beams ``beams`` of a region (each
    beam ``HALF_BEAM_RAD`` wide on either side of its bearing), by its centre's bearing
    from the robot (``info`` of an env step)."""
    bearing = true_target_bearing(info)  # rad, robot frame
    bearings = laser_bearings_rad()
    return bool(bearings[beams.start] - HALF_BEAM_RAD <= bearing <= bearings[beams.stop - 1] + HALF_BEAM_RAD)


def save_png(frame: np.ndarray, path: Path) -> None:
    """Write an ``(H, W, 3)`` uint8 RGB ``frame`` to ``path`` as a PNG, creating its folder."""
    import pygame

    path.parent.mkdir(parents=True, exist_ok=True)
    pygame.image.save(pygame.surfarray.make_surface(np.ascontiguousarray(frame.swapaxes(0, 1))), str(path))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0, help="the arena's seed (default 0)")
    parser.add_argument(
        "--min-time-s", type=float, default=2.0, help="take no frame before this simulated time, s (default 2)"
    )
    parser.add_argument("--max-steps", type=int, default=800, help="steps to search (default 800)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"PNG to write (default {DEFAULT_OUT})")
    args = parser.parse_args(argv)
    try:
        frame, time_s = render_frame(args.seed, args.min_time_s, args.max_steps)
    except (ValueError, RuntimeError) as error:
        parser.exit(2, f"render_frame: {error}\n")
    save_png(frame, args.out)
    print(f"{args.out}: seed {args.seed}, t = {time_s:.2f} s, {frame.shape[1]}x{frame.shape[0]} px")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
