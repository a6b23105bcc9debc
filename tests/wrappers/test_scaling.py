"""``ScaledObservation``: every observation entry from its declared bounds to [−1, 1]."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from stable_baselines3.common.env_checker import check_env as sb3_check_env

from attentive_gym.agents.config import RunSpec
from attentive_gym.agents.training import env_factory
from attentive_gym.wrappers import ScaledObservation, make_env


class _BoxEnv(gym.Env):
    """A one-step env whose observation space is ``space`` and whose observation is ``value``."""

    action_space = gym.spaces.Discrete(1)

    def __init__(self, space, value):
        self.observation_space = space
        self.value = value

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return self.value, {}

    def step(self, action):
        return self.value, 0.0, True, False, {}


def test_entries_map_linearly_from_their_bounds_and_back():
    env = make_env("focus", arena_size_m=8.0, num_distractors=2)
    scaled = ScaledObservation(make_env("focus", arena_size_m=8.0, num_distractors=2))
    raw, _ = env.reset(seed=3)
    obs, _ = scaled.reset(seed=3)
    for _ in range(20):
        for key, space in env.observation_space.spaces.items():
            low, high = space.low.astype(np.float64), space.high.astype(np.float64)
            back = obs[key].astype(np.float64) * 0.5 * (high - low) + 0.5 * (low + high)
            np.testing.assert_allclose(back, raw[key], atol=1e-5 * max(1.0, float(np.abs(high).max())), err_msg=key)
            assert obs[key].dtype == np.float32 and scaled.observation_space[key].contains(obs[key]), key
        action = env.action_space.sample()
        raw = env.step(action)[0]
        obs = scaled.step(action)[0]


def test_bounds_land_on_minus_one_and_one_and_a_constant_on_zero():
    space = gym.spaces.Box(np.array([0.0, -3.0, 2.0]), np.array([20.0, 1.0, 2.0]), dtype=np.float32)
    for value, expected in (([0.0, -3.0, 2.0], [-1.0, -1.0, 0.0]), ([20.0, 1.0, 2.0], [1.0, 1.0, 0.0]),
                            ([5.0, -1.0, 2.0], [-0.5, 0.0, 0.0])):
        env = ScaledObservation(_BoxEnv(space, np.array(value, np.float32)))
        assert env.reset()[0].tolist() == expected
    assert env.observation_space == gym.spaces.Box(-1.0, 1.0, (3,), np.float32)


@pytest.mark.filterwarnings("ignore:.*is different from the unwrapped version")  # it is wrapped on purpose
def test_the_scaled_variants_pass_the_gymnasium_and_sb3_checkers():
    for variant in ("raw", "focus", "oracle"):
        check_env(ScaledObservation(make_env(variant)), skip_render_check=True)
        sb3_check_env(ScaledObservation(make_env(variant)), warn=False)


@pytest.mark.parametrize("space, message", [
    (gym.spaces.Dict({"a": gym.spaces.Box(0.0, 1.0, (2,)), "laser": gym.spaces.Box(0.0, np.inf, (3,))}),
     "observation entry 'laser' has bounds"),
    (gym.spaces.Box(-np.inf, 1.0, (2,)), "the observation has bounds"),
    (gym.spaces.Dict({"k": gym.spaces.Discrete(3)}), "observation entry 'k' is a Discrete"),
    (gym.spaces.Discrete(3), "needs a Box or a Dict of Boxes"),
])
def test_spaces_it_cannot_scale_are_refused_by_name(space, message):
    with pytest.raises(ValueError, match=message):
        ScaledObservation(_BoxEnv(space, space.sample()))


def test_runs_scale_by_default_and_old_specs_read_as_unscaled():
    assert RunSpec().obs_scaling == "bounds"
    scaled = env_factory(RunSpec(variant="raw"))()
    assert isinstance(scaled, ScaledObservation) and scaled.observation_space["laser"].high.max() == 1.0
    plain = env_factory(RunSpec(variant="raw", obs_scaling="none"))()
    assert not isinstance(plain, ScaledObservation) and plain.observation_space["laser"].high.max() == 20.0
    written_before = {k: v for k, v in RunSpec().to_dict().items() if k != "obs_scaling"}
    assert RunSpec.from_dict(written_before).obs_scaling == "none"
    assert RunSpec.from_dict(RunSpec().to_dict()) == RunSpec()
    with pytest.raises(ValueError, match=r"unknown obs_scaling 'minmax'; allowed: \['bounds', 'none'\]"):
        RunSpec(obs_scaling="minmax")
