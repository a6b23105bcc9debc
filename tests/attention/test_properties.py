"""Property tests: outputs finite and in range for any valid input; no fire below threshold."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from attentive_gym.attention import AttentionConfig, AttentionModel, Goal

ranges = st.floats(0.0, 30.0, allow_nan=False, allow_infinity=False)
goals = st.sampled_from(
    [
        (),
        (Goal.between("speed", 0.5, 0.9),),
        (Goal.greater("speed", 0.2), Goal.direction_is("towards")),
        (Goal.smaller("distance", 2.0), Goal.direction_is("static")),
        (Goal.equal("distance", 4.0),),
    ]
)


@settings(max_examples=40, deadline=None)
@given(
    sonar=arrays(float, (6, 16), elements=ranges),
    laser=arrays(float, (6, 180), elements=ranges),
    steps=arrays(float, (6,), elements=st.floats(0.001, 0.5)),
    odometry=arrays(float, (6, 2), elements=st.floats(-1.5, 1.5)),
    goal_set=goals,
    weights=arrays(float, (6,), elements=st.floats(0.0, 3.0)),
    gain=st.floats(0.1, 3.0),
    grid=st.sampled_from(["sonar", "laser"]),
)
def test_outputs_finite_in_range_and_fire_only_above_threshold(
    sonar, laser, steps, odometry, goal_set, weights, gain, grid
):
    model = AttentionModel(AttentionConfig(grid=grid))
    model.set_goals(*goal_set)
    model.set_weights(weights)
    model.set_state(gain)
    t = 0.0
    for k in range(6):
        t += steps[k]
        out = model.step(t, sonar[k], laser[k], odometry[k])
        for name in ("F", "C", "C_BU", "C_TD", "M", "L"):
            assert np.all(np.isfinite(getattr(out, name))), name
        assert out.F.min() >= 0.0 and out.F.max() <= 1.0 + 1e-12
        assert out.C.min() >= 0.0 and out.C.max() <= 1.0 + 1e-12
        assert out.M.min() >= 0.0 and out.L.min() >= 0.0
        np.testing.assert_allclose(out.L, gain * out.M * out.C)
        assert out.saliency == out.L.max()
        if out.focus is None:
            assert out.L.max() < model.config.threshold and not out.fired and out.origin is None
        else:
            assert out.L[out.focus] >= model.config.threshold and out.focus == int(np.argmax(out.L))
            assert out.origin == ("top-down" if out.C_TD[out.focus] > out.C_BU[out.focus] else "bottom-up")
        inactive = [k for k in range(6) if model.weights[f"F{k + 1}"] == 0.0]
        assert np.all(out.F[inactive] == 0.0)
