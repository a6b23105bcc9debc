"""The speed benchmarks' ``--csv``: each run replaces its benchmark's rows of the sections it
wrote, in their place, keeps every other row, and records the machine it ran on."""

import csv

from support import load_benchmark

tidy_csv = load_benchmark("tidy_csv")


def _read(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_a_benchmark_replaces_its_own_rows_and_keeps_the_others(tmp_path):
    path = tmp_path / "performance.csv"
    env = tidy_csv.Figures("env")
    env.add("peers", "AttentiveRescue-v0", {"steps_per_s": 12345.678901})
    env.write(path)
    vector = tidy_csv.Figures("vector")
    vector.add("peers", "focus", {"native_us": 100.0, "sync_us": 250.0}, num_envs=16)
    vector.write(path)
    again = tidy_csv.Figures("env")
    again.add("peers", "AttentiveRescue-v0", {"steps_per_s": 2.0})
    again.write(path)
    rows = _read(path)
    assert list(rows[0]) == list(tidy_csv.COLUMNS)
    by_benchmark = {}
    for row in rows:
        by_benchmark.setdefault(row["benchmark"], []).append(
            (row["section"], row["subject"], row["num_envs"], row["metric"], row["value"])
        )
    assert by_benchmark["vector"][-2:] == [
        ("peers", "focus", "16", "native_us", "100"),
        ("peers", "focus", "16", "sync_us", "250"),
    ]
    assert by_benchmark["env"][-1] == ("peers", "AttentiveRescue-v0", "", "steps_per_s", "2")  # the old row is gone
    assert len(by_benchmark["env"]) == 3  # with the machine's cores and numba threads
    machine = {row[3]: int(row[4]) for row in by_benchmark["env"] if row[0] == "run"}
    assert machine.keys() == {"cpus", "numba_threads"} and machine["cpus"] >= 1 and machine["numba_threads"] >= 1


def test_a_run_of_some_sections_keeps_the_benchmarks_other_sections_in_place(tmp_path):
    path = tmp_path / "performance.csv"
    full = tidy_csv.Figures("vector")
    full.add("peers", "focus", {"native_us": 100.0}, num_envs=16)
    full.add("scaling", "focus", {"steps_per_s": 5000.0}, num_envs=64)
    full.write(path)
    wrappers = tidy_csv.Figures("wrappers")
    wrappers.add("variants", "focus", {"step_us": 30.0})
    wrappers.write(path)
    partial = tidy_csv.Figures("vector")
    partial.add("peers", "focus", {"native_us": 90.0}, num_envs=16)
    partial.write(path)
    rows = [(row["benchmark"], row["section"], row["metric"], row["value"]) for row in _read(path)]
    assert [row[:3] for row in rows] == [
        ("vector", "run", "cpus"),
        ("vector", "run", "numba_threads"),
        ("vector", "peers", "native_us"),
        ("vector", "scaling", "steps_per_s"),
        ("wrappers", "run", "cpus"),
        ("wrappers", "run", "numba_threads"),
        ("wrappers", "variants", "step_us"),
    ]
    assert rows[2][3] == "90" and rows[3][3] == "5000"  # the new peers row, the committed scaling row


def test_a_section_new_to_the_file_goes_after_the_benchmarks_rows(tmp_path):
    path = tmp_path / "performance.csv"
    for benchmark, section in (("vector", "peers"), ("wrappers", "variants"), ("vector", "floor")):
        figures = tidy_csv.Figures(benchmark)
        figures.add(section, "focus", {"step_us": 1.0})
        figures.write(path)
    sections = [(row["benchmark"], row["section"]) for row in _read(path) if row["section"] != "run"]
    assert sections == [("vector", "peers"), ("vector", "floor"), ("wrappers", "variants")]
