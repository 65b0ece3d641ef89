"""Sphinx configuration: the documentation site (make docs; warnings are errors).

Markdown pages through MyST, the API reference from the docstrings (autodoc, numpy style),
and a gallery made at build time by running the examples (gallery.py), so a broken example
or a stale name fails the build.
"""

from __future__ import annotations

import sys
from pathlib import Path

from sphinx.application import Sphinx

sys.path.insert(0, str(Path(__file__).resolve().parent))

project = "stiction"
author = "the stiction developers"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
source_suffix = {".md": "markdown"}
exclude_patterns = ["_build"]
myst_heading_anchors = 3
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_custom_sections = ["Ports", "Variables"]
autodoc_member_order = "bysource"
html_theme = "alabaster"
html_title = "stiction"


def setup(app: Sphinx) -> None:
    """Run the examples into docs/_generated before the pages are read."""
    from gallery import write_gallery

    app.connect("builder-inited", lambda app: write_gallery(Path(app.srcdir)))
