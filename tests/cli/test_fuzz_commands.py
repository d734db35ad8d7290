"""Issue 20, item 5: every command fuzzed as typed, each case in its own process with a time and a memory cap.

The command lines come from :mod:`fuzz_strategies` (the commands' click options and the parameter
declarations).  Whatever is drawn, the outcome is one of

* exit 0 with one JSON object that passes the physical checks of :mod:`fuzz_checks` (no negative
  dissipation, the energy balance of periodic results, kind consistent with its numbers, options echoed);
* exit 2 (bad input, or work refused by its estimate) or 1 (a run that could not finish) with one line
  ``error: ...`` on stderr (warnings aside), nothing on stdout and no file left behind;

never a traceback, an ignored exception, a run past :data:`TIME_CAP`, a crash at the address-space cap
:data:`MEMORY_CAP` or a peak resident size past :data:`RSS_BOUND`.

Two profiles: the default run draws a few cases per command (derandomized: the same cases every run),
cheap or hostile; ``-m slow`` draws many more, at random, and also values at the allowed extremes (the
ends of the ranges: work that must be refused by its estimate when it is too large).  Neither shrinks a failing case (a hang would cost the time cap
at every step): the report shows the command line as drawn.
"""

from __future__ import annotations

import json
import math
import os
import resource
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import frictionflow

from . import fuzz_checks as C
from .fuzz_strategies import COMMANDS, OPTIONS, Case, cases, toml_text

SRC = str(Path(frictionflow.__file__).resolve().parents[1])
#: seconds a case may take (the cheap draws finish in a few; work past it must have been refused up front)
TIME_CAP = 60.0
#: address space of a case's process (numba, dask and the BLAS threads reserve far more than they touch)
MEMORY_CAP = 3 << 30
#: peak resident size of a case's process
RSS_BOUND = 1 << 30

DEFAULT = settings(max_examples=2, deadline=None, derandomize=True, database=None,
                   phases=(Phase.explicit, Phase.generate), suppress_health_check=list(HealthCheck))
#: the slow profile's cases per command (FUZZ_EXAMPLES=N for another number)
SLOW = settings(max_examples=int(os.environ.get("FUZZ_EXAMPLES", "40")), deadline=None,
                phases=(Phase.explicit, Phase.reuse, Phase.generate), suppress_health_check=list(HealthCheck))
#: reproduce's cheapest valid run takes ~15 s: the default run draws only hostile command lines for it
COSTLY = {"reproduce"}


@dataclass
class Outcome:
    code: int
    out: str
    err: str
    seconds: float
    cpu: float  # seconds of CPU, the case's processes together
    timed_out: bool
    peak_rss: int  # bytes: the case's process's own peak, sampled while it runs


def _caps() -> None:  # pragma: no cover - runs in the child
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP, MEMORY_CAP))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def run(argv: list[str], cwd: Path) -> Outcome:
    """``python -m frictionflow ARGV`` in its own process group, capped in time and address space.

    Its CPU time (``os.wait4`` on it) and peak resident size (:func:`_high_water`, read while it runs) are its
    own, not the change of this process's children's totals: a child another test left running (a compile in
    the background) was reaped by the next ``Popen`` and its 2 GiB counted as this case's."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH")])))
    t0 = time.monotonic()
    proc = subprocess.Popen([sys.executable, "-m", "frictionflow", *argv], cwd=cwd, env=env, text=True,
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=_caps, start_new_session=True)
    texts: dict[str, str] = {}
    readers = [threading.Thread(target=lambda k=k, f=f: texts.__setitem__(k, f.read()))
               for k, f in (("out", proc.stdout), ("err", proc.stderr))]
    for r in readers:
        r.start()
    timed_out, peak = False, 0
    while True:
        peak = max(peak, _high_water(proc.pid))
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            break
        if time.monotonic() - t0 > TIME_CAP:
            os.killpg(proc.pid, signal.SIGKILL)  # the case's own group: its dask workers too
            _, status, usage = os.wait4(proc.pid, 0)
            timed_out = True
            break
        time.sleep(0.01)
    for r in readers:
        r.join()
    proc.stdout.close()
    proc.stderr.close()
    proc.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait for it again
    return Outcome(proc.returncode, texts["out"], texts["err"], time.monotonic() - t0,
                   usage.ru_utime + usage.ru_stime, timed_out, peak)


def _high_water(pid: int) -> int:
    """The process's peak resident size so far (VmHWM, bytes; 0 once it has exited).  Not wait4's ru_maxrss:
    that keeps the largest of the process's memories before exec too, the fork of this test process (2 GiB
    after a cold compile), so every case looked that large."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def listing(d: Path) -> set[str]:
    return {str(p.relative_to(d)) for p in d.rglob("*")}


