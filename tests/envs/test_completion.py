"""The batched completion of a step (``envs.completion``) against each member's own step, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from attentive_gym.attention.goals import Goal
from attentive_gym.envs.completion import INFO_KEYS, complete_resets, complete_steps
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.envs.reward import RewardConfig
from attentive_gym.sensors import SensorReading

#: Members of one batch that differ in everything the completion reads: scan intervals
#: (the usarsim profile, and intervals that are not multiples of each other), a fixed
#: scenario without a task (reward 0, truncation by its duration), a crowded arena whose
#: targets pursue or evade the robot (contacts, blocked movers), short limits (truncation),
#: a large success radius (episodes that end by success) and another reward.
MEMBERS = (
    {"sensor_profile": "usarsim", "time_limit_s": 3.0},
    {"scenario": "exp01"},
    {
        "time_limit_s": 2.0,
        "arena_size_m": 7.0,
        "num_distractors": 4,
        "rubble_per_100m2": 15.0,
        "goals": (Goal.direction_is("towards"), Goal.direction_is("away")),
    },
    {"sonar_scan_interval_s": 0.15, "laser_scan_interval_s": 0.1, "time_limit_s": 1.5},
    {"reward": RewardConfig(success_radius_m=4.0, collision_per_s=3.0), "arena_size_m": 7.0},
)


def _typed(value):
    """``value`` with its types spelled out, so that equal numbers of other types differ."""
    if isinstance(value, dict):
        return {key: _typed(item) for key, item in value.items()}
    if isinstance(value, (tuple, list)):
        return (type(value).__name__, [_typed(item) for item in value])
    if isinstance(value, np.ndarray):
        return ("ndarray", value.dtype.str, value.shape, value.tobytes())
    return (type(value).__name__, value)


def _stacked(readings: list[SensorReading]) -> SensorReading:
    return SensorReading(
        *(np.stack([getattr(r, name) for r in readings]) for name in SensorReading.__dataclass_fields__)
    )


def test_a_batch_of_members_completes_as_each_member_alone():
    """Singles step by ``step``; the twins move alone and complete in one ``complete_steps`` call."""
    singles = [AttentiveRescueEnv(**kwargs) for kwargs in MEMBERS]
    twins = [AttentiveRescueEnv(**kwargs) for kwargs in MEMBERS]
    for j, (single, twin) in enumerate(zip(singles, twins)):
        assert _typed(single.reset(seed=j)) == _typed(twin.reset(seed=j))
    rng = np.random.default_rng(1)
    ended = {"terminated": 0, "truncated": 0}
    touched_any = scanned_apart = False
    for _ in range(160):
        actions = rng.uniform((0.2, -1.2), (1.2, 1.2), (len(MEMBERS), 2)).astype(np.float32)  # mostly forward
        expected = [single.step(action) for single, action in zip(singles, actions)]
        touched = [twin.move(*twin.command(action)) for twin, action in zip(twins, actions)]
        completed = complete_steps(twins, touched, _stacked([t.sensors.read(*t.sensing_request()) for t in twins]))
        got = list(
            zip(
                completed.observations(),
                completed.rewards,
                completed.terminations,
                completed.truncations,
                completed.infos(),
            )
        )
        assert _typed(got) == _typed(expected)
        assert list(completed.infos()[0]) == list(completed.info) == list(INFO_KEYS)
        touched_any |= any(touched)
        scanned_apart |= completed.info["laser_time_s"] != completed.info["time_s"]
        for j, (_, _, terminated, truncated, _) in enumerate(expected):
            if terminated or truncated:
                ended["terminated" if terminated else "truncated"] += 1
                assert _typed(singles[j].reset()) == _typed(twins[j].reset())
    assert touched_any, "no member touched anything"
    assert scanned_apart, "no reading was held"
    assert ended["terminated"] > 0 and ended["truncated"] > 0


def test_a_batched_reset_gives_each_members_first_observation_and_info():
    singles = [AttentiveRescueEnv(**kwargs) for kwargs in MEMBERS]
    expected = [single.reset(seed=3) for single in singles]
    twins = [AttentiveRescueEnv(**kwargs) for kwargs in MEMBERS]
    for twin in twins:
        twin.reset(seed=3)
    fresh = _stacked([twin._reading for twin in twins])  # what each reset read (every sensor scans at a reset)
    for twin in twins:
        twin._scans.reset()
    completed = complete_resets(twins, fresh)
    assert _typed(list(zip(completed.observations(), completed.infos()))) == _typed(expected)
    assert not any(completed.rewards) and not any(completed.terminations) and not any(completed.truncations)


def test_bad_blocks_are_refused_naming_what_was_wrong():
    envs = [AttentiveRescueEnv(), AttentiveRescueEnv()]
    for env in envs:
        env.reset(seed=0)
    reading = _stacked([env.sensors.read(*env.sensing_request()) for env in envs])
    with pytest.raises(ValueError, match=r"touched must have one flag per env \(2\), got 1"):
        complete_steps(envs, [False], reading)
    one = SensorReading(reading.sonar[:1], reading.laser, reading.sonar_owner, reading.laser_owner)
    with pytest.raises(ValueError, match=r"fresh.sonar must be a \(k, ·\) block with k = 2 rows .*got \(1, 16\)"):
        complete_steps(envs, [False, False], one)
