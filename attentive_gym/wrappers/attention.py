"""``AttentionWrapper``: run the attentional model inside the environment loop.

Each step the wrapper feeds the base environment's readings (``"sonar"``, ``"laser"``),
time (``info["time_s"]``) and odometry to an ``AttentionModel`` and returns the attended
observation of the chosen mode (``attentive_gym.wrappers.encoders``). The episode's goal
(decoded from ``obs["goal"]``) becomes the model's top-down goal at every reset, unless
a goal was chosen with ``set_goal`` (e.g. by ``GoalActionWrapper``).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

import gymnasium as gym
import numpy as np

from attentive_gym.attention import (
    ATTENTIVE_STATES,
    MODEL_VERSIONS,
    AttentionConfig,
    AttentionModel,
    AttentionOutput,
    Goal,
    check_model_version,
    version_fields,
)
from attentive_gym.attention.tracking.tracker import TRACK_TABLE_FIELDS
from attentive_gym.attention.working_memory import WorkingMemory
from attentive_gym.world.world import physics_substeps
from attentive_gym.wrappers.encoders import ENCODERS, NO_EVENT, FocusEncoder

__all__ = ["AttentionWrapper", "OBSERVATION_MODES", "SELECTIONS", "DEFAULT_MEMORY_SLOTS", "default_config"]

#: The observation modes, the first being the default.
OBSERVATION_MODES = tuple(ENCODERS)
#: How the ``"focus"`` observation's region is chosen: the model's winner, or at random.
SELECTIONS = ("winner", "random")
#: Bodies the ``"focus"`` observation's working memory holds by default.
DEFAULT_MEMORY_SLOTS = 3
_REQUIRED_KEYS = ("sonar", "laser", "odometry", "goal")


class AttentionWrapper(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Agents observe what the robot attends to.

    Args:
        env: an environment with ``AttentiveRescue-v0``'s observation (a ``Dict`` with
            ``"sonar"``, ``"laser"``, ``"odometry"``, ``"goal"``) and ``info["time_s"]``.
        mode: ``"focus"`` (default), ``"saliency"`` or ``"masked"`` (see the encoders).
        config: the model's ``AttentionConfig``. When None: ``default_config(env,
            version)``, the defaults with ``range_noise_rel`` set to the relative noise σ of
            the base environment's sensors (``env.unwrapped.sensor_noise``; a uniform ±a
            noise has σ = a/√3), the laser's mounting point taken from its
            ``LaserConfig`` and the dead reckoning of its physics, so that the tracker
            assumes the robot it is given.
        weights: map weights for ``AttentionModel.set_weights`` (default: the config's).
        state: the Global Attentive State ("drowsy", "alert", "vigilant" or a gain).
        memory_slots: ``"focus"`` only: bodies in the working memory of the last attended
            tracks (``attentive_gym.attention.working_memory``; 0 = none; default 3).
        proximity: ``"focus"`` only: add the ``"proximity"`` entry, every region's nearest
            reading (``FocusEncoder``; default False).
        selection: ``"focus"`` only: ``"winner"`` (default) attends the model's focus;
            ``"random"`` attends a region drawn uniformly each step (a control: the same
            bottleneck without the model's choice; ``"event"`` is then all zeros). The
            draws come from the wrapper's own generator, seeded by ``reset(seed=...)``.
        version: the version of the model's defaults when ``config`` is None (one of
            ``attention.MODEL_VERSIONS``; default the latest).

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
        memory_slots: int | None = None,
        selection: str = "winner",
        proximity: bool = False,
        version: int = MODEL_VERSIONS[-1],
    ) -> None:
        gym.utils.RecordConstructorArgs.__init__(
            self,
            mode=mode,
            config=config,
            weights=weights,
            state=state,
            memory_slots=memory_slots,
            selection=selection,
            proximity=proximity,
            version=version,
        )
        gym.Wrapper.__init__(self, env)
        if mode not in ENCODERS:
            raise ValueError(f"unknown observation mode {mode!r}; allowed: {list(OBSERVATION_MODES)}")
        if selection not in SELECTIONS:
            raise ValueError(f"unknown selection {selection!r}; allowed: {list(SELECTIONS)}")
        if mode != "focus" and (memory_slots is not None or selection != "winner" or proximity):
            raise ValueError(
                f"memory_slots, selection and proximity apply to the 'focus' observation only, got mode={mode!r}"
            )
        if memory_slots is None:
            memory_slots = DEFAULT_MEMORY_SLOTS
        if not isinstance(memory_slots, int) or isinstance(memory_slots, bool) or memory_slots < 0:
            raise ValueError(f"memory_slots must be an integer >= 0, got {memory_slots!r}")
        base = env.observation_space
        if not isinstance(base, gym.spaces.Dict) or any(k not in base.spaces for k in _REQUIRED_KEYS):
            raise ValueError(f"AttentionWrapper needs a Dict observation with keys {list(_REQUIRED_KEYS)}, got {base}")
        self.mode = mode
        self.model = AttentionModel(default_config(env, version) if config is None else config)
        if weights is not None:
            self.model.set_weights(weights)
        if state is not None:
            self.model.set_state(state)
        if mode == "focus":
            self._encoder = FocusEncoder(self.model.config, base, memory_slots, proximity=proximity)
        else:  # L's ceiling allows every named attentive state, or the higher gain asked for, and the weights in force
            in_force = dataclasses.replace(self.model.config, weights=tuple(self.model.weights.values()))
            self._encoder = ENCODERS[mode](in_force, base, gain=max(self.model.state, max(ATTENTIVE_STATES.values())))
        self.observation_space = self._encoder.space
        self.selection = selection
        self.memory = WorkingMemory(memory_slots) if mode == "focus" and memory_slots else None
        self._selection_rng: np.random.Generator | None = None
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
        if self.memory is not None:
            self.memory.reset()
        if seed is not None or self._selection_rng is None:
            self._selection_rng = np.random.default_rng(None if seed is None else [seed, _SELECTION_STREAM])
        if not self._goal_chosen:
            task_goal = Goal.decode(raw["goal"])
            self.model.set_goals() if task_goal is None else self.model.set_goals(task_goal)
        return self.observe_step(raw, info), info

    def step(self, action):
        raw, reward, terminated, truncated, info = self.env.step(action)
        return self.observe_step(raw, info), reward, terminated, truncated, info

    # --- the stages of a step (``attentive_gym.vector.protocol.ModelStage``; a fleet batches the models) ---
    def observe_step(self, raw: dict[str, np.ndarray], info: dict[str, Any]) -> dict[str, np.ndarray]:
        """The attended observation of a step's ``raw`` one and its ``info`` (which gains
        ``"attention"``): ``observe_output`` of the model's step on ``model_reading``."""
        t, sonar, laser, odometry, sonar_time_s, laser_time_s = self.model_reading(raw, info)
        output = self.model.step(t, sonar, laser, odometry, sonar_time_s=sonar_time_s, laser_time_s=laser_time_s)
        return self.observe_output(raw, info, output)

    def observe_output(
        self, raw: dict[str, np.ndarray], info: dict[str, Any], output: AttentionOutput
    ) -> dict[str, np.ndarray]:
        """The attended observation of a step's ``raw`` one, given the model's ``output`` on it
        (``info`` gains ``"attention"``): ``observe_outputs`` of this one wrapper, whose
        encoder encodes the one step directly (``encode_many``'s case k = 1)."""
        self.last_output = info["attention"] = output
        if self.mode != "focus":
            observation = self._encoder.encode(raw, output)
        else:
            region, event = self._attended(output)
            observation = self._encoder.encode_region(raw, output, region, event, self._remember(output, region))
        if self.render_mode == "human":
            self.env.render()  # the step's one frame (the base env leaves it to its overlay's owner)
        return observation

    @classmethod
    def observe_outputs(
        cls,
        wrappers: Sequence[AttentionWrapper],
        raws: Sequence[dict[str, np.ndarray]],
        infos: Sequence[dict[str, Any]],
        outputs: Sequence[AttentionOutput],
    ) -> list[dict[str, np.ndarray]]:
        """The attended observations of k wrappers' steps at once (a fleet steps its members'
        models together, then calls this), each the one ``observe_output`` would give.

        Each wrapper keeps its model's output (``last_output``, ``info["attention"]``), picks
        its region (its own random draw for ``selection="random"``) and writes its working
        memory; then one call of the shared encoder writes all k observations into one block
        (``encoders``' ``encode_many``), the numbers each wrapper alone would give.

        Args:
            wrappers: k distinct ``AttentionWrapper`` of one observation (the same mode and
                encoder settings).
            raws, infos, outputs: each wrapper's raw observation, info and model output.

        Returns:
            The k observations, in order.

        Raises:
            ValueError: for lists of different lengths, something that is not an
                ``AttentionWrapper``, a wrapper listed twice, or wrappers whose observations differ.
        """
        count = len(wrappers)
        if not len(raws) == len(infos) == len(outputs) == count:
            raise ValueError(
                f"observe_outputs takes one raw observation, info and output per wrapper ({count}), "
                f"got {len(raws)}, {len(infos)} and {len(outputs)}"
            )
        if count == 0:
            return []
        first = wrappers[0]
        if not isinstance(first, AttentionWrapper):
            raise ValueError(f"wrapper 0 is a {type(first).__name__}, not an AttentionWrapper")
        if count == 1:
            return [first.observe_output(raws[0], infos[0], outputs[0])]
        for i, wrapper in enumerate(wrappers[1:], start=1):
            if not isinstance(wrapper, AttentionWrapper):
                raise ValueError(f"wrapper {i} is a {type(wrapper).__name__}, not an AttentionWrapper")
            if wrapper._encoder.settings != first._encoder.settings:
                raise ValueError(
                    f"wrapper {i}'s observation ({wrapper.mode!r}) differs from wrapper 0's ({first.mode!r}); "
                    "the observations of one call share their mode and encoder settings"
                )
        if len({id(wrapper) for wrapper in wrappers}) != count:
            raise ValueError("observe_outputs takes each wrapper once")
        for wrapper, info, output in zip(wrappers, infos, outputs):
            wrapper.last_output = info["attention"] = output
        if first.mode == "focus":
            regions, events, memories = [], [], []
            for wrapper, output in zip(wrappers, outputs):
                region, event = wrapper._attended(output)
                regions.append(region)
                events.append(event)
                memories.append(wrapper._remember(output, region))
            observations = first._encoder.encode_many(raws, outputs, regions, events, memories)
        else:
            observations = first._encoder.encode_many(raws, outputs)
        for wrapper in wrappers:
            if wrapper.render_mode == "human":
                wrapper.env.render()  # the step's one frame (the base env leaves it to its overlay's owner)
        return observations

    @staticmethod
    def model_reading(raw: dict[str, np.ndarray], info: dict[str, Any]) -> tuple:
        """``AttentionModel.step``'s arguments for a raw observation and its ``info``:
        ``(t, sonar, laser, odometry, sonar_time_s, laser_time_s)``."""
        return (
            info["time_s"],
            raw["sonar"],
            raw["laser"],
            raw["odometry"],
            info.get("sonar_time_s"),
            info.get("laser_time_s"),
        )

    def _attended(self, output: AttentionOutput) -> tuple[int | None, tuple[bool, bool, bool]]:
        """The attended region (None: no focus) and the step's (fired, bottom-up, top-down) event."""
        if self.selection == "random":
            return int(self._selection_rng.integers(self.model.grid.n_regions)), NO_EVENT
        return output.focus, (output.fired, output.origin == "bottom-up", output.origin == "top-down")

    def _remember(self, output: AttentionOutput, region: int | None) -> np.ndarray | None:
        """Write the attended region's track into the working memory; its rows now (None: empty or no memory)."""
        pose = None if self.memory is None else self.model.odometry_pose
        if pose is None:  # no memory, or no tracks without the tracker: nothing to remember
            return None
        track = None if region is None else output._track_row(region)
        if track is not None:
            self.memory.attend(
                output.t,
                pose,
                int(track[_TRACK_ID]),
                track[_TRACK_X : _TRACK_X + 2],
                track[_TRACK_VX : _TRACK_VX + 2],
                float(track[_TRACK_SPEED]),
                bool(output.goal_fulfilled[region]),
            )
        return self.memory.read(output.t, pose, self.model.config.max_distance_m)

    def _draw_overlay(self, renderer, surface) -> None:
        """Draw the latest focus and saliency (called by the base environment's renderer)."""
        from attentive_gym.wrappers.overlay import draw_attention  # pygame: loaded only by rendering

        if self.last_output is not None:
            draw_attention(renderer, surface, self.env.unwrapped.world.robot.pose, self.model.grid, self.last_output)


