"""``AttentionWrapper``: run the attentional model inside the environment loop.

Each step the wrapper feeds the base environment's readings (``"sonar"``, ``"laser"``),
time (``info["time_s"]``) and odometry to an ``AttentionModel`` and returns the attended
observation of the chosen mode (``attentive_gym.wrappers.encoders``). The episode's goal
(decoded from ``obs["goal"]``) becomes the model's top-down goal at every reset, unless
a goal was chosen with ``set_goal`` (e.g. by ``GoalActionWrapper``).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import gymnasium as gym
import numpy as np

from attentive_gym.attention import ATTENTIVE_STATES, AttentionConfig, AttentionModel, AttentionOutput, Goal
from attentive_gym.wrappers.encoders import ENCODERS
from attentive_gym.wrappers.overlay import draw_attention

__all__ = ["AttentionWrapper", "OBSERVATION_MODES"]

#: The observation modes, the first being the default.
OBSERVATION_MODES = tuple(ENCODERS)
_REQUIRED_KEYS = ("sonar", "laser", "odometry", "goal")


class AttentionWrapper(gym.Wrapper):
    """Agents observe what the robot attends to.

    Args:
        env: an environment with ``AttentiveRescue-v0``'s observation (a ``Dict`` with
            ``"sonar"``, ``"laser"``, ``"odometry"``, ``"goal"``) and ``info["time_s"]``.
        mode: ``"focus"`` (default), ``"saliency"`` or ``"masked"`` (see the encoders).
        config: the model's ``AttentionConfig``. When None: the default parameters, with
            ``range_noise_rel`` set to the relative noise σ of the base environment's
            sensors (``env.unwrapped.sensor_noise``; a uniform ±a noise has σ = a/√3)
            and the laser's mounting point taken from its ``LaserConfig``, so that the
            tracker assumes the sensors the robot has.
        weights: map weights for ``AttentionModel.set_weights`` (default: the config's).
        state: the Global Attentive State ("drowsy", "alert", "vigilant" or a gain).

    The model is reset with the environment and fed the time of each sensor's scan
    (``info["sonar_time_s"]``, ``info["laser_time_s"]``), so that readings held between
    scans are not taken for new ones. ``info["attention"]`` carries the step's
    ``AttentionOutput``. ``render()`` draws the focus and each region's saliency over
    the world's picture.
    """

    def __init__(
        self,
        env: gym.Env,
        mode: str = "focus",
        config: AttentionConfig | None = None,
        weights: Mapping[str, float] | None = None,
        state: str | float | None = None,
    ) -> None:
        super().__init__(env)
        if mode not in ENCODERS:
            raise ValueError(f"unknown observation mode {mode!r}; allowed: {list(OBSERVATION_MODES)}")
        base = env.observation_space
        if not isinstance(base, gym.spaces.Dict) or any(k not in base.spaces for k in _REQUIRED_KEYS):
            raise ValueError(f"AttentionWrapper needs a Dict observation with keys {list(_REQUIRED_KEYS)}, got {base}")
        self.mode = mode
        self.model = AttentionModel(_config_for(env) if config is None else config)
        if weights is not None:
            self.model.set_weights(weights)
        if state is not None:
            self.model.set_state(state)
        # L's ceiling allows every named attentive state, or the higher gain asked for
        self._encoder = ENCODERS[mode](self.model.config, base, gain=max(self.model.state, max(ATTENTIVE_STATES.values())))
        self.observation_space = self._encoder.space
        self._chosen_goal: Goal | None = None
        self._goal_chosen = False
        self.last_output: AttentionOutput | None = None
        if hasattr(env.unwrapped, "render_overlay"):
            env.unwrapped.render_overlay = self._draw_overlay

    def set_goal(self, goal: Goal | None) -> None:
        """Drive attention with ``goal`` (None: no top-down goal) instead of the task's,
        from the next step on, until ``clear_goal()``."""
        if goal is not None and not isinstance(goal, Goal):
            raise ValueError(f"set_goal takes a Goal or None, got {goal!r}")
        self._chosen_goal, self._goal_chosen = goal, True
        self.model.set_goals() if goal is None else self.model.set_goals(goal)

    def clear_goal(self) -> None:
        """Go back to the task's goal (applied at the next reset)."""
        self._chosen_goal, self._goal_chosen = None, False

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        raw, info = self.env.reset(seed=seed, options=options)
        self.model.reset()
        if not self._goal_chosen:
            task_goal = Goal.decode(raw["goal"])
            self.model.set_goals() if task_goal is None else self.model.set_goals(task_goal)
        observation = self._attend(raw, info)
        if self.render_mode == "human":
            self.env.render()  # again, now with this step's focus
        return observation, info

    def step(self, action):
        raw, reward, terminated, truncated, info = self.env.step(action)
        observation = self._attend(raw, info)
        if self.render_mode == "human":
            self.env.render()  # again, now with this step's focus
        return observation, reward, terminated, truncated, info

    def _attend(self, raw: dict[str, np.ndarray], info: dict[str, Any]) -> dict[str, np.ndarray]:
        output = self.model.step(info["time_s"], raw["sonar"], raw["laser"], raw["odometry"],
                                 sonar_time_s=info.get("sonar_time_s"), laser_time_s=info.get("laser_time_s"))
        self.last_output = output
        info["attention"] = output
        return self._encoder.encode(raw, output)

    def _draw_overlay(self, renderer, surface) -> None:
        """Draw the latest focus and saliency (called by the base environment's renderer)."""
        if self.last_output is not None:
            draw_attention(renderer, surface, self.env.unwrapped.world.robot.pose, self.model.grid, self.last_output)


#: σ of a uniform noise on [−a, a], in units of a.
_UNIFORM_SIGMA_PER_HALF_WIDTH = 1.0 / math.sqrt(3.0)


def _config_for(env: gym.Env) -> AttentionConfig:
    """The default configuration, assuming the range noise and laser mount of ``env``'s sensors."""
    base = env.unwrapped
    settings = {}
    noise = getattr(base, "sensor_noise", None)
    if noise is not None:
        uniform = getattr(base, "noise_model", "gaussian") == "uniform"
        settings["range_noise_rel"] = float(noise) * (_UNIFORM_SIGMA_PER_HALF_WIDTH if uniform else 1.0)
    sensors = getattr(base, "sensors", None)
    if sensors is not None:
        laser = sensors.laser_scanner.config
        settings["laser_mount_x_m"], settings["laser_mount_y_m"] = laser.mount_x_m, laser.mount_y_m
    return AttentionConfig(**settings)
