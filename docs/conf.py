"""Sphinx configuration of the gear_dyn documentation.

Build (warnings are errors, and every cross-reference must resolve: ``-n``), from the
repository root::

    pip install ".[docs]" && python -m sphinx -n -W --keep-going -b html docs docs/_build/html

Pages: Markdown (MyST) beside this file; the API reference from the docstrings (autodoc,
autosummary, numpydoc; ``docs/api/``); the gallery runs ``examples/plot_*.py``
(sphinx-gallery, pictures taken from the PNG files each example writes: ``_ext/gallery_files.py``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import gear_dyn

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))
import external_inventories  # noqa: E402  (docs/_ext, on the path just above)

os.environ.setdefault("MPLBACKEND", "Agg")

project = "gear_dyn"
author = "the gear_dyn authors"
copyright = "the gear_dyn authors, MIT licence"
release = version = gear_dyn.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "sphinx_copybutton",
    "demo_output",          # runs `gear-dyn demo` for the quick start (_ext/demo_output.py)
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_generated", "README.md", "gallery/*.ipynb", "gallery/*.py",
                    "gallery/*.zip", "gallery/*.md5", "gallery/*.json", "gallery/*.codeobj.json"]
templates_path = ["_templates"]

# --- MyST: the Markdown pages -----------------------------------------------------------------
# equations: $...$ inline, $$...$$ displayed (with a label: $$ ... $$ (name)), and LaTeX
# environments such as \begin{aligned}; rendered by MathJax (sphinx.ext.mathjax: loaded from
# its CDN by the reader's browser; to read the pages offline, see docs/development.md)
myst_enable_extensions = ["colon_fence", "dollarmath", "amsmath", "substitution"]
myst_dmath_double_inline = True
# {{ version }}, + the demo's figures (filled by _ext/demo_output.py)
myst_substitutions: dict[str, str] = {"version": version}
myst_heading_anchors = 3

# --- links into the other packages' docs: intersphinx, offline -----------------------------------
# Each project's inventory is a small local file (docs/_inventories/, written by
# _ext/external_inventories.py from its list of the names our docs cite, with their real
# addresses): the links point at the published pages, and the build reads no network.
intersphinx_mapping = external_inventories.intersphinx_mapping()

# nitpicky builds (-n, as CI runs them): every cross-reference must resolve. The only exceptions
# are the names of pythonfmu and pythonfmu3, shown as base classes, which have no inventory in
# docs/_inventories/. They stay plain text. One exact name per entry (no patterns), and no warning
# type is suppressed (no suppress_warnings).
nitpick_ignore = [
    ("py:class", "pythonfmu.fmi2slave.Fmi2Slave"), ("py:class", "pythonfmu.enums.Fmi2Causality"),
    ("py:class", "pythonfmu.enums.Fmi2Variability"),
    ("py:class", "pythonfmu3.fmi3slave.Fmi3Slave"), ("py:class", "pythonfmu3.enums.Fmi3Causality"),
    ("py:class", "pythonfmu3.enums.Fmi3Variability"),
]

# --- API reference: autodoc + autosummary + numpydoc -------------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autosummary_ignore_module_all = False   # a package's page lists the names of its __all__
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"          # the numpydoc Parameters sections give types and units
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
# the types of Parameters/Returns sections link to their docs: numpydoc's aliases (float, int,
# str, bool, None, ndarray, array_like, ...: numpydoc.xref.DEFAULT_LINKS) and those below; any
# other word stays plain text ("all")
numpydoc_xref_param_type = True
numpydoc_xref_ignore = "all"
numpydoc_xref_aliases = {
    "matplotlib.figure.Figure": ":class:`matplotlib.figure.Figure`",
    "matplotlib.axes.Axes": ":class:`matplotlib.axes.Axes`",
    "numpy.random.Generator": ":class:`numpy.random.Generator`",
}

# --- gallery -------------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": ["../examples"],
    "gallery_dirs": ["gallery"],
    "filename_pattern": r"/plot_",          # run every example (all are plot_*.py)
    "ignore_pattern": r"__init__\.py",
    "image_scrapers": ("gallery_files.scrape_pngs",),
    "reset_argv": "gallery_files.example_argv",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "show_memory": False,
    "min_reported_time": 1,
    # the tutorial first, then the examples by name
    "within_subsection_order": "gallery_files.TutorialFirst",
}

# --- copy button: the prompt and the output are not copied -------------------------------------
copybutton_prompt_text = r"\$ |>>> |\.\.\. "
copybutton_prompt_is_regexp = True
copybutton_only_copy_prompt_lines = False

# --- HTML ----------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"gear_dyn {version}"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 8,
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"index": []}
html_show_sourcelink = False

