"""The cross-path agreement matrix: one physical point, every path that can compute it, one answer.

For every registered law x stick rule x zeta in {0, > 0} x unforced/forced x
each solver that declares the law -- and, on a moving belt V_b(tau) (at the
forcing's frequency, their common period), the switch-rule and band points at
zeta > 0 through each solver that runs one -- the point is run through

* ``simulate`` + ``analyze`` (the reference),
* ``frictionflow simulate --json`` (the CLI, in process),
* the sweep's chunk computation (the batched kernels a Dask worker runs),
* ``basins`` with one initial state (the sweep's store and the labelling),
* ``frequency_response`` at one frequency (forced points),
* ``find_orbit`` / ``find_forced_orbit`` where the point is a stable
  periodic orbit the shooting method defines (Coulomb's stick rule),

and each path must give the same kind, period, P_fin, R_c, R_f and TR_B:
1e-9 relative between exact paths (rounding and the closed forms' root
finding), the solver's own tolerance otherwise.  A path that does not define
a case says why (``undefined``).

The parameter sets include the reference paper's Case I (Karnopp,
F_s = F_d = 0.02, V_b = 0.01, zeta = 0: an undamped circle grazing the stick
band) and a belt at rest (V_b = 0, where friction puts in no power: R_c and
R_f are null on every path).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
from dataclasses import dataclass, replace

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, frequency_response, simulate
from frictionflow.basins import basins as basins_study
from frictionflow.cli import main as cli_main
from frictionflow.friction.registry import law_class, law_names
from frictionflow.orbits import find_forced_orbit, find_orbit
from frictionflow.quantities import KINDS
from frictionflow.solvers.registry import solver_classes
from frictionflow.sweep.compute import VARIABLES, compute_chunk

#: every quantity a point has through every path: the steady state, its power flow, transmissibility and extremes
KEYS = ("kind", "period", "P_fin", "R_c", "R_f", "P_belt", "P_heat", "TR_B", "X_max", "X_min", "V_max", "V_min",
        "stick_fraction")
POWER = ("P_fin", "R_c", "R_f", "P_belt", "P_heat")
EXTREMES = ("X_max", "X_min", "V_max", "V_min")
T_END = 300.0
FORCING = {"fex": 0.01, "omega": 0.8}
#: a moving belt, at the forcing's frequency: V_b(tau) = V_b + 0.005 sin(0.8 tau + 0.3)
BELT = {"vb_amplitude": 0.005, "vb_omega": 0.8, "vb_phi": 0.3}
#: the points also run on a moving belt (law, label)
BELT_POINTS = (("coulomb", "fs2"), ("karnopp", "fs2"), ("stribeck", "falling"))

#: per law: parameter sets (name, law settings, V_b) -- stick-slip, the paper's F_s = F_d, a belt at rest
POINTS = {
    "coulomb": [("fs2", {"fd": 0.02, "fs": 0.04}, 0.01), ("fs=fd", {"fd": 0.02, "fs": 0.02}, 0.01),
                ("belt at rest", {"fd": 0.02, "fs": 0.04}, 0.0)],
    "karnopp": [("case I", {"fd": 0.02, "fs": 0.02}, 0.01), ("fs2", {"fd": 0.02, "fs": 0.04}, 0.01)],
    "stribeck": [("falling", {"fd": 0.02, "fs": 0.04, "vs": 0.05, "delta": 1.0}, 0.01)],
    "cubic": [("hopf side", {"fs": 0.4, "k1": 0.45, "k3": 0.6}, 0.3)],
    # laws with internal state: soft bristles (sigma0 = 100 k) keep the runs short; stick-slip at V_b = 0.01
    "lugre": [("stick-slip", {"fd": 0.02, "fs": 0.04, "vs": 0.01, "delta": 2.0, "sigma0": 100.0, "sigma1": 5.0}, 0.01)],
    "dahl": [("sliding", {"fd": 0.02, "sigma0": 100.0, "alpha": 1.0}, 0.01)],
    "elastoplastic": [("stick-slip", {"fd": 0.02, "fs": 0.04, "vs": 0.01, "sigma0": 100.0, "sigma1": 5.0,
                                      "z_ba": 1e-4}, 0.01)],
    # D_c above Rice & Ruina's critical 0.0169: steady sliding, reached by a decaying oscillation
    "rate_state": [("sliding", {"normal": 1.0, "mu0": 0.6, "a": 0.01, "b": 0.015, "dc": 0.02, "vref": 0.01}, 0.02)],
}


@dataclass(frozen=True)
class Case:
    law: str
    label: str
    settings: tuple
    vb: float
    stick_force: str
    zeta: float
    forced: bool
    solver: str
    belt: bool = False

    @property
    def id(self) -> str:
        drive = "forced" if self.forced else "free"
        return f"{self.law}[{self.label}]-{self.stick_force}-z{self.zeta:g}-{drive}{'-belt' if self.belt else ''}-{self.solver}"

    def law_object(self):
        rule = {} if self.stateful else {"stick_force": self.stick_force}
        return law_class(self.law)(**dict(self.settings), **rule)

    @property
    def stateful(self) -> bool:
        """A law with internal state: its stick is the state's (no stick rule at V_r = 0 to choose)."""
        return law_class(self.law).stick_rule == "state"

    def batched(self) -> bool:
        """Whether the solver declares a batched kernel (sweeps and basins refuse a solver without one; forced
        points a solver has no batched forced kernel for run through simulate inside the sweep)."""
        return next(c for c in solver_classes() if c.name == self.solver).batched is not None

    def model(self) -> BeltOscillator:
        return BeltOscillator(zeta=self.zeta, vb=self.vb, **(FORCING if self.forced else {}), **(BELT if self.belt else {}))

    def options(self) -> dict:
        """The point as a sweep's or the CLI's settings."""
        rule = {} if self.stateful else {"stick_force": self.stick_force}
        return {"friction": self.law, **dict(self.settings), **rule, "zeta": self.zeta,
                "vb": self.vb, "solver": self.solver, **(FORCING if self.forced else {}), **(BELT if self.belt else {})}

    @property
    def rtol(self) -> float:
        """How closely two paths must agree: rounding for the exact solver, else the solver's own tolerance."""
        return 1e-9 if self.solver == "exact" else 1e-6


