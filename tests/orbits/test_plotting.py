"""Bifurcation diagrams: stable solid, unstable dashed, sweep points overlaid, formats by extension."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.orbits import find_orbit
from frictionflow.orbits.branches import (
    Bifurcation,
    Branch,
    BranchPoint,
    ContinuationResult,
)
from frictionflow.orbits.measures import equilibrium_measures
from frictionflow.orbits.plotting import plot_bifurcation, plot_orbit


def _point(value, kind, stability, amp):
    m = equilibrium_measures(0.02, 0.01, 0.02)
    m.extremes.update(X_min=0.02 - amp, X_max=0.02 + amp)
    return BranchPoint(value=value, kind=kind, stability=stability, x=0.02 + amp, measures=m, period=None if kind == "equilibrium" else 6.3)


@pytest.fixture
def result():
    eq = Branch("equilibrium", [_point(v, "equilibrium", s, 0.0) for v, s in ((0.0, "unstable"), (0.1, "unstable"), (0.2, "stable"), (0.3, "stable"))], seed="eq")
    orbits = ((0.2, "unstable", 0.001), (0.25, "unstable", 0.004), (0.3, "stable", 0.006), (0.2, "stable", 0.008))
    cyc = Branch("periodic", [_point(v, "periodic", s, a) for v, s, a in orbits], seed="hopf")
    return ContinuationResult(
        param="zeta", start=0.0, stop=0.3, params={"zeta": 0.1, "vb": 0.01, "friction": "stribeck"}, branches=[eq, cyc],
        bifurcations=[Bifurcation("hopf", 0.15, 0), Bifurcation("fold", 0.3, 1)],
        sweep=[{"value": 0.05, "kind": "periodic", "amplitude": 0.004}, {"value": 0.25, "kind": "equilibrium", "amplitude": 0.0}],
    )


def _lines(ax):
    return [l for l in ax.get_lines() if len(l.get_xdata()) > 1]


def test_stable_solid_unstable_dashed(result):
    fig = plot_bifurcation(result)
    ax = fig.axes[0]
    styles = {(tuple(l.get_xdata()), l.get_linestyle()) for l in _lines(ax)}
    # equilibrium: unstable 0 .. 0.2 (the run ends on the first stable point), then stable
    assert ((0.0, 0.1, 0.2), "--") in styles and ((0.2, 0.3), "-") in styles
    # orbits: dashed while unstable, solid once stable
    assert ((0.2, 0.25, 0.3), "--") in styles and ((0.3, 0.2), "-") in styles
    # the sweep points are drawn as dots, the bifurcations as markers
    dots = [l for l in ax.get_lines() if l.get_marker() == "." and len(l.get_xdata()) == 2]
    assert dots and list(dots[0].get_xdata()) == [0.05, 0.25]
    assert {l.get_marker() for l in ax.get_lines() if len(l.get_xdata()) == 1} >= {"o", "s"}


@pytest.mark.parametrize("ext", [".png", ".pdf", ".svg"])
def test_formats_by_extension(result, tmp_path, ext):
    path = tmp_path / f"bif{ext}"
    plot_bifurcation(result, path)
    head = path.read_bytes()[:8]
    assert {".png": head.startswith(b"\x89PNG"), ".pdf": head.startswith(b"%PDF"), ".svg": b"<?xml" in head or b"<svg" in head}[ext]


def test_orbit_figure(tmp_path):
    orbit = find_orbit(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04))
    plot_orbit(orbit, tmp_path / "orbit.png")
    assert (tmp_path / "orbit.png").stat().st_size > 1000
