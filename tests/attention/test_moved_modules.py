"""The library's old flat module paths still import, with a ``DeprecationWarning`` (``attention._moved``)."""

from __future__ import annotations

import importlib
import importlib.util
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import attentive_gym.attention as attention
from attentive_gym.attention import _moved
from attentive_gym.attention.io.rosbag import BagTopics

REPO = Path(__file__).resolve().parents[2]
OLD_PATHS = sorted(_moved.MOVED)


@pytest.fixture
def forget(monkeypatch):
    """Forget that an old path was imported (its ``sys.modules`` entry and the package's
    attribute), so that importing it runs the finder again; undone after the test."""

    def forget_path(old: str) -> None:
        monkeypatch.delitem(sys.modules, old, raising=False)
        name = old.rsplit(".", 1)[1]
        if name in vars(attention):  # not hasattr: reading the attribute would import it
            monkeypatch.delattr(attention, name)

    return forget_path


def test_the_old_paths_are_the_flat_modules_and_the_new_ones_exist():
    package = Path(attention.__file__).parent
    for old, new in _moved.MOVED.items():
        name = old.rsplit(".", 1)[1]
        assert not (package / f"{name}.py").exists(), old
        assert new.rsplit(".", 1)[1] == name and new.count(".") == old.count(".") + 1
        assert importlib.util.find_spec(new) is not None, new


@pytest.mark.parametrize("old", OLD_PATHS)
def test_an_old_path_warns_and_gives_the_moved_module(old, forget):
    forget(old)
    new = _moved.MOVED[old]
    with pytest.warns(DeprecationWarning, match=f"{old} moved to {new}") as caught:
        module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    assert module.__name__ == new and module.__spec__.name == new  # the moved module itself, untouched
    assert sys.modules[old] is module
    assert caught[0].filename == __file__  # the warning points at the import, not at the machinery


def test_every_form_of_import_of_an_old_path_warns_at_the_importing_line(forget):
    from attentive_gym.attention.tracking import tracker

    forget("attentive_gym.attention.tracker")
    with pytest.warns(DeprecationWarning, match="tracking.tracker") as caught:
        from attentive_gym.attention import tracker as old_by_from
    assert old_by_from is tracker and caught[0].filename == __file__

    forget("attentive_gym.attention.tracker")
    with pytest.warns(DeprecationWarning, match="tracking.tracker") as caught:
        import attentive_gym.attention.tracker as old_by_import
    assert old_by_import is tracker and caught[0].filename == __file__

    forget("attentive_gym.attention.tracker")
    with pytest.warns(DeprecationWarning, match="tracking.tracker") as caught:
        old_by_attribute = attention.tracker
    assert old_by_attribute is tracker and len(caught) == 1 and caught[0].filename == __file__


def test_an_object_pickled_under_an_old_path_loads(forget):
    topics = BagTopics(laser="/scan", odometry="/odom")
    data = pickle.dumps(topics, protocol=0)
    assert b"attentive_gym.attention.io.rosbag" in data
    forget("attentive_gym.attention.rosbag")
    with pytest.warns(DeprecationWarning, match="io.rosbag"):
        loaded = pickle.loads(data.replace(b"attentive_gym.attention.io.rosbag", b"attentive_gym.attention.rosbag"))
    assert loaded == topics and type(loaded) is BagTopics


def test_a_name_that_never_was_a_module_is_still_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'tracks'"):
        attention.tracks  # noqa: B018
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("attentive_gym.attention.tracks")


def test_installing_twice_keeps_one_finder():
    _moved.install()
    _moved.install()
    assert sum(type(finder).__name__ == "_MovedFinder" for finder in sys.meta_path) == 1


def test_importing_every_module_at_its_new_path_warns_nothing():
    """In a fresh interpreter, where every import runs: a DeprecationWarning is an error."""
    code = textwrap.dedent(
        """
        import pkgutil, warnings
        warnings.simplefilter("error", DeprecationWarning)
        import attentive_gym.attention as attention
        from attentive_gym.attention import *
        names = [info.name for info in pkgutil.walk_packages(attention.__path__, "attentive_gym.attention.")]
        for name in names:
            __import__(name)
        assert "attentive_gym.attention.tracking.tracker" in names and "attentive_gym.attention.io.rosbag" in names
        print(len(names))
        """
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert int(result.stdout) >= 25
