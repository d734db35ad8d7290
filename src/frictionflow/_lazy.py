"""Heavy third-party modules loaded on first use, so that importing the command line stays quick.

The layer rule forbids importing a frictionflow module inside a function, so
every command's module is imported with the CLI; xarray (with pandas, about
0.45 s) is needed only once a command builds a dataset.  ``lazy_module``
returns the module object at once and executes it on its first attribute
access (:class:`importlib.util.LazyLoader`).
"""

from __future__ import annotations

import importlib.util
import sys
from types import ModuleType


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
