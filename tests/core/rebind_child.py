"""Child process of ``test_rebind.py``: a user law's simulation and a built-in law's sweep point in one process.

``python rebind_child.py OUT [UID]`` writes JSON to OUT: the sweep point's
P_belt and the counter value (numba's per-process uid) in the symbol of
``dopri.run_unforced`` inside the cached batched kernel.  With UID, a
:class:`~frictionflow.SlipLaw` simulation runs first, its rebuilt
``run_unforced`` compiled with that counter value: what a process whose
compilations happened to count up to it would do.
"""

from __future__ import annotations

import json
import math
import re
import sys
import tempfile
from pathlib import Path

from numba.core import bytecode

from frictionflow import BeltOscillator, SlipLaw, simulate
from frictionflow.core import batch, dopri
from frictionflow.sweep import run_sweep
from frictionflow.sweep.config import parse_sweep

#: the point of the golden case ``sweep_adaptive`` the failure was seen at
SPEC = {"friction": "stribeck", "fs": 0.04, "vs": 0.05, "t_end": 300.0, "grid": {"zeta": [0.02], "vb": [0.01]}}


def user_law(x: float) -> float:
    """The slip law of test_certificate's SlipLaw test: Stribeck-like with a bump."""
    return 0.02 + 0.02 * math.exp(-x / 0.05) + 0.01 * math.exp(-(((x - 0.2) / 0.02) ** 2))


def give_uid(uid: int) -> None:
    """The rebuilt copy of ``dopri.run_unforced`` (same code, other globals) gets numba's counter value ``uid``."""
    from_function = bytecode.FunctionIdentity.from_function.__func__
    code = dopri.run_unforced.py_func.__code__

    def patched(cls, pyfunc):
        ident = from_function(cls, pyfunc)
        if ident.code is code and ident.func.__globals__ is not vars(dopri):
            ident.unique_id = uid
            ident.unique_name = f"{ident.func_qualname}${uid}"
        return ident

    bytecode.FunctionIdentity.from_function = classmethod(patched)


def linked_uid() -> int:
    """The counter value in the symbol of ``dopri.run_unforced`` that the batched kernel links."""
    names = [f.name for cres in batch._adaptive_points.overloads.values() for f in cres.library._get_module_for_linking().functions]
    (uid,) = {int(m.group(1)) for n in names if (m := re.search(r"5dopri12run_unforcedB\d+v(\d+)", n))}
    return uid


def main(out: str, uid: str | None = None) -> None:
    if uid is not None:
        give_uid(int(uid))
        simulate(BeltOscillator(0.03, 0.12), SlipLaw(user_law), t_end=20.0)
    with tempfile.TemporaryDirectory() as d:
        ds = run_sweep(parse_sweep(SPEC), Path(d) / "point.zarr")
        p_belt = float(ds["P_belt"].values.ravel()[0])
    Path(out).write_text(json.dumps({"P_belt": p_belt, "uid": linked_uid()}))


if __name__ == "__main__":
    main(*sys.argv[1:])
