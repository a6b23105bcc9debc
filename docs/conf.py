"""Sphinx configuration of the attentive_gym documentation (MyST Markdown, furo theme).

Build, warnings as errors (from the repository root)::

    sphinx-build -W --keep-going -b html docs docs/_build/html
"""

from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _installed_version

project = "attentive_gym"
author = "the attentive_gym authors"
copyright = "the attentive_gym authors"
try:
    release = _installed_version("attentive_gym")
except PackageNotFoundError:  # building from a checkout that is not installed
    release = ""
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "README.md"]

# MyST: "#heading-anchors" links up to level 3 headings; "$...$" is not math (the pages use
# code spans for formulas); ::: fences for notes.
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

# API reference: the public names in each package's __all__, in source order, with the
# Google-style docstrings the code uses.
autodoc_default_options = {"members": True, "member-order": "bysource", "show-inheritance": True}
autodoc_typehints = "description"
autodoc_preserve_defaults = True
autodoc_inherit_docstrings = False  # document this project's docstrings, not those of gymnasium's base classes
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_ivar = True  # "Attributes:" as fields of the class, so properties are not described twice

html_theme = "furo"
html_title = "attentive_gym"
