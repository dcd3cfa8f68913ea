"""Sphinx configuration of the selfrighting-landscape documentation.

Build (offline, warnings as errors, the gallery executed)::

    .venv/bin/pip install -c constraints.txt -e '.[docs]'
    .venv/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

``LANDSCAPE_DOCS_FULL=1`` runs the gallery's full versions (longer sweeps, finer grids) instead of the quick
ones CI runs; each example says what its full version changes.
"""

from __future__ import annotations

import os
import sys
from importlib.metadata import version as _version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")

project = "selfrighting-landscape"
author = "selfrighting-landscape developers"
release = _version("selfrighting-landscape")
version = release
copyright = "the selfrighting-landscape developers (MIT licence)"

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
    "apiref",  # docs/_ext/apiref.py: what the API reference documents, for its templates
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_ext", "_templates", "examples", "sg_execution_times.rst"]
templates_path = ["_templates"]
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]  # pages moved from the README start at level-2 headings in places

# ---------------------------------------------------------------------------------------------- API reference
# docs/api/index.md lists the modules and their functions and classes in autosummary tables; the module tables
# generate one page per module (docs/_templates/autosummary/module.rst: docstring, constants, a table), whose
# tables generate one page per function or class (function.rst, class.rst, exception.rst: the docstring and the
# gallery's examples that use it), all into docs/api/generated/ (not committed).
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc type lines say shape and unit; the signature keeps the names
autosummary_generate = True
autosummary_ignore_module_all = False  # a module with __all__ documents what __all__ lists
autosummary_context: dict = {}  # apiref adds api_members and api_aliases
numpydoc_show_class_members = False  # autodoc's :members: lists them once
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# numpydoc's validation at build time (a failure under -W), kept to the checks that find a wrong docstring rather
# than a terse one: unknown (GL06) or misordered (GL07) sections, a documented parameter that is not in the
# signature (PR02) or out of its order (PR03), a parameter without a type (PR04) or with a malformed one (PR05,
# PR06, PR10), a missing summary (SS01), deprecation notes (GL09, GL10). The style checks (ES01 extended summary,
# EX01 examples, SA01 See Also, RT01 Returns, PR01 every parameter described, SS05/SS06 summary wording) report
# some 2,500 places: they are review matters, not build failures, and stay off.
numpydoc_validation_checks = {
    "GL06",
    "GL07",
    "GL09",
    "GL10",
    "PR02",
    "PR03",
    "PR04",
    "PR05",
    "PR06",
    "PR10",
    "SS01",
}
numpydoc_validation_exclude = {
    r"\.__\w+__$",  # dunders (dataclass machinery)
    r"\.ConvexHull$",  # scipy's, imported by geometry.hull and sim.model (its own docstring breaks GL07)
    r"^landscape\.cli\.",
    r"^landscape\.service\.",
}

# ---------------------------------------------------------------------------------------------- gallery
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",  # every plot_*.py runs at build time
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": False,  # an error is a build warning, hence a failure under -W
    "only_warn_on_example_error": True,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "show_memory": False,
    "min_reported_time": 1,
    # "Examples using ..." on each function's and class's page: the examples that call it (not committed)
    "backreferences_dir": "gen_modules/backreferences",
    "doc_module": ("geometry", "landscape", "sim"),
}

# ---------------------------------------------------------------------------------------------- HTML
html_theme = "pydata_sphinx_theme"
html_title = "selfrighting-landscape"
html_static_path = ["_static"]
html_css_files = ["custom.css"]  # long commands wrap; long titles break
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    # the header in one row at 1400 px (tests/test_docs_layout.py): every top-level page, the search as an icon
    "header_links_before_dropdown": 8,
    "navbar_persistent": ["search-button"],
    "navbar_align": "left",
    "secondary_sidebar_items": {"**": ["page-toc"], "getting_started": []},
}
# Getting started has no pages under it: its left sidebar lists its own sections instead of an empty section
# navigation (and the right one, which would repeat them, is left out).
html_sidebars = {"getting_started": ["page-toc"]}
html_show_sourcelink = False
