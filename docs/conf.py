"""Sphinx configuration of the geomexact documentation site.

Build (warnings are errors; ``scripts/test`` runs the same)::

    sphinx-build -W --keep-going -b html docs docs/_build/html

The Markdown pages are read by myst-parser.  At ``builder-inited``,
``docs/_site_tools.py`` writes ``docs/_generated/`` (not committed): the specs' pages.
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(DOCS))

import _site_tools  # noqa: E402  (docs/_site_tools.py, beside this file)

from geomexact._version import __version__  # noqa: E402

project = "geomexact"
author = "the geomexact authors"
copyright = "the geomexact authors, MIT licence"
release = __version__
version = __version__

extensions = ["myst_parser", "sphinx.ext.autodoc"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
# the tour's fragments are included by tour.md, not pages of their own
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "_generated/tour/*"]

myst_heading_anchors = 4
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
suppress_warnings: list[str] = []

html_theme = "alabaster"
html_title = f"geomexact {__version__}"
html_static_path: list[str] = []
html_theme_options = {"page_width": "1100px", "sidebar_width": "230px"}

autodoc_member_order = "bysource"
autodoc_typehints = "none"


def setup(app: object) -> dict[str, object]:
    _site_tools.setup(app)
    return {"parallel_read_safe": True}
