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


@pytest.mark.parametrize(
    ("kinematics", "options"),
    [
        ("tracker", {}),
        ("window", {}),
        ("tracker", {"silent_goal_maps_out": True}),
        ("tracker", {"track_speed_goal_probability": True}),
    ],
)
def test_a_batch_gives_each_models_own_numbers(readings, kinematics, options):
    config = AttentionConfig(range_noise_rel=0.05, kinematics=kinematics, **options)
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
    capacity = team[2].model_state.layout.course_capacity
    for model in (team[2], solo[2]):
        for region in range(capacity + 1):  # more courses than the batch has room for
            model._courses.start_bottom_up(region % model.grid.n_regions, readings[2][half][0] - 0.01 * region)
    for step in range(half, N_STEPS):
        outputs = batch.step([run[step] for run in readings])
        for i in range(N_MODELS):
            _assert_same(_solo_step(solo[i], readings[i][step]), outputs[i])
    assert all(model.model_state.layout.course_capacity > capacity for model in team)
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


MANY = 16
MANY_STEPS = 150


@pytest.fixture(scope="module")
def many_readings():
    """``MANY`` runs of ``MANY_STEPS`` random-drive steps of the raw env at 5 % noise (seeds
    10, 11, ...): contacts, blocked and moving bodies, as in the vector envs."""
    runs = []
    for seed in range(10, 10 + MANY):
        env = make_env("raw")
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        run = []
        for _ in range(MANY_STEPS):
            obs, _, _, _, info = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
            run.append((info["time_s"], obs["sonar"].copy(), obs["laser"].copy(), obs["odometry"].copy(), None, None))
        runs.append(run)
    return runs


def _settle(models: list[AttentionModel], step: int) -> None:
    """The settings schedule of the long runs: goals from step 20 (two kinds), other
    weights for the even models from 60, a reset of model 1 at 90, vigilance from 100."""
    for i, model in enumerate(models):
        if step == 20:
            model.set_goals(GOALS[i % 2], Goal.smaller("distance", 2.0 + 0.1 * i))
        if step == 60 and i % 2 == 0:
            model.set_weights(F1=1.0, F2=0.5, F3=0.25, F4=2.0, F6=1.0)
        if step == 90 and i == 1:
            model.reset()
        if step == 100:
            model.set_state("vigilant" if i % 3 else 0.7)


@pytest.mark.parametrize("kinematics", ["tracker", "window"])
@pytest.mark.parametrize("n_models", [1, 2, MANY])
def test_batches_of_any_size_give_each_models_own_numbers(many_readings, kinematics, n_models):
    config = AttentionConfig(range_noise_rel=0.05, kinematics=kinematics)
    solo = [AttentionModel(config) for _ in range(n_models)]
    team = [AttentionModel(config) for _ in range(n_models)]
    batch = ModelBatch(team)
    fired = 0
    for step in range(MANY_STEPS):
        _settle(solo, step)
        _settle(team, step)
        outputs = batch.step([run[step] for run in many_readings[:n_models]])
        for i in range(n_models):
            _assert_same(_solo_step(solo[i], many_readings[i][step]), outputs[i])
            fired += outputs[i].fired
    assert fired > 0
    if kinematics == "tracker":
        assert sum(len(out.tracks) for out in outputs) > 0


def _toggled(models: list[AttentionModel], step: int) -> None:
    """A distance goal dropped every ``7 + i`` steps: each drop releases model i's held
    course, each return starts another, and the released ones decay for seconds."""
    for i, model in enumerate(models):
        model.set_goals(*(() if step % (7 + i) == 6 else (Goal.smaller("distance", 8.0),)))


def test_course_books_that_grow_in_a_batch_keep_each_models_numbers(many_readings):
    config = AttentionConfig(kinematics="window", td_tau_off_s=5.0, weights=(0.0, 0.0, 0.5, 0.0, 0.0, 1.0))
    solo, team = [AttentionModel(config) for _ in range(2)], [AttentionModel(config) for _ in range(2)]
    batch = ModelBatch(team)
    capacity = team[0].model_state.layout.course_capacity
    for step in range(MANY_STEPS):
        _toggled(solo, step)
        _toggled(team, step)
        outputs = batch.step([run[step] for run in many_readings[:2]])
        for i in range(2):
            _assert_same(_solo_step(solo[i], many_readings[i][step]), outputs[i])
    assert team[0].model_state.layout.course_capacity > capacity  # the courses outgrew the first buffers
    assert team[0].model_state.layout is team[1].model_state.layout  # and the batch followed


