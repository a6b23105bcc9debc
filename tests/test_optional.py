"""The lean core: without pygame or matplotlib the package imports and the environments run;
rendering and figures raise an ``ImportError`` that names the extra to install."""

import subprocess
import sys
import textwrap
from pathlib import Path

import gymnasium as gym
import pytest

import attentive_gym  # noqa: F401  (registers the environments)
from attentive_gym._optional import EXTRAS, MissingExtraError, require

REPO = Path(__file__).resolve().parents[1]
_RENDER_MESSAGE = 'rendering needs pygame: pip install "attentive_gym[render]"'


@pytest.fixture
def no_pygame(monkeypatch):
    """As if pygame were not installed (``import pygame`` raises ``ModuleNotFoundError``)."""
    monkeypatch.setitem(sys.modules, "pygame", None)


@pytest.fixture
def no_matplotlib(monkeypatch):
    """As if matplotlib were not installed, even where ``matplotlib.pyplot`` was imported before."""
    monkeypatch.setitem(sys.modules, "matplotlib", None)


def test_require_returns_the_module_asked_for():
    import matplotlib.pyplot

    assert require("matplotlib.pyplot", "plotting") is matplotlib.pyplot


def test_require_names_the_purpose_the_package_and_the_extra(no_pygame):
    with pytest.raises(MissingExtraError) as caught:
        require("pygame", "rendering")
    assert str(caught.value) == _RENDER_MESSAGE
    assert isinstance(caught.value, ImportError) and caught.value.name == "pygame"


def test_require_sees_a_missing_package_behind_a_cached_submodule(no_matplotlib):
    with pytest.raises(MissingExtraError, match=r'drawing needs matplotlib: pip install "attentive_gym\[plot\]"'):
        require("matplotlib.pyplot", "drawing")


def test_require_refuses_a_module_that_is_not_an_optional_dependency():
    with pytest.raises(
        ValueError,
        match=r"'numba' is not an optional dependency; "
        r"allowed packages: pygame, matplotlib, torch, stable_baselines3, moviepy",
    ):
        require("numba", "compiling")


def test_a_broken_install_is_not_reported_as_a_missing_extra(tmp_path, monkeypatch):
    """An import that fails inside an installed package keeps its own error."""
    (tmp_path / "broken_extra").mkdir()
    (tmp_path / "broken_extra" / "__init__.py").write_text("import a_module_that_does_not_exist\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(EXTRAS, "broken_extra", ("broken-extra", "render"))
    with pytest.raises(ModuleNotFoundError) as caught:
        require("broken_extra", "testing")
    assert not isinstance(caught.value, MissingExtraError)
    assert caught.value.name == "a_module_that_does_not_exist"


def test_each_extra_named_in_a_message_installs_its_package():
    tomllib = pytest.importorskip("tomllib")
    extras = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    for distribution, extra in EXTRAS.values():
        assert any(req.startswith(distribution) for req in extras[extra]), (extra, extras[extra])


@pytest.mark.parametrize("env_id", ["AttentiveRescue-v0", "AttentiveRescueFocus-v1"])
@pytest.mark.parametrize("render_mode", ["rgb_array", "human"])
def test_making_an_env_that_renders_without_pygame_names_the_render_extra(no_pygame, env_id, render_mode):
    with pytest.raises(MissingExtraError, match=_RENDER_MESSAGE.replace("[", r"\[").replace("]", r"\]")):
        gym.make(env_id, render_mode=render_mode)


def test_each_figure_without_matplotlib_names_the_plot_extra(no_matplotlib, tmp_path):
    from attentive_gym.agents.plots import plot_learning_curves
    from attentive_gym.experiments.figures import plot_experiment
    from attentive_gym.viz.trace_figure import plot_trace

    expected = r'needs matplotlib: pip install "attentive_gym\[plot\]"'
    with pytest.raises(MissingExtraError, match=r"drawing an attention trace " + expected):
        plot_trace(tmp_path / "trace.npz")
    with pytest.raises(MissingExtraError, match=r"drawing an experiment's figure " + expected):
        plot_experiment(None, tmp_path / "exp01.png")
    with pytest.raises(MissingExtraError, match=r"drawing a comparison's figures " + expected):
        plot_learning_curves([], tmp_path / "curves.png")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "command", [["experiment", "exp01", "--out", "{out}"], ["attend", "{out}/log.csv", "--out", "{out}"]]
)
def test_cli_commands_that_draw_stop_before_any_work_without_matplotlib(no_matplotlib, tmp_path, capsys, command):
    from attentive_gym.cli import EXIT_USAGE, main

    status = main([part.format(out=tmp_path) for part in command])
    assert status == EXIT_USAGE
    assert 'needs matplotlib: pip install "attentive_gym[plot]"' in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_the_package_and_every_environment_work_with_neither_pygame_nor_matplotlib():
    """In a fresh interpreter, so that no module imported by other tests hides an import."""
    code = textwrap.dedent(
        """
        import sys
        sys.modules["pygame"] = None  # importing them now raises ImportError
        sys.modules["matplotlib"] = None
        import gymnasium as gym
        import attentive_gym, attentive_gym.cli, attentive_gym.experiments, attentive_gym.perception
        import attentive_gym.viz, attentive_gym.wrappers
        from attentive_gym.registration import VARIANT_IDS
        for env_id in VARIANT_IDS.values():
            env = gym.make(env_id)
            env.reset(seed=0)
            env.step(env.action_space.sample())
            env.close()
        print("ok")
        """
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "ok"


@pytest.mark.parametrize("missing", ["torch", "stable_baselines3"])
@pytest.mark.parametrize("command", [["train", "--steps", "512", "--out", "{out}/run"], ["compare", "--quick"]])
def test_agent_commands_without_the_agents_extra_stop_before_any_work(monkeypatch, tmp_path, capsys, missing, command):
    from attentive_gym.cli import EXIT_USAGE, main

    monkeypatch.setitem(sys.modules, missing, None)
    monkeypatch.chdir(tmp_path)
    status = main([part.format(out=tmp_path) for part in command])
    assert status == EXIT_USAGE
    assert f'attentive-gym {command[0]} needs {EXTRAS[missing][0]}: pip install "attentive_gym[agents]"' in (
        capsys.readouterr().err
    )
    assert not list(tmp_path.iterdir())


def test_evaluate_with_video_without_moviepy_names_the_video_extra_before_loading_the_model(
    monkeypatch, tmp_path, capsys
):
    from attentive_gym.cli import EXIT_USAGE, main

    monkeypatch.setitem(sys.modules, "moviepy", None)
    status = main(["evaluate", str(tmp_path / "no-such-run"), "--video", str(tmp_path / "videos")])
    assert status == EXIT_USAGE
    err = capsys.readouterr().err
    assert 'needs moviepy: pip install "attentive_gym[video]"' in err
    assert "no-such-run" not in err  # refused before the model is looked for
    assert not list(tmp_path.iterdir())
