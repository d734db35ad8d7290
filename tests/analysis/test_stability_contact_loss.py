"""A stability scan through values where steady sliding loses a contact (QA: ``stability`` on a model whose normal
load follows the tangential dof refused the whole scan at the first value with N* <= 0).

The model is Hoffmann's two-dof structure with the normal load N = P + c x1 (c = 2): K_eff = K - mu e n^T is
symmetric, and the steady sliding state's load, derived below by hand, is N* = P det K / det K_eff -- it changes
sign through infinity where det K_eff = 0, at mu* = det K / (c K22).  The expectations are those closed forms.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from frictionflow.analysis.stability import KINDS, StabilityScan, stability_scan
from frictionflow.cli import main
from frictionflow.system import assemble, load_system

HN = """
dof = ["x1", "x2"]
mass = [1.0, 1.0]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x2 = 1.0 }
k = 0.5
[[spring]]
on = { x1 = -1.0, x2 = 1.0 }
k = 0.5
[[spring]]
on = { x2 = 1.0 }
k = 1.0
[[contact]]
on = { x1 = 1.0 }
belt = 1.0
friction = "coulomb"
fd = 0.7
fs = 2.0
normal = { preload = 1.0, x1 = 2.0 }
"""

# K by hand from the springs: k1 = 1 on x1; 0.5 + 1 on x2; 0.5 (-1, 1)(-1, 1)^T
K = np.array([[1.0 + 0.5, -0.5], [-0.5, 0.5 + 1.0 + 0.5]])
P, C = 1.0, 2.0  # the preload and the load's coefficient on x1


def normal_load(mu: float) -> float:
    """N* = P + C x1*, with q* = K_eff^-1 (mu P, 0) and K_eff = K - mu (1, 0)(C, 0)^T, solved here by hand."""
    k_eff = K - mu * np.array([[C, 0.0], [0.0, 0.0]])
    det = k_eff[0, 0] * k_eff[1, 1] - k_eff[0, 1] * k_eff[1, 0]
    x1 = mu * P * k_eff[1, 1] / det
    return P + C * x1


#: det K_eff = (K11 - mu C) K22 - K12 K21 = 0: N* = P det K / det K_eff changes sign there (through infinity)
MU_STAR = (K[0, 0] * K[1, 1] - K[0, 1] * K[1, 0]) / (C * K[1, 1])


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "hn.toml"
    path.write_text(HN)
    return path


def scan_of(model, values, entry="contact.0.fd") -> StabilityScan:
    system = load_system(model)
    return stability_scan(lambda v: assemble(system.with_entry(entry, v)), values, param=entry)


def test_the_closed_form_is_the_qa_reports():
    assert MU_STAR == 0.6875  # 2.75 / 4
    for mu in (0.3, 0.6, 0.68, 0.7, 0.9):
        assert normal_load(mu) == pytest.approx(2.75 / (2.75 - 4.0 * mu), rel=1e-12)
    assert normal_load(0.687) > 0 > normal_load(0.688)


def test_the_model_file_assembles_to_the_matrices_derived_by_hand(model):
    a = assemble(load_system(model))
    assert np.array_equal(a.stiffness, K)
    assert np.array_equal(np.asarray(a.normal).reshape(-1), [P, C, 0.0])


@pytest.mark.parametrize("values", [np.linspace(0.3, 0.9, 61), np.linspace(0.9, 0.3, 61), np.linspace(0.3, 0.9, 49)])
def test_the_scan_goes_on_and_locates_where_the_contact_is_lost(model, values):
    # linspace(0.3, 0.9, 49) has 0.6875 itself among its values (K_eff singular there: no isolated equilibrium)
    scan = scan_of(model, values)
    lost = np.array([abs(v - MU_STAR) < 1e-12 or not normal_load(v) > 0 for v in values])
    assert np.array_equal(scan.lost, lost) and 0 < lost.sum() < len(values)
    assert np.all(np.isnan(scan.eigenvalues[lost])) and not np.any(np.isnan(scan.eigenvalues[~lost]))
    assert not np.any(scan.stable[lost])
    [crit] = scan.critical
    assert crit.kind == "contact_loss" and "contact_loss" in KINDS
    assert abs(crit.value - MU_STAR) < 1e-8
    assert crit.unstable_above is True  # lost above mu*, whichever way the values run
    assert math.isnan(crit.frequency)
    assert "contact_loss" in repr(scan) and "no steady sliding at" in repr(scan)


def test_the_valid_values_are_those_of_a_scan_restricted_to_them(model):
    values = np.linspace(0.3, 0.9, 61)
    scan = scan_of(model, values)
    valid = values[values < MU_STAR]
    restricted = scan_of(model, valid)
    assert np.array_equal(scan.eigenvalues[~scan.lost], restricted.eigenvalues)
    assert np.array_equal(scan.stable[~scan.lost], restricted.stable)
    # and they are the undamped ones: M = I, K_eff symmetric positive definite below mu*: lambda = +-i sqrt(eig)
    for v, lam in zip(valid, restricted.eigenvalues):
        w = np.sqrt(np.linalg.eigvalsh(K - v * np.array([[C, 0.0], [0.0, 0.0]])))
        assert np.allclose(np.sort(np.abs(lam.imag)), np.sort(np.r_[w, w]), rtol=1e-12)
        assert np.all(np.abs(lam.real) < 1e-12)


def test_a_lost_stretch_between_two_valid_ones_has_a_boundary_on_each_side(model):
    # spring.2.on.x1 = a: K = [[1 + a^2 / 2, a / 2], [a / 2, 2]], det K_eff = 2 - 4 mu + 3 a^2 / 4 (mu = 0.7):
    # no steady sliding for |a| < sqrt(16 / 15); each stretch tracked on its own
    values = np.linspace(-2.0, 2.0, 40)
    scan = scan_of(model, values, "spring.2.on.x1")
    a_star = math.sqrt((4 * 0.7 - 2.0) / 0.75)
    assert np.array_equal(scan.lost, np.abs(values) < a_star)
    low, high = scan.critical
    assert (low.kind, high.kind) == ("contact_loss", "contact_loss")
    assert low.value == pytest.approx(-a_star, abs=1e-8) and low.unstable_above is True
    assert high.value == pytest.approx(a_star, abs=1e-8) and high.unstable_above is False
    for part in (values[values < -a_star], values[values > a_star]):
        alone = scan_of(model, part, "spring.2.on.x1")
        assert np.array_equal(scan.eigenvalues[np.isin(values, part)], alone.eigenvalues)


def test_the_scan_reads_as_json_with_nulls_where_it_is_lost(model):
    values = np.linspace(0.3, 0.9, 61)
    scan = scan_of(model, values)
    report = json.loads(json.dumps(scan.to_dict(), allow_nan=False))
    assert report["lost"] == scan.lost.tolist()
    for row, lost in zip(report["eigenvalues"], scan.lost):
        assert len(row) == 4
        assert all((z["re"] is None and z["im"] is None) == bool(lost) for z in row)
    [crit] = report["critical"]
    assert crit["kind"] == "contact_loss" and crit["frequency"] is None and crit["unstable_above"] is True
    assert abs(crit["value"] - MU_STAR) < 1e-8


def test_the_command_keeps_the_valid_part_and_lists_the_boundary(model, capsys):
    assert main(["stability", "--model", str(model), "--param", "contact.0.fd", "--from", "0.3", "--to", "0.9",
                 "--json"]) == 0
    out, _ = capsys.readouterr()
    report = json.loads(out)
    [crit] = [c for c in report["critical"] if c["kind"] == "contact_loss"]
    assert abs(crit["value"] - MU_STAR) < 1e-8 and crit["unstable_above"] is True
    values = np.array(report["values"])
    assert report["lost"] == (values > MU_STAR).tolist()
    assert all(z["re"] is not None for row, v in zip(report["eigenvalues"], values) if v < MU_STAR for z in row)


def test_a_range_where_every_value_is_lost_is_refused_in_one_line(model, capsys):
    assert main(["stability", "--model", str(model), "--param", "contact.0.fd", "--from", "0.7", "--to", "0.9",
                 "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.strip().count("\n") == 0 and "the contact is lost" in err and "every other value" in err
    with pytest.raises(ValueError, match=r"^contact\.0\.fd = 0\.7: contact\.0: the normal load .* no steady sliding"):
        scan_of(model, np.linspace(0.7, 0.9, 5))


def test_the_figure_draws_the_valid_stretch_and_marks_the_boundary(model, tmp_path):
    import frictionflow  # noqa: F401  (registers the figures)
    from frictionflow.stability_plot import MARKERS

    assert set(MARKERS) == set(KINDS)
    values = np.linspace(0.3, 0.9, 61)
    scan = scan_of(model, values)
    path = tmp_path / "loci.png"
    fig = scan.plot(path)
    assert path.stat().st_size > 0
    top, bottom = fig.axes[:2]
    [mark] = [line for line in top.lines if line.get_marker() == MARKERS["contact_loss"][0]]
    assert mark.get_xdata()[0] == scan.critical[0].value
    assert not [line for line in bottom.lines if line.get_marker() == MARKERS["contact_loss"][0]]
    loci = [line for line in bottom.lines if line.get_marker() in ("None", "", None) and len(line.get_xdata()) == 61]
    assert len(loci) == 2
    for line in loci:  # drawn where steady sliding exists, broken (NaN) where it does not
        y = np.asarray(line.get_ydata(), dtype=float)
        assert np.all(np.isfinite(y[values < MU_STAR])) and np.all(np.isnan(y[values > MU_STAR]))
    spans = [p for p in top.patches]  # the shaded lost values, from the boundary on
    assert len(spans) == 1
    x0, x1 = spans[0].get_x(), spans[0].get_x() + spans[0].get_width()
    assert x0 == pytest.approx(scan.critical[0].value, abs=1e-12) and x1 == pytest.approx(0.9)
