"""The attended observations hold what they document, and only that."""

import dataclasses

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig
from attentive_gym.attention.config import MAP_NAMES
from attentive_gym.wrappers import AttentionWrapper, make_env
from attentive_gym.wrappers.encoders import LASER_BINS, FocusEncoder, map_ceilings


def test_focus_observation_is_small_and_describes_the_focused_region(exp01_focus_env, run_until_focus):
    env = exp01_focus_env
    assert sum(int(np.prod(s.shape)) for s in env.observation_space.spaces.values()) <= 64
    obs, info = run_until_focus(env)
    out = info["attention"]
    view = out.view
    j = out.focus
    assert j == 3  # exp01: the robot in sonar s4's cone
    assert obs["region"].argmax() == j and obs["region"].sum() == 1
    assert obs["event"][0] == out.fired and obs["event"][1] == (out.origin == "bottom-up")
    assert obs["sonar"][0] == pytest.approx(view.sonar_range_m, rel=1e-6) and obs["sonar"][1] == 1.0
    bins = np.array_split(view.laser_ranges_m, LASER_BINS)
    np.testing.assert_allclose(obs["laser"], [b.min() for b in bins], rtol=1e-6)
    np.testing.assert_allclose(obs["features"], out.F[:, j], rtol=1e-6)
    assert obs["motion"][1:].sum() == 1.0
    assert obs["distance"][0] == pytest.approx(view.distance_m, rel=1e-6)
    assert env.observation_space.contains(obs)


def test_focus_observation_carries_nothing_from_outside_the_focus(exp01_focus_env, run_until_focus):
    env = exp01_focus_env
    obs, info = run_until_focus(env)
    out = info["attention"]
    j = out.focus
    encoder = env._encoder
    raw = {"odometry": obs["odometry"], "goal": obs["goal"]}
    others = np.arange(out.F.shape[1]) != j
    grid, readings, valid, rates, nearest, *tracker_sources = out._sources
    readings, rates, nearest = readings.copy(), rates.copy(), nearest.copy()
    outside = np.ones(readings.shape, bool)
    outside[int(grid.region_sonar[j])] = False
    outside[8:188][grid.beam_indices[j]] = False
    readings[outside] = 0.42
    rates[outside] = -0.3
    nearest[others] = 0.1
    F, L, M = out.F.copy(), out.L.copy(), out.M.copy()
    F[:, others], L[others], M[others] = 0.77, 0.0, 2.0
    perturbed = dataclasses.replace(
        out, F=F, L=L, M=M, _sources=(grid, readings, valid, rates, nearest, *tracker_sources)
    )
    event = (out.fired, out.origin == "bottom-up", out.origin == "top-down")
    again = encoder.encode(raw, perturbed.view, event, obs["memory"].reshape(-1, 6))
    for key in obs:
        np.testing.assert_array_equal(again[key], obs[key], err_msg=key)


def test_focus_observation_without_focus_is_the_none_slot_only():
    env = make_env("focus", scenario="exp01", sensor_noise=0.0, weights={"motion": 1.0}, proximity=False)
    obs, info = env.reset(seed=0)
    assert info["attention"].focus is None  # nothing moves in the first reading
    assert obs["region"][-1] == 1.0 and obs["region"][:-1].sum() == 0.0
    for key in ("event", "sonar", "laser", "motion", "distance", "features", "memory"):
        assert not obs[key].any(), key


def test_focus_mode_refuses_the_laser_grid():
    env = make_env("raw", scenario="exp01")
    with pytest.raises(ValueError, match="grid='sonar'"):
        AttentionWrapper(env, "focus", config=AttentionConfig(grid="laser"))


def test_saliency_observation_holds_the_maps(run_until_focus):
    env = make_env("saliency", scenario="exp01", sensor_noise=0.0)
    env.reset(seed=0)
    obs, info = run_until_focus(env)
    np.testing.assert_allclose(obs["L"], info["attention"].L, rtol=1e-6)
    np.testing.assert_allclose(obs["M"], info["attention"].M, rtol=1e-6)
    assert env.observation_space.contains(obs)


def test_map_ceilings_bound_the_attentional_map():
    config = AttentionConfig()
    m_high, l_high = map_ceilings(config, gain=1.5)
    # one bottom-up and two top-down courses, spread over the neighbours (e^-2 each)
    assert m_high == pytest.approx(
        1.0 + 3.0 * (1.0 + 2 * np.exp(-2.0) + 2 * np.exp(-8.0) + 2 * np.exp(-18.0)), rel=1e-9
    )
    assert l_high == pytest.approx(1.5 * m_high)


@pytest.mark.parametrize(
    ("weights", "balance", "c_high"),
    [
        ((1, 1, 1, 1, 1, 1), True, 6.0),  # the top-down group scaled to the bottom-up total 3
        ((1, 1, 1, 1, 0, 0), True, 6.0),  # F4 alone weighs 3 while its goal is set
        ((1, 1, 1, 1, 0, 0), False, 4.0),
        ((0, 0, 0, 2, 1, 0), True, 3.0),  # no bottom-up map: nothing to balance
        ((2, 0, 0, 0, 0, 0), True, 2.0),
    ],
)
def test_unnormalised_ceiling_follows_the_balanced_weights(weights, balance, c_high):
    config = AttentionConfig(normalise_combined=False, balance_groups=balance, weights=weights)
    m_high, l_high = map_ceilings(config, gain=1.0)
    assert l_high == pytest.approx(m_high * c_high)