def run_case(case: Case, d: Path) -> tuple[Outcome, list[str]]:
    cfg = None
    if case.config:
        (d / "cfg.toml").write_text(toml_text(case.config))
        cfg = "cfg.toml"
    argv = case.argv(cfg)
    return run(argv, d), argv


def check(case: Case, o: Outcome, argv: list[str], d: Path, before: set[str]) -> None:
    """The outcome is a checked result or a one-line error, within the caps."""
    shown = " ".join(argv) + (f"\nconfig:\n{toml_text(case.config)}" if case.config else "")
    assert not o.timed_out, f"past {TIME_CAP:g} s: {shown}"
    assert o.peak_rss <= RSS_BOUND, f"peak resident {o.peak_rss / 2**20:.0f} MiB: {shown}"
    assert "Traceback" not in o.err and "Exception ignored" not in o.err, f"{shown}\n{o.err}"
    lines = [ln for ln in o.err.strip().splitlines() if not ln.startswith("warning: ")]
    if o.code != 0:
        assert o.code in (1, 2), f"exit {o.code}: {shown}\n{o.err}"
        assert len(lines) == 1 and lines[0].startswith("error: "), f"{shown}\n{o.err}"
        assert o.out == "", f"a failing command printed a result: {shown}\n{o.out[:500]}"
        assert listing(d) == before, f"a failing command left {listing(d) - before}: {shown}\n{o.err}"
        return
    assert not lines, f"{shown}\n{o.err}"
    data = _json(o.out, shown)
    given = {**{k: str(v) for k, v in case.config.items() if not isinstance(v, dict)}, **case.given}
    PHYSICS[case.command](data, given, d)
    opts = OPTIONS[case.command]
    # an option whose value names a parameter (continue --param, map --x/--y): the command varies that one
    # a study names the parameter it varies as NAME or NAME=FROM:TO:N (--vary, map's --x/--y)
    varied = {str(given.get(n, opt.default)).split("=")[0] for n, opt in opts.items() if opt.kind == "text" and opt.param is None}
    C.echoed(data, given, {n for n, opt in opts.items() if opt.param is not None}, varied & set(C.PARAMS))


def _json(out: str, shown: str) -> Any:
    try:
        return json.loads(out)
    except json.JSONDecodeError as e:
        raise AssertionError(f"not one JSON object ({e}): {shown}\n{out[:500]}") from None


# -- the physical checks of each command's result ----------------------------------------------------

