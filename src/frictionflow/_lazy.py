"""Heavy third-party modules loaded on first use, so that importing the command line stays quick.

The layer rule forbids importing a frictionflow module inside a function, so
every command's module is imported with the CLI; xarray (with pandas, about
0.45 s) is needed only once a command builds a dataset.  ``lazy_module``
returns the module object at once and executes it on its first attribute
access (:class:`importlib.util.LazyLoader`).  ``module_alone`` executes a
module of constants without its packages' ``__init__``: the DOP853 tables
sit in ``scipy.integrate``, whose ``__init__`` imports ``scipy.optimize`` and
more (about 0.4 s).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

#: the heavy modules no command needs before it has read its options: loaded where first used, never by
#: importing the package or its command line (a test and ``benchmarks/bench_startup.py`` check it)
DEFERRED = ("xarray", "pandas", "matplotlib", "dask", "distributed", "scipy.optimize", "scipy.integrate",
            "scipy.linalg", "scipy.sparse", "scipy.special")


def lazy_module(name: str) -> ModuleType:
    """The module ``name``: already imported, or registered now and executed on first attribute access."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.find_spec(name)
    if spec is None or spec.loader is None:
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    loader = importlib.util.LazyLoader(spec.loader)
    spec.loader = loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    loader.exec_module(module)
    return module


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
