"""Heavy third-party modules loaded on first use, so that importing the command line stays quick.

The layer rule forbids importing a frictionflow module inside a function, so
every command's module is imported with the CLI; xarray (with pandas, about
0.45 s) is needed only once a command builds a dataset.  ``lazy_module``
returns a stand-in at once; its first attribute access imports the module
and every access is read from it.  The import goes through
:func:`importlib.import_module`, whose per-module lock makes a second thread
wait for a module another thread is importing (Python 3.11's
:class:`importlib.util.LazyLoader` lets it read the half-executed module: a
model sweep's threads met ``scipy.optimize`` without ``brentq``).
``module_alone`` executes a
module of constants without its packages' ``__init__``: the DOP853 tables
sit in ``scipy.integrate``, whose ``__init__`` imports ``scipy.optimize`` and
more (about 0.4 s).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

#: the heavy modules no command needs before it has read its options: loaded where first used, never by
#: importing the package or its command line (a test and ``benchmarks/bench_startup.py`` check it)
DEFERRED = ("xarray", "pandas", "matplotlib", "dask", "distributed", "scipy.optimize", "scipy.integrate",
            "scipy.linalg", "scipy.sparse", "scipy.special")


class _Deferred(ModuleType):
    """Stands for the module of its ``__name__`` until an attribute is read, then reads it from that module."""

    def __getattr__(self, attr: str) -> Any:  # (called only for what the stand-in itself lacks: all but its name)
        module = self.__dict__.get("_module")
        if module is None:
            module = importlib.import_module(self.__name__)  # waits while another thread imports it
            self.__dict__["_module"] = module
        return getattr(module, attr)


def lazy_module(name: str) -> ModuleType:
    """The module ``name`` if already imported, else a stand-in that imports it on first attribute access
    (safe from several threads at once).  Only for other packages' modules: the package's own imports are
    statements the layer order can read (``tests/test_layers.py``)."""
    if name.partition(".")[0] == __name__.partition(".")[0]:
        raise ValueError(f"lazy_module is for other packages' modules, not {name!r}")
    if name in sys.modules:
        return sys.modules[name]
    if importlib.util.find_spec(name) is None:
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    return _Deferred(name)


def module_alone(name: str) -> ModuleType:
    """The module ``name`` (``package.sub.module``) executed from its file, without running its packages'
    ``__init__``: for a module that imports only what is already cheap (absolute imports; it is not registered
    in :data:`sys.modules`, so ``import name`` later loads the real one)."""
    top, *parts = name.split(".")
    spec = importlib.util.find_spec(top)
    if spec is None or not spec.submodule_search_locations or not parts:
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    path = Path(spec.submodule_search_locations[0]).joinpath(*parts[:-1], parts[-1] + ".py")
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None or not path.is_file():
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
