"""The quantities table: every report follows its order, and the equilibrium's row follows its rules."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Exact, SlidingEquilibrium, Stribeck, analyze, simulate, sliding_equilibrium
from frictionflow import quantities as Q
from frictionflow.analysis.power_flow import PowerFlow
from frictionflow.analysis.summary import DEFAULT_RTOL
from frictionflow.core import batch
from frictionflow.core import sections as sec
from frictionflow.orbits import equilibria
from frictionflow.orbits.branches import POINT_POWER
from frictionflow.orbits.measures import POWER_KEYS, equilibrium_measures
from frictionflow.sweep import KIND_NAMES, VARIABLES, run_sweep

FD, FS = 0.02, 0.04
#: what the golden outputs recorded: the order of the sweep variables / kernel row and of the JSON objects
RECORDED_ROW = ("kind", "period", "P_dv", "P_df", "P_fin", "R_c", "R_f", "P_belt", "P_heat", "TR_B",
                "X_min", "X_max", "V_min", "V_max", "stick_fraction", "energy_residual", "P_ex")
RECORDED_AVERAGES = ("P_dv", "P_df", "P_fin", "R_c", "R_f", "P_belt", "P_heat", "P_f")
RECORDED_AMPLITUDE = ("X_min", "X_max", "V_min", "V_max")


def json_value(d: dict, q: Q.Quantity):
    """Quantity ``q`` in a ``simulate --json`` dict, where the table says it is reported (kinds as codes)."""
    if q.report == q.name:
        value = d[q.name]
    elif q.forced_only and q.name not in d[q.report]:  # an unforced report leaves it out: no force, no work
        value = 0.0
    else:
        value = d[q.report][q.name]
    if q.name == "kind":
        return float(Q.KINDS.index(value))
    return math.nan if value is None else value


def same(got: float, want: float, rel: float = 0.0) -> bool:
    return (math.isnan(got) and math.isnan(want)) or got == pytest.approx(want, rel=rel, abs=0.0)


# -- the table and its layouts ---------------------------------------------------------------


def test_the_table_keeps_the_recorded_orders():
    assert tuple(q.name for q in Q.SWEPT) == RECORDED_ROW
    assert Q.AVERAGES == RECORDED_AVERAGES
    assert Q.AMPLITUDE == RECORDED_AMPLITUDE
    assert Q.REPORTS == ("steady_state", "averages", "TR_B", "amplitude", "energy_residual")
    assert Q.PAPER_AVERAGES == ("P_fin", "P_df", "P_dv", "R_c", "R_f", "P_belt", "P_heat", "P_f")


def test_the_kernel_row_is_the_table_prefix():
    assert batch.NR == Q.NR == len(RECORDED_ROW)
    assert Q.TABLE[: Q.NR] == Q.SWEPT
    for name, pos in [("kind", batch.R_KIND), ("period", batch.R_PERIOD), ("P_dv", batch.R_P_DV), ("P_df", batch.R_P_DF),
                      ("P_fin", batch.R_P_FIN), ("R_c", batch.R_R_C), ("R_f", batch.R_R_F), ("P_belt", batch.R_P_BELT),
                      ("P_heat", batch.R_P_HEAT), ("TR_B", batch.R_TR_B), ("X_min", batch.R_X_MIN), ("X_max", batch.R_X_MAX),
                      ("V_min", batch.R_V_MIN), ("V_max", batch.R_V_MAX), ("stick_fraction", batch.R_STICK),
                      ("energy_residual", batch.R_RESID)]:
        assert pos == Q.index(name), name
    for name, pos in [("P_dv", sec.P_DV), ("P_f", sec.P_F), ("R_c", sec.R_C), ("TR_B", sec.S_TRB),
                      ("stick_fraction", sec.S_STICK), ("energy_residual", sec.RESID)]:
        assert pos == Q.index(name), name
    assert sec.NS == Q.NQ + 2 and (sec.S_T0, sec.S_T1) == (Q.NQ, Q.NQ + 1)


def test_sweep_variables_and_result_dataclass_follow_the_table():
    assert VARIABLES == tuple((q.name, q.units, q.long_name) for q in Q.SWEPT)
    assert KIND_NAMES == Q.KINDS == ("periodic", "equilibrium", "not_settled", "diverged", "quasi_periodic", "chaotic")
    assert [f.name for f in dataclasses.fields(PowerFlow)] == ["window", *Q.FORCED_AVERAGES, "energy_residual"]
    assert Q.FORCED_AVERAGES == (*Q.AVERAGES, "P_ex")
    assert POWER_KEYS == Q.PAPER_AVERAGES
    assert POINT_POWER == tuple(n for n in Q.PAPER_AVERAGES if n != "P_f")


def test_table_fields_needs_the_anchor_field():
    with pytest.raises(TypeError, match="no field 'window'"):
        Q.table_fields(Q.AVERAGES, after="window")(type("Empty", (), {"__annotations__": {"x": "float"}}))


# -- every consumer reads the quantities where the table puts them ----------------------------


@pytest.fixture(scope="module")
def points():
    """Stick-slip (periodic), sliding (equilibrium) and a negative belt speed: (zeta, vb, fs) per point."""
    return [(0.05, 0.01, FS), (0.05, 0.01, FD), (0.02, -0.02, FS)]


@pytest.fixture(scope="module")
def kernel_rows(points):
    laws = [Coulomb(FD, fs) for _, _, fs in points]
    p = np.array([law.kernel_params() for law in laws])
    zeta = np.array([z for z, _, _ in points])
    vb = np.array([v for _, v, _ in points])
    out = np.empty((len(points), batch.NR))
    batch.exact_points(p, zeta, vb, np.full(len(points), FD), vb.copy(), 300.0, DEFAULT_RTOL["exact"], 3, 1e-13, out)
    return out


def test_json_keys_follow_the_table(points):
    zeta, vb, fs = points[0]
    d = analyze(simulate(BeltOscillator(zeta, vb), Coulomb(FD, fs), Exact(), t_end=300.0)).to_dict()
    assert list(d) == ["params", "solver", *Q.REPORTS, "events"]
    assert tuple(d["averages"]) == Q.AVERAGES
    assert tuple(d["amplitude"]) == Q.AMPLITUDE


def test_kernel_rows_hold_what_simulate_reports_at_the_table_positions(points, kernel_rows):
    kinds = set()
    for (zeta, vb, fs), row in zip(points, kernel_rows, strict=True):
        d = analyze(simulate(BeltOscillator(zeta, vb), Coulomb(FD, fs), Exact(), t_end=300.0)).to_dict()
        kinds.add(d["steady_state"]["kind"])
        for q in Q.SWEPT:
            want = json_value(d, q)
            if q.name != "energy_residual":  # rounding noise, summed over different spans
                assert same(row[Q.index(q.name)], want, rel=1e-9), (zeta, vb, fs, q.name)
    assert kinds == {"periodic", "equilibrium"}


def test_sweep_dataset_stores_the_rows_under_the_table_names(tmp_path, points, kernel_rows):
    zeta, vb, fs = points[0]
    ds = run_sweep({"friction": "coulomb", "fs": fs, "fd": FD, "t_end": 300.0, "grid": {"zeta": [zeta], "vb": [vb]}},
                   tmp_path / "s.zarr").load()
    assert set(ds.data_vars) == {q.name for q in Q.SWEPT}
    for q in Q.SWEPT:
        assert ds[q.name].attrs["units"] == q.units and ds[q.name].attrs["long_name"] == q.long_name
        assert same(float(ds[q.name].values.ravel()[0]), kernel_rows[0, Q.index(q.name)]), q.name
    assert ds["kind"].dtype == np.int8
    assert ds["kind"].attrs["flag_meanings"] == "periodic equilibrium not_settled diverged quasi_periodic chaotic"
    assert list(ds["kind"].attrs["flag_values"]) == [0, 1, 2, 3, 4, 5]


# -- the sliding equilibrium, written once ------------------------------------------------------


def closed_form(x: float, vb: float, fd: float, resid: float, stick: float = 0.0) -> dict[str, float]:
    """The equilibrium's values by hand: at rest at X*, the belt's power X* V_b all heat (0 stuck)."""
    belt = 0.0 if stick >= 0.5 else x * vb
    nan = math.nan
    return {"kind": 1.0, "period": nan, "P_dv": 0.0, "P_df": 0.0, "P_fin": 0.0, "R_c": nan, "R_f": nan,
            "P_belt": belt, "P_heat": belt, "TR_B": abs(x) / fd, "X_min": x, "X_max": x, "V_min": 0.0, "V_max": 0.0,
            "stick_fraction": stick, "energy_residual": resid, "P_f": 0.0, "P_ex": 0.0}


@pytest.mark.parametrize("vb", [0.01, -0.03])
def test_equilibrium_row_is_the_closed_form_for_coulomb(vb):
    eq = sliding_equilibrium(BeltOscillator(zeta=0.05, vb=vb), Coulomb(FD, FS))
    assert eq.x == math.copysign(FD, vb)  # X* = F(V_b) = F_d sign(V_b)
    row = sec.equilibrium_row(eq.x, vb, FD, 0.0, 3e-16)
    want = closed_form(eq.x, vb, FD, 3e-16)
    assert set(want) == set(Q.NAMES)
    for name, value in want.items():
        assert same(row[Q.index(name)], value), name
    assert row[Q.index("P_belt")] == FD * abs(vb) > 0  # the belt always delivers power


def test_resting_in_a_stick_band_takes_no_belt_power():
    row = sec.equilibrium_row(0.015, 0.01, FD, 1.0, 0.0)
    for name, value in closed_form(0.015, 0.01, FD, 0.0, stick=1.0).items():
        assert same(row[Q.index(name)], value), name
    assert math.isnan(sec.equilibrium_row(0.015, 0.01, 0.0, 0.0, 0.0)[Q.index("TR_B")])  # no F_d to refer to


def test_kernels_analysis_and_orbits_report_the_same_equilibrium(points, kernel_rows):
    zeta, vb, fs = points[1]  # sliding: fs = fd
    res = analyze(simulate(BeltOscillator(zeta, vb), Coulomb(FD, fs), Exact(), t_end=300.0))
    assert res.steady_state.kind == "equilibrium"
    want = closed_form(FD, vb, FD, res.energy_residual)
    d = res.to_dict()
    for q in Q.TABLE:
        if q.report != "steady_state" and not q.forced_only:  # an unforced run reports no P_ex
            assert same(json_value(d, q), want[q.name]), q.name
    for q in Q.SWEPT:
        if q.name != "energy_residual":
            assert same(kernel_rows[1, Q.index(q.name)], want[q.name]), q.name
    m = equilibrium_measures(FD, vb, FD)
    for name, value in m.power.averages().items():
        assert same(value, want[name]), name
    assert m.TR_B == 1.0 and m.extremes == dict.fromkeys(("X_min", "X_max"), FD) | dict.fromkeys(("V_min", "V_max"), 0.0)


def test_one_sliding_equilibrium_class_with_stability_from_the_effective_damping():
    assert equilibria.Equilibrium is SlidingEquilibrium
    model, law = BeltOscillator(zeta=0.1, vb=0.012), Stribeck(FD, FS, vs=0.01, delta=2.0)
    u = (0.012 / 0.01) ** 2
    slope = -(FS - FD) * 2.0 * u / 0.012 * math.exp(-u)  # dF/dV_r by hand
    eq = sliding_equilibrium(model, law)
    assert eq.x == pytest.approx(FD + (FS - FD) * math.exp(-u), rel=1e-14)
    assert eq.damping == pytest.approx(0.2 + slope, rel=1e-12)
    assert eq.stability == ("stable" if 0.2 + slope > 0 else "unstable")
    for lam in eq.eigenvalues:
        assert abs(lam * lam + eq.damping * lam + 1.0) < 1e-14
    assert eq.decay_rate == pytest.approx(eq.damping / 2, rel=1e-12)
    assert np.trace(eq.jacobian) == -eq.damping
    on_branch = equilibria.equilibrium(model, law, 0.7)
    assert on_branch == dataclasses.replace(eq, value=0.7)
