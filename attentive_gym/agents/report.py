"""The README's RL results, regenerated from the committed tidy CSVs.

Two steps, so that batches of runs trained in different sessions add up:

- ``python -m attentive_gym.agents.report add RUNS/results.csv [--algo recurrent-ppo]
  [--obs-scaling none]``: merge a comparison's ``results.csv`` (or a sweep's ``sweep.csv``,
  with ``--clutter``; or a comparison's ``results.csv`` as one point of the sweep, with
  ``--clutter --num-distractors N``) into ``docs/results/rl_comparison.csv``
  (``docs/results/rl_clutter.csv``). Rows carry their ``algo`` and ``obs_scaling`` (rows
  written before that column existed read as ``"none"``); a (variant, algo, obs_scaling,
  seed[, num_distractors]) already there is replaced.
- ``python -m attentive_gym.agents.report render``: write the figures under
  ``docs/figures/`` and the README's block between ``<!-- rl-results:start -->`` and
  ``<!-- rl-results:end -->``: the summary table and the targets of attention against the
  bounds and controls at each training budget (``budgets``: runs trained on past a budget
  count there with their curves cut at it, each at its last evaluation at or below the
  budget, which the table's env-steps column shows), and the clutter table. ``--check`` writes nothing and exits 1 when
  the README is not what the CSVs give.

A variant trained with another algorithm than PPO, or without observation normalisation, is
shown as ``"<variant> (<algo>, unscaled)"``; the targets compare each attended variant with
the raw and oracle runs of the same algorithm and scaling. The learning-curve figure
shows the runs with normalised observations (all runs when there are none).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
from pathlib import Path
from typing import Any, Mapping, Sequence

from attentive_gym.agents.config import ALGOS, OBS_SCALINGS, SB3_LEARNING_RATE, RunSpec, canonical_rate
from attentive_gym.agents.plots import (curve_stats, plot_learning_curves, plot_success_vs_distractors, split_label,
                                        steps_label)
from attentive_gym.agents.results import EVAL_COLUMNS, read_csv, summarise, summary_markdown, write_csv_atomic, write_text_atomic
from attentive_gym.agents.sweep import sweep_tables
from attentive_gym.wrappers.variants import VARIANTS

__all__ = ["COMPARISON_COLUMNS", "CLUTTER_COLUMNS", "algo_tag", "merge_rows", "labelled", "budgets", "targets",
           "learning_curve_figures", "render_block", "main"]

COMPARISON_COLUMNS = ("algo", "obs_scaling", *EVAL_COLUMNS)
CLUTTER_COLUMNS = ("algo", "obs_scaling", "num_distractors", *EVAL_COLUMNS)
#: The scaling of the runs whose learning curves the figures show (``RunSpec``'s default).
SCALED = "running"
#: Variants that bound or control attention, and the baselines; the rest are "attended".
BASELINE, ORACLE = "raw", "oracle"
_NOT_ATTENDED = {"raw", "raw-stack", "oracle", "random-focus"}
START, END = "<!-- rl-results:start -->", "<!-- rl-results:end -->"
_DEFAULT = {"comparison": Path("docs/results/rl_comparison.csv"), "clutter": Path("docs/results/rl_clutter.csv"),
            "readme": Path("README.md"), "figures": Path("docs/figures")}


def merge_rows(existing: Sequence[Mapping[str, Any]], new: Sequence[Mapping[str, Any]], algo: str,
               keys: Sequence[str], obs_scaling: str = SCALED) -> list[dict[str, Any]]:
    """``existing`` rows with every run of ``new`` (tagged with ``algo`` and ``obs_scaling``)
    replacing the rows of the same run; a run is identified by ``keys`` (with ``algo`` and
    ``obs_scaling``; an existing row without ``obs_scaling`` has ``"none"``)."""
    tagged = [{"algo": algo, "obs_scaling": obs_scaling, **row} for row in new]
    run = lambda row: tuple(row[k] for k in ("algo", "obs_scaling", *keys))  # noqa: E731
    replaced = {run(row) for row in tagged}
    kept = [{"obs_scaling": "none", **row} for row in existing]
    return [row for row in kept if run(row) not in replaced] + tagged


def labelled(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Rows whose variant names their algorithm when it is not PPO and says "unscaled" when
    the policy saw the observation in its own units (``obs_scaling`` ``"none"``, or absent)."""
    out = []
    for row in rows:
        notes = [row["algo"]] if row["algo"] != "ppo" else []
        notes += ["unscaled"] if row.get("obs_scaling", "none") == "none" else []
        out.append({**row, "variant": f"{row['variant']} ({', '.join(notes)})" if notes else row["variant"]})
    return out


