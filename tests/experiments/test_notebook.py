"""notebooks/experiments.ipynb runs top to bottom (in a temporary folder) and shows five figures."""

import shutil
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

pytestmark = pytest.mark.slow  # a kernel runs the whole notebook

NOTEBOOK = Path(__file__).resolve().parents[2] / "notebooks" / "experiments.ipynb"


def test_experiments_notebook_executes(tmp_path):
    shutil.copy(NOTEBOOK, tmp_path / NOTEBOOK.name)
    notebook = nbformat.read(tmp_path / NOTEBOOK.name, as_version=4)
    NotebookClient(
        notebook, timeout=60, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    ).execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.get("outputs", [])]
    assert not [o for o in outputs if o.output_type == "error"]
    images = [o for o in outputs if o.output_type == "display_data" and "image/png" in o.get("data", {})]
    assert len(images) == 5
    assert sorted(p.name for p in (tmp_path / "experiment_figures").glob("*.png")) == [
        f"exp0{i}.png" for i in range(1, 6)
    ]
