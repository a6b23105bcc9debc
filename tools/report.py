"""Every generated results page, and the README's headline, from the committed CSVs.

Two commands, so that batches of runs trained at different times add up:

- ``python tools/report.py add RUNS/results.csv [--algo TAG] [--obs-scaling none]``: merge
  a comparison's ``results.csv`` (or a sweep's ``sweep.csv``, with ``--clutter``; or a
  comparison's ``results.csv`` as one point of the sweep, with ``--clutter
  --num-distractors N``) into ``docs/results/rl_comparison.csv``
  (``docs/results/rl_clutter.csv``). Rows carry their ``algo`` tag (the comparison's
  ``compare.json`` beside the file tells it) and ``obs_scaling``; a (variant, algo,
  obs_scaling, seed[, num_distractors]) already there is replaced.
- ``python tools/report.py render [--check]``: write ``docs/results/rl.md``,
  ``perception.md``, ``checks.md``, ``performance.md``, ``safe_rescue.md``, ``real_bags.md``,
  ``goal_action.md`` and ``generalisation.md`` from the CSVs beside them, the figures under
  ``docs/figures/``, and the README's block between ``<!-- results-headline:start -->`` and
  ``<!-- results-headline:end -->``. ``--check`` writes nothing and exits 1 naming every
  file that differs from what the CSVs give.

The CSVs come from ``tools/report.py add`` (RL), ``benchmarks/bench_perception.py --csv``
(perception), ``tools/experiments_table.py`` (the experiments' checks), the benchmarks'
``--csv`` option (performance), ``tools/safe_rescue_table.py`` (safe rescue),
``benchmarks/bench_real_bags.py --csv`` (real bags), a goal-action comparison's
``goal_choice.csv`` (learned attention control) and ``attentive-gym generalise``
(generalisation).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import checks_page
import generalisation_page
import goal_action_page
import headline
import perception_page
import performance_page
import real_bags_page
import rl_page
import safe_rescue_page
from attentive_gym.agents.config import ALGOS, OBS_SCALINGS
from attentive_gym.agents.merged import CLUTTER_COLUMNS, COMPARISON_COLUMNS, SCALED, algo_tag, merge_rows, tagged_rate
from attentive_gym.agents.results import read_csv, write_csv_atomic, write_text_atomic
from page_text import README, RESULTS

#: The repository's root (this file is in ``tools/``).
ROOT = Path(__file__).resolve().parents[1]
#: The generated pages: file name in ``docs/results/`` → ``page(root, write_figures)``.
PAGES: dict[str, Callable[[Path, bool], str]] = {
    rl_page.NAME: rl_page.page,
    perception_page.NAME: perception_page.page,
    checks_page.NAME: checks_page.page,
    performance_page.NAME: performance_page.page,
    safe_rescue_page.NAME: safe_rescue_page.page,
    real_bags_page.NAME: real_bags_page.page,
    goal_action_page.NAME: goal_action_page.page,
    generalisation_page.NAME: generalisation_page.page,
}


def generated(root: Path, write_figures: bool = True) -> dict[Path, str]:
    """Every generated file under ``root`` and the text it should hold: the pages and the
    README with its headline block filled; draws the figures unless told not to.

    Raises:
        FileNotFoundError: a CSV or the README is missing.
        ValueError: a CSV lacks what its page needs, or the README has no headline block.
    """
    readme = root / README
    text = readme.read_text(encoding="utf-8")  # before any figure is drawn: a missing README fails first
    headline.replace_block(text, "", readme)
    files = {root / RESULTS / name: page(root, write_figures) for name, page in PAGES.items()}
    files[readme] = headline.replace_block(text, headline.block(root), readme)
    return files


def stale(files: Mapping[Path, str]) -> list[Path]:
    """The files whose text on disk differs from ``files``' (missing ones included)."""
    return [path for path, text in files.items() if not path.is_file() or path.read_text(encoding="utf-8") != text]


def _render(args) -> int:
    files = generated(args.root, write_figures=not args.check)
    if args.check:
        out_of_date = stale(files)
        for path in out_of_date:
            print(f"{path} differs from what the CSVs give", file=sys.stderr)
        if out_of_date:
            print("run 'python tools/report.py render' and commit the result", file=sys.stderr)
        return 1 if out_of_date else 0
    for path in stale(files):
        write_text_atomic(path, files[path])
        print(f"wrote {path}")
    print(f"the figures are in {args.root / 'docs' / 'figures'}")
    return 0


def _trained_with(csv: Path) -> dict[str, Any]:
    """The run settings of the comparison that wrote ``csv`` (its ``compare.json``, or those
    of a sweep's points, which must share their algorithm, learning rate and scaling); {} when
    there is none."""
    if (csv.parent / "compare.json").is_file():
        return json.loads((csv.parent / "compare.json").read_text()).get("run", {})
    points = {
        path.parent.name: json.loads(path.read_text()).get("run", {})
        for path in sorted(csv.parent.glob("distractors-*/compare.json"))
    }
    kinds = {name: (algo_tag(run), run.get("obs_scaling")) for name, run in points.items()}
    if len(set(kinds.values())) > 1:
        raise ValueError(
            f"the points of the sweep beside {csv} were trained with different settings "
            f"({', '.join(f'{name}: {tag!r}, {scaling}' for name, (tag, scaling) in kinds.items())}); "
            "add each point's results.csv with --clutter --num-distractors N"
        )
    return next(iter(points.values()), {})


