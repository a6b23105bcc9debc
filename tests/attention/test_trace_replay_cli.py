"""Trace recording, log replay and the ``attentive-gym attend`` command."""

import json

import numpy as np
import pytest

from attentive_gym.attention import (
    AttentionConfig,
    AttentionModel,
    Goal,
    TraceRecorder,
    load_log,
    load_trace,
    parse_goal,
    parse_maps,
    replay_log,
)
from attentive_gym.attention.io.replay import LogFormatError
from attentive_gym.cli import main

T = 30
DT = 0.05


def _readings(n_sonar=16):
    t = DT * np.arange(T)
    sonar = np.full((T, n_sonar), 4.5)
    sonar[:, 3] = 4.0 - 0.6 * t
    laser = np.full((T, 180), 8.0)
    laser[:, 95:100] = (4.0 - 0.6 * t)[:, None]
    return t, sonar, laser


def _write_csv(path, t, sonar, laser, odometry=None, drop=None):
    names = ["t", *(f"sonar_{i}" for i in range(sonar.shape[1])), *(f"laser_{i}" for i in range(180))]
    table = [t[:, None], sonar, laser]
    if odometry is not None:
        names += ["v", "w"]
        table.append(odometry)
    table = np.concatenate(table, axis=1)
    if drop is not None:
        keep = [k for k, n in enumerate(names) if n != drop]
        names, table = [names[k] for k in keep], table[:, keep]
    lines = [",".join(names)] + [",".join(repr(float(x)) for x in row) for row in table]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_recorder_round_trip(tmp_path):
    cfg = AttentionConfig(ego_motion=None)
    model, recorder = AttentionModel(cfg), TraceRecorder(cfg)
    t, sonar, laser = _readings()
    for k in range(T):
        recorder.append(model.step(t[k], sonar[k], laser[k]), sonar[k], laser[k])
    path = recorder.save(tmp_path / "sub" / "trace.npz")
    trace = load_trace(path)
    assert trace.n_steps == T and trace.n_regions == 8
    assert trace.F.shape == (T, 6, 8) and trace.O1.shape == (T, 8) and trace.O2.shape == (T, 180)
    assert trace.focus.dtype == np.int64 and trace.origin.dtype == np.int8 and trace.fired.dtype == bool
    assert set(np.unique(trace.origin)) <= {-1, 0} and (trace.focus == -1).sum() == (trace.origin == -1).sum()
    assert trace.config == json.loads(cfg.to_json())
    assert list(tmp_path.joinpath("sub").iterdir()) == [path]  # no temporary file left behind
    with np.load(path) as data:
        assert json.loads(str(data["config_json"]))["grid"] == "sonar"


def test_replay_equals_stepping_by_hand(tmp_path):
    t, sonar, laser = _readings(8)
    np.savez(tmp_path / "log.npz", t=t, sonar=sonar, laser=laser)
    model = AttentionModel(AttentionConfig(ego_motion=None))
    trace = replay_log(load_log(tmp_path / "log.npz"), model)
    by_hand = AttentionModel(AttentionConfig(ego_motion=None))
    outs = [by_hand.step(t[k], sonar[k], laser[k]) for k in range(T)]
    np.testing.assert_array_equal(trace.M, np.stack([o.M for o in outs]))
    np.testing.assert_array_equal(trace.focus, [-1 if o.focus is None else o.focus for o in outs])


def test_parse_goal_and_maps():
    assert parse_goal("speed:between:0.5:0.9") == Goal.between("speed", 0.5, 0.9)
    assert parse_goal("direction:towards") == Goal.direction_is("towards")
    assert parse_goal("direction:equal:away") == Goal.direction_is("away")
    assert parse_goal("distance:smaller:2") == Goal.smaller("distance", 2.0)
    assert parse_goal("speed:equal:0.7:0.05") == Goal.equal("speed", 0.7, tolerance=0.05)
    for bad in ("speed", "speed:between:0.5", "speed:around:1", "speed:greater:x", "direction:up"):
        with pytest.raises(ValueError):
            parse_goal(bad)
    assert parse_maps("F1,F3") == {"F1": 1.0, "F3": 1.0}
    assert parse_maps("motion=2, goal_speed=0.5") == {"F1": 2.0, "F4": 0.5}
    for bad in ("F9", "F1,F1", "F1=-1", ""):
        with pytest.raises(ValueError):
            parse_maps(bad)


