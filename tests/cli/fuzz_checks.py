"""What a successful command's JSON must satisfy, computed from the JSON itself (and the options given).

* no negative dissipation: P_dv, P_df, P_fin, P_heat >= 0 (to rounding of the power that flows);
* the averages agree with each other: P_f = P_fin - P_df = P_belt - P_heat, R_c = P_dv / P_fin, R_f = P_df / P_fin;
* the energy balance of every periodic result: over whole periods the stored energy returns, so
  P_fin - P_df - P_dv + P_ex = 0 -- to within what the result says of how closely it closes (a Newton residual,
  the steady-state tolerance of the solver that classified it);
* the kind agrees with its numbers (a periodic result has a period and a window of whole periods; an
  equilibrium has no spread in X and X' and no vibration power; only a periodic result has a period);
* the options given are echoed in ``params``.
"""

from __future__ import annotations

import math
from typing import Any, Iterator

import numpy as np

from frictionflow import quantities as Q
from frictionflow.parameters import declared
from frictionflow.solvers.registry import solver_classes

PARAMS = declared()
#: rounding of sums of work integrals, relative to the power that flows
ROUND = 1e-9
STEADY_RTOL = {cls.name: cls.steady_rtol for cls in solver_classes()}
LOOSEST_RTOL = max(STEADY_RTOL.values())


def arr(x: Any) -> np.ndarray:
    """A JSON number, null or list of them as a float array (null: NaN)."""
    if isinstance(x, list):
        return np.array([np.nan if v is None else v for v in x], dtype=float)
    return np.array([np.nan if x is None else x], dtype=float)


def _close(a: np.ndarray, b: np.ndarray, tol: np.ndarray, what: str) -> None:
    ok = ~(np.abs(a - b) > tol)  # NaN on either side: not compared here
    assert ok.all(), f"{what}: {a[~ok]} vs {b[~ok]} (tolerance {np.broadcast_to(tol, a.shape)[~ok]})"


def powers(rec: dict[str, Any], periodic: np.ndarray, closing: np.ndarray) -> None:
    """The checks of one record of averages (numbers or per-point lists).

    ``periodic``: where the record is over whole periods of a periodic motion; ``closing``: the largest
    |P_fin - P_df - P_dv + P_ex| its own precision allows there (the stored energy's possible change over
    the window, divided by the window).
    """
    p = {k: arr(rec[k]) for k in ("P_dv", "P_df", "P_fin", "P_heat", "P_belt", "P_f", "P_ex", "R_c", "R_f")
         if k in rec}
    flow = p["P_fin"] + p["P_df"] + p["P_dv"] + np.abs(p.get("P_ex", 0.0)) + np.abs(p.get("P_heat", 0.0))
    tiny = ROUND * np.nan_to_num(flow) + 1e-300
    for k in ("P_dv", "P_df", "P_fin", "P_heat"):
        if k in p:
            assert not (p[k] < -tiny).any(), f"negative dissipation {k} = {p[k]}"
    if "P_f" in p:
        _close(p["P_f"], p["P_fin"] - p["P_df"], tiny, "P_f vs P_fin - P_df")
        if "P_belt" in p and "P_heat" in p:
            _close(p["P_f"], p["P_belt"] - p["P_heat"], tiny + ROUND * np.abs(p["P_belt"]), "P_f vs P_belt - P_heat")
    has_input = p["P_fin"] > 0
    for ratio, num in (("R_c", "P_dv"), ("R_f", "P_df")):
        if ratio in p:
            r, expect = p[ratio], np.where(has_input, p[num] / np.where(has_input, p["P_fin"], 1.0), np.nan)
            _close(r, expect, ROUND * np.abs(expect) + 1e-300, f"{ratio} vs {num}/P_fin")
            # null only where friction puts in nothing next to the other flows (documented: above rounding)
            input_seen = p["P_fin"] > ROUND * np.nan_to_num(flow)
            assert not (np.isnan(r) & input_seen).any(), f"{ratio} is null although P_fin = {p['P_fin']} of {flow}"
    balance = p["P_fin"] - p["P_df"] - p["P_dv"] + p.get("P_ex", 0.0)
    bad = periodic & (np.abs(balance) > closing + tiny)
    assert not bad.any(), f"energy balance of a periodic result: {balance[bad]} (allowed {(closing + tiny)[bad]})"


