"""``docs/results/performance.md``: speed against peers timed in the same run.

From ``docs/results/performance.csv``, the tidy rows the speed benchmarks write with
``--csv`` (``benchmarks/tidy_csv.py``: benchmark, section, subject, num_envs, metric, value):

- ``Figures(rows)``: look-ups into the rows, ``None`` where a figure was not measured;
- ``env_speeds`` / ``model_costs`` / ``vector_peers``: the figures that both the page and
  the README's headline give, looked up in one place;
- ``single_env_table`` / ``vector_tables`` / ``machine_text``: the page's parts;
- ``headline(root)``: up to three figures for the README (native vector env against the
  sync one, a raw step against BipedalWalker-v3, the model's share of a raw step);
- ``page(root)``: the whole page.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from page_text import RESULTS, banner, number, read_rows, table

NAME = "performance.md"
SOURCE = RESULTS / "performance.csv"
WRITTEN_BY = "the speed benchmarks' --csv option (see the page's last section)"
#: The attended variants, in the order the page lists them.
ATTENDED = ("focus", "saliency", "masked", "goal-action")
_COMMANDS = """\
pip install -e ".[bench]"    # BipedalWalker-v3 (Box2D), VMAS, SB3
python benchmarks/bench_env.py --csv docs/results/performance.csv         # also runs bench_sensors.py
python benchmarks/bench_attention.py --csv docs/results/performance.csv
python benchmarks/bench_wrappers.py --csv docs/results/performance.csv
python benchmarks/bench_training.py --csv docs/results/performance.csv
python benchmarks/bench_vector.py --csv docs/results/performance.csv
python tools/report.py render"""


class Figures:
    """The benchmarks' figures: ``get(benchmark, section, subject, metric, num_envs)``."""

    def __init__(self, rows: Sequence[Mapping[str, str]]):
        self._values = {
            (row["benchmark"], row["section"], row["subject"], row["num_envs"], row["metric"]): float(row["value"])
            for row in rows
        }
        self.rows = rows

    def get(self, benchmark: str, section: str, subject: str, metric: str, num_envs: int | None = None) -> float | None:
        """The figure, or None where it was not measured."""
        return self._values.get((benchmark, section, subject, "" if num_envs is None else str(num_envs), metric))

    def sizes(self, benchmark: str, section: str) -> list[int]:
        """The numbers of envs that ``section`` of ``benchmark`` measured, smallest first."""
        return sorted(
            {
                int(row["num_envs"])
                for row in self.rows
                if row["benchmark"] == benchmark and row["section"] == section and row["num_envs"]
            }
        )


def _ratio(numerator: float | None, denominator: float | None, digits: int = 2) -> str:
    if numerator is None or denominator is None:
        return "—"
    return f"{numerator / denominator:.{digits}f}"


def _us(value: float | None) -> str:
    return "—" if value is None else f"{value:.0f} µs"


def machines(figures: Figures) -> dict[str, tuple[int, int]]:
    """Each benchmark's machine: ``{benchmark: (cores, numba threads)}``."""
    runs: dict[str, dict[str, int]] = {}
    for row in figures.rows:
        if row["section"] == "run":
            runs.setdefault(row["benchmark"], {})[row["metric"]] = int(float(row["value"]))
    return {name: (run["cpus"], run["numba_threads"]) for name, run in sorted(runs.items())}


def _machine(cpus: int, threads: int) -> str:
    return f"a machine with {cpus} cores, numba on {threads} thread{'s' * (threads != 1)}"


def machine_text(figures: Figures) -> str:
    """The machine of the runs: the cores and numba threads most benchmarks had, and the
    benchmarks that had others."""
    by_kind: dict[tuple[int, int], list[str]] = {}
    for name, kind in machines(figures).items():
        by_kind.setdefault(kind, []).append(name)
    common = max(by_kind, key=lambda kind: len(by_kind[kind]))
    others = [
        f"{', '.join(f'`{name}`' for name in names)} on {_machine(*kind)}"
        for kind, names in by_kind.items()
        if kind != common
    ]
    return _machine(*common) + (f" ({'; '.join(others)})" if others else "")