def test_a_pickled_batched_model_goes_on_alone_and_the_batch_goes_on(many_readings):
    config = AttentionConfig(range_noise_rel=0.05)
    solo, team = [AttentionModel(config) for _ in range(4)], [AttentionModel(config) for _ in range(4)]
    batch = ModelBatch(team)
    for step in range(40):
        _settle(solo, step), _settle(team, step)
        batch.step([run[step] for run in many_readings[:4]])
        for i in range(4):
            _solo_step(solo[i], many_readings[i][step])
    data = pickle.dumps(team[2])
    assert len(data) < 1.5 * len(pickle.dumps(solo[2]))  # its own rows, not the batch's buffers
    alone, alone_solo = pickle.loads(data), pickle.loads(pickle.dumps(solo[2]))
    for step in range(40, 80):
        outputs = batch.step([run[step] for run in many_readings[:4]])
        for i in range(4):
            _assert_same(_solo_step(solo[i], many_readings[i][step]), outputs[i])
        _assert_same(_solo_step(alone_solo, many_readings[2][step]), _solo_step(alone, many_readings[2][step]))


def test_a_batched_steps_outputs_are_views_of_one_record(many_readings):
    team = [AttentionModel() for _ in range(3)]
    outputs = ModelBatch(team).step([run[0] for run in many_readings[:3]])
    record = outputs[0].F.base
    assert record is not None and record.dtype.names is not None  # a structured array
    for out in outputs:
        for name in FIELDS:
            assert getattr(out, name).base is record, name
    assert outputs[0].goal_fulfilled.dtype == np.bool_ and outputs[0]._sources[2].dtype == np.bool_


@pytest.mark.parametrize(
    ("member", "change", "message"),
    [
        (7, lambda r: (r[0], r[1], np.where(np.arange(180) == 5, np.nan, r[2]), *r[3:]), "laser readings must be"),
        (12, lambda r: (r[0], r[1][:5], *r[2:]), "sonar must hold"),
        (3, lambda r: (r[0] - 1.0, *r[1:]), "t must increase"),
        (9, lambda r: (*r[:3], (0.1, np.inf), *r[4:]), "odometry must be 2 finite"),
        (15, lambda r: (*r[:4], r[0] + 1.0, None), "sonar_time_s"),
    ],
)
def test_one_bad_reading_among_many_raises_before_any_model_changes(many_readings, member, change, message):
    config = AttentionConfig(range_noise_rel=0.05)
    solo, team = [AttentionModel(config) for _ in range(MANY)], [AttentionModel(config) for _ in range(MANY)]
    batch = ModelBatch(team)
    for step in range(5):
        batch.step([run[step] for run in many_readings])
        for i in range(MANY):
            _solo_step(solo[i], many_readings[i][step])
    readings = [run[5] for run in many_readings]
    readings[member] = change(readings[member])
    with pytest.raises(ValueError, match=f"^model {member}: {message}"):
        batch.step(readings)
    for step in range(5, 12):
        outputs = batch.step([run[step] for run in many_readings])
        for i in range(MANY):
            _assert_same(_solo_step(solo[i], many_readings[i][step]), outputs[i])


def _reform(reading: tuple, form: int) -> tuple:
    """``reading`` in another accepted form: 0 as recorded, 1 float64 arrays, 2 lists and a
    tuple odometry, 3 front sonars only and the scan times given."""
    t, sonar, laser, odometry, _, _ = reading
    if form == 1:
        return t, sonar.astype(np.float64), laser.astype(np.float64), odometry.astype(np.float64), None, None
    if form == 2:
        return t, sonar.tolist(), laser.tolist(), tuple(odometry.tolist()), None, None
    if form == 3:
        return t, sonar[:8], laser, odometry, t, t - 0.01
    return reading


@pytest.mark.parametrize("forms", [(0,), (1,), (0, 1, 2, 3)])
def test_readings_of_every_accepted_form_give_each_models_own_numbers(many_readings, forms):
    """Arrays of either float type, lists, front sonars only, scan times, mixed within a
    step: each model's numbers as its own step gives them."""
    config = AttentionConfig(range_noise_rel=0.05)
    solo, team = [AttentionModel(config) for _ in range(4)], [AttentionModel(config) for _ in range(4)]
    batch = ModelBatch(team)
    for step in range(60):
        readings = [_reform(run[step], forms[i % len(forms)]) for i, run in enumerate(many_readings[:4])]
        outputs = batch.step(readings)
        for i in range(4):
            _assert_same(_solo_step(solo[i], readings[i]), outputs[i])
