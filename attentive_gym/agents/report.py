"""Deprecated: the README's RL results moved out of the installed package.

- The computations (``merge_rows``, ``labelled``, ``budgets``, ``targets``,
  ``clutter_targets``, ``algo_tag``, ``learning_curve_figures``, the column tuples) are in
  ``attentive_gym.agents.merged``; this module re-exports them.
- The commands that rewrite the docs (``add``, ``render``) are the repository's
  ``tools/report.py``, which ``render`` now writes ``docs/results/rl.md`` with, besides the
  other results pages and the README's headline. In a checkout of the repository (an
  editable install), where ``tools/`` is, ``main`` forwards to that tool and ``render_block``
  still works; elsewhere both raise ``RuntimeError`` naming the replacement. ``main`` takes
  the tool's options: ``add`` as before, and ``render [--check] [--root DIR]``, which writes
  every page under ``DIR`` (default: the checkout); the old ``render`` options
  ``--comparison``, ``--clutter-csv``, ``--readme`` and ``--figures`` are gone, and paths are
  the checkout's, not the working directory's.

Importing this module warns with a ``DeprecationWarning``.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from attentive_gym._scripts import CHECKOUT_TOOLS, load_checkout_tool
from attentive_gym.agents.merged import (
    CLUTTER_COLUMNS,
    COMPARISON_COLUMNS,
    algo_tag,
    budgets,
    clutter_targets,
    labelled,
    learning_curve_figures,
    merge_rows,
    targets,
)

__all__ = [
    "COMPARISON_COLUMNS",
    "CLUTTER_COLUMNS",
    "algo_tag",
    "merge_rows",
    "labelled",
    "budgets",
    "targets",
    "clutter_targets",
    "learning_curve_figures",
    "render_block",
    "main",
]

#: What replaces this module.
REPLACEMENT = (
    "attentive_gym.agents.merged for the computations, and 'python tools/report.py add|render' "
    "(in a checkout of the repository) for the commands"
)
#: The repository's tools folder, where a checkout has it.
TOOLS = CHECKOUT_TOOLS

warnings.warn(f"attentive_gym.agents.report is deprecated; use {REPLACEMENT}", DeprecationWarning, stacklevel=2)


def _tool(name: str) -> ModuleType:
    """The module ``tools/<name>.py`` of the checkout this package was installed from.

    Raises:
        RuntimeError: the package is not installed from a checkout (no ``tools/`` beside it).
    """
    return load_checkout_tool(
        name, "attentive_gym.agents.report's commands", f"it from a checkout ({REPLACEMENT})", TOOLS
    )


def render_block(
    comparison: Sequence[Mapping[str, Any]],
    clutter: Sequence[Mapping[str, Any]],
    figures: Path,
    sources: Sequence[Path],
    readme_dir: Path = Path("."),
    write_figures: bool = True,
) -> str:
    """Deprecated: ``tools/rl_page.py``'s ``results_markdown``, the results as Markdown
    (``sources`` is no longer named in it: the page's banner names them)."""
    warnings.warn(f"render_block is deprecated; use {REPLACEMENT}", DeprecationWarning, stacklevel=2)
    return _tool("rl_page").results_markdown(comparison, clutter, figures, readme_dir, write_figures)


def main(argv: Sequence[str] | None = None) -> int:
    """Deprecated: ``python tools/report.py`` with the same arguments."""
    warnings.warn(
        f"python -m attentive_gym.agents.report is deprecated; use {REPLACEMENT}", DeprecationWarning, stacklevel=2
    )
    return _tool("report").main(argv)


if __name__ == "__main__":
    sys.exit(main())
