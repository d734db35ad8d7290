"""Readable functions: none over 80 lines, none with more than 12 parameters (issue 19, item 6).

``OVER_LIMIT`` lists the functions that still exceed a limit, with their size
when the rule was introduced: the list may only shrink.  A function not in it
that crosses a limit fails; so does a listed one that grows, and a listed one
that is now within the limits (take it off the list).
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
MAX_LINES = 80
MAX_PARAMS = 12

#: name -> (lines, parameters) of the functions still over a limit
OVER_LIMIT = {
}


def _count_params(args: ast.arguments) -> int:
    names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
    n = len(names) + (args.vararg is not None) + (args.kwarg is not None)
    return n - (1 if names and names[0] in ("self", "cls") else 0)


def function_sizes() -> dict[str, tuple[int, int]]:
    """``module:Class.function`` -> (lines, parameters) of every function of the package."""
    sizes = {}
    for path in sorted((SRC / "frictionflow").rglob("*.py")):
        module = path.relative_to(SRC).with_suffix("").as_posix().replace("/", ".")

        def visit(node: ast.AST, prefix: str) -> None:
            for n in ast.iter_child_nodes(node):
                if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    sizes[f"{module}:{prefix}{n.name}"] = (n.end_lineno - n.lineno + 1, _count_params(n.args))
                    visit(n, f"{prefix}{n.name}.")
                elif isinstance(n, ast.ClassDef):
                    visit(n, f"{prefix}{n.name}.")

        visit(ast.parse(path.read_text(encoding="utf-8")), "")
    return sizes


SIZES = function_sizes()


def _over(size: tuple[int, int]) -> bool:
    return size[0] > MAX_LINES or size[1] > MAX_PARAMS


def test_no_new_function_over_the_limits():
    new = {k: v for k, v in SIZES.items() if _over(v) and k not in OVER_LIMIT}
    assert not new, f"over {MAX_LINES} lines or {MAX_PARAMS} parameters (split it; pass records): {new}"


def test_listed_functions_do_not_grow():
    grown = {k: (OVER_LIMIT[k], v) for k, v in SIZES.items() if k in OVER_LIMIT
             and (v[0] > max(OVER_LIMIT[k][0], MAX_LINES) or v[1] > max(OVER_LIMIT[k][1], MAX_PARAMS))}
    assert not grown, f"(listed, now): {grown}"


def test_the_list_only_names_functions_still_over_a_limit():
    stale = [k for k in OVER_LIMIT if k not in SIZES or not _over(SIZES[k])]
    assert not stale, f"within the limits now (or gone): take them off OVER_LIMIT: {stale}"
