"""Every public name of gear_dyn has a complete numpy-style docstring whose Examples run.

Two checks over ``gear_dyn.__all__`` and the public methods of its classes (functions defined
in the class body; properties are attributes, described by their own one-line docstrings):

- numpydoc's own validation (:func:`numpydoc.validate.validate`, the checks behind
  ``numpydoc lint``) for the codes in :data:`ENFORCED`;
- the Examples sections run as doctests (:mod:`doctest`, ``ELLIPSIS`` and
  ``NORMALIZE_WHITESPACE``), in the namespace of the module that defines the name.
"""

from __future__ import annotations

import doctest
import inspect
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from numpydoc.validate import validate

import gear_dyn

#: numpydoc validation codes enforced on every public name and public method
ENFORCED = {
    "GL08": "the object has a docstring",
    "PR01": "every parameter is documented",
    "PR02": "no documented parameter that the signature does not have",
    "RT01": "a Returns section where the callable returns something",
    "SA01": "a See Also section",
    "EX01": "an Examples section",
}


def _inherits_doc(cls: type, name: str, value: Any) -> bool:
    """An override without a docstring of its own: the reference shows the base's text
    (autodoc inherits docstrings), which is checked where the base is."""
    return getattr(value, "__doc__", None) is None and any(
        getattr(getattr(base, name, None), "__doc__", None) for base in cls.__mro__[1:]
    )


def _public_methods(cls: type) -> Iterator[str]:
    """Names of the public methods defined in ``cls`` itself (not inherited, no properties,
    no undocumented overrides of a documented base method)."""
    for name, value in vars(cls).items():
        if name.startswith("_") or _inherits_doc(cls, name, value):
            continue
        if inspect.isfunction(value) or isinstance(value, classmethod | staticmethod):
            yield name


def _targets() -> Iterator[tuple[str, str]]:
    """(short name, import path) of each public name and each public method of its classes."""
    for name in gear_dyn.__all__:
        obj = getattr(gear_dyn, name)
        path = f"{obj.__module__}.{obj.__qualname__}"
        yield name, path
        if inspect.isclass(obj):
            for method in _public_methods(obj):
                yield f"{name}.{method}", f"{path}.{method}"


TARGETS = dict(_targets())


def _resolve(short: str) -> Any:
    obj: Any = gear_dyn
    for part in short.split("."):
        obj = getattr(obj, part)
    return obj


def test_the_targets_cover_the_public_api() -> None:
    """All 39 public names (and their methods) are checked, none left out."""
    assert len(gear_dyn.__all__) >= 39
    assert set(gear_dyn.__all__) <= set(TARGETS)


@pytest.mark.parametrize("short", sorted(TARGETS))
def test_numpydoc_validation(short: str) -> None:
    """numpydoc finds none of the :data:`ENFORCED` errors in the docstring."""
    report = validate(TARGETS[short])
    errors = [f"{code}: {message}" for code, message in report["errors"] if code in ENFORCED]
    assert not errors, f"{short}:\n" + "\n".join(errors)


@pytest.mark.parametrize("short", sorted(TARGETS))
def test_examples_run(short: str) -> None:
    """The Examples of the docstring pass as doctests."""
    obj = _resolve(short)
    owner = obj if not short.count(".") else _resolve(short.split(".")[0])
    globs = dict(vars(sys.modules[owner.__module__]))
    finder = doctest.DocTestFinder(recurse=False)
    tests = [t for t in finder.find(obj, short, globs=globs) if t.examples]
    assert tests, f"{short} has no doctest examples"
    runner = doctest.DocTestRunner(
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    )
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {short} failed"
