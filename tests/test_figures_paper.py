"""Figures fit for a paper: every figure a user can write is opened and its size and resolution read back.

A PNG's pixel size must be the figure's size in inches times the dpi asked
for (150 by default), and its pHYs chunk must say that dpi; a PDF's, SVG's
or EPS's page must be the figure's size in points.  Besides: phase portraits
in equal aspect, legends beside the data (never over an axes), numbers in
legends and titles in significant digits and parameters in math text, long
time histories cut to the end of the steady-state window, ``plot_map`` on
log axes for log-spaced values, and the CSV's ``is_sample`` and ``switch``.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from PIL import Image  # noqa: E402

import frictionflow.cli.forced_orbit  # noqa: F401,E402  (registers the forced commands)
from frictionflow import BeltOscillator, Coulomb, analyze, simulate  # noqa: E402
from frictionflow.analysis.response import frequency_response  # noqa: E402
from frictionflow.cli import main  # noqa: E402
from frictionflow.io import DEFAULT_DPI, write_trajectory  # noqa: E402
from frictionflow.orbits import find_orbit  # noqa: E402
from frictionflow.orbits.forced import continue_forced, find_forced_orbit  # noqa: E402
from frictionflow.orbits.forced_plot import plot_forced_branches, plot_forced_orbit  # noqa: E402
from frictionflow.orbits.plotting import plot_orbit  # noqa: E402
from frictionflow.plotting import SHOWN_PERIODS, plot_response, plot_run, plot_trajectory  # noqa: E402
from frictionflow.sweep import plot_cut, plot_map  # noqa: E402

VB = 0.00772279  # a belt speed whose digits must not all reach a legend or title
#: a PNG's pHYs chunk holds whole pixels per metre: a dpi comes back within one of them (0.0254 dpi)
PHYS = 0.0254


# -- reading a written figure back ----------------------------------------------------------------

def png_dpi_and_size(path: Path) -> tuple[tuple[float, float], tuple[int, int]]:
    with Image.open(path) as im:
        assert im.format == "PNG"
        return im.info["dpi"], im.size


def assert_png(path: Path, fig, dpi: float) -> None:
    """The PNG says ``dpi`` and is the figure's size in inches times ``dpi`` pixels (whole ones)."""
    said, size = png_dpi_and_size(path)
    assert said == pytest.approx((dpi, dpi), abs=PHYS)
    w, h = fig.get_size_inches()
    assert size == (int(w * dpi), int(h * dpi))  # Agg truncates the canvas to whole pixels


def page_points(path: Path) -> tuple[float, float]:
    """A vector file's page size in points (1/72 inch), from its own header."""
    data = path.read_bytes()
    if path.suffix == ".pdf":
        assert data.startswith(b"%PDF")
        m = re.search(rb"/MediaBox\s*\[\s*0 0 ([\d.]+) ([\d.]+)\s*\]", data)
    elif path.suffix == ".svg":
        assert b"<svg" in data[:2000]
        m = re.search(rb'<svg[^>]*width="([\d.]+)pt" height="([\d.]+)pt"', data)
    else:
        assert data.startswith(b"%!PS-Adobe") and b"EPSF" in data[:40]
        m = re.search(rb"%%BoundingBox: 0 0 (\d+) (\d+)", data)
    assert m, path
    return float(m.group(1)), float(m.group(2))


def assert_vector(path: Path, fig) -> None:
    w, h = fig.get_size_inches() * 72
    got = page_points(path)
    tol = 1.0 if path.suffix == ".eps" else 0.01  # the EPS bounding box is in whole points
    assert got == pytest.approx((w, h), abs=tol)


def texts(fig) -> list[str]:
    """Every title, label, tick-free text and legend entry of the figure."""
    out = [t.get_text() for t in fig.findobj(matplotlib.text.Text)]
    return [t for t in out if t]


def assert_legends_beside_the_data(fig) -> None:
    """No legend overlaps the data area of any axes of the figure."""
    if not hasattr(fig.canvas, "get_renderer"):  # a figure closed once written: draw it on a canvas of its own
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legends = [a.get_legend() for a in fig.axes if a.get_legend() is not None]
    assert legends
    for leg in legends:
        box = leg.get_window_extent(renderer)
        for ax in fig.axes:
            if ax.get_label() == "<colorbar>":
                continue
            assert not box.overlaps(ax.get_window_extent(renderer)), (leg.get_texts()[0].get_text(), ax.get_title())


