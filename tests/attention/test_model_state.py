"""The model's state seam: ``AttentionModel.model_state`` and ``bind_state``."""

import copy
import pickle

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, Goal
from attentive_gym.attention.compiled.records import STATE_FIELDS, ModelState


def _run(model, steps, start=0):
    rng = np.random.default_rng(start)
    return [
        model.step(0.05 * k, rng.uniform(0.5, 4.0, 16), rng.uniform(0.5, 8.0, 180), (0.3, 0.1))
        for k in range(start, start + steps)
    ]


def test_the_models_arrays_are_views_of_its_state():
    model = AttentionModel()
    state = model.model_state
    assert set(state.layout.shapes) == set(STATE_FIELDS)
    model.set_goals(Goal.between("speed", 0.2, 0.6))
    np.testing.assert_array_equal(state.field("wanted_speed"), [0.2, 0.6])
    model.set_state("vigilant")
    assert state.field("gain")[0] == 1.5
    _run(model, 5)
    assert model.model_state is state
    assert state.field("memory_state")[1] == 5 and state.field("counts").sum() >= 0
    assert state.field("tracker.alive").dtype == np.bool_


@pytest.mark.parametrize("how", ["deepcopy", "pickle"])
def test_a_copy_moves_to_a_state_of_its_own_and_steps_as_the_original(how):
    model = AttentionModel(AttentionConfig(range_noise_rel=0.05))
    model.set_goals(Goal.smaller("distance", 2.0))
    _run(model, 10)
    clone = copy.deepcopy(model) if how == "deepcopy" else pickle.loads(pickle.dumps(model))
    assert clone.model_state is not model.model_state
    assert not np.shares_memory(clone.model_state.floats, model.model_state.floats)
    for mine, theirs in zip(_run(clone, 20, 10), _run(model, 20, 10)):
        assert mine == theirs


def test_bind_state_moves_the_values_and_refuses_another_layout():
    model, twin = AttentionModel(), AttentionModel()
    _run(model, 8), _run(twin, 8)
    layout = model.model_state.layout
    buffers = layout.allocate(3)
    rows = ModelState(layout, tuple(buffer[1:2] for buffer in buffers))
    model.bind_state(rows)
    assert model.model_state is rows and buffers[0][1].any() and not buffers[0][0].any()
    for mine, theirs in zip(_run(model, 10, 8), _run(twin, 10, 8)):
        assert mine == theirs
    other = AttentionModel(AttentionConfig(kinematics="window")).model_state
    with pytest.raises(ValueError, match="layout"):
        model.bind_state(ModelState(other.layout))


def test_state_buffers_of_the_wrong_shape_are_refused():
    layout = AttentionModel().model_state.layout
    floats, ints, flags = layout.allocate(2)
    with pytest.raises(ValueError, match="C-contiguous"):
        ModelState(layout, (floats, ints[:1], flags[:1]))


@pytest.mark.parametrize("grid", ["sonar", "laser"])
def test_kept_outputs_keep_their_values_over_many_steps(grid):
    """Outputs are views of step records allocated a block at a time: no later step writes
    into an earlier one's."""
    model = AttentionModel(AttentionConfig(grid=grid, range_noise_rel=0.05))
    model.set_goals(Goal.smaller("distance", 3.0))
    outputs, copies = [], []
    for start in range(50):
        outputs += _run(model, 1, start)
        copies.append(copy.deepcopy(outputs[-1]))
    _run(model, 20, 50)
    assert all(out == kept for out, kept in zip(outputs, copies))
    assert not np.shares_memory(outputs[0].F, outputs[1].F)
    assert outputs[-1].F[:, :].any() and outputs[-1].goal_fulfilled.dtype == np.bool_


def test_the_tracker_is_public_and_lives_in_the_state():
    model = AttentionModel()
    _run(model, 6)
    assert model.tracker is not None and model.model_state.holds(model.tracker.cv_P)
    assert model.tracker.hits.max() > 0
    assert AttentionModel(AttentionConfig(kinematics="window")).tracker is None
