"""Ego-motion compensation (docs/model.md §3): a robot driving past static walls sees no motion.

The compensation of the sensorial memory (re-projected scans, the sonar models) serves the
window's range rates; the tracker compensates in its odometry-fixed frame (test_tracker.py).
"""

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel

# a 6 m wide corridor closed by a wall 4.5 m ahead of the start (all within sonar range)
ROOM = [(-50.0, 3.0, 50.0, 3.0), (-50.0, -3.0, 50.0, -3.0), (4.5, -3.0, 4.5, 3.0)]
SPEED_MPS = 0.5
DT_S = 0.05
WARM_UP_STEPS = 5


def _drive(scene, ego_motion, steps=60, kinematics="tracker"):
    model = AttentionModel(AttentionConfig(ego_motion=ego_motion, kinematics=kinematics))
    model.set_weights(F1=1.0)  # motion saliency only
    outs = []
    for k in range(steps):
        t = k * DT_S
        sonar, laser = scene.readings((SPEED_MPS * t, 0.0), 0.0, segments=ROOM)
        outs.append(model.step(t, sonar, laser, odometry=(SPEED_MPS, 0.0)))
    return outs[WARM_UP_STEPS:]


@pytest.mark.parametrize("kinematics", ["tracker", "window", "literal"])
def test_driving_past_static_walls_gives_no_motion_saliency(scene, kinematics):
    outs = _drive(scene, "odometry", kinematics=kinematics)
    assert max(o.F[0].max() for o in outs) < 0.02
    assert not any(o.fired for o in outs)
    assert max(o.speeds_mps.max() for o in outs) < 0.05


def test_without_compensation_the_same_drive_is_salient(scene):
    # the window's range rates see the walls' range change; the tracker never tracks walls
    # (structure longer than any mover), so this test is the window's
    outs = _drive(scene, None, kinematics="window")
    assert max(o.F[0].max() for o in outs) > 0.3
    assert any(o.fired for o in outs)
    approaching = outs[-1]
    assert approaching.directions[3] == -1 and approaching.directions[4] == -1  # the end wall comes closer


def test_compensated_laser_sees_a_static_world_and_moving_targets_still_move(scene):
    model = AttentionModel(AttentionConfig(kinematics="window"))
    walls_only = np.ones(180, bool)
    for k in range(40):
        t = k * DT_S
        target = (3.0 - 0.6 * t, 0.2, 0.25)  # a robot coming at 0.6 m/s along the corridor
        sonar, laser = scene.readings((SPEED_MPS * t, 0.0), 0.0, segments=ROOM, circles=[target])
        walls_only &= laser == scene.readings((SPEED_MPS * t, 0.0), 0.0, segments=ROOM)[1]
        model.step(t, sonar, laser, odometry=(SPEED_MPS, 0.0))
    rates = model._memory.range_rates(5)
    # sonar 3 (+10 deg) sees the target closing at 0.6 + 0.5 m/s, minus the robot's own 0.5 m/s
    assert rates[3] == pytest.approx(-0.6, abs=0.05)
    assert walls_only.sum() > 100
    # beams that saw only walls are static, but for a few next to the target's edges, where
    # the re-projected scan interpolates across the occlusion
    assert np.mean(np.abs(rates[8:][walls_only]) < 0.05) > 0.95


def test_point_model_is_exact_for_a_post_on_the_sonar_axis(scene):
    post = [(4.0, 0.0, 0.05)]  # a thin post dead ahead, seen by sonars 3 and 4 (+-10 deg)
    model = AttentionModel(AttentionConfig(sonar_ego_model="point", kinematics="window"))
    for k in range(20):
        t = k * DT_S
        sonar, laser = scene.readings((SPEED_MPS * t, 0.0), 0.0, circles=post)
        model.step(t, sonar, laser, odometry=(SPEED_MPS, 0.0))
    rates = model._memory.range_rates(5)[:8]
    # the post lies 10 deg off both sonars' axes: the point model leaves |0.5 (1 - cos 10 deg)|
    np.testing.assert_allclose(rates[3:5], 0.0, atol=0.5 * (1 - np.cos(np.radians(10))) + 1e-3)