def assert_rounded(fig) -> None:
    """No number in the figure's texts carries more than 4 significant digits (the belt speed's 6 never)."""
    for t in texts(fig):
        assert "7722" not in t, t
        for number in re.findall(r"\d+\.\d+(?:e-?\d+)?", t):
            mantissa = number.split("e")[0].replace(".", "").lstrip("0")
            assert len(mantissa) <= 4, t


# -- one run ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def long_run():
    """500 tau of a stick-slip cycle of period ~8: a time history that would be a solid band."""
    return analyze(simulate(BeltOscillator(0.05, VB), Coulomb(0.02, 0.04), t_end=500.0))


def test_plot_run_png_at_150_dpi_by_default(long_run, tmp_path):
    path = tmp_path / "run.png"
    fig = plot_run(long_run, path)
    assert DEFAULT_DPI == 150
    assert_png(path, fig, 150)


@pytest.mark.parametrize("dpi", [72, 300])
def test_plot_run_png_at_the_dpi_asked_for(long_run, tmp_path, dpi):
    path = tmp_path / "run.png"
    fig = long_run.plot(path, dpi=dpi)  # the result's .plot() passes dpi on
    assert_png(path, fig, dpi)


@pytest.mark.parametrize("suffix", [".pdf", ".svg", ".eps"])
def test_vector_formats_by_suffix(long_run, tmp_path, suffix):
    path = tmp_path / f"run{suffix}"
    fig = plot_run(long_run, path, dpi=200)
    assert_vector(path, fig)


def test_plot_run_reads_as_a_figure_for_a_paper(long_run):
    fig = plot_run(long_run)
    history, phase = fig.axes[0], fig.axes[1]
    assert phase.get_aspect() == 1.0  # X and X' in the same units
    assert_legends_beside_the_data(fig)
    assert_rounded(fig)
    title = fig._suptitle.get_text()
    assert r"$V_b=0.00772$" in title and r"$\zeta=0.05$" in title  # math text, rounded
    # 500 tau would be ~60 periods: the history shows the last SHOWN_PERIODS of the steady-state window
    ss = long_run.steady_state
    t0, t1 = history.get_lines()[0].get_xdata()[[0, -1]]
    assert t1 == pytest.approx(ss.window[1], abs=0.05)
    assert t1 - t0 == pytest.approx(SHOWN_PERIODS * ss.period, rel=0.01)
    assert "of $[0, 500]$" in history.get_title()
    plt.close(fig)


def test_a_short_run_shows_its_whole_history():
    result = analyze(simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=60.0))
    fig = plot_run(result)
    t = fig.axes[0].get_lines()[0].get_xdata()
    assert t[0] == 0.0 and t[-1] == pytest.approx(60.0) and fig.axes[0].get_title() == "time history"
    plt.close(fig)


def test_plot_trajectory_png_and_pdf(long_run, tmp_path):
    traj = long_run.trajectory
    fig = plot_trajectory(traj, tmp_path / "t.png", dpi=120)
    assert_png(tmp_path / "t.png", fig, 120)
    fig = traj.plot(tmp_path / "t.pdf")
    assert_vector(tmp_path / "t.pdf", fig)
    assert fig.axes[1].get_aspect() == 1.0
    t = fig.axes[0].get_lines()[0].get_xdata()
    assert t[-1] - t[0] == pytest.approx(SHOWN_PERIODS * 2 * math.pi, rel=1e-3)  # the natural period: no analysis
    assert_legends_beside_the_data(fig)
    assert_rounded(fig)


def test_bad_dpi_or_suffix_writes_nothing(long_run, tmp_path):
    for dpi in (0, -5, 1e5, float("nan"), "300", True):
        with pytest.raises(ValueError, match=r"^dpi must be a number in \[10, 2400\]"):
            plot_run(long_run, tmp_path / "r.png", dpi=dpi)
    with pytest.raises(ValueError, match=r"^path must end in one of \.png, \.pdf, \.svg, \.eps"):
        plot_run(long_run, tmp_path / "r.jpg")
    assert list(tmp_path.iterdir()) == []


# -- the CSV -------------------------------------------------------------------------------------------