def commands(figures: Figures) -> str:
    """The commands that measure the figures again, with the run's numba threads where all
    benchmarks shared a number below the cores (numba's default is every core)."""
    kinds = set(machines(figures).values())
    lines = _COMMANDS.splitlines()
    if len(kinds) == 1:
        cpus, threads = kinds.pop()
        if threads < cpus:
            lines.insert(1, f"export NUMBA_NUM_THREADS={threads}    # as in the run above")
    return "\n".join(lines)


def env_speeds(f: Figures) -> tuple[float | None, float | None]:
    """Steps per second of a raw ``AttentiveRescue-v0`` step and of BipedalWalker-v3 (same run)."""
    return (
        f.get("env", "peers", "AttentiveRescue-v0", "steps_per_s"),
        f.get("env", "peers", "BipedalWalker-v3", "steps_per_s"),
    )


def model_costs(f: Figures) -> tuple[float | None, float | None, float | None]:
    """µs of the attentional model's step (six maps) with the robot still and moving, and of
    a raw env step (same run)."""
    return (
        f.get("attention", "model", "robot still", "step_us"),
        f.get("attention", "model", "robot moving", "step_us"),
        f.get("attention", "model", "raw AttentiveRescue-v0", "step_us"),
    )


def vector_peers(f: Figures, variant: str) -> tuple[float | None, float | None, float | None]:
    """µs per env-step, with 16 envs running ``variant``, of the native vector env, of
    gymnasium's sync vector env and of BipedalWalker-v3 (one env) (same run)."""
    return (
        f.get("vector", "peers", variant, "native_us", 16),
        f.get("vector", "peers", variant, "sync_us", 16),
        f.get("vector", "peers", variant, "bipedal_walker_us", 16),
    )


def single_env_table(f: Figures) -> str:
    """The single env's figures, each beside its peer of the same run."""
    ours, walker = env_speeds(f)
    analytic, per_ray = (
        f.get("sensors", "sweep", name, "sweep_us") for name in ("analytic kernels", "pymunk per-ray queries")
    )
    rays = f.get("sensors", "sweep", "pymunk per-ray queries", "rays")
    few, many = (f.get("env", "rubble", f"{n} rubble pieces", "step_us") for n in (10, 200))
    few_shapes, many_shapes = (f.get("env", "rubble", f"{n} rubble pieces", "shapes") for n in (10, 200))
    still, moving, env_us = model_costs(f)
    variant_rates = [f.get("wrappers", "variants", name, "steps_per_s") for name in ATTENDED]
    wrapper_walker = f.get("wrappers", "variants", "BipedalWalker-v3", "steps_per_s")
    ppo = next(
        (
            row["subject"]
            for row in f.rows
            if row["benchmark"] == "training" and row["section"] == "ppo" and row["subject"] != "trivial"
        ),
        None,
    )
    clock = next(
        (
            row["metric"].removesuffix("_steps_per_s")
            for row in f.rows
            if row["benchmark"] == "training" and row["metric"].endswith("_steps_per_s")
        ),
        "cpu",
    )
    trained = f.get("training", "ppo", ppo or "", f"{clock}_steps_per_s")
    trivial = f.get("training", "ppo", "trivial", f"{clock}_steps_per_s")
    in_env = f.get("training", "ppo", ppo or "", "env_fraction")
    n_envs = f.get("training", "ppo", ppo or "", "n_envs")
    earlier = f.get("training", "earlier defaults", ppo or "", f"{clock}_steps_per_s")
    earlier_envs = f.get("training", "earlier defaults", ppo or "", "n_envs")
    rows = [
        [
            "raw `AttentiveRescue-v0` step, random actions",
            _us(ours and 1e6 / ours),
            f"BipedalWalker-v3: {_us(walker and 1e6 / walker)}",
            f"{_ratio(ours, walker)}× its speed",
        ],
        [
            "sensor sweep: 180 laser beams and 16 exact sonar cones",
            _us(analytic),
            f"pymunk's per-ray queries ({number(rays, 0)} rays): {_us(per_ray)}",
            f"{_ratio(per_ray, analytic, 1)}× its speed",
        ],
        [
            "step cost, 10 → 200 rubble pieces",
            f"{_us(few)} → {_us(many)}",
            f"shapes: {number(few_shapes, 0)} → {number(many_shapes, 0)} ({_ratio(many_shapes, few_shapes, 1)}×)",
            f"{_ratio(many, few, 1)}× the cost",
        ],
        [
            "attentional model step, six maps, robot still / moving",
            f"{_us(still)} / {_us(moving)}",
            f"raw env step: {_us(env_us)}",
            f"{_ratio(still, env_us)} / {_ratio(moving, env_us)} of a step",
        ],
        [
            f"attended env step: {' / '.join(ATTENDED)}",
            " / ".join(_us(rate and 1e6 / rate) for rate in variant_rates),
            f"BipedalWalker-v3: {_us(wrapper_walker and 1e6 / wrapper_walker)}",
            " / ".join(_ratio(rate, wrapper_walker) for rate in variant_rates) + "× its speed",
        ],
        [
            f"PPO training on `{ppo}`, {_envs(n_envs)}, one torch thread ({clock} time)",
            f"{number(trained, 0)} env-steps/s",
            f"PPO on a trivial env with the same spaces: {number(trivial, 0)}",
            f"{_ratio(trained, trivial)}× its speed; {number(in_env and 100 * in_env, 0)} % of the time in the env",
        ],
    ]
    if earlier is not None:
        rows.append(
            [
                f"PPO training on `{ppo}`, today's defaults against the earlier ones ({_envs(earlier_envs)}, "
                "256-step rollouts, minibatch 256)",
                f"{number(trained, 0)} env-steps/s",
                f"the earlier defaults: {number(earlier, 0)}",
                f"{_ratio(trained, earlier)}× their speed",
            ]
        )
    return table(["what", "measured", "peer, same run", "ratio"], rows)