def budgets(rows: Sequence[Mapping[str, Any]], keys: Sequence[str] = ("variant", "seed")
            ) -> list[tuple[int, list[Mapping[str, Any]]]]:
    """``(budget, rows)`` for each distinct final env-step count of the runs in ``rows``
    (a run: the values of ``keys``; a sweep's runs also differ in ``num_distractors``),
    smallest first: the rows of every run trained at least that far, up to that budget."""
    run = lambda row: tuple(row[k] for k in keys)  # noqa: E731
    finals: dict[tuple[Any, ...], int] = {}
    for row in rows:
        finals[run(row)] = max(finals.get(run(row), 0), row["env_steps"])
    return [(budget, [row for row in rows if finals[run(row)] >= budget and row["env_steps"] <= budget])
            for budget in sorted(set(finals.values()))]


def targets(rows: Sequence[Mapping[str, Any]], summary: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """For every attended variant, the figures of the comparison's targets against ``raw``
    and ``oracle`` of the same algorithm and scaling (NaN where they are missing):

    - ``steps_fraction``: the env steps at which its mean curve first reaches raw's final
      mean success, as a fraction of raw's budget (target ≤ 0.5);
    - ``above_raw``: its final-success CI lies wholly above raw's;
    - ``gap_closed``: (its final success − raw's) / (oracle's − raw's) (target ≥ 0.7).
    """
    by_variant = {row["variant"]: row for row in summary}
    out = []
    for row in summary:
        if split_label(row["variant"])[0] in _NOT_ATTENDED:
            continue
        setting = split_label(row["variant"])[1]
        raw, oracle = by_variant.get(BASELINE + setting), by_variant.get(ORACLE + setting)
        steps_fraction = gap = math.nan
        above = False
        if raw is not None:
            steps, mean_curve, _, _ = curve_stats(rows, row["variant"], "success_rate")
            reached = [s for s, m in zip(steps, mean_curve) if m >= raw["final_success_mean"]]
            steps_fraction = reached[0] / raw["final_env_steps"] if reached else math.nan
            above = row["final_success_ci_low"] > raw["final_success_ci_high"]
            if oracle is not None and oracle["final_success_mean"] > raw["final_success_mean"]:
                gap = (row["final_success_mean"] - raw["final_success_mean"]) / (
                    oracle["final_success_mean"] - raw["final_success_mean"])
        out.append({"variant": row["variant"], "steps_fraction": steps_fraction, "above_raw": above, "gap_closed": gap})
    return out


def _targets_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    def number(value, fmt):
        return "—" if math.isnan(value) else f"{value:{fmt}}"

    lines = ["| attended variant | env steps to raw's final success (÷ raw's budget; target ≤ 0.5) "
             "| final success CI above raw's (target: yes) | gap raw → oracle closed (target ≥ 0.7) |",
             "|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['variant']} | {number(row['steps_fraction'], '.2f')} | {'yes' if row['above_raw'] else 'no'} "
                     f"| {number(row['gap_closed'], '.2f')} |")
    return "\n".join(lines) + "\n"


def _count_header(first: str, counts: Sequence[int]) -> list[str]:
    """The two header lines of a table with a ``first`` column and a column per distractor count."""
    return ["| " + " | ".join([first, *(f"{n} distractor{'s' * (n != 1)}" for n in counts)]) + " |",
            "|---|" + "---|" * len(counts)]


def _clutter_markdown(summary: Sequence[Mapping[str, Any]], variants: Sequence[str]) -> str:
    """The clutter table: a row per variant (in the order of ``variants``), a column per count."""
    counts = sorted({row["num_distractors"] for row in summary})
    cell = {(row["variant"], row["num_distractors"]): row for row in summary}
    lines = _count_header("variant", counts)
    for variant in variants:
        values = []
        for n in counts:
            row = cell.get((variant, n))
            if row is None:
                values.append("—")
            elif math.isnan(row["final_success_ci_low"]):
                values.append(f"{row['final_success_mean']:.2f} (n={row['n_seeds']})")
            else:
                values.append(f"{row['final_success_mean']:.2f} [{row['final_success_ci_low']:.2f}, "
                              f"{row['final_success_ci_high']:.2f}] (n={row['n_seeds']})")
        lines.append(f"| {variant} | " + " | ".join(values) + " |")
    return "\n".join(lines) + "\n"


def clutter_targets(summary: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """For every attended variant of a clutter sweep's ``summary`` and every distractor count,
    its margin over ``raw`` of the same algorithm and scaling (final success minus raw's) and
    the gap between raw and ``oracle`` it closes (NaN where raw or the oracle is missing,
    or the oracle is not above raw), in ``summary``'s order."""
    cell = {(row["variant"], row["num_distractors"]): row for row in summary}
    out = []
    for row in summary:
        if split_label(row["variant"])[0] in _NOT_ATTENDED:
            continue
        n, setting = row["num_distractors"], split_label(row["variant"])[1]
        raw, oracle = cell.get((BASELINE + setting, n)), cell.get((ORACLE + setting, n))
        margin = gap = math.nan
        if raw is not None:
            margin = row["final_success_mean"] - raw["final_success_mean"]
            if oracle is not None and oracle["final_success_mean"] > raw["final_success_mean"]:
                gap = margin / (oracle["final_success_mean"] - raw["final_success_mean"])
        out.append({"variant": row["variant"], "num_distractors": n, "margin": margin, "gap_closed": gap})
    return out


def _clutter_targets_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """A row per attended variant, a column per count: "margin over raw (gap closed)"."""
    counts = sorted({row["num_distractors"] for row in rows})
    cell = {(row["variant"], row["num_distractors"]): row for row in rows}
    lines = _count_header("attended variant", counts)
    for variant in dict.fromkeys(row["variant"] for row in rows):
        values = []
        for n in counts:
            row = cell.get((variant, n))
            if row is None or math.isnan(row["margin"]):
                values.append("—")
            else:
                gap = "" if math.isnan(row["gap_closed"]) else f" ({row['gap_closed']:.2f})"
                values.append(f"{row['margin']:+.2f}{gap}")
        lines.append(f"| {variant} | " + " | ".join(values) + " |")
    return "\n".join(lines) + "\n"


def render_block(comparison: Sequence[Mapping[str, Any]], clutter: Sequence[Mapping[str, Any]], figures: Path,
                 sources: Sequence[Path], readme_dir: Path = Path("."), write_figures: bool = True) -> str:
    """The README block (markdown) of the results read from ``sources``, with paths relative
    to ``readme_dir``; writes the figures into ``figures`` unless told not to."""
    link = Path(os.path.relpath(figures, readme_dir))
    rows = labelled(_ordered(comparison))
    # the curves of the runs on normalised observations where there are some, one figure per setting
    figures_of_settings = learning_curve_figures([row for row in rows if row.get("obs_scaling") == SCALED] or rows)
    parts = ["_Generated by `python -m attentive_gym.agents.report render` from "
             + " and ".join(f"`{Path(os.path.relpath(path, readme_dir)).as_posix()}`" for path in sources) + "._", ""]
    for name, setting, _ in figures_of_settings:
        parts += [f"![learning curves, {setting}]({(link / name).as_posix()})", ""]
    for budget, at_budget in budgets(rows):
        summary = summarise(at_budget)
        parts += [f"After {steps_label(budget)} env steps:", "", summary_markdown(summary),
                  "Attention against its bounds and controls:", "", _targets_markdown(targets(at_budget, summary))]
    if write_figures:
        for name, setting, setting_rows in figures_of_settings:
            plot_learning_curves(setting_rows, figures / name,
                                 title=f"{setting}: mean over seeds, shaded: 95 % bootstrap CI")
    if clutter:
        clutter_rows = labelled(_ordered(clutter))
        variants = list(dict.fromkeys(row["variant"] for row in clutter_rows))
        clutter_budgets = budgets(clutter_rows, ("variant", "num_distractors", "seed"))
        for k, (budget, at_budget) in enumerate(clutter_budgets):
            clutter_summary = sweep_tables(at_budget)
            after = f" after {steps_label(budget)} env steps" if len(clutter_budgets) > 1 else ""
            parts += [f"Final success against clutter{after} (mean [95 % bootstrap CI]):", "",
                      _clutter_markdown(clutter_summary, [v for v in variants if any(
                          row["variant"] == v for row in clutter_summary)]),
                      "Final success over raw's at each count, and in brackets the gap raw → oracle it closes "
                      "(where the oracle was run at that count):", "",
                      _clutter_targets_markdown(clutter_targets(clutter_summary))]
            if k == 0:  # the figure: the sweep at the budget every run reached, normalised runs where there are
                parts += [f"![final success against distractors]({(link / 'rl_clutter.png').as_posix()})", ""]
                if write_figures:
                    scaled_variants = {row["variant"] for row in at_budget if row.get("obs_scaling") == SCALED}
                    plot_success_vs_distractors([row for row in clutter_summary if row["variant"] in scaled_variants]
                                                or clutter_summary, figures / "rl_clutter.png",
                                                budget if len(clutter_budgets) > 1 else None)
    return "\n".join(parts).rstrip() + "\n"


def learning_curve_figures(rows: Sequence[Mapping[str, Any]]) -> list[tuple[str, str, list[Mapping[str, Any]]]]:
    """One learning-curve figure per training setting (the rows' ``algo`` tag), so that no
    figure mixes more curves than a reader can tell apart: ``(file name, setting, rows)``,
    today's default setting (``RunSpec``'s) first, in ``rl_learning_curves.png``, the others
    in ``rl_learning_curves_<setting>.png``; the first setting present takes the plain name
    when the default's is absent."""
    default = algo_tag(RunSpec().to_dict())
    settings = sorted(dict.fromkeys(row["algo"] for row in rows), key=lambda tag: tag != default)
    figures = []
    for k, tag in enumerate(settings):
        suffix = "_" + re.sub(r"[^0-9A-Za-z]+", "-", tag).strip("-") if k else ""
        setting = f"{tag} (today's defaults)" if tag == default else tag
        figures.append((f"rl_learning_curves{suffix}.png", setting, [row for row in rows if row["algo"] == tag]))
    return figures


def _ordered(rows: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """``rows`` in the tables' order: the runs on normalised observations first, then PPO's
    before other algorithms', then by variant in ``VARIANTS``' order (raw first, the bound and
    the control last); rows of one variant and setting keep their order."""
    rank = {variant: k for k, variant in enumerate(VARIANTS)}
    return sorted(rows, key=lambda row: (row.get("obs_scaling", "none") != SCALED, row["algo"] != "ppo",
                                         rank.get(row["variant"], len(rank))))


def _replace_block(text: str, block: str, readme: Path) -> str:
    if START not in text or END not in text or text.index(START) > text.index(END):
        raise ValueError(f"{readme} has no '{START}' … '{END}' block to fill (the start marker before the end marker)")
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{START}\n{block}{END}{tail}"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m attentive_gym.agents.report", description=__doc__.split("\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    add = commands.add_parser("add", help="merge a comparison's results.csv (or a sweep's sweep.csv) into docs/results")
    add.add_argument("csv", type=Path)
    add.add_argument("--algo", metavar="TAG",
                     help="the rows' algorithm tag: the algorithm the runs trained with (one of "
                          f"{', '.join(ALGOS)}), optionally followed by ', <note>' (e.g. 'ppo, lr lin_3e-4, 1M') "
                          "(default: the comparison's compare.json beside the file tells: its algorithm, with "
                          "', lr <schedule>' when its learning rate decays, else ppo); a learning-rate note "
                          "must be the runs' own")
    add.add_argument("--clutter", action="store_true", help="the file is a sweep's sweep.csv (or, with "
                     "--num-distractors, a comparison's results.csv)")
    add.add_argument("--num-distractors", type=int, metavar="N",
                     help="with --clutter: the file is a comparison's results.csv, trained with N distractors; "
                          "its runs become the sweep's point N")
    add.add_argument("--obs-scaling", choices=OBS_SCALINGS,
                     help=f"the runs' --obs-scaling (default: the comparison's compare.json beside the file, else "
                          f"{SCALED})")
    render = commands.add_parser("render", help="write the figures and the README's results block")
    render.add_argument("--check", action="store_true", help="write nothing; exit 1 if the README is out of date")
    for sub in (add, render):
        sub.add_argument("--comparison", type=Path, default=_DEFAULT["comparison"])
        sub.add_argument("--clutter-csv", type=Path, default=_DEFAULT["clutter"])
    render.add_argument("--readme", type=Path, default=_DEFAULT["readme"])
    render.add_argument("--figures", type=Path, default=_DEFAULT["figures"])
    args = parser.parse_args(argv)
    try:
        return _add(args) if args.command == "add" else _render(args)
    except (ValueError, OSError) as err:
        print(f"report {args.command}: error: {err}", file=sys.stderr)
        return 2


def _trained_with(csv: Path) -> dict[str, Any]:
    """The run settings of the comparison that wrote ``csv`` (its ``compare.json``, or those
    of a sweep's points, which must share their algorithm, learning rate and scaling); {} when
    there is none."""
    if (csv.parent / "compare.json").is_file():
        return json.loads((csv.parent / "compare.json").read_text()).get("run", {})
    points = {path.parent.name: json.loads(path.read_text()).get("run", {})
              for path in sorted(csv.parent.glob("distractors-*/compare.json"))}
    kinds = {name: (algo_tag(run), run.get("obs_scaling")) for name, run in points.items()}
    if len(set(kinds.values())) > 1:
        raise ValueError(f"the points of the sweep beside {csv} were trained with different settings "
                         f"({', '.join(f'{name}: {tag!r}, {scaling}' for name, (tag, scaling) in kinds.items())}); "
                         "add each point's results.csv with --clutter --num-distractors N")
    return next(iter(points.values()), {})


def algo_tag(run: Mapping[str, Any]) -> str:
    """The tag of the rows of a comparison whose run settings (``compare.json``'s ``"run"``)
    are ``run``: its algorithm, followed by ``", lr <rate>"`` unless its learning rate is
    SB3's constant ``SB3_LEARNING_RATE`` (a schedule, the default since ``algo_defaults`` 2,
    or another number given in ``algo_kwargs``), so that runs at different rates never
    share a tag."""
    spec = RunSpec.from_dict(run)
    if spec.learning_rate() == SB3_LEARNING_RATE:
        return spec.algo
    return f"{spec.algo}, lr {spec.hyper_parameters()['learning_rate']}"


def _tagged_rate(tag: str) -> float | str:
    """The learning rate a tag names (its ``"lr <rate>"`` part, as ``canonical_rate`` writes
    it), ``SB3_LEARNING_RATE`` for none; ``ValueError`` for a rate that is no number or schedule."""
    note = next((part.strip() for part in tag.split(",")[1:] if part.strip().startswith("lr ")), None)
    if note is None:
        return SB3_LEARNING_RATE
    text = note[len("lr "):].strip()
    try:
        return canonical_rate("learning_rate", text if text.startswith("lin_") else float(text))
    except ValueError:
        raise ValueError(f"--algo {tag!r}: {note!r} names no learning rate; write e.g. 'lr lin_3e-4' or "
                         "'lr 1e-4'") from None


def _tags(args) -> tuple[str, str]:
    """``(algo tag, obs_scaling)`` of ``report add``'s rows: the flags, checked against the
    comparison's own settings where they are beside the file (``algo_tag``); ``ValueError``
    for a tag that does not start with a known algorithm or contradicts them."""
    run = _trained_with(args.csv)
    trained_tag = algo_tag(run) if run else None
    if trained_tag is None and args.algo is None:
        print(f"report add: note: no compare.json beside {args.csv}: its rows are tagged 'ppo' (PPO at a constant "
              "learning rate 3e-4); pass --algo (e.g. 'ppo, lr lin_3e-4') if they were trained otherwise")
    algo = args.algo if args.algo is not None else trained_tag or "ppo"
    name = algo.split(",", 1)[0].strip()
    if name not in ALGOS:
        raise ValueError(f"--algo {algo!r} must start with one of {', '.join(ALGOS)} (e.g. 'ppo' or 'ppo, lr lin_3e-4')")
    if trained_tag is not None and _tagged_rate(algo) != _tagged_rate(trained_tag):
        raise ValueError(f"--algo {algo!r} does not name the runs' learning rate: the comparison beside {args.csv} "
                         f"trained with the tag {trained_tag!r}; start the tag with it")
    scaling = args.obs_scaling if args.obs_scaling is not None else run.get("obs_scaling", SCALED)
    for flag, given, trained in (("--algo", name, run.get("algo")), ("--obs-scaling", scaling, run.get("obs_scaling"))):
        if trained is not None and given != trained:
            raise ValueError(f"{flag} {given!r} contradicts the comparison's settings beside {args.csv} "
                             f"({trained!r}); leave the flag out")
    return algo, scaling


def _add(args) -> int:
    new = read_csv(args.csv)
    if not new:
        raise ValueError(f"{args.csv} holds no rows")
    algo, scaling = _tags(args)
    if args.num_distractors is not None:
        if not args.clutter or args.num_distractors < 0 or "num_distractors" in new[0]:
            raise ValueError(f"--num-distractors {args.num_distractors} needs --clutter, a count >= 0 and a "
                             f"comparison's results.csv (without a num_distractors column; {args.csv} "
                             f"{'has one' if 'num_distractors' in new[0] else 'has none'})")
        new = [{"num_distractors": args.num_distractors, **row} for row in new]
    if not args.clutter and "num_distractors" in new[0]:
        raise ValueError(f"{args.csv} has a num_distractors column: it is a sweep's sweep.csv; add it with --clutter")
    target, columns = (args.clutter_csv, CLUTTER_COLUMNS) if args.clutter else (args.comparison, COMPARISON_COLUMNS)
    _check_columns(args.csv, new, columns, "a sweep.csv" if args.clutter else "a results.csv")
    keys = ("variant", "seed", *(("num_distractors",) if args.clutter else ()))
    seen: set[tuple[Any, ...]] = set()
    for row in new:
        evaluation = tuple(row[k] for k in (*keys, "env_steps"))
        if evaluation in seen:
            raise ValueError(f"{args.csv} holds the evaluation {dict(zip((*keys, 'env_steps'), evaluation))} twice")
        seen.add(evaluation)
    rows = merge_rows(read_csv(target) if target.is_file() else [], new, algo, keys, scaling)
    write_csv_atomic(target, rows, columns)
    print(f"{target}: {len(rows)} rows ({len(new)} from {args.csv})")
    return 0


def _check_columns(path: Path, rows: Sequence[Mapping[str, Any]], columns: Sequence[str], what: str,
                   tagged: bool = False) -> None:
    """``ValueError`` naming the ``columns`` the first of ``rows`` (read from ``path``) lacks;
    ``algo`` and ``obs_scaling`` are not required unless ``tagged`` (``report add`` adds them)."""
    required = [c for c in columns if tagged or c not in ("algo", "obs_scaling")]
    missing = [c for c in required if rows and c not in rows[0]]
    if missing:
        raise ValueError(f"{path} lacks the columns {missing} ({what} has them)")


def _render(args) -> int:
    comparison = read_csv(args.comparison)
    clutter = read_csv(args.clutter_csv) if args.clutter_csv.is_file() else []
    if not comparison:
        raise ValueError(f"{args.comparison} holds no rows; add a comparison with 'report add'")
    _check_columns(args.comparison, comparison, ("algo", *EVAL_COLUMNS), "a file written by 'report add'", tagged=True)
    _check_columns(args.clutter_csv, clutter, ("algo", "num_distractors", *EVAL_COLUMNS),
                   "a file written by 'report add --clutter'", tagged=True)
    sources = [args.comparison, *([args.clutter_csv] if clutter else [])]
    text = args.readme.read_text()  # before any figure is written: a missing README fails first
    _replace_block(text, "", args.readme)
    block = render_block(comparison, clutter, args.figures, sources, args.readme.parent, write_figures=not args.check)
    updated = _replace_block(text, block, args.readme)
    if args.check:
        if updated != text:
            print(f"{args.readme}'s results block differs from what {args.comparison} gives; run without --check",
                  file=sys.stderr)
            return 1
        return 0
    write_text_atomic(args.readme, updated)
    print(f"wrote {args.readme} and the figures in {args.figures}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