def test_csv_has_is_sample_and_switch(long_run, tmp_path):
    traj = long_run.trajectory
    path = write_trajectory(traj, tmp_path / "t.csv")
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert table.dtype.names[-2:] == ("is_sample", "switch")
    assert np.all(table["is_sample"] == 1)  # every row of a solver's trajectory is its own sample
    flagged = np.flatnonzero(table["switch"] == 1)
    # a flagged row is where the mode changes: the mode differs from the row before or after
    mode = table["mode"]
    before = np.r_[mode[0], mode[:-1]]
    after = np.r_[mode[1:], mode[-1]]
    assert len(flagged) > 20 and np.all((mode[flagged] != before[flagged]) | (mode[flagged] != after[flagged]))
    # the same flags as the NetCDF file's (the trajectory's own dataset)
    ds = traj.to_xarray(dense=False)
    assert np.array_equal(table["switch"].astype(bool), ds["switch"].values)
    assert np.array_equal(table["tau"], traj.t)


def test_trajectory_attributes_name_the_law_once(long_run):
    attrs = long_run.trajectory.to_xarray(dense=False).attrs
    assert attrs["friction"] == "coulomb" and attrs["friction_fd"] == 0.02 and attrs["friction_fs"] == 0.04
    assert not any(k.startswith("friction_friction") for k in attrs)


# -- orbits, forced orbits, the frequency response ----------------------------------------------------

def test_plot_orbit(tmp_path):
    orbit = find_orbit(BeltOscillator(zeta=0.05, vb=VB), Coulomb(fd=0.02, fs=0.04))
    fig = plot_orbit(orbit, tmp_path / "o.png", dpi=100)
    assert_png(tmp_path / "o.png", fig, 100)
    assert fig.axes[0].get_aspect() == 1.0
    assert_legends_beside_the_data(fig)
    assert_rounded(fig)
    fig = orbit.plot(tmp_path / "o.svg")
    assert_vector(tmp_path / "o.svg", fig)


SUB = dict(fex=0.5, omega=1.0)


@pytest.fixture(scope="module")
def forced():
    model = BeltOscillator(zeta=0.05, vb=0.1, **SUB)
    law = Coulomb(0.5, 1.0)
    return model, law


def test_plot_forced_orbit(forced, tmp_path):
    orbit = find_forced_orbit(*forced, m=3)
    fig = plot_forced_orbit(orbit, tmp_path / "f.png", dpi=110)
    assert_png(tmp_path / "f.png", fig, 110)
    assert fig.axes[0].get_aspect() == 1.0
    assert_legends_beside_the_data(fig)
    assert r"$F_{ex}=0.5$" in fig._suptitle.get_text()


def test_plot_forced_branches(forced, tmp_path):
    branch = continue_forced(*forced, "omega", 1.25, 1.3, m=3, max_points=8)
    fig = plot_forced_branches(branch, tmp_path / "b.pdf")
    assert_vector(tmp_path / "b.pdf", fig)
    fig = plot_forced_branches(branch, tmp_path / "b.png", dpi=90)
    assert_png(tmp_path / "b.png", fig, 90)
    assert_legends_beside_the_data(fig)


def test_plot_response(tmp_path):
    from frictionflow import Karnopp, RK4

    ds = frequency_response(BeltOscillator(zeta=0.1, vb=0.0, fex=0.3), Karnopp(0.05, 0.05), [0.8, 1.0, 1.2],
                            solver=RK4(dt=3e-4), periods=20)
    fig = plot_response(ds, tmp_path / "r.png")
    assert_png(tmp_path / "r.png", fig, DEFAULT_DPI)
    assert_legends_beside_the_data(fig)
    assert "$F_{ex}=0.3$" in fig._suptitle.get_text()


# -- sweeps: heat maps on the axes' own scale -----------------------------------------------------------

def sweep_like() -> xr.Dataset:
    """A sweep's shape: vb log-spaced (scale = "log"), zeta linear, R_c over both."""
    vb = np.geomspace(1e-3, 0.1, 5)
    zeta = np.linspace(0.0, 0.04, 3)
    rc = np.outer(zeta, np.log(vb))
    return xr.Dataset({"R_c": (("zeta", "vb"), rc, {"long_name": "damper ratio"})}, coords={"zeta": zeta, "vb": vb})


def test_plot_map_takes_a_log_axis_for_log_spaced_values(tmp_path):
    ds = sweep_like()
    fig = plot_map(ds, "R_c", "vb", "zeta", tmp_path / "m.png", dpi=100)
    assert_png(tmp_path / "m.png", fig, 100)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "linear"
    mesh = ax.collections[0]
    edges = mesh.get_coordinates()[0, :, 0]
    vb = ds.vb.values
    # each cell centred on its value on the log axis: the edges are the geometric means of neighbours
    assert np.allclose(edges[1:-1], np.sqrt(vb[1:] * vb[:-1]), rtol=1e-12)
    assert edges[0] > 0 and np.allclose(edges[0], vb[0] ** 2 / edges[1], rtol=1e-12)
    assert ax.get_xlabel() == "$V_b$" and ax.get_ylabel() == r"$\zeta$"


