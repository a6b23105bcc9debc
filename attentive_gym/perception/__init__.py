"""Scripted baselines and perception metrics over the attended environments.

What ``benchmarks/bench_perception.py`` measures the attentional model with, as tested
library code:

- ``controllers``: scripted policies (``FocusController``, ``memory_controller``, the
  ``true_bearing_controller`` oracle, ``RandomController``, ``Wander``, ``stand_still``)
  and ``control_success``, how often one reaches the target;
- ``records``: ``record_episode``, one episode's truth and the model's outputs step by step
  (``EpisodeRecord``);
- ``metrics``: the speed error, the focus on target and why it is or is not there, from
  records;
- ``geometry``: robot-frame geometry and what counts as in view;
- ``settings``: the benchmark's attended environments (``make_attentive_env``) and arenas;
- ``motion``: scenes where a walker stops and goes or runs along structure, and the onset
  latency, false moving labels and recall measured on them (``record_motion``,
  ``motion_metrics``);
- ``bound``: the perfect-perception bound, the model fed the simulator's true kinematics
  of the movers the laser sees (``PerfectPerceptionModel``, ``make_bound_env``: a raw
  environment whose ``info["attention"]`` is that model's output).

The environments come from ``attentive_gym.wrappers.make_env`` (an attended variant, whose
``info["attention"]`` is the model's output); this package needs gymnasium and pymunk.

Example:
    >>> from attentive_gym.attention import AttentionConfig, Goal
    >>> from attentive_gym.perception import Wander, focus_on_target, record_episode, speed_metrics
    >>> from attentive_gym.wrappers import make_env
    >>> env = make_env("saliency", attention=AttentionConfig(kinematics="tracker"), num_distractors=3)
    >>> goal = Goal.between("speed", 0.5, 0.9)
    >>> record = record_episode(env, seed=0, goal=goal, policy=Wander(seed=0), seconds=2.0)
    >>> record.region_speed.shape == (len(record.t_s), 8)
    True
    >>> focus = focus_on_target([record])[str(goal)]   # focus.rate of focus.steps, focus.low–high
    >>> metrics = speed_metrics([record])                    # region_median_mps, ...
"""

from attentive_gym.perception.controllers import (
    FocusController,
    Policy,
    RandomController,
    Wander,
    control_success,
    focus_bearing,
    memory_controller,
    stand_still,
    steer,
    true_bearing_controller,
)
from attentive_gym.perception.geometry import in_sight, in_view, region_of, to_robot_frame, true_target_bearing
from attentive_gym.perception.metrics import (
    case_key,
    error_stats,
    focus_after_turns,
    focus_by_track_age,
    focus_on_target,
    pair_masks,
    speed_metrics,
    target_cases,
)
from attentive_gym.perception.records import TARGET_CASES, EpisodeRecord, record_episode, static_regions
from attentive_gym.perception.settings import CONTROL_ARENA, PERCEPTION_ARENA, VARIANT, make_attentive_env

__all__ = [
    "CONTROL_ARENA",
    "PERCEPTION_ARENA",
    "TARGET_CASES",
    "VARIANT",
    "EpisodeRecord",
    "FocusController",
    "Policy",
    "RandomController",
    "Wander",
    "case_key",
    "control_success",
    "error_stats",
    "focus_after_turns",
    "focus_bearing",
    "focus_by_track_age",
    "focus_on_target",
    "in_view",
    "in_sight",
    "make_attentive_env",
    "memory_controller",
    "pair_masks",
    "record_episode",
    "region_of",
    "speed_metrics",
    "stand_still",
    "static_regions",
    "steer",
    "target_cases",
    "to_robot_frame",
    "true_bearing_controller",
    "true_target_bearing",
]
