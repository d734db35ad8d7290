"""Where the "spring" stick rule says slip but neither slip direction leaves the belt, the exact engine stops and says why.

The rule compares the held force without the dampers' share with F_s N; the
friction force the contact really holds includes it.  When the first is on F_s
N and the second below F_d N, slipping either way turns V_r straight back to
0: the motion slides along V_r = 0, which a switch model cannot represent.
The single mass's exact solver stops there with that reason; the structure's
exact engine stopped at the same instant with only "switched without time
passing" (found by comparing random 3-dof structures with the scipy reference,
which loops there for ever).  Both now give the reason, and its numbers are
checked here against the single mass's closed form: one dof stuck on a belt
at V_b holds X + 2 zeta V_b - f(t), of which the rule reads X - f(t).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly
from frictionflow.solvers.structure_motion import sliding_hint

from ..cli.processes import cli, one_line
from . import reference as ref
from .builders import single_mass

# zeta, V_b, F_d, F_s, F_ex, Omega: the damper's share 2 zeta V_b = 0.04 exceeds F_s - F_d = 0.02
ZETA, VB, FD, FS, FEX, OMEGA = 0.2, 0.1, 0.3, 0.32, 0.5, 0.5
MODEL = f"""
dof = ["x"]
mass = [1.0]
[[spring]]
on = {{ x = 1.0 }}
k = 1.0
[[damper]]
on = {{ x = 1.0 }}
c = {2 * ZETA}
[[contact]]
on = {{ x = 1.0 }}
belt = {VB}
friction = "coulomb"
fd = {FD}
fs = {FS}
stick_force = "spring"
[[force]]
on = {{ x = 1.0 }}
amplitude = {FEX}
omega = {OMEGA}
[initial]
q = {{ x = {FD} }}
v = {{ x = {VB} }}
"""
NUMBER = r"([0-9.eE+-]+)"


def law(rule: str = "spring") -> ff.Coulomb:
    return ff.Coulomb(fd=FD, fs=FS, stick_force=rule)


def test_the_exact_engine_stops_where_the_single_mass_does_and_says_why():
    with pytest.raises(RuntimeError) as single:
        ff.simulate(ff.BeltOscillator(zeta=ZETA, vb=VB, fex=FEX, omega=OMEGA), law(), x0=FD, v0=VB, t_end=100.0)
    tau, x = (float(v) for v in re.search(rf"tau={NUMBER}, X={NUMBER}", str(single.value)).groups())
    with pytest.raises(RuntimeError) as structure:
        run_assembly(single_mass(ZETA, VB, law(), FD, VB, force=(FEX, OMEGA, 0.0)), 100.0)
    text = str(structure.value)
    assert "status 'stuck'" in text and 'use stick_force = "resultant"' in text
    t = float(re.search(rf"stopped at t={NUMBER}", text).group(1))
    assert t == pytest.approx(tau, rel=1e-10)
    # the reason's numbers, from the single mass's state: the rule reads |X - f|, the contact holds |X + 2 zeta V_b - f|
    f = FEX * math.cos(OMEGA * tau)
    rule, limit, whole, level = (float(v) for v in re.search(
        rf"dampers' {NUMBER} >= F_s N = {NUMBER}\).*held force {NUMBER} < F_d N = {NUMBER}", text).groups())
    assert (limit, level) == (pytest.approx(FS), pytest.approx(FD))
    assert rule == pytest.approx(abs(x - f), rel=1e-5) and rule >= FS * (1 - 1e-9)
    assert whole == pytest.approx(abs(x + 2 * ZETA * VB - f), rel=1e-5) and whole < FD


def test_the_reference_stops_at_the_same_instant():
    """The scipy reference (tests/structure/reference.py) refuses the same release: it used to loop there for ever."""
    asm = single_mass(ZETA, VB, law(), FD, VB, force=(FEX, OMEGA, 0.0))
    with pytest.raises(RuntimeError) as structure:
        run_assembly(asm, 100.0)
    t = float(re.search(rf"stopped at t={NUMBER}", str(structure.value)).group(1))
    with pytest.raises(RuntimeError, match="contact 0 can neither stick nor slip") as reference:
        ref.integrate(asm, 100.0, rtol=1e-12, atol=1e-14)
    assert float(re.search(rf"at t = {NUMBER}", str(reference.value)).group(1)) == pytest.approx(t, abs=1e-9)


def test_with_the_whole_force_as_its_rule_the_same_structure_runs_on():
    asm = single_mass(ZETA, VB, law("resultant"), FD, VB, force=(FEX, OMEGA, 0.0))
    motion = run_assembly(asm, 100.0)
    single = ff.simulate(ff.BeltOscillator(zeta=ZETA, vb=VB, fex=FEX, omega=OMEGA), law("resultant"), x0=FD, v0=VB,
                         t_end=100.0)
    np.testing.assert_allclose(motion.switches, single.events["t"], rtol=1e-12, atol=1e-13)


@pytest.mark.parametrize("rule, x, expected", [
    ("spring", FEX + FS + 1e-3, False),      # |X - f| over F_s, and slipping is consistent: |X + 2 zeta V_b - f| > F_d
    ("spring", FEX - FS - 1e-3, True),       # |X - f| over F_s, the dampers' share takes the whole force below F_d
    ("resultant", FEX - FS - 1e-3, False),   # the rule reads the whole force: never this reason
    ("spring", FEX, False),                  # |X - f| = 0, within F_s
], ids=["slip is consistent", "sliding", "resultant rule", "within the limit"])
def test_the_reason_is_given_only_where_it_holds(rule, x, expected):
    """Stuck at V_b at t = 0 (f = F_ex): the reason needs the spring rule, |X - f| >= F_s and |X + 2 zeta V_b - f| < F_d."""
    asm = single_mass(ZETA, VB, law(rule), x, VB, force=(FEX, OMEGA, 0.0))
    hint = sliding_hint(asm, (np.array([x, VB]), 0.0, np.array([1], dtype=np.int8)), 0)
    assert expected == (rule == "spring" and abs(x - FEX) >= FS and abs(x + 2 * ZETA * VB - FEX) < FD)  # the case's own
    assert (hint != "") == expected


def test_simulate_model_says_it_in_one_line(tmp_path):
    (tmp_path / "m.toml").write_text(MODEL)
    code, stdout, err, _ = cli("simulate", "--model", str(tmp_path / "m.toml"), "--t-end", "100")
    assert code == 1 and stdout == ""
    one_line(err, "contact.0 switched without time passing", 'stick_force "spring"', 'use stick_force = "resultant"')


@pytest.mark.parametrize("order", [(0.5, FS), (FS, 0.5)])
def test_a_sweep_says_at_which_grid_point_the_run_stopped(tmp_path, order):
    """F_s = 0.5 runs on (the damper's share 0.04 cannot bridge F_s - F_d = 0.2), F_s = 0.32 stops: the sweep's line
    names that point, whether it stops in a chunk or in the estimate's probe (the grid's first point), and
    carries the run's own reason."""
    (tmp_path / "m.toml").write_text(MODEL)
    (tmp_path / "s.toml").write_text(f'model = "m.toml"\nt_end = 100.0\n[grid]\n"contact.0.fs" = {list(order)}\n')
    code, stdout, err, _ = cli("sweep", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o.nc"), "--chunk-size", "1")
    assert code == 1 and stdout == ""
    one_line(err, f"grid point (contact.0.fs = {FS:g}): solver=exact: the run stopped", 'stick_force "spring"',
             'use stick_force = "resultant"')
