"""The speed benchmarks' ``--csv``: each benchmark replaces its own rows of the shared file,
keeps the others', and records the machine it ran on."""

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
