"""Sphinx configuration of the frictionflow documentation.

Build (warnings are errors, the gallery is executed)::

    pip install ".[docs]" && sphinx-build -W -b html docs docs/_build/html

The user guide is written in Markdown (MyST), the API reference comes from the
docstrings (NumPy sections, read by napoleon), the command-line reference from
the command definitions (``_ext/cli_reference.py``), and the equations are
typeset by a copy of MathJax shipped with the site (``sphinx-mathjax-offline``):
the pages need no network.
"""

from __future__ import annotations

import builtins
import inspect
import re
import sys
from importlib.metadata import version as _version
from pathlib import Path

import sphinx.ext.autosummary
from sphinx.addnodes import pending_xref

import matplotlib

matplotlib.use("Agg")  # the gallery draws off screen

project = "frictionflow"
author = "the frictionflow authors"
copyright = "the frictionflow authors"  # noqa: A001 - Sphinx's name
release = _version("frictionflow")
version = release

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static/mathjax: equations render offline
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
    "myst_parser",
    "cli_reference",
]

# -- the user guide: Markdown with $...$ math ----------------------------------------------------
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# -- API reference from the docstrings (NumPy style, read by napoleon) ----------------------------
# one page per topic documents its objects itself; the autosummary tables there only link to them
autosummary_generate = False
# a summary ends at the first full stop: not at "Eq. 3" or "Fig. 2"
sphinx.ext.autosummary.WELL_KNOWN_ABBREVIATIONS = (
    *sphinx.ext.autosummary.WELL_KNOWN_ABBREVIATIONS, "Eq.", "Eqs.", "Fig.", "Figs.", "Ref.", "cf.")
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_format = "short"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
# the docstrings name parameters such as "t, x, v, fc:" that are not cross-reference targets
nitpicky = True
# Types of other packages and of the standard library: no intersphinx (the build needs no network), so
# these cannot resolve; every other unresolved reference (``sphinx-build -n``) is the project's own.
nitpick_ignore = [
    ("py:class", "numpy.ndarray"),
    ("py:class", "pathlib.Path"),
    ("py:class", "Path"),  # pathlib.Path in the short form of the type hints
    ("py:class", "xarray.Dataset"),
    ("py:class", "xarray.core.dataset.Dataset"),
    ("py:class", "collections.abc.Sequence"),
    ("py:class", "collections.abc.Iterable"),
    ("py:class", "collections.abc.Callable"),
    ("py:class", "collections.abc.Mapping"),
    ("py:class", "enum.IntEnum"),
    ("py:class", "abc.ABC"),
    # The compiled core (frictionflow.core) is private and has no API page (tests/test_docs.py keeps it off
    # them), yet the type hints of public functions name its records: the structure's arrays that
    # frictionflow.system.assemble returns, and the step control of the adaptive sweep kernel.
    ("py:class", "frictionflow.core.assembly.Assembly"),
    ("py:class", "frictionflow.core.batch.Ode"),
]
nitpick_ignore_regex = [
    (r"py:class", r"(numpy|xarray|pandas|matplotlib|distributed|dask|typing|collections\.abc|pathlib|dataclasses)\..*"),
]

# -- the gallery: every example runs at each build, so none can rot --------------------------------
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",  # run every plot_*.py
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "show_memory": False,
    "matplotlib_animations": False,
    "reset_modules": ("matplotlib",),
    # the examples' run times are written here, not beside the sources
    "write_computation_times": False,
}

# "--verify" and "X'" are typed as they are meant: no dashes or curly quotes made of them
smartquotes = False

# -- HTML ---------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"frictionflow {release}"
# examples/ holds the gallery's sources; sphinx-gallery turns them into auto_examples/
# generated/cli.md is written by _ext/cli_reference.py and included by cli.rst
exclude_patterns = ["_build", "examples", "generated", "exit_codes.md", "Thumbs.db", ".DS_Store"]


# Docstrings are written for the terminal: |V_r| is an absolute value, not a
# reStructuredText substitution.  Escape it outside literals before the
# docstring is parsed.
_LITERAL = re.compile(r"(``.*?``|`[^`]*`_?)")


def _escape_math_text(line: str) -> str:
    parts = _LITERAL.split(line)
    for i in range(0, len(parts), 2):  # the even parts lie outside literals
        parts[i] = parts[i].replace("|", r"\|")
    return "".join(parts)


def _plain_docstrings(app, what, name, obj, options, lines):  # noqa: ANN001 - Sphinx's hook signature
    """Escape math pipes, and end a field list napoleon made with a blank line before the text after it."""
    out: list[str] = []
    in_literal_block = in_fields = False
    for line in lines:
        indented = line.startswith((" ", "\t"))
        if line.rstrip().endswith("::"):
            in_literal_block = True
        elif in_literal_block and line.strip() and not indented:
            in_literal_block = False
        if line.startswith(":"):
            in_fields = True
        elif in_fields and line.strip() and not indented:
            out.append("")  # docutils wants a blank line after a field list
            in_fields = False
        elif not line.strip():
            in_fields = False
        if not in_literal_block and not line.lstrip().startswith(("..", ">>>", "=")):
            line = _escape_math_text(line)
        out.append(line)
    lines[:] = out


def _public_bases(app, name, obj, options, bases):  # noqa: ANN001 - Sphinx's hook signature
    """"Bases:" names public classes only: a private helper (``frictionflow._display.Summarized``) has no page."""
    bases[:] = [b for b in bases if not getattr(b, "__module__", "").startswith("frictionflow._")] or [object]


def _quoted_forward_ref(app, env, node, contnode):  # noqa: ANN001, ANN202 - Sphinx's hook signature
    """Link a forward reference quoted inside a type hint (``type["FrictionLaw"]``) as the name it quotes.

    A module that imports a class for type checking only names it in quotes inside a subscript; autodoc
    keeps the quotes, so the target is ``'FrictionLaw'``.  Resolved like the bare name, or left missing.
    """
    target = node.get("reftarget", "")
    if node.get("refdomain") != "py" or len(target) < 3 or target[0] not in "'\"" or target[-1] != target[0]:
        return None
    bare = node.deepcopy()
    bare["reftarget"] = target[1:-1]
    return env.domains["py"].resolve_xref(env, node["refdoc"], app.builder, node["reftype"], target[1:-1],
                                          bare, contnode)


def _builtin_hints(app, doctree):  # noqa: ANN001, ANN202 - Sphinx's hook signature
    """A built-in class named in a type hint (``type``, ``dict[str, type]``) is Python's: plain text, as ``int`` is.

    Sphinx looks a hint's name up in every namespace and falls back to attributes, so without this ``type`` would
    link to the attribute ``Bifurcation.type``.
    """
    for node in list(doctree.findall(pending_xref)):
        if (node.get("refdomain") == "py" and node.get("reftype") in ("class", "obj")
                and inspect.isclass(getattr(builtins, node.get("reftarget", ""), None))):
            node.replace_self(node.children)


def setup(app):  # noqa: ANN001, ANN201
    app.connect("autodoc-process-docstring", _plain_docstrings)
    app.connect("missing-reference", _quoted_forward_ref)
    app.connect("doctree-read", _builtin_hints)
    app.connect("autodoc-process-bases", _public_bases)

