"""The import graph of ``src/frictionflow`` keeps the layer order of :mod:`frictionflow._layers`.

Built from the source with :mod:`ast` (nothing imported): every ``import`` and
``from ... import`` naming a frictionflow module, relative ones resolved, at
any depth.  Fails on

(a) an import of a frictionflow module inside a function or method body
    (lazy imports of optional third-party packages, dask or matplotlib, may stay);
(b) a cycle among the modules (the cycle is shown);
(c) an import of a higher layer from a lower one (file and line shown).

Imports under ``if TYPE_CHECKING:`` never run: annotations only, they are
exempt from (b) and (c) (``core.certificate.radius`` names the law type it
duck-types) but still obey (a).  A package's ``__init__`` is not counted as imported
by its submodules (Python runs it first, but the modules do not name it).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

from frictionflow._layers import LAYERS, layer_of
from frictionflow._lazy import lazy_module

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "frictionflow"


@dataclass(frozen=True)
class Import:
    source: str  # importing module
    target: str  # imported module
    path: Path
    line: int
    in_function: bool
    type_only: bool

    def where(self) -> str:
        return f"{self.path.relative_to(SRC.parent)}:{self.line}"


def modules() -> dict[str, tuple[Path, bool]]:
    """Dotted name -> (file, is a package's __init__)."""
    out = {}
    for path in sorted((SRC / PACKAGE).rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        out[".".join(parts[:-1] if is_package else parts)] = (path, is_package)
    return out


MODULES = modules()


def _known(name: str) -> str:
    """The module ``name`` lives in (``pkg.mod.attr`` -> ``pkg.mod``)."""
    while name not in MODULES:
        name = name.rpartition(".")[0]
    return name


def _targets(module: str, is_package: bool, node: ast.Import | ast.ImportFrom) -> list[str]:
    if isinstance(node, ast.Import):
        return [_known(a.name) for a in node.names if a.name.split(".")[0] == PACKAGE]
    if node.level:
        base = module.split(".") if is_package else module.split(".")[:-1]
        base = base[: len(base) - node.level + 1]
        origin = ".".join(base + ([node.module] if node.module else []))
    else:
        origin = node.module or ""
    if origin.split(".")[0] != PACKAGE:
        return []
    # `from pkg import sub` imports the submodule sub; `from pkg import name` imports pkg
    return sorted({_known(f"{origin}.{a.name}") if f"{origin}.{a.name}" in MODULES else _known(origin) for a in node.names})


def _is_type_checking(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)


def imports() -> list[Import]:
    found: list[Import] = []
    for module, (path, is_package) in MODULES.items():
        def visit(node: ast.AST, in_function: bool, type_only: bool) -> None:
            for child in ast.iter_child_nodes(node):
                func = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
                typed = type_only or _is_type_checking(child)
                if isinstance(child, (ast.Import, ast.ImportFrom)):
                    for target in _targets(module, is_package, child):
                        found.append(Import(module, target, path, child.lineno, func, typed))
                visit(child, func, typed)

        visit(ast.parse(path.read_text(encoding="utf-8")), False, False)
    return found


def command_table() -> list[Import]:
    """The CLI's plugin table (``COMMAND_MODULES``): each command's module, imported when it runs, as edges."""
    path, _ = MODULES[f"{PACKAGE}.cli"]
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "COMMAND_MODULES" for t in node.targets):
            table = ast.literal_eval(node.value)
            return [Import(f"{PACKAGE}.cli", f"{PACKAGE}.cli.{m}", path, node.lineno, False, False)
                    for m in sorted(set(table.values()))]
    return []


def dynamic_imports() -> list[str]:
    """Places that import by name at run time (importlib.import_module, __import__)."""
    found = []
    for module, (path, _) in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and ast.unparse(node.func) in ("importlib.import_module", "__import__"):
                found.append(f"{path.relative_to(SRC.parent)}:{node.lineno}")
    return found


IMPORTS = imports() + command_table()


def cycles(edges: list[Import]) -> list[tuple[int, list[str]]]:
    """(size, one loop through it) of each strongly connected component of more than one module (Tarjan)."""
    graph: dict[str, set[str]] = {m: set() for m in MODULES}
    for e in edges:
        if e.target != e.source:
            graph[e.source].add(e.target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def connect(v: str) -> None:  # recursion depth <= number of modules
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                components.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            connect(v)
    return [(len(c), _cycle_through(c, graph)) for c in components]


def _cycle_through(component: list[str], graph: dict[str, set[str]]) -> list[str]:
    """A shortest cycle from the component's first module back to it (breadth first)."""
    members, start = set(component), component[0]
    parent: dict[str, str] = {}
    queue = [start]
    while queue:
        v = queue.pop(0)
        for w in sorted(graph[v] & members):
            if w == start:
                path = [v]
                while path[-1] != start:
                    path.append(parent[path[-1]])
                return [*reversed(path), start]
            if w not in parent:
                parent[w] = v
                queue.append(w)
    return component  # unreachable: a component is strongly connected


def test_every_module_has_a_layer():
    missing = []
    for module, (_, is_package) in MODULES.items():
        try:
            layer_of(module, is_package)
        except KeyError:
            missing.append(module)
    assert not missing, "modules in no layer of frictionflow._layers.LAYERS: " + ", ".join(missing)


def test_figure_modules_are_in_the_figure_layer():
    """A new figure module (``plotting``, ``*_plot``) must join the leaf layer, where nothing below can import it."""
    figures = [name for name, _ in LAYERS].index("figures")
    stray = [m for m, (_, pkg) in MODULES.items()
             if m.rpartition(".")[2] in ("plotting",) or m.endswith("_plot")
             if layer_of(m, pkg)[0] != figures]
    assert not stray, "figure modules outside the figures layer: " + ", ".join(stray)


def test_no_package_import_inside_a_function():
    inner = [i for i in IMPORTS if i.in_function]
    statements = sorted({(i.where(), i.source) for i in inner})
    if statements:
        pytest.fail(
        f"{len(statements)} import statement(s) of frictionflow modules inside functions "
        "(hoist them to the module's top; a cycle that forces one means code is in the wrong layer):\n"
        + "\n".join(f"  {w}  ({s})" for w, s in statements), pytrace=False)


def test_no_import_cycle():
    found = cycles([i for i in IMPORTS if not i.type_only])
    if found:
        pytest.fail(f"{len(found)} import cycle(s), each shown by one loop through it:\n" + "\n".join(
            f"  [{n} modules] " + " -> ".join(c) for n, c in found), pytrace=False)


def test_no_import_from_a_higher_layer():
    bad = []
    for i in (i for i in IMPORTS if not i.type_only):
        src_rank, src_layer = layer_of(i.source, MODULES[i.source][1])
        dst_rank, dst_layer = layer_of(i.target, MODULES[i.target][1])
        if dst_rank > src_rank:
            bad.append(f"  {i.where()}  {i.source} ({src_layer}) imports {i.target} ({dst_layer})")
    order = " < ".join(name for name, _ in LAYERS)
    if bad:
        pytest.fail(f"{len(bad)} import(s) from a higher layer ({order}):\n" + "\n".join(sorted(bad)), pytrace=False)


@pytest.mark.parametrize("source, expected", [
    ("from . import x", ["frictionflow.core.x"]),
    ("from .. import params", ["frictionflow.params"]),
    ("from ..friction.base import FrictionLaw", ["frictionflow.friction.base"]),
    ("import frictionflow.io", ["frictionflow.io"]),
    ("from ..analysis import analyze", ["frictionflow.analysis"]),
])
def test_relative_imports_resolve(source, expected, monkeypatch):
    """The resolver used above: relative to a module in frictionflow.core."""
    monkeypatch.setitem(MODULES, "frictionflow.core.x", (Path("x.py"), False))
    node = ast.parse(source).body[0]
    assert _targets("frictionflow.core.flowmap", False, node) == expected


def test_the_only_import_by_name_is_the_cli_command_table():
    """A run-time import hides an edge from this graph; the CLI's table of command modules is the one
    allowed, and its edges are read from the table (``command_table``).  ``_lazy``'s deferred import of
    other packages' heavy modules is not an edge of the graph: it refuses the package's own modules."""
    assert len(command_table()) == len(set(MODULES) & {i.target for i in command_table()}) > 5
    places = dynamic_imports()
    allowed = ("src/frictionflow/cli/__init__.py", "src/frictionflow/_lazy.py")
    assert all(p.startswith(allowed) for p in places), places
    for own in ("frictionflow", "frictionflow.sweep.model"):
        with pytest.raises(ValueError, match="other packages"):
            lazy_module(own)
