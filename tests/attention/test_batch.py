"""``ModelBatch``: models stepped together give each model's own numbers, bit for bit."""

import pickle

import numpy as np
import pytest

from attentive_gym.attention import AttentionConfig, AttentionModel, Goal
from attentive_gym.attention.compiled.batch import ModelBatch
from attentive_gym.wrappers.variants import make_env

N_MODELS = 3
N_STEPS = 120
GOALS = (Goal.between("speed", 0.5, 0.9), Goal.between("speed", 0.15, 0.45))
FIELDS = ("F", "C", "C_BU", "C_TD", "M", "L", "origins", "goal_fulfilled", "directions", "speeds_mps", "distances_m")


@pytest.fixture(scope="module")
def readings():
    """``(t, sonar, laser, odometry, sonar_time_s, laser_time_s)`` of ``N_STEPS`` random-drive
    steps of the raw env at 5 % noise, one run per model (seeds 0, 1, 2)."""
    runs = []
    for seed in range(N_MODELS):
        env = make_env("raw")
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        run = []
        for _ in range(N_STEPS):
            obs, _, _, _, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
            run.append((info["time_s"], obs["sonar"].copy(), obs["laser"].copy(), obs["odometry"].copy(), None, None))
        runs.append(run)
    return runs


def _models(config: AttentionConfig) -> list[AttentionModel]:
    models = [AttentionModel(config) for _ in range(N_MODELS)]
    for i, model in enumerate(models):
        model.set_goals(GOALS[i % 2])
    return models


def _assert_same(solo, batched) -> None:
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(solo, name), getattr(batched, name), err_msg=name)
    assert (solo.t, solo.focus, solo.fired, solo.origin, solo.saliency) == (
        batched.t,
        batched.focus,
        batched.fired,
        batched.origin,
        batched.saliency,
    )
    assert solo.tracks == batched.tracks


def _solo_step(model: AttentionModel, reading: tuple):
    t, sonar, laser, odometry, sonar_time_s, laser_time_s = reading
    return model.step(t, sonar, laser, odometry, sonar_time_s=sonar_time_s, laser_time_s=laser_time_s)


@pytest.mark.parametrize("kinematics", ["tracker", "window"])
def test_a_batch_gives_each_models_own_numbers(readings, kinematics):
    config = AttentionConfig(range_noise_rel=0.05, kinematics=kinematics)
    solo, team = _models(config), _models(config)
    batch = ModelBatch(team)
    for step in range(N_STEPS):
        outputs = batch.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _assert_same(_solo_step(solo[i], readings[i][step]), outputs[i])
    assert sum(len(out.tracks) for out in outputs) > 0 or kinematics == "window"


def test_members_steps_some_models_and_lone_steps_act_on_the_batch(readings):
    config = AttentionConfig(range_noise_rel=0.05)
    solo, team = _models(config), _models(config)
    batch = ModelBatch(team)
    for step in range(N_STEPS):
        if step % 3 == 0:  # model 1 alone, by its own step; the others together
            _assert_same(_solo_step(solo[1], readings[1][step]), _solo_step(team[1], readings[1][step]))
            members = [2, 0]
        else:
            members = [0, 1, 2]
        outputs = batch.step([readings[i][step] for i in members], members)
        for i, output in zip(members, outputs):
            _assert_same(_solo_step(solo[i], readings[i][step]), output)
        if step == 40:
            team[0].reset(), solo[0].reset()


def test_models_that_left_the_batch_are_taken_back(readings):
    """A pickled batch (its models' arrays are copies then) and a course book grown past the
    batch's capacity both continue as the models alone do."""
    config = AttentionConfig(range_noise_rel=0.05)
    solo, team = _models(config), _models(config)
    batch = ModelBatch(team)
    half = N_STEPS // 2
    for step in range(half):
        batch.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _solo_step(solo[i], readings[i][step])
    clone, clone_solo = pickle.loads(pickle.dumps(batch)), pickle.loads(pickle.dumps(solo))
    capacity = team[2]._courses._bu_regions.shape[0]
    for model in (team[2], solo[2]):
        for region in range(capacity + 1):  # more courses than the batch has room for
            model._courses.start_bottom_up(region % model.grid.n_regions, readings[2][half][0] - 0.01 * region)
    for step in range(half, N_STEPS):
        outputs = batch.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _assert_same(_solo_step(solo[i], readings[i][step]), outputs[i])
    assert batch._arrays["_bu_regions"].shape[1] > capacity
    for step in range(half, N_STEPS):
        outputs = clone.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _assert_same(_solo_step(clone_solo[i], readings[i][step]), outputs[i])


def test_a_bad_reading_raises_before_any_model_changes(readings):
    config = AttentionConfig(range_noise_rel=0.05)
    solo, team = _models(config), _models(config)
    batch = ModelBatch(team)
    for step in range(10):
        batch.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _solo_step(solo[i], readings[i][step])
    t, sonar, laser, odometry, _, _ = readings[2][10]
    bad_laser = laser.copy()
    bad_laser[5] = np.nan
    with pytest.raises(ValueError, match="laser readings must be finite"):
        batch.step([readings[0][10], readings[1][10], (t, sonar, bad_laser, odometry, None, None)])
    with pytest.raises(ValueError, match="take 2 readings, got 3"):
        batch.step([run[10] for run in readings], [0, 1])
    with pytest.raises(ValueError, match="distinct indices"):
        batch.step([readings[0][10], readings[0][10]], [0, 0])
    for step in range(10, 20):  # nothing changed: the batch goes on as the models alone
        outputs = batch.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _assert_same(_solo_step(solo[i], readings[i][step]), outputs[i])


def test_models_that_cannot_share_a_batch_are_refused():
    with pytest.raises(ValueError, match="at least one model"):
        ModelBatch([])
    with pytest.raises(ValueError, match="configuration differs"):
        ModelBatch([AttentionModel(), AttentionModel(AttentionConfig(kinematics="window"))])
    with pytest.raises(ValueError, match="sonar grid"):
        ModelBatch([AttentionModel(AttentionConfig(grid="laser"))])
    model = AttentionModel()
    with pytest.raises(ValueError, match="each model once"):
        ModelBatch([model, model])