def test_plot_map_log_given_is_honoured(tmp_path):
    ds = sweep_like()
    fig = plot_map(ds, "R_c", "vb", "zeta", log=(False, False))
    assert fig.axes[0].get_xscale() == "linear"
    edges = fig.axes[0].collections[0].get_coordinates()[0, :, 0]
    assert np.allclose(edges[1:-1], 0.5 * (ds.vb.values[1:] + ds.vb.values[:-1]), rtol=1e-12)
    plt.close(fig)
    fig = plot_map(ds, "R_c", "zeta", "vb", log=(False, True))
    assert fig.axes[0].get_yscale() == "log"
    plt.close(fig)


def test_plot_cut_rounds_its_legend_and_puts_it_beside_the_data(tmp_path):
    ds = sweep_like()
    ds = ds.assign_coords(vb=np.array([VB, 0.01, 0.02, 0.05, 0.1]))
    fig = plot_cut(ds, "R_c", "zeta", tmp_path / "c.eps", hue="vb")
    assert_vector(tmp_path / "c.eps", fig)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels[0] == "$V_b=0.00772$"
    assert_legends_beside_the_data(fig)


# -- the command line: --dpi on every command that writes a figure -------------------------------------

COMMANDS = {
    "simulate": ["simulate", "--t-end", "40"],
    "orbit": ["orbit", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--vb", "0.01", "--zeta", "0.05",
              "--t-end", "50"],
    "continue": ["continue", "--param", "vb", "--from", "0.005", "--to", "0.025", "--friction", "stribeck", "--delta",
                 "1", "--viscous", "0.05", "--zeta", "0.1", "--points", "11", "--seeds", "hopf", "--max-points", "20"],
    "response": ["response", "--fex", "0.3", "--zeta", "0.1", "--vb", "0", "--friction", "karnopp", "--fd", "0.05",
                 "--solver", "rk4", "--dt", "5e-3", "--periods", "20", "--omega", "0.9:1.1:2"],
    "forced-orbit": ["forced-orbit", "--zeta", "0.05", "--vb", "0.1", "--fex", "0.5", "--omega", "1.0", "--friction",
                     "coulomb", "--fd", "0.5", "--fs", "1.0", "--m", "3"],
    "forced-continue": ["forced-continue", "--zeta", "0.05", "--vb", "0.1", "--fex", "0.5",
                        "--friction", "coulomb", "--fd", "0.5", "--fs", "1.0", "--m", "3", "--from", "1.25", "--to",
                        "1.3", "--max-points", "8"],
    "map": ["map", "--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.01", "--x", "vb", "--x-from",
            "0.008", "--x-to", "0.02", "--x-points", "4", "--y", "zeta", "--y-from", "0", "--y-to", "1", "--curves",
            "hopf"],
    "basins": ["basins", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--zeta", "0.05", "--vb", "0.01",
               "--t-end", "60", "--x0=0:0.04:3", "--v0=-0.02:0.02:3"],
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_command_writes_its_figure_at_the_dpi_asked_for(command, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "f.png"
    code = main([*COMMANDS[command], "--plot", str(path), "--dpi", "120", "--json"])
    assert code == 0, capsys.readouterr().err
    said, (w, h) = png_dpi_and_size(path)
    assert said == pytest.approx((120, 120), abs=PHYS)
    assert 4 <= w / 120 <= 20 and 3 <= h / 120 <= 12  # a figure's size in inches, at the dpi said


@pytest.mark.parametrize("dpi", ["0", "9.9", "2401", "x"])
def test_a_bad_dpi_is_refused_before_any_work(dpi, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code = main([*COMMANDS["simulate"], "--plot", "f.png", "--dpi", dpi])
    err = capsys.readouterr().err
    assert code == 2 and "--dpi" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_the_cli_writes_vector_figures_by_suffix(tmp_path, capsys):
    for suffix in (".pdf", ".svg", ".eps"):
        path = tmp_path / f"f{suffix}"
        assert main([*COMMANDS["simulate"], "--plot", str(path), "--json"]) == 0
        w, h = page_points(path)
        assert 4 * 72 <= w <= 20 * 72 and 3 * 72 <= h <= 12 * 72
    capsys.readouterr()