def _envs(n: float | None) -> str:
    """``"32 envs"``; ``"4 envs"`` for a CSV written before the count was recorded (the defaults then)."""
    return f"{int(n) if n is not None else 4} envs"


def split_text(f: Figures) -> str:
    """One ``focus`` step split into its parts."""
    parts = [f.get("wrappers", "split", "focus", metric) for metric in ("base_env_us", "model_us", "encoding_us")]
    if None in parts:
        return ""
    return (
        f"One `focus` step, split: the base env {parts[0]:.0f} µs, the attentional model {parts[1]:.0f} µs, "
        f"the encoding and working memory {parts[2]:.0f} µs.\n"
    )


def vector_tables(f: Figures) -> list[str]:
    """The native vector env against the sync vector env, BipedalWalker-v3 and VMAS; its
    scaling; and its floor."""
    out = []

    def vector(section: str, subject: str, metric: str, n: int) -> float | None:
        return f.get("vector", section, subject, metric, n)

    peers = []
    for variant in ("focus", "raw"):
        native, sync, walker = vector_peers(f, variant)
        if native is not None:
            peers.append(
                [
                    f"`{variant}`",
                    _us(native),
                    _us(sync),
                    _us(walker),
                    f"{_ratio(sync, native)}×",
                    f"{_ratio(walker, native)}×",
                ]
            )
    if peers:
        out += [
            "Random actions with autoreset, N = 16, µs per env-step (medians of alternating rounds):",
            "",
            table(
                [
                    "variant",
                    "native",
                    "sync vector env",
                    "BipedalWalker-v3 (one env)",
                    "native ÷ sync speed",
                    "native ÷ BipedalWalker-v3 speed",
                ],
                peers,
            ),
        ]
    vmas = [
        [
            str(n),
            *(_us(vector("vmas", "env-step", m, n)) for m in ("vmas_us", "focus_us", "raw_us")),
            *(
                f"{_ratio(vector('vmas', 'env-step', 'vmas_us', n), vector('vmas', 'env-step', m, n))}×"
                for m in ("focus_us", "raw_us")
            ),
        ]
        for n in f.sizes("vector", "vmas")
    ]
    if vmas:
        out += [
            "Against VMAS (`flocking`, one agent, a 196-ray lidar, CPU, one torch thread), µs per env-step:",
            "",
            table(["N", "VMAS", "native `focus`", "native `raw`", "`focus` ÷ VMAS speed", "`raw` ÷ VMAS speed"], vmas),
        ]
    scaling = [
        [
            str(n),
            _us(f.get("vector", "scaling", "focus", "env_step_us", n)),
            number(f.get("vector", "scaling", "focus", "memory_per_env_mib", n)),
        ]
        for n in f.sizes("vector", "scaling")
    ]
    if scaling:
        out += [
            "The native `focus` env by the number of envs (resident memory per env in a fresh process):",
            "",
            table(["N", "per env-step", "MiB per env"], scaling),
        ]
    floor = {
        m: f.get("vector", "floor", "focus", m, 16)
        for m in (
            "sensor_sweep_us",
            "models_us",
            "pymunk_us",
            "floor_us",
            "whole_step_us",
            "bipedal_walker_us",
            "sync_us",
        )
    }
    if None not in floor.values():
        out += [
            "**The floor** of the native `focus` env at N = 16: the work no design of the step around today's "
            "kernels can skip (the compiled sensor sweep and attentional models, timed inside the running env, "
            "and the fewest pymunk calls a step of each world makes), beside the budgets that 3× "
            "BipedalWalker-v3's speed and 4× the sync vector env's leave (µs per env-step):",
            "",
            table(
                [
                    "sensor sweep",
                    "models",
                    "pymunk calls",
                    "floor",
                    "whole step",
                    "3× BipedalWalker-v3 budget",
                    "4× sync budget",
                ],
                [
                    [
                        number(floor[m], 1)
                        for m in ("sensor_sweep_us", "models_us", "pymunk_us", "floor_us", "whole_step_us")
                    ]
                    + [number(floor["bipedal_walker_us"] / 3, 1), number(floor["sync_us"] / 4, 1)]
                ],
            ),
        ]
    return out