def _solver(case: Case):
    return next(cls for cls in solver_classes() if cls.name == case.solver)()


def _cases() -> list[Case]:
    cases = []
    for law in law_names():
        for label, settings, vb in POINTS.get(law, ()):
            rules = ("state",) if law_class(law).stick_rule == "state" else ("resultant", "spring")
            for rule in rules:
                for zeta in (0.0, 0.05):
                    for forced in (False, True):
                        probe = law_class(law)(**settings, **({} if rule == "state" else {"stick_force": rule}))
                        for cls in solver_classes():
                            if cls().supports(probe):  # the solver's own declaration
                                cases.append(Case(law, label, tuple(sorted(settings.items())), vb, rule, zeta, forced,
                                                  cls.name))
    belt = [replace(c, belt=True) for c in cases if (c.law, c.label) in BELT_POINTS and c.zeta > 0.0
            and _solver(c).runs_belt_motion(c.law_object())]
    return cases + belt


CASES = _cases()


def test_every_registered_law_has_points():
    assert set(POINTS) == set(law_names()), "add parameter points for a newly registered law"


# -- the paths ------------------------------------------------------------------------------------

def _from_quantities(q: dict) -> dict:
    return {k: q[k] for k in KEYS}


def reference(case: Case) -> dict:
    return _from_quantities(analyze(simulate(case.model(), case.law_object(), _solver(case), t_end=T_END)).quantities())


def via_cli(case: Case) -> dict:
    args = ["simulate", "--json", "--t-end", repr(T_END)]
    for k, v in case.options().items():
        args += ["--" + k.replace("_", "-"), str(v)]
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert cli_main(args) == 0
    d = json.loads(buf.getvalue())
    ss, av = d["steady_state"], d["averages"]
    return {"kind": KINDS.index(ss["kind"]), "period": ss["period"], **{k: av[k] for k in POWER},
            "TR_B": d["TR_B"], **d["amplitude"], "stick_fraction": ss["stick_fraction"]}


def via_sweep(case: Case) -> dict | str:
    if not case.batched() and not case.stateful:  # (a law with internal states: a stiff run per point)
        return f"undefined: solver={case.solver} has no batched kernel for sweeps"
    settings = {k: v for k, v in case.options().items() if k != "zeta"}
    out = compute_chunk({"settings": {**settings, "t_end": T_END}, "grid": {"zeta": [case.zeta]}}, (0,), (1,))
    names = [v[0] for v in VARIABLES]
    return {k: float(out[names.index(k)].ravel()[0]) for k in KEYS}