#: Columns of the track rows (``AttentionOutput._track_row``) the working memory takes.
_TRACK_ID, _TRACK_X, _TRACK_VX, _TRACK_SPEED = (TRACK_TABLE_FIELDS.index(name) for name in ("id", "x", "vx", "speed"))

#: Second word of the random selection's seed, so that its stream differs from the env's.
_SELECTION_STREAM = 0x5E1EC7

#: σ of a uniform noise on [−a, a], in units of a.
_UNIFORM_SIGMA_PER_HALF_WIDTH = 1.0 / math.sqrt(3.0)


def default_config(env: gym.Env, version: int = MODEL_VERSIONS[-1]) -> AttentionConfig:
    """The defaults of model ``version`` (one of ``MODEL_VERSIONS``) for ``env``'s robot: the
    range noise and laser mount of its sensors and, from version 1, the dead reckoning of its
    physics sub-steps (``AttentionConfig.odometry_previous_weight`` = ``(S + 1) / (2 S)``).

    Raises:
        ValueError: for an unknown version (listing the known ones).
    """
    check_model_version(version)
    base = env.unwrapped
    settings: dict[str, Any] = version_fields(version)
    dt = getattr(base, "dt", None)
    if version >= 1 and isinstance(dt, float):
        substeps = physics_substeps(dt)
        settings["odometry_previous_weight"] = (substeps + 1) / (2 * substeps)
    noise = getattr(base, "sensor_noise", None)
    if noise is not None:
        uniform = getattr(base, "noise_model", "gaussian") == "uniform"
        settings["range_noise_rel"] = float(noise) * (_UNIFORM_SIGMA_PER_HALF_WIDTH if uniform else 1.0)
    sensors = getattr(base, "sensors", None)
    if sensors is not None:
        laser = sensors.laser_scanner.config
        settings["laser_mount_x_m"], settings["laser_mount_y_m"] = laser.mount_x_m, laser.mount_y_m
    return AttentionConfig(**settings)
