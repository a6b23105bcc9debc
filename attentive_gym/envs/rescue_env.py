"""``AttentiveRescue-v0``: find the victim the goal describes, with sonars and a laser.

- ``AttentiveRescueEnv``: the Gymnasium environment (see its docstring for the spaces,
  reward, termination, truncation, info and keyword arguments).
- ``resolve_scenario``: a scenario name, file path or object → a scenario source.
"""

from __future__ import annotations

import inspect
import math
import numbers
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from attentive_gym import _pymunk_access
from attentive_gym._optional import require
from attentive_gym.attention.goals import GOAL_ENCODING_SIZE, Goal
from attentive_gym.envs.completion import complete_resets, complete_steps
from attentive_gym.envs.config_mappings import config_from
from attentive_gym.envs.geodesic import GeodesicDistance
from attentive_gym.envs.reward import RewardConfig
from attentive_gym.sensors import LaserConfig, ScanHold, SensorReading, SensorSuite, SonarConfig, resolve_sensor_profile
from attentive_gym.world.arena import ArenaConfig, generate_arena
from attentive_gym.world.builtin import BUILTIN_SCENARIOS, builtin_scenario
from attentive_gym.world.robot import RobotConfig
from attentive_gym.world.scenario import Scenario, TaskSpec
from attentive_gym.world.scenario_io import SCENARIO_SUFFIXES, load_scenario
from attentive_gym.world.world import ROBOT_ID, World

__all__ = ["AttentiveRescueEnv", "resolve_scenario", "PROCEDURAL_SCENARIO", "checked_action"]

#: Name of the procedurally generated arena (a new random arena every reset).
PROCEDURAL_SCENARIO = "rescue"
_RESET_OPTIONS = ("goal",)
_MAX_GOAL_BOUND = 20.0  # m: the largest distance a goal can name (laser saturation)


def resolve_scenario(scenario: str | os.PathLike | Scenario) -> Scenario | None:
    """The fixed scenario named by ``scenario``, or ``None`` for the procedural arena.

    Accepts ``"rescue"`` (procedural), a built-in name (``exp01`` … ``exp05``), a path to a
    ``.yaml``/``.yml``/``.json`` file, or a ``Scenario``.
    """
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, str) and scenario == PROCEDURAL_SCENARIO:
        return None
    if isinstance(scenario, str) and scenario in BUILTIN_SCENARIOS:
        return builtin_scenario(scenario)
    if isinstance(scenario, (str, os.PathLike)) and Path(scenario).suffix.lower() in SCENARIO_SUFFIXES:
        if not Path(scenario).is_file():
            raise ValueError(f"scenario file {scenario} does not exist")
        return load_scenario(scenario)
    raise ValueError(
        f"unknown scenario {scenario!r}; allowed: {PROCEDURAL_SCENARIO!r}, {sorted(BUILTIN_SCENARIOS)}, "
        f"a path ending in {SCENARIO_SUFFIXES}, or a Scenario object"
    )


_FLOAT_DTYPES = (np.dtype(np.float32), np.dtype(np.float64))


def checked_action(action: Any, shape: tuple[int, ...], layout: str = "") -> np.ndarray:
    """``action`` as a float64 array of ``shape``, or ``ValueError`` naming what is wrong with
    it (complex or non-numeric values, another shape, NaN or inf); ``layout`` names the
    entries in the message, e.g. ``"(linear, angular)"``."""
    what = f"shape {shape}" + (f" = {layout}" if layout else "")
    if np.iscomplexobj(action):
        raise ValueError(f"action must be real numbers with {what}, got complex {action!r}")
    try:
        command = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"action must be numeric with {what}, got {action!r}") from None
    if command.shape != shape:
        raise ValueError(f"action must have {what}, got shape {command.shape}")
    if not np.all(np.isfinite(command)):
        raise ValueError(f"action must be finite, got {command.tolist()}")
    return command


def _check_goal_bounds(goal: Goal | None) -> None:
    """``ValueError`` for a goal whose bounds exceed ``_MAX_GOAL_BOUND`` (the laser's range)."""
    if goal is not None and max(goal.lo or 0.0, goal.hi or 0.0, goal.tolerance) > _MAX_GOAL_BOUND:
        raise ValueError(f"goal {goal}: bounds above {_MAX_GOAL_BOUND} (the laser's range) are not allowed")