def _simulate(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    ss, av, ext, params = data["steady_state"], data["averages"], data["amplitude"], data["params"]
    kind = ss["kind"]
    assert kind in C.Q.KINDS
    C.extremes_order(ext)
    C.stick_fraction(ss.get("stick_fraction"))
    w0, w1 = ss["window"]
    assert w0 < w1 <= float(given.get("t_end", "500")) * (1 + 1e-12), ss["window"]
    assert (ss["period"] is not None) == (kind == "periodic"), ss
    whole_periods = kind == "periodic" and not ss["manual_window"]  # --window T0:T1 averages over what it says
    if whole_periods:
        n, period = ss["n_periods"], ss["period"]
        assert period > 0 and n >= 1 and abs((w1 - w0) - n * period) <= 0.25 * period, ss
    if kind == "equilibrium":
        _at_rest(ext, av, params)
    rel = max(float(given.get("rtol", 0.0)), C.STEADY_RTOL[data["solver"]["name"]], ss.get("jitter") or 0.0)
    closing = C.closing_of_window(ext, rel, w1 - w0)
    C.powers(av, np.array([whole_periods]), closing)
    if params.get("zeta") == 0.0:
        assert av["P_dv"] == 0.0, av
    if kind in ("periodic", "equilibrium"):
        C.trb_bound(data["TR_B"], ext, C.reference_force(params), 1e-9 if data["solver"]["name"] == "exact" else 1e-6)


def _at_rest(ext: dict[str, Any], av: dict[str, Any], params: dict[str, Any]) -> None:
    """An equilibrium: no spread in X or X' and no vibration power."""
    scale = max(abs(ext["X_min"]), abs(ext["X_max"]), abs(params.get("vb", 0.0)), params.get("fs", 0.0))
    assert ext["X_max"] - ext["X_min"] <= 1e-6 * scale and ext["V_max"] - ext["V_min"] <= 1e-6 * scale, ext
    for k in ("P_dv", "P_df", "P_fin"):
        assert av[k] <= 1e-9 * scale * scale + 1e-300, av


def _orbit(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    ext, period, params = data["extremes"], data["period"], data["params"]
    assert period > 0 and math.isfinite(period)
    C.extremes_order(ext)
    x, v = data["state"]["X"], data["state"]["V"]
    assert ext["X_min"] <= x <= ext["X_max"] and ext["V_min"] <= v <= ext["V_max"], (data["state"], ext)
    assert C.is_close(data["amplitude"], (ext["X_max"] - ext["X_min"]) / 2, 1e-9), data["amplitude"]
    durations = [ph["duration"] for ph in data["phases"]]
    assert C.is_close(sum(durations), period, 1e-9), (durations, period)
    stick = sum(ph["duration"] for ph in data["phases"] if ph["mode"] == "stick") / period
    assert C.is_close(stick, data["stick_fraction"], 1e-9) or abs(stick - data["stick_fraction"]) < 1e-12
    modulus = math.hypot(*data["multiplier"])
    assert not (data["stability"] == "stable" and modulus >= 1) and not (data["stability"] == "unstable" and modulus <= 1)
    residual = data["newton"]["residual"] * max(params["fs"], abs(params["vb"]))
    C.powers(data["averages"], np.array([True]), _newton_closing(ext, residual, period))
    C.trb_bound(data["TR_B"], ext, C.reference_force(params), 1e-9)


def _newton_closing(ext: dict[str, Any], residual: Any, period: Any) -> np.ndarray:
    """The energy an orbit that closes to ``residual`` (in X and X') can gain per period, per unit time."""
    xa = np.maximum(np.abs(C.arr(ext["X_min"])), np.abs(C.arr(ext["X_max"])))
    va = np.maximum(np.abs(C.arr(ext.get("V_min", 0.0))), np.abs(C.arr(ext.get("V_max", 0.0))))
    return 10.0 * (xa + va + C.arr(residual)) * C.arr(residual) / C.arr(period)


def _continue(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    lo, hi = sorted((data["from"], data["to"]))
    params = data["params"]
    tol = float(given.get("tol", "1e-9")) * max(params["fs"], abs(params["vb"]), 1e-300)
    for branch in data["branches"]:
        for pt in branch:
            assert lo - 1e-9 * (hi - lo) <= pt["value"] <= hi + 1e-9 * (hi - lo), (pt["value"], lo, hi)
            assert pt["kind"] in ("equilibrium", "periodic"), pt["kind"]
            ext = {k: pt[k] for k in ("X_min", "X_max")}
            C.extremes_order({**ext, "V_min": 0.0, "V_max": 0.0})
            C.stick_fraction(pt["stick_fraction"])
            if pt["kind"] == "equilibrium":
                assert pt["amplitude"] == 0.0 and pt["X_min"] == pt["X_max"] == pt["X"], pt
                assert pt["P_fin"] == pt["P_df"] == pt["P_dv"] == 0.0 and pt["period"] is None, pt
                continue
            assert pt["period"] > 0 and C.is_close(pt["amplitude"], (pt["X_max"] - pt["X_min"]) / 2, 1e-9), pt
            C.powers(pt, np.array([True]), _newton_closing(ext, 10 * tol, pt["period"]))


def _forced_orbit(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    params = data["params"]
    assert C.is_close(data["period"], data["m"] * 2 * math.pi / params["omega"], 1e-12), data["period"]
    _forced_point(data, data["state"], data["period"], params, data["settings"]["steps_per_period"])
    for (re, im), mod in zip(data["multipliers"], data["moduli"]):
        assert C.is_close(math.hypot(re, im), mod, 1e-12)
    if data["stability"] == "stable":
        assert max(data["moduli"]) < 1, data["moduli"]


def _forced_point(pt: dict[str, Any], state: dict[str, Any], period: float, params: dict[str, Any],
                  steps: int) -> None:
    """A forced orbit: its state found on the RK4 map (``steps`` per forcing period), its averages over one
    period of the package's solver from there -- which closes to the RK4 map's accuracy, (h nu)^4 of the
    flow with h the step and nu the fastest rate (1 or Omega), not to the Newton residual."""
    ext = {"X_min": pt["X_min"], "X_max": pt["X_max"], "V_min": -abs(state["V"]), "V_max": abs(state["V"])}
    assert pt["X_min"] <= state["X"] <= pt["X_max"], (state, ext)
    assert C.is_close(pt["amplitude"], (pt["X_max"] - pt["X_min"]) / 2, 1e-9), pt["amplitude"]
    C.stick_fraction(pt["stick_fraction"])
    av = pt["averages"]
    omega = params["omega"]
    flow = av["P_fin"] + av["P_df"] + av["P_dv"] + abs(av["P_ex"])
    rk4 = (2 * math.pi / omega / steps * max(1.0, omega)) ** 4 * flow
    C.powers(av, np.array([True]), _newton_closing(ext, pt.get("residual", 0.0), period) + rk4)
    C.trb_bound(pt["TR_B"], ext, C.reference_force(params), 1e-6)


def _forced_continue(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    lo, hi = sorted(float(v) for v in given["vary"].split("=")[1].split(":")[:2])
    for branch in data["branches"]:
        params, m = branch["params"], branch["m"]
        for pt in branch["points"]:
            lam = pt["lambda"]
            assert lo - 1e-9 * abs(hi - lo) <= lam <= hi + 1e-9 * abs(hi - lo), (lam, lo, hi)
            omega = lam if branch["parameter"] == "omega" else params["omega"]
            at = {**params, branch["parameter"]: lam}
            _forced_point(pt, {"X": pt["X"], "V": pt["V"]}, m * 2 * math.pi / omega, at, int(given.get("steps_per_period", 512)))


def _response(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    omega = np.array(data["omega"])
    start, stop, n = given["vary"].split("=")[1].split(":")
    assert np.allclose(omega, np.linspace(float(start), float(stop), int(n)), rtol=1e-12, atol=0), omega
    rel = max(float(given.get("rtol", 0.0)), C.LOOSEST_RTOL)
    for direction in ("up", "down"):
        r = data.get(direction)
        if r is None:
            continue
        kind = C.arr(r["kind"])
        C.kinds_known(kind)
        period = C.arr(r["period"])
        periodic = kind == 0
        assert (~np.isnan(period) == periodic).all(), (r["kind"], r["period"])
        expect = C.arr(r["multiple"]) * 2 * np.pi / omega
        assert np.allclose(period[periodic], expect[periodic], rtol=1e-12), (period, expect)
        C.extremes_order(r)
        C.stick_fraction(r["stick_fraction"])
        C.powers(r, periodic, C.closing_of_window(r, rel, period))


def _lyapunov(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    ex, s = C.arr(data["exponents"]), data["settings"]
    ex[np.array(data["minus_infinity"])] = -np.inf
    assert not np.isnan(ex).any() and (np.diff(ex) <= 1e-12 * np.abs(ex[:-1]) + 1e-300).all(), data["exponents"]
    assert s["t_end"] >= float(given.get("t_end", s["t_end"])) * (1 - 1e-12)
    assert s["t_transient"] >= float(given.get("t_transient", s["t_transient"])) * (1 - 1e-12)
    assert C.is_close(s["blocks"] * s["block"], s["t_end"] - s["t_transient"], 1e-9), s
    minus_inf = data["minus_infinity"]
    # a collapse is a stick's (an exponent -inf); an exponent the frame lost (no room for enough QRs) is not one
    assert not data["collapsed"] or any(minus_inf), data
    assert all((x is None) if inf else (x >= 0) for x, inf in zip(data["spread"], minus_inf)), data["spread"]


def _basins(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    n = data["design"]["points"]
    counts = [o["count"] for o in data["outcomes"]]
    assert sum(counts) == n, (counts, n)
    for o in data["outcomes"]:
        f = o["count"] / n
        assert C.is_close(o["fraction"], f, 1e-12) and C.is_close(o["stderr"], math.sqrt(f * (1 - f) / n), 1e-9), o
        if o["kind"] == "periodic" and o["count"]:
            assert o["period"] > 0 and o["amplitude"] >= 0, o
            C.stick_fraction(o["stick_fraction"])


def _map(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    x_from, x_to, *n = given["x"].split("=")[1].split(":")
    x = np.linspace(float(x_from), float(x_to), int(n[0]) if n else 41)
    assert np.allclose(data["x_values"], x, rtol=1e-12, atol=0), data["x_values"]
    lo, hi = sorted(data["y_range"])
    x_lo, x_hi = sorted((x[0], x[-1]))
    for curve in data["curves"]:
        for pt in curve["points"]:
            assert lo - 1e-9 * (hi - lo) <= pt["y"] <= hi + 1e-9 * (hi - lo), (curve["kind"], pt)
            assert x_lo - 1e-9 * (x_hi - x_lo) <= pt["x"] <= x_hi + 1e-9 * (x_hi - x_lo), (curve["kind"], pt)
            if curve["kind"] == "hopf" and data["params"]["friction"] == "stribeck":
                _stribeck_hopf({**data["params"], data["x_param"]: pt["x"], data["y_param"]: pt["y"]})


def _stribeck_hopf(p: dict[str, Any]) -> None:
    """At a Hopf point of the sliding equilibrium the net damping vanishes: 2 zeta + F'(|V_b|) = 0, with
    F(v) = F_d + (F_s - F_d) exp(-(v / V_s)^delta) + c_v v (derived here, not taken from the package)."""
    v, vs, delta = abs(p["vb"]), p["vs"], p["delta"]
    slope = -(p["fs"] - p["fd"]) * delta / vs * (v / vs) ** (delta - 1) * math.exp(-((v / vs) ** delta)) + p["viscous"]
    assert abs(2 * p["zeta"] + slope) <= 1e-6 * (2 * p["zeta"] + abs(slope)), (p, slope)


def _sweep(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    if "dims" not in data:  # --verify: its findings
        return
    import xarray as xr

    assert sum(data["kinds"].values()) == data["points"] == int(np.prod(list(data["dims"].values()))), data
    path = d / data["out"]
    ds = xr.open_zarr(path) if path.suffix == ".zarr" else xr.open_dataset(path)
    with ds:
        rec = {k: ds[k].values.ravel().tolist() for k in ("P_dv", "P_df", "P_fin", "P_heat", "P_belt", "P_f", "R_c", "R_f")
               if k in ds}
        kind = ds["kind"].values.ravel()
        C.kinds_known(kind)
        period = ds["period"].values.ravel()
        assert (~np.isnan(period) == (kind == 0)).all()
        ext = {k: ds[k].values.ravel().tolist() for k in ("X_min", "X_max", "V_min", "V_max") if k in ds}
        closing = C.closing_of_window(ext, C.LOOSEST_RTOL, period) if len(ext) == 4 else np.zeros(kind.shape)
        C.powers(rec, kind == 0, closing)


def _reproduce(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    out = d / given["out"]
    for name in data["files"]:
        assert (out / name).exists(), name


def _stability(data: dict[str, Any], given: dict[str, str], d: Path) -> None:
    """Each row's eigenvalues closed under conjugation (a real system); the critical points inside the range,
    of a known kind, and accounting for every change in the count of unstable eigenvalues between two values."""
    from frictionflow.analysis.stability import KINDS

    values = np.array(data["values"])
    lost = np.array(data["lost"], dtype=bool)  # no steady sliding there: null eigenvalues
    lam = np.array([[complex(np.nan if z["re"] is None else z["re"], np.nan if z["im"] is None else z["im"])
                     for z in row] for row in data["eigenvalues"]])
    assert lam.shape[0] == len(values) >= 2 and np.all(np.isnan(lam[lost])) and np.all(np.isfinite(lam[~lost]))
    assert np.all(np.diff(values) > 0) or np.all(np.diff(values) < 0), values
    scale = np.abs(lam).max(axis=1)
    for row, s in zip(lam[~lost], scale[~lost]):
        gap = np.abs(row[:, None] - np.conj(row)[None, :]).min(axis=1)
        assert gap.max() <= 1e-12 * s, row
    unstable = [int(np.sum((row.real > 1e-8 * s) & (row.imag >= 0))) for row, s in zip(lam, scale)]
    for c in data["critical"]:
        assert c["kind"] in KINDS and min(values) < c["value"] < max(values), c
        assert c["frequency"] is None if c["kind"] == "contact_loss" else c["frequency"] >= 0, c
    for i in range(len(values) - 1):
        if lost[i] or lost[i + 1]:
            continue  # a contact lost at either end: its boundary, not a change in the count of unstable modes
        lo, hi = sorted(values[i:i + 2])
        step = sum((1 if c["unstable_above"] else -1) * (1 if values[i + 1] > values[i] else -1)
                   for c in data["critical"] if lo < c["value"] < hi)
        assert unstable[i + 1] - unstable[i] == step, (i, unstable, data["critical"])


PHYSICS = {"simulate": _simulate, "orbit": _orbit, "continue": _continue, "forced-orbit": _forced_orbit,
           "forced-continue": _forced_continue, "response": _response, "lyapunov": _lyapunov, "basins": _basins,
           "map": _map, "sweep": _sweep, "reproduce": _reproduce, "stability": _stability}


def test_every_command_is_fuzzed():
    assert set(PHYSICS) == set(COMMANDS) == set(OPTIONS)


def _fuzz(command: str, data: st.DataObject, tmp_path_factory: pytest.TempPathFactory, modes: tuple[str, ...]) -> None:
    case = data.draw(cases(command, modes))
    d = tmp_path_factory.mktemp(command)
    before = listing(d) | ({"cfg.toml"} if case.config else set())
    o, argv = run_case(case, d)
    print(f"\nexit {o.code} in {o.seconds:.1f} s ({o.cpu:.1f} s CPU): {' '.join(argv)}\n  {o.err.strip()[:300]}")
    check(case, o, argv, d, before)


@pytest.mark.parametrize("command", COMMANDS)
@DEFAULT
@given(data=st.data())
def test_fuzz(command, data, tmp_path_factory):
    _fuzz(command, data, tmp_path_factory, ("hostile",) if command in COSTLY else ("cheap", "cheap", "hostile"))


@pytest.mark.slow
@pytest.mark.parametrize("command", COMMANDS)
@SLOW
@given(data=st.data())
def test_fuzz_slow(command, data, tmp_path_factory):
    _fuzz(command, data, tmp_path_factory, ("cheap", "hostile", "edge"))


def _simulated(capsys: pytest.CaptureFixture, *argv: str) -> dict[str, Any]:
    from frictionflow.cli import main

    assert main(["simulate", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("damage", ["negative P_df", "unbalanced", "equilibrium that moves", "period of a not_settled",
                                    "fd not echoed", "TR_B below max|X|/F_d"])
def test_the_checks_catch_a_damaged_result(damage, capsys):
    """The physical checks are not vacuous: a real result passes, each kind of damage to it is caught."""
    given = {"t_end": "30", "zeta": "0.0", "fd": "0.02"}
    data = _simulated(capsys, *(x for n, v in given.items() for x in (f"--{n.replace('_', '-')}", v)))
    _simulate(data, given, Path("."))
    C.echoed(data, given, set(given), set())
    av, ss = data["averages"], data["steady_state"]
    if damage == "negative P_df":
        av["P_df"], av["P_fin"] = -av["P_df"], av["P_fin"] - 2 * av["P_df"]  # P_f = P_fin - P_df kept
    elif damage == "unbalanced":
        av["P_fin"] *= 1 + 1e-6
        av["P_f"], av["P_belt"] = av["P_fin"] - av["P_df"], av["P_fin"] - av["P_df"] + av["P_heat"]
        av["R_c"], av["R_f"] = av["P_dv"] / av["P_fin"], av["P_df"] / av["P_fin"]  # only the balance is off
    elif damage == "equilibrium that moves":
        ss.update(kind="equilibrium", period=None)
    elif damage == "period of a not_settled":
        ss["kind"] = "not_settled"
    elif damage == "TR_B below max|X|/F_d":
        data["TR_B"] *= 0.99
    if damage == "fd not echoed":
        data["params"]["fd"] = 0.03
        with pytest.raises(AssertionError):
            C.echoed(data, given, set(given), set())
        return
    with pytest.raises(AssertionError):
        _simulate(data, given, Path("."))


def test_a_case_s_peak_is_its_own_not_another_child_s(tmp_path):
    """A child another test left behind (a background compile, here 600 MiB) is reaped by the next ``Popen``'s
    clean-up once it has ended and its object is gone; its peak counted as the next case's (CI: `basins` at
    "2007 MiB")."""
    hog = subprocess.Popen([sys.executable, "-c", "x = bytearray(600 << 20); x[::4096] = b'1' * len(x[::4096])"])
    del hog  # dropped while running: subprocess keeps it to reap at the next Popen
    time.sleep(3.0)
    outcome = run(["--help"], tmp_path)
    assert outcome.code == 0 and 20 << 20 < outcome.peak_rss < 400 << 20  # measured, and its own
    grown = bytearray(800 << 20)  # this process larger than any case: a fork's copy of it is not the case's
    grown[::4096] = b"1" * len(grown[::4096])
    outcome = run(["--help"], tmp_path)
    assert outcome.code == 0 and 20 << 20 < outcome.peak_rss < 400 << 20
    del grown
