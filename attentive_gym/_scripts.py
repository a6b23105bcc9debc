"""Scripts of the repository (``tools/``, ``benchmarks/``) loaded as modules by file path.

- ``load_script(folder, name)``: the module of ``<folder>/<name>.py``.
- ``CHECKOUT_TOOLS``: the ``tools/`` folder of the checkout this package is installed from
  (it exists only in an editable install of a checkout: tools are not installed).
- ``load_checkout_tool(name, moved, replacement)``: a tool of that folder, for the
  deprecated entry points that forward to it, or a ``RuntimeError`` naming the replacement.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

__all__ = ["CHECKOUT_TOOLS", "load_checkout_tool", "load_script"]

CHECKOUT_TOOLS = Path(__file__).resolve().parents[1] / "tools"


def load_script(folder: Path, name: str) -> ModuleType:
    """The module of ``<folder>/<name>.py``, registered in ``sys.modules`` under ``name``
    (dataclasses resolve their module by name; a module already loaded from that file is
    returned as it is, so that a patch of it reaches the siblings that imported it). The
    folder is on ``sys.path`` while it loads, so that the script can import its siblings
    (``bench_env``, ``page_text``)."""
    path = Path(folder) / f"{name}.py"
    loaded = sys.modules.get(name)
    if loaded is not None and getattr(loaded, "__file__", None) == str(path):
        return loaded
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    sys.path.insert(0, str(folder))
    try:
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(folder))
    return module


def load_checkout_tool(name: str, moved: str, replacement: str, tools: Path = CHECKOUT_TOOLS) -> ModuleType:
    """The module of ``<tools>/<name>.py`` (``load_script``).

    Raises:
        RuntimeError: there is no such file (the package is not installed from a checkout),
            saying that ``moved`` (what the user ran) moved to the tool, and ``replacement``.
    """
    if not (Path(tools) / f"{name}.py").is_file():
        raise RuntimeError(
            f"{moved} moved to the repository's tools/{name}.py, which is not installed; run {replacement}"
        )
    return load_script(tools, name)