def via_basins(case: Case) -> dict | str:
    if not case.batched():
        return f"undefined: solver={case.solver} has no batched kernel (a basin is a sweep over initial states)"
    x0, v0 = case.law_object().start(case.vb)  # simulate's default start, as a one-point basin grid
    ds = basins_study({**case.options(), "t_end": T_END}, x0=(x0, x0, 1), v0=(v0, v0, 1)).dataset
    return {k: float(ds[k].values.ravel()[0]) for k in KEYS}


def via_response(case: Case) -> dict | str:
    if not case.forced:
        return "undefined: a frequency response needs a forcing"
    if case.belt:
        return "undefined: a frequency response sweeps Omega on a belt at constant speed (it refuses a moving one)"
    model = case.model()
    periods = int(T_END / model.forcing_period)
    x0, v0 = case.law_object().start(case.vb)  # simulate's default start
    ds = frequency_response(model, case.law_object(), [model.omega], solver=_solver(case), periods=periods,
                            directions=("up",), x0=x0, v0=v0)
    return {k: float(ds[k].values.ravel()[0]) for k in KEYS}


def via_orbit(case: Case, ref: dict) -> dict | str:
    if KINDS[int(ref["kind"])] != "periodic":
        return "undefined: the point's steady state is not a periodic orbit"
    if case.zeta == 0.0:
        return "undefined: undamped orbits form a continuum (neutral multiplier 1): shooting has no isolated orbit"
    if case.belt:
        return "undefined: the orbit engines run a belt at constant speed (they refuse a moving one)"
    law = case.law_object()
    if case.forced:
        try:
            orbit = find_forced_orbit(case.model(), law, 1, law.fd, case.vb)
        except (ValueError, RuntimeError) as e:
            return f"undefined: {e}"
        av = orbit.averages
        return {"kind": 0, "period": orbit.period, **{k: av[k] for k in POWER}, "TR_B": orbit.TR_B,
                **{k: getattr(orbit, k) for k in EXTREMES}, "stick_fraction": orbit.stick_fraction}
    try:
        orbit = find_orbit(case.model(), law, tol=1e-13)
    except (ValueError, RuntimeError) as e:
        return f"undefined: {e}"
    m = orbit.measures
    return {"kind": 0, "period": orbit.period, **{k: getattr(m.power, k) for k in POWER}, "TR_B": m.TR_B,
            **m.extremes, "stick_fraction": orbit.stick_fraction}


def disagreements(want: dict, got: dict, rtol: float) -> list:
    bad = []
    for k in KEYS:
        a = math.nan if want[k] is None else float(want[k])
        b = math.nan if got[k] is None else float(got[k])
        if math.isnan(a) and math.isnan(b):
            continue
        same = a == b if k == "kind" else abs(a - b) <= rtol * max(abs(a), abs(b))
        if not same:
            bad.append((k, a, b))
    return bad


# -- the matrix -----------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def references():
    return {}


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_simulate_cli_sweep_and_response_agree(case, references):
    want = reference(case)
    references[case] = want
    paths = {"cli": via_cli(case), "sweep": via_sweep(case), "response": via_response(case)}
    for name, got in paths.items():
        if isinstance(got, str):
            assert got.startswith("undefined: "), (name, got)
            continue
        assert not disagreements(want, got, case.rtol), (name, KINDS[int(want["kind"])], disagreements(want, got, case.rtol))


BASIN_CASES = CASES
#: the exact engine's moving-belt rows, each against the adaptive kernel's row of the same point
CROSS_BELT = [c for c in CASES if c.belt and c.solver == "exact"]


@pytest.mark.parametrize("case", CROSS_BELT, ids=[c.id for c in CROSS_BELT])
def test_exact_and_adaptive_agree_on_a_moving_belt(case):
    """Two engines that share only the stick phase: closed-form slips against Dormand-Prince, to its tolerance.

    Over twice the matrix's span: on a moving belt the stroboscopic section converges geometrically (no stick
    phase resets it), and at T_END its transient is still above the exact solver's steady tolerance (1e-10)."""
    other = replace(case, solver="adaptive")
    want, got = (_from_quantities(analyze(simulate(c.model(), c.law_object(), _solver(c), t_end=2.0 * T_END)).quantities())
                 for c in (case, other))
    assert KINDS[int(want["kind"])] == "periodic"
    assert not disagreements(want, got, other.rtol), disagreements(want, got, other.rtol)


