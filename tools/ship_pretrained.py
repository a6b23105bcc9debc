"""Ship a finished training run as the package's pretrained policy of its variant.

Copies the run's ``final_model.zip``, ``obs_normalization.npz`` and ``spec.json`` into
``attentive_gym/agents/pretrained/<variant>/``, evaluates the shipped copy on ``--episodes``
fixed episodes (seeds from the run's evaluation seed), and writes ``record.json``: how it was
trained, and its success rate with a 95 % bootstrap interval over those episodes, which the
tests hold it to::

    python tools/ship_pretrained.py runs/pretrained/focus-s0 --episodes 40

A run whose files exceed 1 MB, or one not finished, is refused before anything is written.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from attentive_gym.agents.evaluation import evaluate_policy
from attentive_gym.agents.pretrained import PRETRAINED, RECORD_FILE, pretrained_run
from attentive_gym.agents.training import env_factory, eval_seed, load_policy
from attentive_gym.registration import VARIANT_IDS
from attentive_gym.statistics import bootstrap_ci

#: The files of a run that make a shipped policy.
FILES = ("final_model.zip", "obs_normalization.npz", "spec.json")
#: The most a shipped policy may weigh (bytes).
MAX_BYTES = 1_000_000


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tools/ship_pretrained.py", description=__doc__.split("\n")[0])
    parser.add_argument("run", type=Path, help="a finished run folder of 'attentive-gym train'")
    parser.add_argument("--episodes", type=int, default=40, help="evaluation episodes of the record (default 40)")
    args = parser.parse_args(argv)
    if not (args.run / "done").is_file():
        parser.error(f"{args.run} is not a finished run (no 'done' marker)")
    missing = [name for name in FILES if not (args.run / name).is_file()]
    if missing:
        parser.error(f"{args.run} lacks {missing}")
    size = sum((args.run / name).stat().st_size for name in FILES)
    if size > MAX_BYTES:
        parser.error(f"{args.run}'s policy weighs {size:,} bytes, more than {MAX_BYTES:,}")
    spec = json.loads((args.run / "spec.json").read_text())
    if spec["variant"] not in PRETRAINED:
        parser.error(f"variant {spec['variant']!r} has no pretrained slot; allowed: {', '.join(PRETRAINED)}")
    if args.episodes < 2:
        parser.error(f"--episodes must be at least 2 (an interval needs two), got {args.episodes}")
    target = pretrained_run(spec["variant"])
    with tempfile.TemporaryDirectory(dir=target.parent) as staging:  # the old policy stays until the new one is whole
        staged = Path(staging) / "policy"
        staged.mkdir()
        for name in FILES:
            shutil.copy2(args.run / name, staged / name)
        policy, run_spec = load_policy(staged)
        first = eval_seed(run_spec)
        result = evaluate_policy(policy, env_factory(run_spec), args.episodes, first)
        rate, low, high = bootstrap_ci([float(s) for s in result.successes], bounds=(0.0, 1.0))
        record = {
            "env_id": VARIANT_IDS[run_spec.variant],
            "trained": {"seed": run_spec.seed, "total_steps": run_spec.total_steps, "env_kwargs": run_spec.env_kwargs},
            "episodes": args.episodes,
            "first_seed": first,
            "success_rate": rate,
            "success_ci": [low, high],
        }
        (staged / RECORD_FILE).write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
        if target.exists():
            shutil.rmtree(target)
        staged.rename(target)
    print(f"shipped {args.run} as {target}: success {rate:.2f} [{low:.2f}, {high:.2f}] on {args.episodes} episodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
