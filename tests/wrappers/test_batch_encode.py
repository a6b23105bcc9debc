"""The attended observations of many steps encoded at once equal those of each step alone, bit for bit."""

import numpy as np
import pytest

from attentive_gym.wrappers import AttentionWrapper, make_env

MEMBERS = 4


def _attention(env):
    """The ``AttentionWrapper`` inside ``env`` (itself or the layer below)."""
    return env if isinstance(env, AttentionWrapper) else env.env


def _assert_same(got, expected, where):
    assert list(got) == list(expected), where
    for key in expected:
        assert got[key].dtype == expected[key].dtype, (where, key)
        np.testing.assert_array_equal(got[key], expected[key], err_msg=f"{where} {key}")


@pytest.mark.parametrize(
    ("variant", "settings"),
    [
        ("focus", {}),
        ("focus", {"memory_slots": 0}),
        ("focus", {"memory_slots": 5, "sensor_noise": 0.05}),
        ("focus", {"scenario": "exp01"}),
        ("focus", {"proximity": True}),
        ("random-focus", {}),
        ("random-focus", {"proximity": True}),
        ("goal-action", {}),
        ("saliency", {}),
        ("masked", {}),
    ],
)
def test_observe_outputs_of_a_fleet_equals_each_member_stepped_alone(variant, settings):
    alone = [make_env(variant, **settings) for _ in range(MEMBERS)]
    together = [make_env(variant, **settings) for _ in range(MEMBERS)]
    wrappers = [_attention(env) for env in together]
    for i, (a, b) in enumerate(zip(alone, together)):
        _assert_same(b.reset(seed=10 + i)[0], a.reset(seed=10 + i)[0], "reset")
    rng = np.random.default_rng(5)
    low, high = alone[0].action_space.low, alone[0].action_space.high
    focused = remembered = 0
    for step in range(150):
        actions = rng.uniform(low, high, (MEMBERS, *low.shape)).astype(np.float32)
        expected = [env.step(action) for env, action in zip(alone, actions)]
        raws, infos, outputs = [], [], []
        for env, wrapper, action in zip(together, wrappers, actions):
            inner = env.action(action) if env is not wrapper else action  # the goal-action hook
            raw, _, _, _, info = wrapper.env.step(inner)
            outputs.append(wrapper.model.step(*wrapper.model_reading(raw, info)[:4]))
            raws.append(raw)
            infos.append(info)
        observations = AttentionWrapper.observe_outputs(wrappers, raws, infos, outputs)
        for i, (observation, info, output, result) in enumerate(zip(observations, infos, outputs, expected)):
            _assert_same(observation, result[0], f"step {step} member {i}")
            assert info["attention"] is output and wrappers[i].last_output is output
            assert output == result[4]["attention"]
            focused += output.focus is not None
            remembered += "memory" in observation and bool(observation["memory"].any())
            if result[2] or result[3]:
                _assert_same(together[i].reset()[0], alone[i].reset()[0], "reset")
    assert focused > 0
    assert remembered > 0 or variant in ("saliency", "masked") or settings.get("memory_slots") == 0


def _steps(count, seed=0):
    """``count`` (raw observation, output) pairs of a focus env, and its encoder."""
    env = make_env("focus", sensor_noise=0.05)
    rng = np.random.default_rng(seed)
    raw, info = env.env.reset(seed=seed)
    pairs = []
    for _ in range(count):
        raw, _, _, _, info = env.env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        pairs.append((raw, env.model.step(*env.model_reading(raw, info)[:4])))
    return env, pairs


def test_encode_many_equals_each_steps_encode_of_its_view():
    env, pairs = _steps(60)
    encoder = env._encoder
    rng = np.random.default_rng(1)
    raws, outputs = zip(*pairs)
    regions = [None if r == encoder.grid.n_regions else int(r) for r in rng.integers(0, encoder.grid.n_regions + 1, 60)]
    events = [tuple(bool(b) for b in rng.integers(0, 2, 3)) for _ in pairs]
    memories = [rng.uniform(-1.0, 12.0, (3, 6)).astype(np.float32) if i % 3 else None for i in range(60)]
    many = encoder.encode_many(raws, outputs, regions, events, memories)
    for i, got in enumerate(many):
        view = None if regions[i] is None else outputs[i].view_of(regions[i])
        _assert_same(got, encoder.encode(raws[i], view, events[i], memories[i]), f"step {i}")
        _assert_same(encoder.encode_region(raws[i], outputs[i], regions[i], events[i], memories[i]), got, f"step {i}")


@pytest.mark.parametrize("variant", ["saliency", "masked"])
def test_encode_many_of_the_map_variants_equals_each_steps_encode(variant):
    env = make_env(variant)
    rng = np.random.default_rng(2)
    raw, info = env.env.reset(seed=2)
    raws, outputs = [], []
    for _ in range(40):
        raw, _, _, _, info = env.env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        raws.append(raw)
        outputs.append(env.model.step(*env.model_reading(raw, info)[:4]))
    for i, got in enumerate(env._encoder.encode_many(raws, outputs)):
        _assert_same(got, env._encoder.encode(raws[i], outputs[i]), f"step {i}")
    assert env._encoder.encode_many([], []) == []


def test_bad_batches_are_refused_with_clear_errors():
    env, pairs = _steps(2)
    encoder = env._encoder
    (raw, output), (raw2, output2) = pairs
    info = {}
    with pytest.raises(ValueError, match="one raw observation, info and output per wrapper"):
        AttentionWrapper.observe_outputs([env], [raw, raw2], [info], [output])
    with pytest.raises(ValueError, match="wrapper 1 is a dict"):
        AttentionWrapper.observe_outputs([env, {}], [raw, raw2], [info, {}], [output, output2])
    with pytest.raises(ValueError, match="each wrapper once"):
        AttentionWrapper.observe_outputs([env, env], [raw, raw2], [info, {}], [output, output2])
    other = make_env("focus", memory_slots=2)
    with pytest.raises(ValueError, match="differs from wrapper 0's"):
        AttentionWrapper.observe_outputs([env, other], [raw, raw2], [info, {}], [output, output2])
    assert AttentionWrapper.observe_outputs([], [], [], []) == []
    with pytest.raises(ValueError, match="one output, region, event and memory"):
        encoder.encode_many([raw], [output, output2], [None], [(False,) * 3], [None])
    for region in (-1, 8, 99):
        with pytest.raises(ValueError, match=r"regions must be indices in \[0, 8\)"):
            encoder.encode_many([raw, raw2], [output, output2], [0, region], [(False,) * 3] * 2, [None] * 2)
    with pytest.raises(ValueError, match="triples"):
        encoder.encode_many([raw], [output], [1], [(True, False)], [None])
    with pytest.raises(ValueError, match=r"memory rows must have shape \(3, 6\)"):
        encoder.encode_many([raw], [output], [1], [(True, False, False)], [np.zeros((2, 6), np.float32)])
    with pytest.raises(ValueError, match="one output per raw observation"):
        make_env("saliency")._encoder.encode_many([raw], [])