def _tags(args) -> tuple[str, str, dict[str, Any]]:
    """``(algo tag, obs_scaling, run)`` of ``add``'s rows: the flags, checked against the
    comparison's own settings ``run`` where they are beside the file (``_trained_with``,
    ``algo_tag``); ``ValueError`` for a tag that does not start with a known algorithm or
    contradicts them."""
    run = _trained_with(args.csv)
    trained_tag = algo_tag(run) if run else None
    if trained_tag is None and args.algo is None:
        print(
            f"report add: note: no compare.json beside {args.csv}: its rows are tagged 'ppo' (PPO at a constant "
            "learning rate 3e-4); pass --algo (e.g. 'ppo, lr lin_3e-4') if they were trained otherwise"
        )
    algo = args.algo if args.algo is not None else trained_tag or "ppo"
    name = algo.split(",", 1)[0].strip()
    if name not in ALGOS:
        raise ValueError(
            f"--algo {algo!r} must start with one of {', '.join(ALGOS)} (e.g. 'ppo' or 'ppo, lr lin_3e-4')"
        )
    if trained_tag is not None and tagged_rate(algo) != tagged_rate(trained_tag):
        raise ValueError(
            f"--algo {algo!r} does not name the runs' learning rate: the comparison beside {args.csv} "
            f"trained with the tag {trained_tag!r}; start the tag with it"
        )
    scaling = args.obs_scaling if args.obs_scaling is not None else run.get("obs_scaling", SCALED)
    for flag, given, trained in (("--algo", name, run.get("algo")), ("--obs-scaling", scaling, run.get("obs_scaling"))):
        if trained is not None and given != trained:
            raise ValueError(
                f"{flag} {given!r} contradicts the comparison's settings beside {args.csv} "
                f"({trained!r}); leave the flag out"
            )
    return algo, scaling, run


def _add(args) -> int:
    new = read_csv(args.csv)
    if not new:
        raise ValueError(f"{args.csv} holds no rows")
    algo, scaling, run = _tags(args)
    if args.num_distractors is not None:
        if not args.clutter or args.num_distractors < 0 or "num_distractors" in new[0]:
            raise ValueError(
                f"--num-distractors {args.num_distractors} needs --clutter, a count >= 0 and a "
                f"comparison's results.csv (without a num_distractors column; {args.csv} "
                f"{'has one' if 'num_distractors' in new[0] else 'has none'})"
            )
        new = [{"num_distractors": args.num_distractors, **row} for row in new]
    if not args.clutter and "num_distractors" in new[0]:
        raise ValueError(f"{args.csv} has a num_distractors column: it is a sweep's sweep.csv; add it with --clutter")
    target, columns = (args.clutter_csv, CLUTTER_COLUMNS) if args.clutter else (args.comparison, COMPARISON_COLUMNS)
    rl_page.check_columns(
        args.csv,
        new,
        [c for c in columns if c not in ("algo", "obs_scaling")],
        "a sweep.csv" if args.clutter else "a results.csv",
    )
    keys = ("variant", "seed", *(("num_distractors",) if args.clutter else ()))
    seen: set[tuple[Any, ...]] = set()
    for row in new:
        evaluation = tuple(row[k] for k in (*keys, "env_steps"))
        if evaluation in seen:
            raise ValueError(f"{args.csv} holds the evaluation {dict(zip((*keys, 'env_steps'), evaluation))} twice")
        seen.add(evaluation)
    rows = read_csv(target) if target.is_file() else []
    for variant in dict.fromkeys(row["variant"] for row in new):  # each variant's own warm start (compare.json)
        tag = algo_tag(run, variant) if run and args.algo is None else algo
        rows = merge_rows(rows, [row for row in new if row["variant"] == variant], tag, keys, scaling)
    write_csv_atomic(target, rows, columns)
    print(f"{target}: {len(rows)} rows ({len(new)} from {args.csv})")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tools/report.py", description=__doc__.split("\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    add = commands.add_parser("add", help="merge a comparison's results.csv (or a sweep's sweep.csv) into docs/results")
    add.add_argument("csv", type=Path)
    add.add_argument(
        "--algo",
        metavar="TAG",
        help="the rows' algorithm tag: the algorithm the runs trained with (one of "
        f"{', '.join(ALGOS)}), optionally followed by ', <note>' (e.g. 'ppo, lr lin_3e-4, 1M') "
        "(default: the comparison's compare.json beside the file tells: its algorithm, with "
        "', lr <schedule>' when its learning rate is not SB3's constant, else ppo); a "
        "learning-rate note must be the runs' own",
    )
    add.add_argument(
        "--clutter",
        action="store_true",
        help="the file is a sweep's sweep.csv (or, with --num-distractors, a comparison's results.csv)",
    )
    add.add_argument(
        "--num-distractors",
        type=int,
        metavar="N",
        help="with --clutter: the file is a comparison's results.csv, trained with N distractors; "
        "its runs become the sweep's point N",
    )
    add.add_argument(
        "--obs-scaling",
        choices=OBS_SCALINGS,
        help=f"the runs' --obs-scaling (default: the comparison's compare.json beside the file, else {SCALED})",
    )
    add.add_argument(
        "--comparison",
        type=Path,
        default=ROOT / rl_page.COMPARISON,
        help="the merged comparison (default: docs/results/rl_comparison.csv)",
    )
    add.add_argument(
        "--clutter-csv",
        type=Path,
        default=ROOT / rl_page.CLUTTER,
        help="the merged clutter sweep (default: docs/results/rl_clutter.csv)",
    )
    render = commands.add_parser("render", help="write the results pages, the figures and the README's headline")
    render.add_argument("--check", action="store_true", help="write nothing; exit 1 naming every stale file")
    render.add_argument(
        "--root",
        type=Path,
        default=ROOT,
        help="the repository whose docs/results, docs/figures and README.md to use (default: this one)",
    )
    args = parser.parse_args(argv)
    try:
        return _add(args) if args.command == "add" else _render(args)
    except (ValueError, OSError) as err:
        print(f"report {args.command}: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
