"""Issue 34's motion scenes and measures (attentive_gym.perception.motion)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.perception import motion
from attentive_gym.perception.controllers import stand_still
from attentive_gym.perception.settings import make_attentive_env


@pytest.mark.parametrize("name", sorted(motion.SCENES))
def test_the_scenes_put_a_walker_in_view_that_moves_at_a_goal_speed(name):
    for seed in range(4):
        scenario = motion.SCENES[name](seed)
        env = AttentiveRescueEnv(scenario=scenario, sensor_noise=0.0)
        _, info = env.reset(seed=0)
        target = info["target_index"]
        speeds, distances = [], []
        for _ in range(140):  # 7 s
            _, _, _, _, info = env.step(np.zeros(2, np.float32))
            speeds.append(float(np.linalg.norm(info["mover_velocities"][target])))
            distances.append(float(np.hypot(*(info["mover_positions"][target] - info["robot_pose"][:2]))))
        speeds = np.array(speeds)
        assert 0.5 - 1e-6 <= speeds.max() <= 0.9 + 1e-6
        assert max(distances) < 6.0 and min(distances) > 0.5
        if name == "stop-and-go":  # stands the first 2 s, then walks
            assert speeds[:39].max() < motion.STANDING_MPS
            assert speeds[45:60].min() > motion.MOVING_MPS


def _record(t_s, speed, judged, in_view=None, scan_interval_s=0.05) -> motion.MotionRecord:
    n = len(t_s)
    view = np.ones(n, bool) if in_view is None else np.asarray(in_view)
    false = np.zeros(n, bool)
    return motion.MotionRecord(
        np.asarray(t_s, float),
        np.asarray(speed, float),
        view,
        view,
        np.asarray(judged, bool),
        np.zeros(n, bool),
        np.zeros(n, bool),
        false,
        false,
        scan_interval_s,
    )


def test_onset_latency_counts_from_a_start_after_standing_to_the_first_judgement():
    t = np.arange(60) * 0.05
    speed = np.where((t >= 1.5) & (t < 2.5), 0.6, 0.0)  # stands 1.5 s, walks 1 s, stands
    judged = t >= 1.8 - 1e-9
    latencies = motion.onset_latencies(_record(t, speed, judged))
    assert latencies.tolist() == pytest.approx([0.3])
    never = motion.onset_latencies(_record(t, speed, np.zeros(60, bool)))
    assert never.tolist() == [math.inf]
    short_stand = np.where((t >= 0.5) & (t < 2.5), 0.6, 0.0)  # stood only 0.5 s: not a start
    assert motion.onset_latencies(_record(t, short_stand, judged)).size == 0


def test_metrics_give_latency_percentiles_with_unjudged_starts_as_infinite():
    t = np.arange(140) * 0.05
    walks = ((t >= 1.5) & (t < 2.5)) | ((t >= 3.7) & (t < 4.7)) | ((t >= 5.9) & (t < 6.9))
    speed = np.where(walks, 0.6, 0.0)
    judged = ((t >= 1.6) & (t < 2.5)) | ((t >= 4.1) & (t < 4.7))  # after 0.1 s, 0.4 s, never
    metrics = motion.motion_metrics([_record(t, speed, judged)])
    assert metrics["starts"] == 3
    assert metrics["starts_judged"] == pytest.approx(2 / 3)
    assert metrics["latency_median_s"] == pytest.approx(0.4)
    assert metrics["latency_p90_s"] == math.inf
    assert metrics["latency_median_scans"] == pytest.approx(8.0)  # 0.4 s at a scan every 0.05 s


def test_the_median_latency_in_scans_divides_each_record_by_its_own_scan_interval():
    t = np.arange(60) * 0.05
    speed = np.where((t >= 1.5) & (t < 2.5), 0.6, 0.0)
    judged = t >= 1.9 - 1e-9  # 0.4 s after the start
    fast, slow = _record(t, speed, judged), _record(t, speed, judged, scan_interval_s=0.2)
    assert motion.motion_metrics([slow])["latency_median_scans"] == pytest.approx(2.0)
    assert motion.motion_metrics([fast, slow, slow])["latency_median_scans"] == pytest.approx(2.0)
    assert motion.motion_metrics([fast, fast, slow])["latency_median_scans"] == pytest.approx(8.0)
    # over the records: resampled, three records give medians of 2 (slow ones) or 8 (fast ones)
    mixed = motion.motion_metrics([fast, slow, slow])
    assert (mixed["latency_median_scans_low"], mixed["latency_median_scans_high"]) == pytest.approx((2.0, 8.0))
    one = motion.motion_metrics([slow])
    assert math.isnan(one["latency_median_scans_low"]) and math.isnan(one["latency_median_scans_high"])


def test_a_recorded_episode_holds_the_model_judging_the_walker():
    env = make_attentive_env("tracker", 0.0, sensor_noise=0.0, scenario=motion.along_structure_scene(0))
    record = motion.record_motion(env, 0, stand_still, 6.0)
    assert record.t_s.shape == (120,)
    assert record.scan_interval_s == pytest.approx(0.05)  # scans every step at the default profile
    assert record.target_in_view.mean() > 0.8
    assert record.target_tracked_moving[record.target_speed > motion.MOVING_MPS].mean() > 0.5
    metrics = motion.motion_metrics([record])
    assert 0.0 <= metrics["false_label_steps"] <= 1.0
    with pytest.raises(ValueError, match="seconds"):
        motion.record_motion(env, 0, stand_still, 0.0)