def _check_number(name: str, value: Any, low: float, high: float, low_open: bool = False) -> float:
    ok = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)) and math.isfinite(value)
    ok = ok and (value > low if low_open else value >= low) and value <= high
    if not ok:
        bracket = "(" if low_open else "["
        raise ValueError(f"{name} must be a number in {bracket}{low}, {high}], got {value!r}")
    return float(value)


class AttentiveRescueEnv(gym.Env):
    """A Pioneer P2AT-like robot with 16 sonars and a 180-beam laser in a rescue arena.

    **Task** (default scenario ``"rescue"``): a walled arena with rubble and moving bodies
    (survivors and other robots). The episode's goal — e.g. ``speed in [0.5, 0.9] m/s`` —
    describes one victim, the target; the distractors violate it. Reach the target.

    **Observation** (``Dict``, float32):

    - ``"sonar"`` (16,): ranges in m, [0.15, 5]; 5 means no echo. Indices 0..7 are the
      front ring (+90° … −90°), 8..15 the rear ring (−90° … +90° through the back).
    - ``"laser"`` (180,): ranges in m, [0, 20]; beam i at bearing −90° + (i + 0.5)°.
    - ``"odometry"`` (2,): measured linear (m/s) and angular (rad/s) velocity.
    - ``"goal"`` (13,): ``Goal.encode()`` of the episode's goal (layout in
      ``attentive_gym.attention.goals.GOAL_ENCODING_FIELDS``; zeros = no goal).

    Readings carry multiplicative noise on every echo: by default Gaussian with σ =
    ``sensor_noise`` = 5 % of the reading; with ``noise_model="uniform"`` (or the
    ``"usarsim"`` profile) ``reading · (1 + U(−a, a))``, a = ``sensor_noise``. With a scan
    interval, a sensor takes a new reading only every ``*_scan_interval_s`` seconds and its
    reading (noise included) holds in between. Odometry is exact.

    **Action**: ``Box(-1, 1, (2,))`` = (linear, angular) as fractions of the robot's top
    speeds (0.7 m/s, 140°/s by default). Values outside [−1, 1] are clipped; a NaN/inf
    action or one of the wrong shape raises ``ValueError``. The robot ramps to the command
    within its acceleration limits.

    **Reward** (``attentive_gym.envs.reward``): progress towards the target (1 per m),
    −2 per second in contact with anything, −0.1 per second, +10 on success. Scenarios
    without a task give 0.

    **Termination**: the robot's centre comes within ``success_radius_m`` (1 m) of the
    target's; or, with ``RewardConfig.contact_limit_s`` set, the robot has been in contact
    for longer than that in the episode (no success). **Truncation**: the time limit (the
    task's, default 40 s; or the scenario's ``duration_s``; or ``time_limit_s``).

    **Info**: ``time_s``, ``robot_pose`` (x m, y m, heading rad), ``robot_velocity``
    (odometry), ``mover_positions`` (M, 2), ``mover_velocities`` (M, 2), ``mover_names``,
    ``target_index`` (−1 without a task), ``target_distance_m`` (NaN-free: inf without a
    task), ``collision`` (the robot touched anything during the step), ``contact_s`` (s
    of the episode's steps with a collision), ``success``, ``goal`` (its text), ``sonar_hits`` / ``laser_hits``
    (the entity id each reading came from, −1 for none; they hold between scans with the
    readings), ``sonar_time_s`` / ``laser_time_s`` (world time, s, of the scan each
    current reading came from; equal to ``time_s`` when a sensor scans every step).

    **Keyword arguments** (``gym.make("AttentiveRescue-v0", ...)``): ``scenario`` (name,
    file or ``Scenario``), ``dt`` (s, (0, 0.5]), ``render_mode`` (needs pygame: the
    ``render`` extra), the sensor settings below, the arena's knobs ``arena_size_m`` (side
    or (width, height)), ``num_distractors``, ``rubble_per_100m2``, ``max_mover_speed_mps``,
    ``goals`` (goals to sample from), ``time_limit_s``, and ``reward`` (``RewardConfig``),
    ``robot`` (``RobotConfig``), ``sonar`` (``SonarConfig``), ``laser`` (``LaserConfig``),
    each also as a mapping of some of its fields (``reward={"collision_per_s": 10}``; the
    others keep their defaults; ``envs.config_mappings``): an unknown field raises
    ``ValueError`` listing the allowed ones, a bad value the dataclass's own error, before
    anything is built. Unknown keywords raise ``TypeError`` listing the allowed ones. ``reset(options={"goal": g})``
    fixes the episode's goal (a ``Goal`` or its encoding).

    **Sensor settings** (keyword arguments; None means "not given"):

    - ``sensor_profile``: None or a name in ``attentive_gym.sensors.SENSOR_PROFILES``;
      ``"usarsim"`` = uniform noise, a = 0.05, both scan intervals 0.2 s (USARSim's defaults).
    - ``noise_model``: ``"gaussian"`` or ``"uniform"``.
    - ``sensor_noise``: the relative noise level, [0, 0.5]: σ (gaussian) or the
      half-width a (uniform).
    - ``sonar_scan_interval_s``, ``laser_scan_interval_s``: s between scans, finite, > 0.
      A sensor scans at reset and then once at least its interval has passed since its
      last scan.

    A setting not given takes the profile's value, or without a profile ``"gaussian"``,
    0.05 and a scan every step; given values beat the profile's (pass ``dt`` as an interval
    to scan every step under a profile). The resolved settings are ``env.sensor_settings``
    (a ``SensorProfile``), also read as ``env.noise_model``, ``env.sensor_noise``,
    ``env.sonar_scan_interval_s`` and ``env.laser_scan_interval_s``. Both sensors draw their
    noise every step whatever the intervals (a held reading keeps its scan's noise), so the
    RNG stream, and with it the readings at scan steps, do not depend on the intervals.

    **Version History** (the registered ids' version; any change of a default that can
    change learning results bumps it, as Gymnasium does, and adds a line here):

    - v4 of the five attended ids (2026-12-07): the model's version 3, whose tracker tests each
      standing track's last centroids for a start (``track_onset_log_ratio``, 6 nats). The
      raw, raw-stack and oracle ids stay v1.
    - v3 of the five attended ids (2026-12-07): the model's version 2, whose tracker keeps a
      partly occluded body's probability of moving (``track_occlusion_keeps_motion``). The
      raw, raw-stack and oracle ids stay v1.
    - The safe task (2026-12-07): ``AttentiveRescue-v1``, ``AttentiveRescueStack-v1``,
      ``AttentiveRescueOracle-v1`` and v2 of the five attended ids build version 1 of the task
      (``envs.tasks``): the episode ends after 1 s of contact, a clearance under 0.3 m costs
      up to 4 per second, and the focus layout carries ``proximity``. This class's own
      ``reward`` default stays ``RewardConfig()``; the ids and ``make_env`` pass the task's.
    - v1 of the five attended ids (2026-12-06): the attentional model's motion stages on
      (free-space evidence, the tracker's start and edge rules, the simulator's dead
      reckoning; ``attention.MODEL_VERSIONS``). This environment and the raw, raw-stack and
      oracle ids stay v0.
    - v0: the first version of all eight ids. ``dt`` 0.05 s; 5 % Gaussian noise and a
      scan every step; the spaces above; ``RewardConfig()``, ``RobotConfig()``,
      ``SonarConfig()``, ``LaserConfig()``; the procedural arena of 10 m with 3
      distractors, 6 rubble pieces per 100 m², movers up to 1 m/s and the task goals
      speed in [0.5, 0.9] or [0.15, 0.45] m/s with a 40 s limit; for the attended
      variants, ``AttentionConfig()`` with ``VERSION_0_FIELDS`` and a working memory of 3
      bodies. After 0.1.0,
      pursuing and evading movers measure their distance as ``sqrt(dx*dx + dy*dy)``, not
      ``math.hypot``: the defaults' episodes are unchanged, but arenas with a direction goal
      can follow other trajectories from the same seed (docs/environment.md).
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 20}

    def __init__(
        self,
        scenario: str | os.PathLike | Scenario = PROCEDURAL_SCENARIO,
        *,
        render_mode: str | None = None,
        sensor_profile: str | None = None,
        noise_model: str | None = None,
        sensor_noise: float | None = None,
        sonar_scan_interval_s: float | None = None,
        laser_scan_interval_s: float | None = None,
        dt: float = 0.05,
        arena_size_m: float | tuple[float, float] = 10.0,
        num_distractors: int = 3,
        rubble_per_100m2: float = 6.0,
        max_mover_speed_mps: float = 1.0,
        goals: tuple[Goal, ...] | None = None,
        time_limit_s: float | None = None,
        reward: RewardConfig | Mapping[str, Any] = RewardConfig(),
        robot: RobotConfig | Mapping[str, Any] = RobotConfig(),
        sonar: SonarConfig | Mapping[str, Any] = SonarConfig(),
        laser: LaserConfig | Mapping[str, Any] = LaserConfig(),
        **unknown: Any,
    ) -> None:
        if unknown:
            allowed = [
                n for n in inspect.signature(AttentiveRescueEnv.__init__).parameters if n not in ("self", "unknown")
            ]
            raise TypeError(f"unknown keyword argument(s) {sorted(unknown)}; allowed: {allowed}")
        reward, robot = config_from("reward", reward), config_from("robot", robot)
        sonar, laser = config_from("sonar", sonar), config_from("laser", laser)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        if render_mode is not None:
            require("pygame", "rendering")  # at make, not at the first frame
        self.render_mode = render_mode
        self.dt = _check_number("dt", dt, 0.0, 0.5, low_open=True)
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.dt}
        settings = self.sensor_settings = resolve_sensor_profile(
            sensor_profile,
            noise_model=noise_model,
            noise=None if sensor_noise is None else _check_number("sensor_noise", sensor_noise, 0.0, 0.5),
            sonar_scan_interval_s=sonar_scan_interval_s,
            laser_scan_interval_s=laser_scan_interval_s,
        )
        self.sensor_profile = sensor_profile
        self.sensors = SensorSuite(sonar, laser, noise_std=settings.noise, noise_model=settings.noise_model)
        self._scans = ScanHold(settings.sonar_scan_interval_s, settings.laser_scan_interval_s)
        self.scenario_source = scenario
        self._fixed_scenario = resolve_scenario(scenario)
        if np.isscalar(arena_size_m):
            width = height = arena_size_m.item() if isinstance(arena_size_m, np.generic) else arena_size_m
        elif isinstance(arena_size_m, (tuple, list, np.ndarray)) and np.shape(arena_size_m) == (2,):
            width, height = (v.item() if isinstance(v, np.generic) else v for v in arena_size_m)
        else:
            raise ValueError(f"arena_size_m must be a side in m or a (width, height) pair, got {arena_size_m!r}")
        if isinstance(max_mover_speed_mps, bool) or not isinstance(max_mover_speed_mps, numbers.Real):
            raise ValueError(f"max_mover_speed_mps must be a finite number > 0, got {max_mover_speed_mps!r}")
        if goals is not None and (isinstance(goals, (Goal, str)) or not isinstance(goals, (tuple, list))):
            raise TypeError(f"goals must be a tuple or list of Goal objects, got {goals!r}")
        self.arena = ArenaConfig(
            width_m=width,
            height_m=height,
            rubble_per_100m2=rubble_per_100m2,
            num_distractors=num_distractors,
            max_mover_speed_mps=max_mover_speed_mps,
            distractor_speed_range_mps=(min(0.3, max_mover_speed_mps), min(0.9, max_mover_speed_mps)),
            goals=ArenaConfig.goals if goals is None else tuple(goals),
        )
        self.time_limit_s = (
            None if time_limit_s is None else _check_number("time_limit_s", time_limit_s, 0.0, 1e6, low_open=True)
        )
        self.reward_config = reward
        self.robot_config = robot

        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.observation_space = spaces.Dict(
            {
                "sonar": spaces.Box(0.0, sonar.max_range_m, shape=(16,), dtype=np.float32),
                "laser": spaces.Box(0.0, laser.max_range_m, shape=(laser.num_beams,), dtype=np.float32),
                "odometry": spaces.Box(
                    np.array([-robot.max_linear_mps, -robot.max_angular_rps], dtype=np.float32) * 1.5,
                    np.array([robot.max_linear_mps, robot.max_angular_rps], dtype=np.float32) * 1.5,
                    dtype=np.float32,
                ),
                "goal": spaces.Box(0.0, _MAX_GOAL_BOUND, shape=(GOAL_ENCODING_SIZE,), dtype=np.float32),
            }
        )
        high = self.observation_space["odometry"].high
        self._odometry_limit = (float(high[0]), float(high[1]))  # the float32 bounds, exactly
        self.world: World | None = None
        self.goal: Goal | None = None
        self._goal_cache: tuple = (None, np.zeros(GOAL_ENCODING_SIZE, np.float32), "none")  # goal, encoding, text
        self._renderer = None
        self._reading = None
        self._contact_steps = 0  # steps of the episode with the robot in contact
        self._path_m = math.inf  # the distance to the target that progress counts, at the last step (m)
        self._geodesic: GeodesicDistance | None = None  # the episode's, with RewardConfig(progress="geodesic")
        #: Called as ``overlay(renderer, surface)`` after the world is drawn (e.g. by
        #: ``AttentionWrapper`` to show the focus); None draws nothing more. In human mode an
        #: env with an overlay leaves each step's frame to the overlay's owner, who draws it
        #: once the overlay is up to date: one frame per step, showing that step's overlay.
        self.render_overlay = None

    # --- resolved sensor settings ---------------------------------------------------
    @property
    def noise_model(self) -> str:
        """The range noise model in force: ``"gaussian"`` or ``"uniform"``."""
        return self.sensor_settings.noise_model

    @property
    def sensor_noise(self) -> float:
        """The relative noise level in force: σ (gaussian) or the half-width a (uniform)."""
        return self.sensor_settings.noise

    @property
    def sonar_scan_interval_s(self) -> float | None:
        """Seconds between sonar scans, or None for a scan every step."""
        return self.sensor_settings.sonar_scan_interval_s

    @property
    def laser_scan_interval_s(self) -> float | None:
        """Seconds between laser scans, or None for a scan every step."""
        return self.sensor_settings.laser_scan_interval_s

    # --- episode ------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        goal = self._goal_option(options)  # checked before anything changes: a bad option leaves the env as it was
        _check_goal_bounds(goal)
        super().reset(seed=seed)
        if self._fixed_scenario is None:
            scenario = generate_arena(self.arena, self.np_random, goal)
        else:
            scenario = self._fixed_scenario
            if goal is not None and scenario.task is not None:
                scenario = _with_goal(scenario, goal)
        goal = goal if goal is not None else (scenario.task.goal if scenario.task else None)
        _check_goal_bounds(goal)
        self.scenario, self.goal = scenario, goal
        self.world = World(scenario, self.robot_config)
        self._target_index = scenario.target_index
        geodesic = self.reward_config.progress == "geodesic"
        self._geodesic = GeodesicDistance(scenario, self.world.wall_specs) if geodesic else None
        self._limit_s = self.time_limit_s or (scenario.task.time_limit_s if scenario.task else scenario.duration_s)
        self._scans.reset()
        completed = complete_resets([self], _one_row(self.sensors.read(*self.sensing_request())))
        observation, info = completed.observations()[0], completed.infos()[0]
        if self.render_mode == "human" and self.render_overlay is None:
            self.render()
        return observation, info

    def step(self, action):
        touched = self.move(*self.command(action))
        return self.complete_step(touched, self.sensors.read(*self.sensing_request()))

    # --- the stages of a step (``attentive_gym.vector.protocol.StagedEnv``; a fleet runs them for many envs) --
    def command(self, action) -> tuple[float, float]:
        """``action`` checked and converted to the robot's command: (linear m/s, angular rad/s).

        Nothing moves. Raises ``RuntimeError`` before the first ``reset``, and ``ValueError``
        for an action of another shape, complex or non-numeric values, NaN or inf (values
        outside [-1, 1] are clipped).
        """
        if self.world is None:
            raise RuntimeError("call reset() before step()")
        linear, angular = self._check_action(action)
        return linear * self.robot_config.max_linear_mps, angular * self.robot_config.max_angular_rps

    def move(self, linear_mps: float, angular_rps: float) -> bool:
        """Advance the world by ``dt`` with the robot commanded to ``(linear_mps, angular_rps)``
        (``command``'s result); whether the robot touched anything during the step."""
        if self.world is None:
            raise RuntimeError("call reset() before step()")
        return self.world.step(self.dt, linear_mps, angular_rps)

    def sensing_request(self) -> tuple:
        """``(pose (3,), scene geometry, rng, own owner id)``: the arguments of ``sensors.read``
        (or one row of ``sensors.read_many``) for a reading of the sensors now."""
        return _pymunk_access.pose(self.world.robot.body), self.world.geometry(), self.np_random, ROBOT_ID

    def complete_step(self, touched: bool, reading: SensorReading):
        """The step's ``(observation, reward, terminated, truncated, info)`` once the world has
        moved (``touched``: ``move``'s result), from the fresh sensor reading ``reading`` (a
        ``sensors.read`` of ``sensing_request()``'s arguments, taken after the move)."""
        completed = complete_steps([self], (touched,), _one_row(reading))
        if self.render_mode == "human" and self.render_overlay is None:
            self.render()
        return (
            completed.observations()[0],
            completed.rewards[0],
            completed.terminations[0],
            completed.truncations[0],
            completed.infos()[0],
        )

    # --- helpers ------------------------------------------------------------------
    def _goal_option(self, options: dict[str, Any] | None) -> Goal | None:
        if options is None:
            return None
        if not isinstance(options, dict):
            raise TypeError(f"reset options must be a dict, got {type(options).__name__}")
        unknown = sorted(set(options) - set(_RESET_OPTIONS))
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; allowed: {list(_RESET_OPTIONS)}")
        goal = options.get("goal")
        if goal is None or isinstance(goal, Goal):
            return goal
        if isinstance(goal, (np.ndarray, list, tuple)):
            return Goal.decode(goal)
        raise ValueError(f"options['goal'] must be a Goal, its encoding, or None; got {type(goal).__name__}")

    def _check_action(self, action) -> tuple[float, float]:
        """The action as (linear, angular) floats clipped to [-1, 1], or ``ValueError``."""
        if type(action) is np.ndarray and action.shape == (2,) and action.dtype in _FLOAT_DTYPES:
            linear, angular = float(action[0]), float(action[1])  # fast path: a policy's usual output
            if math.isfinite(linear) and math.isfinite(angular):
                return min(max(linear, -1.0), 1.0), min(max(angular, -1.0), 1.0)
        linear, angular = np.clip(checked_action(action, (2,), "(linear, angular)"), -1.0, 1.0).tolist()
        return linear, angular

    def _goal_cached(self) -> tuple:
        """``(goal, goal.encode(), str(goal))`` of the current goal, computed once per goal."""
        if self._goal_cache[0] is not self.goal:
            goal = self.goal
            self._goal_cache = (
                (None, np.zeros(GOAL_ENCODING_SIZE, np.float32), "none")
                if goal is None
                else (goal, goal.encode(), str(goal))
            )
        return self._goal_cache

    # --- rendering ----------------------------------------------------------------
    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array' or 'human'")
            return None
        if self.world is None:
            raise RuntimeError("call reset() before render()")
        from attentive_gym.envs.rendering import WorldRenderer

        if self._renderer is None or self._renderer_bounds != self.scenario.bounds:
            if self._renderer is not None:
                self._renderer.close()
            self._renderer = WorldRenderer(
                self.scenario.bounds, window=self.render_mode == "human", fps=self.metadata["render_fps"]
            )
            self._renderer_bounds = self.scenario.bounds
        frame = self._renderer.render(
            self.world,
            self.sensors.laser_segments(self.world.robot.pose, self._reading),
            self.sensors.sonar_cones(self.world.robot.pose, self._reading),
            self._target_index,
            overlay=self.render_overlay,
        )
        return frame if self.render_mode == "rgb_array" else None

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["_renderer"] = None  # pygame surfaces do not pickle; a new one is made on demand
        return state


def _one_row(reading: SensorReading) -> SensorReading:
    """``reading`` as (1, ·) blocks (views), the form ``complete_steps`` takes."""
    return SensorReading(reading.sonar[None], reading.laser[None], reading.sonar_owner[None], reading.laser_owner[None])


def _with_goal(scenario: Scenario, goal: Goal) -> Scenario:
    """``scenario`` with its task's goal replaced (the target stays the same body)."""
    task = scenario.task
    return Scenario(**{**vars(scenario), "task": TaskSpec(task.target, goal, task.time_limit_s)})