def headline(root: Path) -> list[str]:
    """Up to three one-line figures for the README, each a ratio measured in one run."""
    f = Figures(read_rows(root, SOURCE.name, WRITTEN_BY))
    lines = []
    native, sync, _ = vector_peers(f, "focus")
    if native is not None and sync is not None:
        lines.append(
            f"the native vector env (`focus`, 16 envs): {_ratio(sync, native)}× the env-steps per second of "
            "gymnasium's sync vector env;"
        )
    ours, walker = env_speeds(f)
    if ours is not None and walker is not None:
        lines.append(f"a raw `AttentiveRescue-v0` step: {_ratio(ours, walker)}× BipedalWalker-v3's steps per second;")
    still, moving, env_us = model_costs(f)
    if None not in (still, moving, env_us):
        lines.append(
            f"the attentional model's step (six maps): {_ratio(still, env_us)} / {_ratio(moving, env_us)} of a raw "
            "env step (robot still / moving)."
        )
    return lines


def page(root: Path, write_figures: bool = True) -> str:
    """The text of ``docs/results/performance.md`` under ``root`` (it has no figures)."""
    f = Figures(read_rows(root, SOURCE.name, WRITTEN_BY))
    return "\n".join(
        [
            "# Performance",
            "",
            banner([SOURCE]),
            f"Each benchmark ran once, on {machine_text(f)}, and timed its peers in the same run, in alternating "
            "rounds. Speeds drift within a run on any machine: read the ratios of the same run, not the absolute "
            "times.",
            "",
            "## A single environment",
            "",
            single_env_table(f),
            split_text(f),
            "## The native vector env",
            "",
            *vector_tables(f),
            "## Reproduce",
            "",
            "```bash",
            commands(f),
            "```",
            "",
        ]
    )