def test_the_ceiling_follows_the_weights_given_to_the_wrapper():
    config = AttentionConfig(normalise_combined=False, balance_groups=False)
    plain = make_env("saliency", attention=config)
    heavy = make_env("saliency", attention=config, weights=dict.fromkeys(MAP_NAMES, 10.0))
    assert heavy.observation_space["L"].high.max() == pytest.approx(10.0 * plain.observation_space["L"].high.max())


@pytest.mark.parametrize("grid", ["sonar", "laser"])
def test_masked_observation_keeps_only_the_focused_readings(grid, run_until_focus):
    env = make_env("masked", scenario="exp01", sensor_noise=0.0, attention=AttentionConfig(grid=grid))
    env.reset(seed=0)
    obs, info = run_until_focus(env)
    out = info["attention"]
    base = env.unwrapped._reading
    kept_beams = np.flatnonzero(obs["laser_mask"])
    np.testing.assert_array_equal(kept_beams, out.view.laser_beams)
    np.testing.assert_allclose(obs["laser"][kept_beams], base.laser[kept_beams], rtol=1e-6)
    assert np.all(obs["laser"][obs["laser_mask"] == 0] == 20.0)
    assert np.flatnonzero(obs["sonar_mask"]).tolist() == [int(env.model.grid.region_sonar[out.focus])]
    assert np.all(obs["sonar"][obs["sonar_mask"] == 0] == 5.0)
    assert env.observation_space.contains(obs)


def test_focus_encoder_space_has_the_documented_layout():
    env = make_env("raw")
    encoder = FocusEncoder(AttentionConfig(), env.observation_space, memory_slots=3)
    sizes = {k: s.shape[0] for k, s in encoder.space.spaces.items()}
    assert sizes == {
        "region": 9,
        "event": 3,
        "sonar": 2,
        "laser": LASER_BINS,
        "distance": 1,
        "motion": 4,
        "features": 6,
        "memory": 18,
        "odometry": 2,
        "goal": 13,
    }
    assert sum(sizes.values()) == 64
    without = FocusEncoder(AttentionConfig(), env.observation_space, memory_slots=0)
    assert "memory" not in without.space.spaces and sum(s.shape[0] for s in without.space.values()) == 46


def _reference_focus_encode(encoder, raw, view, event, memory):
    """The focus observation as the encoder computed it in numpy before its compiled kernel."""
    flat = np.zeros(encoder._size, np.float32)
    obs = {key: flat[part] for key, part in encoder._parts.items()}
    obs["odometry"][:], obs["goal"][:] = raw["odometry"], raw["goal"]
    if memory is not None and "memory" in obs:
        np.minimum(memory.reshape(-1), encoder._memory_high, out=obs["memory"])
    if view is None:
        obs["region"][encoder.grid.n_regions] = 1.0
        return obs
    obs["region"][view.region] = 1.0
    obs["event"][:] = event
    obs["sonar"][:] = view.sonar_range_m, view.sonar_echo
    obs["laser"][:] = np.minimum.reduceat(view.laser_ranges_m, encoder._bin_starts[view.region])
    obs["distance"][0] = (
        encoder._max_distance if view.distance_m is None else min(view.distance_m, encoder._max_distance)
    )
    obs["motion"][0] = min(max(view.range_rate_mps, -encoder._max_speed), encoder._max_speed)
    obs["motion"][2 + view.direction] = 1.0
    obs["features"][:] = view.features
    return obs


def test_focus_encodings_of_a_view_and_of_a_region_equal_the_numpy_encoding_exactly():
    env = make_env("focus", sensor_noise=0.05, proximity=False)
    encoder = env._encoder
    rng = np.random.default_rng(3)
    obs, info = env.reset(seed=3)
    regions = [None, *range(encoder.grid.n_regions)]
    checked = 0
    for step in range(120):
        raw = {"odometry": rng.normal(size=2).astype(np.float32), "goal": rng.uniform(size=13).astype(np.float32)}
        out = info["attention"]
        memory = rng.uniform(-1.0, 12.0, size=(3, 6)).astype(np.float32) if step % 2 else None
        for region in regions:
            event = tuple(bool(b) for b in rng.integers(0, 2, 3))
            view = None if region is None else out.view_of(region)
            expected = _reference_focus_encode(encoder, raw, view, event, memory)
            for got in (
                encoder.encode(raw, view, event, memory),
                encoder.encode_region(raw, out, region, event, memory),
            ):
                assert list(got) == list(expected)
                for key in expected:
                    np.testing.assert_array_equal(got[key], expected[key], err_msg=key)
                    assert got[key].dtype == np.float32
            checked += view is not None and view.distance_m is not None and view.track_id is not None
        obs, _, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        if terminated or truncated:
            obs, info = env.reset()
    assert checked > 0  # some regions had an echo and a track
