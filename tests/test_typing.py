"""The public API is typed: the package ships py.typed, and every public function, method and
constructor annotates its parameters and its return (mypy, run by `make lint`, checks that
the annotations hold)."""

from __future__ import annotations

import inspect
import pathlib

from test_docs import _public_objects

import kreisel


def test_the_package_ships_py_typed():
    assert (pathlib.Path(kreisel.__file__).parent / "py.typed").is_file()


def _signatures():
    for name, obj in _public_objects():
        if isinstance(obj, property):
            continue
        if inspect.isclass(obj):
            if "__init__" not in vars(obj):  # dataclasses' generated __init__ are typed
                continue
            name, obj = f"{name}.__init__", obj.__init__
        fn = inspect.unwrap(obj)
        try:
            sig = inspect.signature(fn)
        except (TypeError, ValueError):  # pragma: no cover (a builtin)
            continue
        yield name, fn, sig


def test_every_public_signature_is_annotated():
    missing = []
    for name, fn, sig in _signatures():
        ann = getattr(fn, "__annotations__", {})
        params = [
            p
            for p, par in sig.parameters.items()
            if p not in ("self", "cls") and par.kind is not inspect.Parameter.VAR_KEYWORD
        ]
        lacking = [p for p in params if p not in ann]
        if lacking or "return" not in ann:
            missing.append(f"{name}: {', '.join(lacking) or 'return'}")
    assert not missing, "not annotated:\n  " + "\n  ".join(missing)


def test_signatures_are_many():
    assert len(list(_signatures())) > 80
