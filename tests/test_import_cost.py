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
    # a module registered by _lazy.lazy_module but not yet executed is not of type ``module``
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
