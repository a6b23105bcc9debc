"""Moved modules' old paths (the batched environments', and the agents' statistics) still
import, with a ``DeprecationWarning`` pointing at the importing line, and give the modules
at their new paths themselves."""

from __future__ import annotations

import importlib
import pickle
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import pytest

import attentive_gym.agents as agents
import attentive_gym.envs as envs
from attentive_gym import _moved, statistics
from attentive_gym.vector import fleet, sb3, vector_env

REPO = Path(__file__).resolve().parents[2]
OLD_PATHS = {
    "attentive_gym.envs.fleet": fleet,
    "attentive_gym.envs.vector_env": vector_env,
    "attentive_gym.agents.native_vec": sb3,
    "attentive_gym.agents.statistics": statistics,
}


@pytest.fixture
def forget(monkeypatch):
    """Forget that an old path was imported, so that importing it runs the finder again."""

    def forget_path(old: str) -> None:
        monkeypatch.delitem(sys.modules, old, raising=False)
        package, name = old.rsplit(".", 1)
        if name in vars(sys.modules[package]):
            monkeypatch.delattr(sys.modules[package], name)

    return forget_path


@pytest.mark.parametrize("old", sorted(OLD_PATHS))
def test_an_old_path_warns_at_the_import_and_gives_the_moved_module(old, forget):
    forget(old)
    new = OLD_PATHS[old]
    with pytest.warns(DeprecationWarning, match=f"{old} moved to {new.__name__}") as caught:
        module = importlib.import_module(old)
    assert module is new and sys.modules[old] is new
    assert caught[0].filename == __file__


#: The names each old module exported.
OLD_NAMES = {
    "attentive_gym.envs.fleet": ("Fleet", "stack_observations"),
    "attentive_gym.envs.vector_env": ("AttentiveRescueVectorEnv", "make_vector_env", "batch_infos", "AUTORESET_MODES"),
    "attentive_gym.agents.native_vec": ("NativeVecEnv",),
    "attentive_gym.agents.statistics": ("bootstrap_ci", "iqm", "probability_of_improvement", "performance_profile"),
}


@pytest.mark.parametrize("old", sorted(OLD_NAMES))
def test_an_old_path_still_has_every_name_it_exported(old):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # the warning itself: the tests above
        module = importlib.import_module(old)
    assert all(hasattr(module, name) for name in OLD_NAMES[old])


def test_every_form_of_import_warns_at_the_importing_line(forget):
    forget("attentive_gym.envs.fleet")
    with pytest.warns(DeprecationWarning, match="vector.fleet") as caught:
        from attentive_gym.envs.fleet import Fleet
    assert Fleet is fleet.Fleet and caught[0].filename == __file__

    forget("attentive_gym.envs.vector_env")
    with pytest.warns(DeprecationWarning, match="vector.vector_env") as caught:
        from attentive_gym.envs import vector_env as old_module
    assert old_module is vector_env and caught[0].filename == __file__

    forget("attentive_gym.agents.native_vec")
    with pytest.warns(DeprecationWarning, match="vector.sb3") as caught:
        old_attribute = agents.native_vec
    assert old_attribute is sb3 and len(caught) == 1 and caught[0].filename == __file__


def test_an_object_pickled_under_an_old_path_loads(forget):
    data = pickle.dumps(vector_env.make_vector_env, protocol=0)  # a function pickles by its module path
    assert b"attentive_gym.vector.vector_env" in data
    forget("attentive_gym.envs.vector_env")
    with pytest.warns(DeprecationWarning, match="vector.vector_env"):
        loaded = pickle.loads(data.replace(b"attentive_gym.vector.vector_env", b"attentive_gym.envs.vector_env"))
    assert loaded is vector_env.make_vector_env


def test_the_new_paths_warn_nothing_and_need_no_sb3():
    """In a fresh interpreter without stable-baselines3, a DeprecationWarning being an error: the
    vector package imports, and its SB3 adapter names the extra it needs."""
    code = textwrap.dedent(
        """
        import sys, warnings
        warnings.simplefilter("error", DeprecationWarning)
        sys.modules["stable_baselines3"] = None  # as if not installed
        import attentive_gym.vector as vector
        from attentive_gym.vector import Fleet, fleet, protocol, threads, vector_env
        from attentive_gym.wrappers import make_env
        from attentive_gym._optional import MissingExtraError
        try:
            vector.NativeVecEnv
        except MissingExtraError as error:
            print(error)
        """
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert 'needs stable-baselines3: pip install "attentive_gym[agents]"' in result.stdout


def test_names_that_never_were_modules_are_attribute_errors():
    with pytest.raises(AttributeError, match="has no attribute 'fleets'"):
        envs.fleets  # noqa: B018
    with pytest.raises(AttributeError, match="has no attribute 'native'"):
        agents.native  # noqa: B018


def test_an_old_path_cannot_be_registered_for_two_new_ones():
    with pytest.raises(ValueError, match="already registered as moved to attentive_gym.vector.fleet"):
        _moved.install({"attentive_gym.envs.fleet": "attentive_gym.vector.protocol"})
    assert _moved.MOVED["attentive_gym.envs.fleet"] == "attentive_gym.vector.fleet"
