"""The modules of python/kreisel import one another without cycles.

The graph is read from the source with ``ast`` (nothing is imported): an edge for every
import of a kreisel module, at module level or inside a function, relative or absolute; an
import of a package is an edge to its ``__init__``. Imports under ``if TYPE_CHECKING:`` are
left out (they never run). The root ``kreisel/__init__.py`` may import submodules, but a
submodule that imports ``kreisel`` (or a name from it) depends on ``__init__``, which
closes a cycle.
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "python" / "kreisel"

# Edges that close cycles in files other people are changing now; each one goes when its
# cycle is broken (test_known_edges_still_close_cycles then says so).
# Edges that close a cycle still to be removed (none left: the one-stack rewrite removed
# _play <-> _simulate and _config -> kreisel); the tests below keep this set honest.
KNOWN: set = set()


def _module_names(root: Path) -> dict:
    """{module name: file} for every module and package under `root` (stubs of compiled
    modules too: they import nothing)."""
    out = {}
    for path in sorted(root.rglob("*.py*")):
        if path.suffix not in (".py", ".pyi"):
            continue
        parts = path.relative_to(root.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out.setdefault(".".join(parts), path)
    return out


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imports(tree: ast.AST):
    """Every Import and ImportFrom node, however deep, but not under `if TYPE_CHECKING:`."""
    todo = [tree]
    while todo:
        node = todo.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        elif isinstance(node, ast.If) and _is_type_checking(node.test):
            todo.extend(node.orelse)
            continue
        todo.extend(ast.iter_child_nodes(node))


def _target(name: str, modules: dict) -> str | None:
    """The module an import of `name` runs: `name` itself, else its longest known parent."""
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name or None


def import_graph(root: Path = PACKAGE) -> dict:
    """{module: set of the modules of the package `root` that it imports}."""
    top = root.name
    modules = _module_names(root)
    graph = {}
    for name, path in modules.items():
        edges = graph.setdefault(name, set())
        if path.suffix == ".pyi":
            continue
        is_package = path.name == "__init__.py"
        package = name if is_package else name.rpartition(".")[0]
        for node in _imports(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.split(".")[0] == top:
                        edges.add(_target(alias.name, modules))
                continue
            if node.level:
                base = package.split(".")
                base = ".".join(base[: len(base) - (node.level - 1)])
                base = f"{base}.{node.module}" if node.module else base
            else:
                base = node.module or ""
            if base.split(".")[0] != top:
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                # a submodule by that name, else a name defined in `base`
                edges.add(sub if sub in modules else _target(base, modules))
        edges.discard(None)
        edges.discard(name)  # a package's __init__ taking a name from itself
    return graph


def components(graph: dict) -> list:
    """The strongly connected components of more than one module (Tarjan's algorithm,
    iterative): each holds a cycle."""
    index, low, on_stack, stack, comps = {}, {}, set(), [], []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = set()
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.add(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    comps.append(comp)
    return comps


def cycles(graph: dict) -> list:
    """One cycle (a list of modules, first repeated last) in every strongly connected
    component."""
    return [_cycle_in(graph, comp) for comp in components(graph)]


def _cycle_in(graph: dict, comp: set) -> list:
    """A shortest cycle through the first module of a strongly connected component."""
    start = min(comp)
    prev, frontier = {start: None}, [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(graph[v] & comp):
                if w == start:
                    path = [v]
                    while prev[path[-1]] is not None:
                        path.append(prev[path[-1]])
                    return [*reversed(path), start]
                if w not in prev:
                    prev[w] = v
                    nxt.append(w)
        frontier = nxt
    raise AssertionError(f"no cycle in {comp}")  # pragma: no cover


def _without(graph: dict, edges: set) -> dict:
    return {v: {w for w in ws if (v, w) not in edges} for v, ws in graph.items()}


def test_the_graph_sees_every_kind_of_import(tmp_path):
    files = {
        "__init__.py": "from . import a\nfrom .sub import f\n",
        "a.py": "import os\nfrom . import b, CONST\nfrom .c import g\n",
        "b.py": "def h():\n    import kreisel.sub.d\n    from kreisel import c\n",
        "c.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from . import a\n"
        "else:\n    from . import _ext\n",
        "_ext.pyi": "def g() -> None: ...\n",
        "sub/__init__.py": "from .. import b\nfrom ..c import g as f\n",
        "sub/d.py": "from . import f\nfrom .. import kreisel_name\n\nclass K:\n"
        "    def m(self):\n        import kreisel\n        from kreisel.sub.d import K\n",
    }
    for name, text in files.items():
        path = tmp_path / "kreisel" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    assert import_graph(tmp_path / "kreisel") == {
        "kreisel": {"kreisel.a", "kreisel.sub"},
        "kreisel.a": {"kreisel.b", "kreisel", "kreisel.c"},
        "kreisel.b": {"kreisel.sub.d", "kreisel.c"},
        "kreisel.c": {"kreisel._ext"},
        "kreisel._ext": set(),
        "kreisel.sub": {"kreisel.b", "kreisel.c"},
        "kreisel.sub.d": {"kreisel.sub", "kreisel"},
    }


def test_the_graph_of_kreisel_holds_the_imports_it_should():
    graph = import_graph()
    assert "kreisel._sweep.run" in graph and "kreisel._core" in graph
    # `from . import _core` (a compiled module) and `from ._errors import ...`
    assert {"kreisel._core", "kreisel._errors"} <= graph["kreisel._batch"]
    # relative imports from a subpackage, and a function-level import
    assert "kreisel._config" in graph["kreisel._sweep.spec"]
    assert "kreisel._batch" in graph["kreisel._sweep.run"]
    # `from . import plot` is the module; `from . import __version__` is the package root
    assert {"kreisel.plot", "kreisel"} <= graph["kreisel._run"]
    # function-level imports of siblings
    assert {"kreisel._heavy", "kreisel._play"} <= graph["kreisel._config"]
    # an import of a subpackage is an edge to its __init__
    assert "kreisel._sweep" in graph["kreisel._cli"]


def test_cycles_are_found_and_shown():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set()}
    assert cycles(graph) == [["a", "b", "c", "a"]]
    assert cycles(_without(graph, {("c", "a")})) == []


def test_no_import_cycles_besides_the_known_ones():
    found = cycles(_without(import_graph(), KNOWN))
    assert not found, "import cycles:\n" + "\n".join(" -> ".join(c) for c in found)


def test_known_edges_still_close_cycles():
    """A known edge that is gone, or no longer closes a cycle, leaves KNOWN."""
    graph = import_graph()
    for edge in sorted(KNOWN):
        assert edge[1] in graph[edge[0]], f"{edge} is gone: remove it from KNOWN"
        others = _without(graph, KNOWN - {edge})
        assert any(set(edge) <= comp for comp in components(others)), (
            f"{edge} closes no cycle: remove it from KNOWN"
        )
