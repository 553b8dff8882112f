"""The examples in the docstrings run and print what they say (doctest).

Each public module is checked with ``doctest.testmod``; the modules that hold the main entry
points (LagrangeTop, HeavyTop, PlayTop, simulate, simulate_many, events, special, SweepSpec,
sweep) must have examples, so that they cannot silently disappear.
"""

from __future__ import annotations

import doctest
import importlib

import pytest

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
    ("kreisel.special", True),
    ("kreisel.plot", False),
    ("kreisel.animate", False),
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
