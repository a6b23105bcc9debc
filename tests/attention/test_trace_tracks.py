"""Traces record the tracker's tracks (flat ``track_*`` arrays) and read them back per step."""

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, TraceRecorder, load_trace
from attentive_gym.attention.io.trace import TRACE_ARRAYS, TRACK_ARRAYS

T = 40
DT = 0.05
#: A body in beams 80..89 approaching by 0.03 m per step; every other beam sees nothing.
BEAMS = slice(80, 90)
START_M, STEP_M = 4.0, 0.03
NO_ECHO_M = 20.0
SONAR_M = 5.0


def _run():
    """Step a tracker model over the synthetic run; returns its outputs and the recorder."""
    cfg = AttentionConfig(kinematics="tracker")
    model, recorder = AttentionModel(cfg), TraceRecorder(cfg)
    sonar = np.full(16, SONAR_M)
    outputs = []
    for k in range(T):
        laser = np.full(180, NO_ECHO_M)
        laser[BEAMS] = START_M - STEP_M * k
        output = model.step(k * DT, sonar, laser)
        recorder.append(output, sonar, laser)
        outputs.append(output)
    return outputs, recorder


@pytest.fixture(scope="module")
def run():
    return _run()


def test_the_run_has_a_confirmed_track_of_the_approaching_body(run):
    outputs, _ = run
    last = outputs[-1].tracks
    assert len(last) == 1 and bool(last.confirmed[0])
    assert all(len(o.tracks) == 1 for o in outputs)  # one body, one track, never lost
    assert last.id[0] == outputs[0].tracks.id[0]
    assert last.velocity_mps[0, 0] < 0.0  # approaching along x


def test_tracks_round_trip_exactly(run, tmp_path):
    outputs, recorder = run
    trace = load_trace(recorder.save(tmp_path / "trace.npz"))
    assert trace.n_track_rows == sum(len(o.tracks) for o in outputs)
    assert trace.track_step.dtype == np.int64 and trace.track_id.dtype == np.int64
    assert trace.track_confirmed.dtype == bool and trace.track_covariance.shape == (trace.n_track_rows, 4, 4)
    for k, output in enumerate(outputs):
        table = trace.tracks_at(k)
        assert table == output.tracks, k  # every field, exactly
        for name in ("position_m", "velocity_mps", "covariance", "age_s", "moving_probability"):
            assert getattr(table, name).dtype == getattr(output.tracks, name).dtype
    assert trace.tracks_at(-1) == outputs[-1].tracks
    in_memory = recorder.to_trace()
    for name, value in trace.arrays().items():
        assert np.array_equal(value, getattr(in_memory, name)), name


def test_tracks_at_refuses_steps_outside_the_trace(run):
    trace = run[1].to_trace()
    with pytest.raises(ValueError, match="step 40"):
        trace.tracks_at(T)
    with pytest.raises(TypeError, match="step"):
        trace.tracks_at(1.0)
    table = trace.tracks_at(np.int64(3))
    assert not table.id.flags.writeable


def test_a_model_without_tracker_records_no_track_rows(tmp_path):
    cfg = AttentionConfig(kinematics="window")
    model, recorder = AttentionModel(cfg), TraceRecorder(cfg)
    laser = np.full(180, 8.0)
    for k in range(3):
        recorder.append(model.step(k * DT, np.full(16, SONAR_M), laser), np.full(16, SONAR_M), laser)
    trace = load_trace(recorder.save(tmp_path / "trace.npz"))
    assert trace.n_track_rows == 0 and len(trace.tracks_at(2)) == 0
    assert trace.track_position_m.shape == (0, 2) and trace.track_covariance.shape == (0, 4, 4)


def test_an_old_trace_without_track_arrays_loads_with_no_tracks(run, tmp_path):
    trace = run[1].to_trace()
    old = tmp_path / "old.npz"
    np.savez(old, **{name: getattr(trace, name) for name in TRACE_ARRAYS}, config_json=np.asarray('{"grid": "sonar"}'))
    loaded = load_trace(old)
    assert loaded.n_steps == T and loaded.n_track_rows == 0
    assert all(len(loaded.tracks_at(k)) == 0 for k in range(T))
    assert np.array_equal(loaded.M, trace.M)


def test_a_trace_with_some_track_arrays_or_bad_rows_is_refused(run, tmp_path):
    trace = run[1].to_trace()
    arrays = trace.arrays()
    partial = tmp_path / "partial.npz"
    np.savez(partial, **{k: v for k, v in arrays.items() if k != "track_covariance"}, config_json=np.asarray("{}"))
    with pytest.raises(ValueError, match="track_covariance"):
        load_trace(partial)
    bad_shape = tmp_path / "shape.npz"
    np.savez(
        bad_shape, **{**arrays, "track_velocity_mps": arrays["track_velocity_mps"][:, :1]}, config_json=np.asarray("{}")
    )
    with pytest.raises(ValueError, match="track_velocity_mps"):
        load_trace(bad_shape)
    unsorted = tmp_path / "unsorted.npz"
    np.savez(unsorted, **{**arrays, "track_step": arrays["track_step"][::-1].copy()}, config_json=np.asarray("{}"))
    with pytest.raises(ValueError, match="track_step"):
        load_trace(unsorted)
    assert set(TRACK_ARRAYS) <= set(arrays)
