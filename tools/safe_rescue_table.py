"""Tabulate trained oracle runs under candidate safe-rescue tasks, beside a scripted bound.

For each run folder given (``attentive-gym train --variant oracle`` with its task's
``--env-kwargs``), the last evaluation row of its ``eval.csv``; and, on the same evaluation
episodes (the run's ``eval_seed`` onwards), two scripted controllers
(``perception.controllers``):

- ``true-bearing``: steers at the target's true bearing at full speed; it reaches the target
  on the straight line and avoids nothing;
- ``clearance``: reads the oracle's observation with ``proximity`` and nothing else, and heads
  for the target through the free heading nearest to it: what that observation allows.

Each row names its setting by the fields that differ from the defaults (``RewardConfig()``,
no proximity)::

    python tools/safe_rescue_table.py runs/safe/*-s4[123] --csv docs/results/safe_rescue.csv

The rows of the runs given replace the CSV's rows of the same (setting, controller, seed, env
steps) and the others are kept, so that runs of one session add to those of another.
``python tools/report.py render`` then writes the table into ``docs/results/rl.md``.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from attentive_gym.agents.config import RunSpec
from attentive_gym.agents.merged import algo_tag
from attentive_gym.agents.results import read_csv, write_csv_atomic
from attentive_gym.agents.training import eval_seed
from attentive_gym.envs import RewardConfig
from attentive_gym.envs.config_mappings import config_as_mapping
from attentive_gym.envs.reward import SAFE_CONTACT_S
from attentive_gym.envs.tasks import task_reward
from attentive_gym.perception.controllers import Policy, clearance_controller, true_bearing_controller
from attentive_gym.wrappers.variants import make_env

#: The repository's root (this file is in ``tools/``).
ROOT = Path(__file__).resolve().parents[1]
DEFAULT_CSV = ROOT / "docs" / "results" / "safe_rescue.csv"
COLUMNS = (
    "setting",
    "controller",
    "seed",
    "env_steps",
    "n_episodes",
    "success_rate",
    "safe_success_rate",
    "mean_contact_s",
    "mean_episode_length",
)


def setting_label(spec: RunSpec) -> str:
    """The fields of the run's task (its ``task_version`` and ``env_kwargs``) that differ from
    task version 0's, e.g. ``contact_limit_s=1, proximity``; ``v0 reward`` when none does.
    ``proximity`` is named where the run's variant has the focus layout and carries it."""
    defaults = config_as_mapping(RewardConfig())
    reward = config_as_mapping(task_reward(spec.task_version, spec.env_kwargs.get("reward")))
    parts = [f"{key}={_text(reward[key])}" for key in defaults if reward[key] != defaults[key]]
    if spec.proximity:
        parts.append("proximity")
    return ", ".join(parts) or "v0 reward"


def controller_label(spec: RunSpec) -> str:
    """``ppo oracle``, with the rollout in brackets when it is not the earlier 4 envs × 256
    steps, the warm start when there is one and the model's version where the variant runs
    it (``merged.algo_tag``): ``ppo oracle (32 envs × 64 steps, batch 512, warm start
    clearance)``."""
    notes = [
        part
        for part in algo_tag(spec.to_dict(), spec.variant).split(", ")[1:]
        if not part.startswith(("lr ", "task v"))  # the task is the row's setting
    ]
    return f"ppo {spec.variant}" + (f" ({', '.join(notes)})" if notes else "")


def _text(value: Any) -> str:
    """A setting's value as the label shows it: numbers in ``g`` format, others as they are."""
    return f"{value:g}" if isinstance(value, (int, float)) else str(value)


def scripted_rows(spec: RunSpec, episodes: int) -> list[dict[str, Any]]:
    """Each scripted controller on ``spec``'s task and evaluation episodes."""
    task = {key: value for key, value in spec.env_kwargs.items() if key != "proximity"}
    raw = make_env("raw", task=spec.task_version, **task)
    oracle = make_env("oracle", proximity=True, task=spec.task_version, **task)
    return [
        scripted_row("true-bearing", true_bearing_controller, raw, spec, episodes),
        scripted_row("clearance", clearance_controller, oracle, spec, episodes),
    ]


def scripted_row(name: str, policy: Policy, env, spec: RunSpec, episodes: int) -> dict[str, Any]:
    """``policy`` on ``env`` over ``spec``'s evaluation episodes, as a row named ``name``."""
    first = eval_seed(spec)
    successes, safe, contacts, lengths = [], [], [], []
    for episode in range(episodes):
        observation, info = env.reset(seed=first + episode)
        steps, ended = 0, False
        while not ended:
            observation, _, terminated, truncated, info = env.step(policy(observation, info))
            steps, ended = steps + 1, terminated or truncated
        successes.append(info["success"])
        safe.append(info["success"] and info["contact_s"] <= SAFE_CONTACT_S)
        contacts.append(info["contact_s"])
        lengths.append(steps)
    return {
        "controller": name,
        "env_steps": 0,
        "n_episodes": episodes,
        "success_rate": float(np.mean(successes)),
        "safe_success_rate": float(np.mean(safe)),
        "mean_contact_s": float(np.mean(contacts)),
        "mean_episode_length": float(np.mean(lengths)),
    }


def rows_of(run: Path) -> list[dict[str, Any]]:
    """The run's last evaluation and the scripted controllers on the same episodes."""
    spec = RunSpec.from_dict(json.loads((run / "spec.json").read_text()))
    last = read_csv(run / "eval.csv")[-1]
    common = {"setting": setting_label(spec), "seed": spec.seed}
    trained = {key: last[key] for key in COLUMNS[3:]} | {"controller": controller_label(spec)}
    return [common | trained, *(common | row for row in scripted_rows(spec, int(last["n_episodes"])))]


def row_key(row: Mapping[str, Any]) -> tuple[str, str, int, int]:
    """What a row measures: its (setting, controller, seed, env steps)."""
    return row["setting"], row["controller"], int(row["seed"]), int(row["env_steps"])


def unique_rows(rows: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """``rows`` without repeats of a ``row_key``: runs of one seed at several budgets share
    their evaluation episodes, so their scripted rows are one."""
    seen: dict[tuple, dict[str, Any]] = {}
    for row in rows:
        seen.setdefault(row_key(row), row)
    return list(seen.values())


def merged_rows(kept: Iterable[Mapping[str, Any]], new: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """The rows ``kept`` (a CSV's) with those of the same ``row_key`` as a row of ``new``
    replaced in place, then the rest of ``new`` in its order."""
    fresh = {row_key(row): row for row in new}
    rows = [fresh.pop(row_key(row), dict(row)) for row in kept]
    return rows + list(fresh.values())


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tools/safe_rescue_table.py", description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, help="finished run folders (each with spec.json and eval.csv)")
    parser.add_argument(
        "--csv", type=Path, default=DEFAULT_CSV, help=f"where to write the rows (default {DEFAULT_CSV})"
    )
    args = parser.parse_args(argv)
    missing = [str(run) for run in args.runs if not (run / "done").is_file()]
    if missing:
        parser.error(f"not finished runs (no 'done' marker): {missing}")
    new = unique_rows(row for run in args.runs for row in rows_of(run))
    rows = merged_rows(read_csv(args.csv) if args.csv.is_file() else [], new)
    write_csv_atomic(args.csv, rows, COLUMNS)
    print(f"wrote {len(new)} rows of {len(args.runs)} runs to {args.csv} ({len(rows)} rows in all)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
