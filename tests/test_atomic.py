"""Atomic writes (attentive_gym._atomic): the old file survives a failed or interrupted
write, no temporary file is left, and the permissions are an ordinary file's."""

import os
import stat

import pytest

from attentive_gym._atomic import atomic_file, save_figure


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def test_a_new_file_gets_the_umask_s_permissions_and_a_replaced_one_keeps_its_own(tmp_path):
    mask = os.umask(0o022)
    try:
        new = tmp_path / "sub" / "new.csv"
        with atomic_file(new) as handle:
            handle.write("a,b\n")
        assert new.read_text() == "a,b\n" and _mode(new) == 0o644  # not mkstemp's 0o600
        new.chmod(0o640)
        with atomic_file(new) as handle:
            handle.write("c\n")
        assert new.read_text() == "c\n" and _mode(new) == 0o640
    finally:
        os.umask(mask)


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
def test_an_interrupted_write_leaves_the_old_file_whole_and_nothing_else(tmp_path, error):
    path = tmp_path / "results.csv"
    path.write_bytes(b"old")
    with pytest.raises(error):
        with atomic_file(path, binary=True) as handle:
            handle.write(b"half of the new")
            raise error
    assert path.read_bytes() == b"old"
    assert os.listdir(tmp_path) == ["results.csv"]


def test_a_figure_interrupted_while_saving_keeps_the_previous_figure(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    path = save_figure(fig, tmp_path / "curve.png", dpi=40)
    before = path.read_bytes()
    assert before.startswith(b"\x89PNG")

    def interrupted(canvas, file, **kwargs):
        file.write(b"\x89PNG partial")
        raise KeyboardInterrupt

    monkeypatch.setattr(type(fig.canvas), "print_figure", interrupted)
    with pytest.raises(KeyboardInterrupt):
        save_figure(fig, path)
    plt.close(fig)
    assert path.read_bytes() == before and os.listdir(tmp_path) == ["curve.png"]