@pytest.mark.parametrize("case", BASIN_CASES, ids=[c.id for c in BASIN_CASES])
def test_basins_agree_with_simulate(case):
    got = via_basins(case)
    if isinstance(got, str):
        assert got.startswith("undefined: ")
        pytest.skip(got)
    want = reference(case)
    assert not disagreements(want, got, case.rtol), disagreements(want, got, case.rtol)


ORBIT_CASES = [c for c in CASES if c.zeta > 0 and c.solver != "rk4"]


@pytest.mark.parametrize("case", ORBIT_CASES, ids=[c.id for c in ORBIT_CASES])
def test_orbits_agree_with_simulate(case):
    want = reference(case)
    got = via_orbit(case, want)
    if isinstance(got, str):
        assert got.startswith("undefined: ")
        pytest.skip(got)
    # the shooting solution is the limit itself; the simulation's window converged onto it to its rtol
    assert not disagreements(want, got, max(case.rtol, 1e-8)), disagreements(want, got, max(case.rtol, 1e-8))


# -- the seams the matrix was built to catch -------------------------------------------------------

def test_case_one_as_a_sweep_point_is_the_simulated_cycle():
    """The paper's Case I: periodic, P_fin = V_b F_d (1 - ...) as simulate finds it, R_f = 1, TR_B 1.45."""
    case = Case("karnopp", "case I", (("fd", 0.02), ("fs", 0.02)), 0.01, "resultant", 0.0, False, "exact")
    got = via_sweep(replace(case))
    assert KINDS[int(got["kind"])] == "periodic"
    assert got["period"] == pytest.approx(2 * math.pi, rel=1e-12)  # undamped: the natural period
    assert got["R_f"] == pytest.approx(1.0, rel=1e-12)  # no damper: friction takes out what it puts in
    # the circle about X* = F_d grazing the band |V_r| = V_d: amplitude V_b - V_d, TR_B = (F_d + V_b - V_d) / F_d
    assert got["TR_B"] == pytest.approx((0.02 + 0.01 - 0.001) / 0.02, rel=1e-12)


def test_undamped_coulomb_with_fs_equal_fd_is_not_an_equilibrium():
    case = Case("coulomb", "fs=fd", (("fd", 0.02), ("fs", 0.02)), 0.01, "resultant", 0.0, False, "exact")
    got = via_sweep(case)
    assert KINDS[int(got["kind"])] == "periodic"
    # the circle of radius V_b about X* = F_d: P_fin = mean of F_d max(X', 0) = F_d V_b / pi
    assert got["P_fin"] == pytest.approx(0.02 * 0.01 / math.pi, rel=1e-12)


def test_default_basins_at_zero_damping_are_settled():
    """``frictionflow basins`` defaults sample states at zeta = 0: none may come out 'not settled' for a
    run long enough to see several periods."""
    res = basins_study({"friction": "karnopp", "fd": 0.02, "zeta": 0.0, "vb": 0.01, "t_end": 200.0},
                       x0=(-0.05, 0.05, 4), v0=(-0.05, 0.05, 4))
    kinds = np.asarray(res.dataset["kind"].values).ravel()
    assert not (kinds == KINDS.index("not_settled")).any()


def test_a_belt_at_rest_has_no_power_ratios_on_any_path():
    """V_b = 0: friction only ever opposes the motion, so it puts in nothing; P_fin is rounding (~1e-21) and
    R_c, R_f are null -- they were 1e16-1e17 on the response path."""
    case = Case("coulomb", "belt at rest", (("fd", 0.02), ("fs", 0.02)), 0.0, "resultant", 0.05, True, "exact")
    model = replace(case.model(), fex=0.05, omega=0.5)
    ref = analyze(simulate(model, case.law_object(), t_end=T_END)).quantities()
    assert abs(ref["P_fin"]) < 1e-12 * ref["P_df"] and ref["P_df"] > 0
    ds = frequency_response(model, case.law_object(), [0.5, 1.0], periods=40, directions=("up",))
    for got in (ref, {k: ds[k].values.ravel()[0] for k in ("R_c", "R_f")}):
        assert math.isnan(float(got["R_c"])) and math.isnan(float(got["R_f"]))
    assert np.isnan(ds["R_c"].values).all()
