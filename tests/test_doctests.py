"""The examples in the docstrings run and print what they say (doctest).

Each public module is checked with ``doctest.testmod``; the modules that hold the main entry
points (LagrangeTop, HeavyTop, PlayTop, simulate, simulate_many, events, special, SweepSpec,
sweep) must have examples, so that they cannot silently disappear; and every public class,
function and method of ``kreisel.__all__`` has one of its own.
"""

from __future__ import annotations

import doctest
import importlib
import inspect

import pytest

import kreisel

# (module, must it hold examples?)
MODULES = [
    ("kreisel", False),
    ("kreisel._lagrange", True),
    ("kreisel._heavy", True),
    ("kreisel._play", True),
    ("kreisel._simulate", True),
    ("kreisel._batch", True),
    ("kreisel._state", False),
    ("kreisel._errors", True),
    ("kreisel._atlas", False),
    ("kreisel._trajectory", False),
    ("kreisel._sweep", True),
    ("kreisel._sweep.spec", True),
    ("kreisel._sweep.store", False),
    ("kreisel.events", True),
    ("kreisel.pivots", True),
    ("kreisel._poincare", True),
    ("kreisel.special", True),
    ("kreisel._fit", True),
    ("kreisel._observations", True),
    ("kreisel.io", True),
    ("kreisel.bodies", True),
    ("kreisel.quantum", True),
    ("kreisel.plot", False),
    ("kreisel.animate", False),
    ("kreisel.explore._geometry", True),
    ("kreisel.explore._api", True),
]


@pytest.mark.parametrize(("name", "has_examples"), MODULES, ids=[m for m, _ in MODULES])
def test_docstring_examples_run(name, has_examples):
    module = importlib.import_module(name)
    result = doctest.testmod(
        module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False
    )
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"
    if has_examples:
        assert result.attempted > 0, f"{name} has no docstring examples"


def _public_callables():
    """(name, object) of every class and function of ``kreisel.__all__`` and of the public
    methods of those classes (inherited ones too: their docstrings are what users read)."""
    for name in kreisel.__all__:
        obj = getattr(kreisel, name)
        if inspect.ismodule(obj) or not callable(obj):
            continue
        yield name, obj
        if inspect.isclass(obj):
            for attr, member in inspect.getmembers(obj):
                if attr.startswith("_"):
                    continue
                if (
                    inspect.isfunction(member)
                    or inspect.ismethod(member)
                    or callable(getattr(member, "__wrapped__", None))
                ):
                    yield f"{name}.{attr}", member


def _submodule_callables(name):
    """(name, object) of the public classes and functions defined in the submodule ``name``
    and of the public methods and properties of those classes."""
    module = importlib.import_module(name)
    for attr, obj in vars(module).items():
        if attr.startswith("_") or getattr(obj, "__module__", None) != name:
            continue
        if not (inspect.isclass(obj) or inspect.isfunction(obj)):
            continue
        yield f"{name}.{attr}", obj
        if inspect.isclass(obj):
            for m, member in vars(obj).items():
                if m.startswith("_"):
                    continue
                if isinstance(member, (staticmethod, classmethod)):
                    member = member.__func__
                if inspect.isfunction(member) or (
                    isinstance(member, property)
                    and member.fget is not None
                    and member.fget.__name__ != "<lambda>"  # plain attributes: no example
                ):
                    yield f"{name}.{attr}.{m}", member


# Submodules whose every public class, function and method has an example of its own.
EXAMPLES_EVERYWHERE = ("kreisel.quantum",)


@pytest.mark.parametrize("name", EXAMPLES_EVERYWHERE)
def test_every_public_callable_of_a_submodule_has_an_example(name):
    found = list(_submodule_callables(name))
    assert len(found) > 10, found  # the walk finds them
    missing = [n for n, obj in found if ">>>" not in (inspect.getdoc(obj) or "")]
    assert not missing, f"no >>> example in the docstring of {len(missing)}: {missing}"


def test_every_public_callable_has_an_example():
    names = [n for n, _ in _public_callables()]
    assert "LagrangeTop.exact" in names and "simulate" in names, names  # the walk finds them
    missing = [n for n, obj in _public_callables() if ">>>" not in (inspect.getdoc(obj) or "")]
    assert not missing, f"no >>> example in the docstring of {len(missing)}: {missing}"
