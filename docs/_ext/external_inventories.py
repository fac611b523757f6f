"""The intersphinx inventories of the other packages' docs, written from a list kept here.

The docs link the names of Python, NumPy, SciPy and Matplotlib that the docstrings and pages
cite (``:class:`matplotlib.figure.Figure```, the numpydoc types ``ndarray``, ``float``,
``array_like``, ...) to those projects' own pages, through ``sphinx.ext.intersphinx``. Its usual
source, each project's ``objects.inv`` downloaded when the build starts, needs the network, and
the build must work offline. So the inventories are small files in ``docs/_inventories/``,
written by this script from :data:`ENTRIES`: each name our docs reference, with its role and
its page in that project's published docs (the ``stable`` docs, checked by hand against the
live pages when an entry is added). ``docs/conf.py`` gives intersphinx ``(url, local file)``
per project, so the links point at the published pages and no file is fetched.

The files use the Sphinx inventory format, version 2 (the one ``objects.inv`` has: four header
lines, then one zlib-compressed line per entry, ``name domain:role priority uri display``), and
are read back with Sphinx's own reader to check them. Refresh after adding an entry::

    python docs/_ext/external_inventories.py

A name the docs cite that no inventory holds fails the nitpicky build (``-n``); add it here,
with its real address, and rerun.
"""

from __future__ import annotations

import sys
import zlib
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
OUT = DOCS / "_inventories"

# project -> (published docs root, version label written in the header)
PROJECTS: dict[str, tuple[str, str]] = {
    "python": ("https://docs.python.org/3/", "3"),
    "numpy": ("https://numpy.org/doc/stable/", "stable"),
    "scipy": ("https://docs.scipy.org/doc/scipy/", "stable"),
    "matplotlib": ("https://matplotlib.org/stable/", "stable"),
}

# project -> [(name, domain:role, page and anchor relative to the project's root, display)].
# They hold every target of numpydoc's type aliases (float, int, str, bool, None, dict, tuple,
# list, callable, sequence, iterable, generator, ndarray, array_like, scalar, ...:
# numpydoc.xref.DEFAULT_LINKS), so that any of those words in a docstring's type links, and the
# names the docstrings and pages cite.
ENTRIES: dict[str, list[tuple[str, str, str, str]]] = {
    "python": [
        ("None", "py:data", "library/constants.html#None", "-"),
        ("True", "py:data", "library/constants.html#True", "-"),
        ("False", "py:data", "library/constants.html#False", "-"),
        ("bool", "py:class", "library/functions.html#bool", "-"),
        ("float", "py:class", "library/functions.html#float", "-"),
        ("int", "py:class", "library/functions.html#int", "-"),
        ("str", "py:class", "library/stdtypes.html#str", "-"),
        ("list", "py:class", "library/stdtypes.html#list", "-"),
        ("tuple", "py:class", "library/stdtypes.html#tuple", "-"),
        ("dict", "py:class", "library/stdtypes.html#dict", "-"),
        ("callable", "py:function", "library/functions.html#callable", "-"),
        ("bltin-boolean-values", "std:label", "library/stdtypes.html#bltin-boolean-values",
         "Boolean Type - bool"),
        ("iterable", "std:term", "glossary.html#term-iterable", "-"),
        ("sequence", "std:term", "glossary.html#term-sequence", "-"),
        ("generator", "std:term", "glossary.html#term-generator", "-"),
        ("contextlib.contextmanager", "py:function",
         "library/contextlib.html#contextlib.contextmanager", "-"),
        ("collections.namedtuple", "py:function",
         "library/collections.html#collections.namedtuple", "-"),
        ("abc.ABC", "py:class", "library/abc.html#abc.ABC", "-"),
        ("ctypes.Structure", "py:class", "library/ctypes.html#ctypes.Structure", "-"),
        ("collections.abc.Callable", "py:class",
         "library/collections.abc.html#collections.abc.Callable", "-"),
        ("collections.abc.Iterable", "py:class",
         "library/collections.abc.html#collections.abc.Iterable", "-"),
        ("collections.abc.Iterator", "py:class",
         "library/collections.abc.html#collections.abc.Iterator", "-"),
        ("concurrent.futures.Executor", "py:class",
         "library/concurrent.futures.html#concurrent.futures.Executor", "-"),
        ("dataclasses.asdict", "py:function", "library/dataclasses.html#dataclasses.asdict", "-"),
    ],
    "numpy": [
        ("numpy.ndarray", "py:class", "reference/generated/numpy.ndarray.html#numpy.ndarray",
         "-"),
        ("array_like", "std:term", "glossary.html#term-array_like", "-"),
        ("arrays.scalars", "std:label", "reference/arrays.scalars.html#arrays-scalars",
         "Scalars"),
        ("numpy", "py:module", "reference/index.html#module-numpy", "-"),
        ("numpy.dtype", "py:class", "reference/generated/numpy.dtype.html#numpy.dtype", "-"),
        ("numpy.float64", "py:class", "reference/arrays.scalars.html#numpy.float64", "-"),
        ("numpy.inf", "py:data", "reference/constants.html#numpy.inf", "-"),
        ("numpy.nan", "py:data", "reference/constants.html#numpy.nan", "-"),
        ("numpy.random.RandomState", "py:class",
         "reference/random/legacy.html#numpy.random.RandomState", "-"),
        ("numpy.random.Generator", "py:class",
         "reference/random/generator.html#numpy.random.Generator", "-"),
        ("numpy.random.default_rng", "py:function",
         "reference/random/generator.html#numpy.random.default_rng", "-"),
    ],
    "scipy": [
        ("scipy.integrate.solve_ivp", "py:function",
         "reference/generated/scipy.integrate.solve_ivp.html#scipy.integrate.solve_ivp", "-"),
        ("scipy.linalg.expm", "py:function",
         "reference/generated/scipy.linalg.expm.html#scipy.linalg.expm", "-"),
    ],
    "matplotlib": [
        ("matplotlib.figure.Figure", "py:class",
         "api/_as_gen/matplotlib.figure.Figure.html#matplotlib.figure.Figure", "-"),
        ("matplotlib.axes.Axes", "py:class",
         "api/_as_gen/matplotlib.axes.Axes.html#matplotlib.axes.Axes", "-"),
    ],
}


def inventory_bytes(project: str) -> bytes:
    """The inventory file of ``project``: the version-2 header, then its entries compressed."""
    _, version = PROJECTS[project]
    header = ("# Sphinx inventory version 2\n"
              f"# Project: {project}\n"
              f"# Version: {version}\n"
              "# The remainder of this file is compressed using zlib.\n")
    body = "".join(f"{name} {role} 1 {uri} {display}\n"
                   for name, role, uri, display in sorted(ENTRIES[project]))
    return header.encode() + zlib.compress(body.encode(), 9)


def inventory_path(project: str) -> Path:
    """Where the inventory of ``project`` is kept (``docs/_inventories/<project>.inv``)."""
    return OUT / f"{project}.inv"


def intersphinx_mapping() -> dict[str, tuple[str, str]]:
    """``intersphinx_mapping`` for docs/conf.py: each project's published root, local file."""
    return {p: (url, str(inventory_path(p))) for p, (url, _) in PROJECTS.items()}


def main() -> int:
    OUT.mkdir(exist_ok=True)
    for project in PROJECTS:
        inventory_path(project).write_bytes(inventory_bytes(project))
        print(f"{inventory_path(project).relative_to(DOCS.parent)}: "
              f"{len(ENTRIES[project])} entries")
    return 0


if __name__ == "__main__":
    sys.exit(main())