@pytest.mark.parametrize("kind", ["csv", "npz"])
def test_cli_attend_writes_trace_and_figure(tmp_path, kind, capsys):
    t, sonar, laser = _readings()
    odometry = np.zeros((T, 2))
    if kind == "csv":
        log = _write_csv(tmp_path / "log.csv", t, sonar, laser, odometry)
    else:
        log = tmp_path / "log.npz"
        np.savez(log, t=t, sonar=sonar, laser=laser, odometry=odometry)
    out = tmp_path / "out"
    code = main(
        [
            "attend",
            str(log),
            "--out",
            str(out),
            "--goal",
            "speed:between:0.5:0.9",
            "--maps",
            "F1,F4",
            "--state",
            "vigilant",
            "--config",
            '{"threshold": 0.2}',
        ]
    )
    assert code == 0
    trace = load_trace(out / "trace.npz")
    assert trace.config["threshold"] == 0.2 and trace.n_steps == T
    assert np.all(trace.F[:, [1, 2, 4, 5]] == 0.0) and trace.F[:, 3].max() == 1.0
    assert 1 in trace.origin  # the goal-speed target wins top-down
    assert (out / "trace.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "30 steps" in capsys.readouterr().out


def _bad_logs(tmp_path):
    t, sonar, laser = _readings()
    nan_laser = laser.copy()
    nan_laser[4, 7] = np.nan
    backwards = t.copy()
    backwards[5] = backwards[4]
    tiny_step = t.copy()
    tiny_step[5] = tiny_step[4] + 1e-12
    logs = {
        "missing laser column": (_write_csv(tmp_path / "a.csv", t, sonar, laser, drop="laser_42"), "laser_42"),
        "missing t": (_write_csv(tmp_path / "b.csv", t, sonar, laser, drop="t"), "time column 't'"),
        "odometry half": (_write_csv(tmp_path / "c.csv", t, sonar, laser, np.zeros((T, 2)), drop="w"), "both columns"),
        "nan csv": (_write_csv(tmp_path / "d.csv", t, sonar, nan_laser), "NaN or inf"),
        "time repeats": (_write_csv(tmp_path / "e.csv", backwards, sonar, laser), "strictly increasing"),
        "time step below the model's": (_write_csv(tmp_path / "k.csv", tiny_step, sonar, laser), "by at least 1e-09 s"),
        "wrong sonar width": (tmp_path / "f.npz", "sonar must be"),
        "missing array": (tmp_path / "g.npz", "missing arrays"),
        "text file": (tmp_path / "h.txt", "unknown log format"),
        "not a number": (tmp_path / "i.csv", "is not a number"),
        "one array named .npz": (tmp_path / "j.npz", "holds one array, not an .npz archive"),
    }
    with open(tmp_path / "j.npz", "wb") as single:
        np.save(single, t)
    np.savez(tmp_path / "f.npz", t=t, sonar=sonar[:, :12], laser=laser)
    np.savez(tmp_path / "g.npz", t=t, sonar=sonar)
    (tmp_path / "h.txt").write_text("t,sonar_0\n")
    text = _write_csv(tmp_path / "i.csv", t, sonar, laser).read_text().replace("4.5", "four", 1)
    (tmp_path / "i.csv").write_text(text)
    return logs


def test_bad_logs_raise_log_format_errors_and_the_cli_exits_2(tmp_path, capsys):
    for name, (path, message) in _bad_logs(tmp_path).items():
        with pytest.raises(LogFormatError, match=message):
            load_log(path)
        code = main(["attend", str(path), "--out", str(tmp_path / "out")])
        err = capsys.readouterr().err
        assert code == 2, name
        assert err.startswith("attentive-gym attend: error:") and message.split("'")[0] in err, name
    assert main(["attend", str(tmp_path / "absent.csv"), "--out", str(tmp_path / "o")]) == 2
    assert main(["attend", str(tmp_path / "a.csv"), "--out", str(tmp_path / "o"), "--goal", "speed:fast"]) == 2
    assert main(["attend", str(tmp_path / "a.csv"), "--out", str(tmp_path / "o"), "--config", '{"grid": 3}']) == 2


def test_a_file_that_is_not_a_trace_archive_is_refused(tmp_path):
    with open(tmp_path / "one.npz", "wb") as single:
        np.save(single, np.zeros(3))
    with pytest.raises(ValueError, match="holds one array, not an attention trace"):
        load_trace(tmp_path / "one.npz")


def test_plot_trace_panels(tmp_path):
    from attentive_gym.viz import plot_trace

    cfg = AttentionConfig(ego_motion=None)
    model, recorder = AttentionModel(cfg), TraceRecorder(cfg)
    t, sonar, laser = _readings()
    for k in range(T):
        recorder.append(model.step(t[k], sonar[k], laser[k]), sonar[k], laser[k])
    fig = plot_trace(recorder.to_trace(), panels=("O1", "F1", "M", "WTA"), path=tmp_path / "f.png")
    assert len(fig.axes) == 3 + 3 + 1  # three heat maps with colour bars and the raster
    assert (tmp_path / "f.png").stat().st_size > 0
    with pytest.raises(ValueError, match="unknown or no panels"):
        plot_trace(recorder.to_trace(), panels=("F9",))
