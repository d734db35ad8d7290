"""A user law's rebuilt kernels never stand in for a built-in law's cached kernels.

The failure this guards against: a sweep of a built-in law (golden case
``sweep_adaptive``) returned the P_belt of the SlipLaw that test_certificate
had simulated earlier in the same process, 10 % off.  numba names a compiled
function's symbol after its module, qualified name, argument types and a
per-process counter; a cached kernel carries the counter of the process that
compiled it.  The rebuilt copy of ``dopri.run_unforced`` had its original's
name, got the same counter value as the one baked into the cached batched
kernel, and the JIT linked that kernel, loaded later, to the copy (the callee
symbols are weak).  Whether the counters met depended on how many functions
the process had compiled before and on which process wrote the cache.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba import njit

from frictionflow import BeltOscillator, SlipLaw, analyze, simulate
from frictionflow.core import certificate, dopri, layout
from frictionflow.core._rebind import REBOUND, binding_tag, rebind
from frictionflow.friction.user import user_slip_force
from frictionflow.sweep import run_sweep
from frictionflow.sweep.config import parse_sweep

from .rebind_child import SPEC, linked_uid, user_law

CHILD = Path(__file__).with_name("rebind_child.py")


def _reference() -> float:
    """The point by a single simulate + analyze (no batched kernel)."""
    _, law, solver = parse_sweep(SPEC).run.build()
    (zeta,), (vb,) = SPEC["grid"]["zeta"], SPEC["grid"]["vb"]
    return analyze(simulate(BeltOscillator(zeta, vb), law, solver, t_end=SPEC["t_end"])).power.P_belt


def test_rebound_copies_have_names_no_cached_kernel_has():
    for module, names in ((dopri, ("rhs", "run_unforced", "run_forced")), (certificate, ("secant_margin", "certified_radius"))):
        copies = rebind(module, names, slip_force=None, slip_magnitude_of=None)  # (nothing compiled)
        for name in names:
            original, copy = getattr(module, name).py_func, copies[name].py_func
            assert copy.__code__ is original.__code__ and copy.__module__ == original.__module__
            assert copy.__qualname__ == f"{REBOUND}.{original.__qualname__}" != original.__qualname__


def test_a_compiled_copy_is_named_apart_from_its_original():
    force = njit(lambda p, speed: 0.03)
    rhs = rebind(dopri, ("rhs",), slip_force=force)["rhs"]
    args = (np.zeros(dopri.NY_FORCED), 0.0, 1.0, 0.05, 0.1, np.zeros(layout.N_PARAMS), np.zeros(dopri.NY_FORCED), False)
    rhs(*args)
    dopri.rhs(*args)
    (sig,) = rhs.signatures
    copy, original = rhs.overloads[sig].fndesc, dopri.rhs.overloads[sig].fndesc
    assert copy.modname == original.modname and copy.qualname == f"{REBOUND}.{original.qualname}"
    # the symbol up to numba's counter (its first tag): the original's can never be the copy's, whatever the counters
    assert not copy.mangled_name.startswith(original.mangled_name[: original.mangled_name.index("B")])


def test_a_user_law_compiled_first_does_not_change_a_cached_sweep_point(tmp_path):
    # this process: the batched kernel in the on-disk cache (written now if it was not), and the counter in its symbol
    ds = run_sweep(parse_sweep(SPEC), tmp_path / "point.zarr")
    here = float(ds["P_belt"].values.ravel()[0])
    uid = linked_uid()
    ref = _reference()
    assert here == pytest.approx(ref, rel=1e-9)
    # a second process, same cache: a SlipLaw simulation whose rebuilt run_unforced gets that counter value, then the point
    out = tmp_path / "child.json"
    proc = subprocess.run([sys.executable, str(CHILD), str(out), str(uid)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    child = json.loads(out.read_text())
    assert child["uid"] == uid  # the cached kernel was loaded, carrying the counter value the copy was given
    assert child["P_belt"] == pytest.approx(ref, rel=1e-9), "the sweep point ran the user's slip law"


def test_copies_bound_to_the_package_s_kernels_are_cached_under_the_binding_s_name():
    law = SlipLaw(user_law)
    args = (np.zeros(dopri.NY_FORCED), 0.0, 1.0, 0.05, 0.1, law.kernel_params(), np.zeros(dopri.NY_FORCED), False)
    kept = rebind(dopri, ("slip_force_at", "rhs"), slip_force=user_slip_force)["rhs"]
    fresh = rebind(dopri, ("slip_force_at", "rhs"), slip_force=njit(lambda p, speed: 0.03))["rhs"]
    kept(*args), fresh(*args)
    original = dopri.rhs.py_func.__qualname__
    assert kept.py_func.__qualname__ == f"{REBOUND}[slip_force=friction.user.user_slip_force].{original}"
    assert fresh.py_func.__qualname__ == f"{REBOUND}.{original}"
    assert kept.stats.cache_path is not None and fresh.stats.cache_path is None  # a lambda's copy is never cached
    assert binding_tag({"slip_force": njit(lambda p, speed: 0.0)}) is None
    assert binding_tag({"slip_force": dopri.rhs, "other": None}) is None


def test_a_second_process_runs_a_user_law_without_compiling_its_kernels():
    # this process: the user law's kernels compiled (or loaded) into the shared on-disk cache
    run = simulate(BeltOscillator(0.03, 0.12), SlipLaw(user_law), t_end=20.0)
    here = analyze(run)
    child = (
        "import json, sys\n"
        "from numba.core import event\n"
        "from frictionflow import BeltOscillator, SlipLaw, analyze, simulate\n"
        "from tests.core.rebind_child import user_law\n"
        "compiled = []\n"
        "class L(event.Listener):\n"
        "    def on_start(self, ev): compiled.append(ev.data['dispatcher'].py_func.__qualname__)\n"
        "    def on_end(self, ev): pass\n"
        "event.register('numba:compile', L())\n"
        "r = analyze(simulate(BeltOscillator(0.03, 0.12), SlipLaw(user_law), t_end=20.0))\n"
        "print(json.dumps({'compiled': compiled, 'P_belt': r.power.P_belt, 'residual': r.energy_residual}))\n"
    )
    proc = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=300,
                          cwd=Path(__file__).parents[2])
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.splitlines()[-1])
    assert not [name for name in out["compiled"] if name.startswith(REBOUND)]
    assert out["P_belt"] == here.power.P_belt and out["residual"] == here.energy_residual
