"""Starting the command line loads no heavy module it does not need yet.

Every command pays the package's import before it reads its options (and the
test suite starts ~100 such processes).  The modules of
:data:`frictionflow._lazy.DEFERRED` (xarray with pandas, matplotlib, dask,
scipy.optimize, scipy.integrate, whose ``__init__`` imports optimize, sparse
and linalg: ~0.4 s) are loaded where they are first used.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import scipy.integrate._ivp.dop853_coefficients as dop853

from frictionflow._lazy import DEFERRED, module_alone
from frictionflow.core import flowmap


def test_importing_the_command_line_loads_no_heavy_module():
    # (_lazy.lazy_module registers nothing: its stand-in imports the module at its first attribute read)
    script = ("import json, sys, frictionflow, frictionflow.cli\n"
              f"print(json.dumps([m for m in {DEFERRED!r} if type(sys.modules.get(m)).__name__ == 'module']))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True)
    assert json.loads(done.stdout) == []


def test_the_dop853_tables_are_scipys():
    """The tables read without scipy.integrate's ``__init__`` are the ones scipy.integrate holds."""
    alone = module_alone("scipy.integrate._ivp.dop853_coefficients")
    assert alone is not dop853
    for name in ("A", "B", "C", "E3", "E5"):
        np.testing.assert_array_equal(getattr(alone, name), getattr(dop853, name))
    np.testing.assert_array_equal(flowmap.A, dop853.A[:flowmap.N_STAGES, :flowmap.N_STAGES])
    np.testing.assert_array_equal(flowmap.B, dop853.B)


def test_a_module_that_is_not_there_is_refused():
    for name in ("scipy", "scipy.integrate._ivp.no_such_tables", "no_such_package.tables"):
        with pytest.raises(ModuleNotFoundError):
            module_alone(name)


RACE = """
import json, threading
from frictionflow._lazy import lazy_module
stand_in = lazy_module("scipy.optimize")
start = threading.Barrier(4)
seen = []
def read():
    start.wait()
    try:
        seen.append(stand_in.brentq.__name__)
    except AttributeError as e:
        seen.append(str(e))
threads = [threading.Thread(target=read) for _ in range(4)]
[t.start() for t in threads]
[t.join() for t in threads]
print(json.dumps(seen))
"""


def test_a_deferred_module_read_by_threads_at_once_is_whole_in_each():
    """Four threads read a deferred module's attribute at the same moment, in a process that has not imported it:
    each gets it (the others wait for the import). Python 3.11's LazyLoader gave three of them the half-executed
    module and ``AttributeError: ... no attribute 'brentq'``, a model sweep's first points in its threads."""
    done = subprocess.run([sys.executable, "-c", RACE], capture_output=True, text=True, timeout=120, check=True)
    assert json.loads(done.stdout) == ["brentq"] * 4
