"""Learning-curve figure: mean across seeds with a t-based 95 % confidence band, per variant."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from attentive_gym.agents.results import mean_ci

__all__ = ["curve_stats", "plot_learning_curves"]


def curve_stats(rows: Sequence[Mapping[str, Any]], variant: str, metric: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(env_steps, mean, ci_low, ci_high) of ``metric`` across seeds at each eval point of ``variant``.

    Only eval points every seed of the variant reached are kept (so a band always spans
    the same seeds).
    """
    by_steps: dict[int, list[float]] = {}
    seeds = {r["seed"] for r in rows if r["variant"] == variant}
    for row in rows:
        if row["variant"] == variant:
            by_steps.setdefault(int(row["env_steps"]), []).append(float(row[metric]))
    steps = sorted(s for s, v in by_steps.items() if len(v) == len(seeds))
    stats = np.array([mean_ci(by_steps[s]) for s in steps]).reshape(-1, 3)
    return np.array(steps), stats[:, 0], stats[:, 1], stats[:, 2]


def plot_learning_curves(
    rows: Sequence[Mapping[str, Any]],
    path: str | os.PathLike,
    metrics: Sequence[str] = ("success_rate", "mean_return"),
    title: str | None = None,
) -> Path:
    """Write a PNG with one panel per metric: per-variant mean curve and 95 % CI band vs env steps."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    variants = list(dict.fromkeys(r["variant"] for r in rows))
    if not variants:
        raise ValueError("no evaluation rows to plot")
    labels = {"success_rate": "success rate", "mean_return": "mean return",
              "mean_collision_steps": "collision steps / episode", "mean_episode_length": "episode length (steps)"}
    fig, axes = plt.subplots(1, len(metrics), figsize=(5.2 * len(metrics), 3.8), squeeze=False)
    for ax, metric in zip(axes[0], metrics):
        for variant in variants:
            steps, mean, low, high = curve_stats(rows, variant, metric)
            n = len({r["seed"] for r in rows if r["variant"] == variant})
            (line,) = ax.plot(steps, mean, marker=".", label=f"{variant} (n={n})")
            ax.fill_between(steps, low, high, color=line.get_color(), alpha=0.2, linewidth=0)
        ax.set_xlabel("environment steps")
        ax.set_ylabel(labels.get(metric, metric))
        ax.grid(alpha=0.3)
    axes[0][0].legend(loc="best", fontsize=8)
    fig.suptitle(title or "mean over seeds, shaded: 95 % CI (t)", fontsize=10)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.tmp.png")
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    os.replace(tmp, path)
    return path