def closing_of_window(extremes: dict[str, Any], rel: float | np.ndarray, length: Any) -> np.ndarray:
    """The stored energy's possible change, per unit time, over a window of ``length`` whose ends agree to ``rel``
    of the motion's amplitude: |d(X^2 + X'^2)/2| <= |X| dX + |X'| dX' with dX <= rel (X_max - X_min)."""
    x0, x1, v0, v1 = (arr(extremes[k]) for k in ("X_min", "X_max", "V_min", "V_max"))
    xa, va = np.maximum(np.abs(x0), np.abs(x1)), np.maximum(np.abs(v0), np.abs(v1))
    de = xa * (x1 - x0) + va * (v1 - v0)
    return 10.0 * rel * np.nan_to_num(de) / arr(length)


def trb_bound(trb: Any, extremes: dict[str, Any], force: float, rel: float) -> None:
    """TR_B = max |X + 2 zeta X'| / F over the window >= max |X| / F: at an extreme of X, X' = 0."""
    if trb is None or not force > 0:
        return
    xa = max(abs(extremes["X_min"]), abs(extremes["X_max"]))
    assert trb * force >= xa * (1 - rel) - 1e-300, f"TR_B = {trb} < max|X|/F = {xa / force}"


def extremes_order(ext: dict[str, Any]) -> None:
    for lo, hi in (("X_min", "X_max"), ("V_min", "V_max")):
        a, b = arr(ext[lo]), arr(ext[hi])
        assert not (a > b).any(), f"{lo} > {hi}: {a} > {b}"


def reference_force(params: dict[str, Any]) -> float:
    """The force TR_B refers to: F_ex when forced, else F_d."""
    fex = params.get("fex") or 0.0
    return fex if fex > 0 else params.get("fd") or 0.0


def dicts_named(data: Any, key: str) -> Iterator[dict[str, Any]]:
    """Every dict held under ``key`` anywhere in ``data``."""
    if isinstance(data, dict):
        for k, v in data.items():
            if k == key and isinstance(v, dict):
                yield v
            yield from dicts_named(v, key)
    elif isinstance(data, list):
        for v in data:
            yield from dicts_named(v, key)


def echoed(data: Any, given: dict[str, str], declared_options: set[str], varied: set[str]) -> None:
    """Every declared parameter given (that the result reports) is in ``params`` with the value given.

    ``declared_options``: the command's options that are the declared parameters of that name; ``varied``:
    the parameters the command itself varies (a continuation's, a map's axes), whose value it sets."""
    reports = list(dicts_named(data, "params"))
    if not reports or "dimensional" in given:
        return
    for name, text in given.items():
        p = PARAMS.get(name)
        if p is None or p.kind == "text" or name not in declared_options or name in varied:
            continue
        value = text if p.kind == "choice" else float(text)
        for params in reports:
            if name in params:
                assert params[name] == value, f"--{name} {text} echoed as {params[name]!r}"
            elif p.report and p.owner in ("oscillator", "law") and not _unforced_forcing(name, params):
                raise AssertionError(f"--{name} {text} given but not in params {params}")


def _unforced_forcing(name: str, params: dict[str, Any]) -> bool:
    """A forcing's frequency and phase describe nothing without its amplitude."""
    return name in ("omega", "phi") and not params.get("fex")


def kinds_known(codes: np.ndarray) -> None:
    ok = np.isin(codes, np.arange(len(Q.KINDS)))
    assert ok.all(), f"kind codes outside {Q.KINDS}: {codes[~ok]}"


def stick_fraction(x: Any) -> None:
    s = arr(x)
    assert not ((s < 0) | (s > 1)).any(), f"stick fraction outside [0, 1]: {s}"


def is_close(a: float, b: float, rel: float) -> bool:
    return math.isclose(a, b, rel_tol=rel, abs_tol=1e-300)
