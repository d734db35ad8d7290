"""The paper's claims, each checked against our data sets, with the numbers.

Every check reads the data sets the figures are drawn from and decides its
verdict from the numbers (a criterion stated in the check), so a verdict can
only change if the numbers do:

``supported``  the paper's statement holds, in direction and rough size;
``refuted``    it does not, and the evidence says why;
``partly``     it holds only in a reading the paper does not state (e.g. at
               one window position of a decaying transient).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._lazy import lazy_module
from .cases import select
from .settings import PAPER_VD

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

VERDICTS = ("supported", "refuted", "partly")


Data = dict[str, "xr.Dataset"]


@dataclass(frozen=True)
class Claim:
    """One statement of the paper and what our results say about it.

    ``key`` names the paper's statement, as ``quote`` gives it, never our
    finding, so that key and verdict read together the way the report's
    table reads ("the paper says ... : refuted"):
    ``case2_settles_on_a_limit_cycle  refuted``.

    Attributes
    ----------
    key:
        A short name of the claim (the keys of ``claims.json``).
    figure:
        The figure of the paper it is about.
    quote:
        What the paper says.
    verdict:
        ``supported``, ``refuted`` or ``partly``.
    evidence:
        Our numbers behind the verdict.
    """

    key: str
    figure: str
    quote: str
    verdict: str
    evidence: str


_CHECKS: list[tuple[str, str, str, Callable[[Data], tuple[str, str]]]] = []


def claim(key: str, figure: str, quote: str):
    """Register a check ``f(data) -> (verdict, evidence)`` for a quoted statement."""

    def register(f: Callable[[Data], tuple[str, str]]):
        _CHECKS.append((key, figure, quote, f))
        return f

    return register


def evaluate(data: Data) -> list[Claim]:
    """Every registered claim, checked against ``data``.

    Parameters
    ----------
    data:
        The studies' data sets by name, from :func:`compute`.
    """

    out = []
    for key, figure, quote, check in _CHECKS:
        verdict, evidence = check(data)
        if verdict not in VERDICTS:
            raise ValueError(f"claim {key}: verdict must be one of {VERDICTS}, got {verdict!r}")
        out.append(Claim(key, figure, quote, verdict, evidence))
    return out


def g(x: float, digits: int = 3) -> str:
    """A number in the report: ``digits`` significant figures."""
    if x is None or not math.isfinite(x):
        return "n/a"
    return f"{x:.{digits}g}"


def _val(ds: xr.Dataset, var: str, solver: str = "rk4", **point: float) -> float:
    return float(select(ds, **point)[var].sel(solver=solver))


#: The paper gives its Case II numbers as orders of magnitude ("smaller than 1e-11", "order 1e-6") or as
#: "about 99.99 %". A quantity that changes by more than a factor 10 with the window has no such value to quote,
#: and an orbit that shrinks by more than a factor 10 during the run is a transient, not a limit cycle.
DECADE = 10.0

#: Steady values come from the exact solver's closed form, exact to round-off (~1e-15). So two steady values
#: that differ by less than 1e-9 are equal. Anything a figure of the paper could show differs by >= 1e-3.
STEADY_TOL = 1e-9


def _window_series(d: Data, var: str) -> np.ndarray:
    """``var`` at every window position of the paper's base case (paper's method, cycles from maxima of X).

    The paper's Case II numbers are all given for (zeta, V_b, F_d) = (0.01, 0.01, 0.02).
    """
    base = select(d["transient"], zeta=0.01, vb=0.01, fd=0.02).sel(solver="rk4", cycle_start="max")
    y = base[var].values
    return y[np.isfinite(y) & (y > 0)]


def _reached(y: np.ndarray, value: float, below: bool = False) -> bool:
    """Whether some window position gives ``value`` (or less, with ``below``).

    Each quantity changes continuously with the window position, so it takes every value between its
    smallest and largest one.
    """
    return bool(y.size) and y.min() <= value and (below or value <= y.max())


def _window_dependent(y: np.ndarray) -> bool:
    """Whether the quantity changes by more than a decade from one window position to another."""
    return bool(y.size) and y.max() > DECADE * y.min()


def _paper_value(d: Data, number: str) -> float:
    """One of the paper's Case II numbers, as the transient data set records it."""
    return float(d["transient"].paper_value.sel(paper_number=number))


def _window_verdict(reached: bool, window_dependent: bool) -> str:
    """The verdict on a number the paper reads off one window of a run.

    Never reached: refuted. Reached, but only at some window positions: partly (the paper does not say where
    its window is). Reached, and within a decade at every window position: supported.
    """
    if not reached:
        return "refuted"
    return "partly" if window_dependent else "supported"


# -- Fig. 2: Case I ------------------------------------------------------------------------------


@claim(
    "case1_power_changes_sign",
    "fig2",
    (
        "the steady-state instantaneous total power of the friction can be positive or negative depending on the "
        "direction of friction and velocity"
    ),
)
def _case1_sign(d: Data) -> tuple[str, str]:
    ds = d["fig2"]
    parts, ok = [], True
    for vb in (0.01, 0.1):
        p = select(ds, zeta=0.0, vb=vb, fd=0.02).P_f
        lo, hi = float(p.min()), float(p.max())
        ok &= lo < 0.0 < hi
        parts.append(f"V_b = {vb:g}: P_f from {g(lo)} to {g(hi)}")
    expected = 0.02 * (0.1 - PAPER_VD)
    return ("supported" if ok else "refuted",
            "; ".join(parts) + f" (both solvers). On the steady circle P_f = F_d X' swings by ±F_d (V_b - V_d) "
            f"= ±{g(expected)} for V_b = 0.1.")


@claim(
    "case1_vb_le_vd_sticks",
    "fig2",
    (
        "When the feeding speed V_b is not greater than the limiting velocity V_d for the Karnopp friction model, "
        "the stick phenomenon will occur."
    ),
)
def _case1_stick(d: Data) -> tuple[str, str]:
    h = d["band_history"]
    vd = float(h.attrs["vd"])
    v_exact = float(h.V.sel(model="karnopp_exact")[-1])
    x_exact = float(h.X_long.sel(model="karnopp_exact")[-1])
    creep = h.creep_speed.values
    stick = abs(v_exact - float(h.attrs["vb"])) < 0.1 * vd  # stick would mean X' = V_b
    sw = d["band_sweep"]
    below = sw.sel(model="karnopp_exact").where(sw.vb < vd, drop=True)
    backwards = float(below.steady_V_min.min()) if below.sizes["vb"] else math.nan
    return ("supported" if stick else "refuted",
            f"At V_b = V_d = {vd:g} the exact solver brings the mass to rest, X' = {g(v_exact)}, at X = {g(x_exact, 4)} "
            f"= F_d - V_b, while the belt moves on at V_b: the relative speed stays V_b, so the mass is not stuck to "
            f"the belt. Karnopp's law (F_c = X inside the band) freezes whatever velocity the mass entered the band "
            f"with. RK4 enters a fraction of a step late and keeps creeping at X' = "
            f"{', '.join(f'{g(c, 2)} (dt={dt:g})' for c, dt in zip(creep, h.dt.values))}, a numerical artefact "
            f"that changes with the step. Below V_d the band even holds the mass while it moves against the belt "
            f"(min X' = {g(backwards)}). Ideal Coulomb friction gives the slip circle of radius V_b instead.")


@claim("case1_periodic_self_excited", "fig2",
       "When the speed of the conveyor belt is larger, the system exhibits periodic self-excited vibrations.")
def _case1_periodic(d: Data) -> tuple[str, str]:
    ds = d["fig2"]
    parts, ok = [], True
    for vb in (0.01, 0.1):
        c = select(ds, zeta=0.0, vb=vb, fd=0.02)
        kinds = set(c.kind.values.tolist())
        period = float(c.period.sel(solver="exact"))
        vmax = float(c.steady_V_max.sel(solver="exact"))
        ok &= kinds == {"periodic"} and abs(period - 2 * math.pi) < 1e-6
        parts.append(f"V_b = {vb:g}: {'/'.join(sorted(kinds))}, period {g(period, 8)}, max X' = {g(vmax, 6)}")
    return ("supported" if ok else "refuted",
            "; ".join(parts) + ". The cycle is the pure-slip circle of radius V_b - V_d about (F_d, 0): Karnopp's "
            "band makes it V_d smaller than ideal Coulomb friction's radius V_b (10 % at V_b = 0.01).")


@claim(
    "case1_friction_input_equals_friction_dissipation",
    "fig2",
    (
        "Over a cycle of periodic oscillation, the total energy input by the friction equals to the energy "
        "dissipated by the friction"
    ),
)
def _case1_balance(d: Data) -> tuple[str, str]:
    ds = d["fig2"]
    parts, worst = [], 0.0
    for vb, fd in ((0.01, 0.02), (0.1, 0.02), (0.01, 0.04)):
        c = select(ds, zeta=0.0, vb=vb, fd=fd)
        pin, pdf = float(c.steady_P_fin.sel(solver="exact")), float(c.steady_P_df.sel(solver="exact"))
        rel = abs(pin - pdf) / pin
        worst = max(worst, rel, abs(pin / float(c.P_fin_closed_form) - 1.0))
        parts.append(f"V_b = {vb:g}, F_d = {fd:g}: P_fin = {g(pin, 6)}, P_df = {g(pdf, 6)}")
    return ("supported" if worst < 1e-9 else "refuted",
            "; ".join(parts) + f" (exact solver; equal, and equal to F_d (V_b - V_d)/pi, to {g(worst, 2)}).")


# -- Fig. 3: Case II phase portraits ---------------------------------------------------------------


@claim("case2_settles_on_a_limit_cycle", "fig3",
       "It demonstrates that case II system is stable and has self-excited periodic vibrations in the steady state.")
def _case2_limit_cycle(d: Data) -> tuple[str, str]:
    ds = d["fig3"]
    parts, decaying = [], True
    for zeta in (0.01, 0.03):
        c = select(ds, zeta=zeta, vb=0.01, fd=0.02)
        rate = float(c.decay_rate.sel(solver="rk4"))
        t_term = float(c.t_terminal.sel(solver="exact"))
        decaying &= abs(rate / zeta - 1.0) < 0.01 and math.isfinite(t_term)
        parts.append(f"zeta = {zeta:g}: amplitude decays at rate {rate:.6f} (RK4), the band is never reached after "
                     f"tau = {g(t_term, 4)} (exact), steady state: {c.kind.sel(solver='exact').values!s}")
    return ("refuted" if decaying else "supported",
            "; ".join(parts) + ". With F_s = F_d the damped motion leaves the band within a turn or two and then "
            "slips for ever with the constant force F_d: a spiral decaying as exp(-zeta tau) onto the sliding "
            "equilibrium X* = F_d. There is no self-excited cycle; the paper's portraits are turns of this spiral.")


def _shrinks_a_decade(c: xr.Dataset) -> bool:
    """Whether an orbit's measured decay rate (RK4) takes it down by more than a decade over its run.

    A limit cycle keeps its size: Case I's fitted rate is ~1e-11, while Case II decays at zeta >= 0.01,
    i.e. by ~e^6 over the run. An unmeasured (NaN) rate does not count as decay.
    """
    rate = float(c.decay_rate.sel(solver="rk4"))
    t_end = float(c.window_end.sel(solver="rk4"))
    return math.isfinite(rate) and rate * t_end > math.log(DECADE)


@claim("case2_larger_damping_smaller_cycle", "fig3",
       "a larger damping ratio correspond to a smaller limit cycle")
def _case2_damping(d: Data) -> tuple[str, str]:
    ds = d["fig3"]
    a1 = _val(ds, "last_amplitude", zeta=0.01, vb=0.01, fd=0.02)
    a3 = _val(ds, "last_amplitude", zeta=0.03, vb=0.01, fd=0.02)
    t = float(select(ds, zeta=0.01, vb=0.01, fd=0.02).window_end.sel(solver="rk4"))
    # smaller, and a limit cycle only if the orbits keep their size; if both decay, the size is set by the window
    transients = all(_shrinks_a_decade(select(ds, zeta=z, vb=0.01, fd=0.02)) for z in (0.01, 0.03))
    verdict = "refuted" if not a3 < a1 else "partly" if transients else "supported"
    return (verdict,
            f"At the end of the run (tau = {g(t, 4)}) the zeta = 0.03 orbit has amplitude {g(a3)} against {g(a1)} for "
            f"zeta = 0.01 (ratio {g(a3 / a1)}, about exp(-0.02 tau)). Smaller, yes -- but because it has decayed "
            f"faster; both shrink to nothing, and the ratio depends on when one looks.")


@claim("case2_belt_speed_barely_changes_cycle_size", "fig3",
       "It also shows that the conveyor belt speed has little influence on the magnitude of the limit cycle.")
def _case2_belt(d: Data) -> tuple[str, str]:
    ds = d["fig3"]
    a1 = _val(ds, "last_amplitude", zeta=0.01, vb=0.01, fd=0.02)
    a10 = _val(ds, "last_amplitude", zeta=0.01, vb=0.1, fd=0.02)
    # "little influence": 3 ~ sqrt(11) is halfway, on a log scale, between no influence (x1) and the start
    # radius V_b - V_d of the spiral (x11 from V_b = 0.01 to 0.1)
    return ("refuted" if a10 / a1 > 3.0 else "supported",
            f"Amplitude {g(a10)} at V_b = 0.1 against {g(a1)} at V_b = 0.01: {g(a10 / a1)} times larger (the spiral "
            f"starts from radius about V_b - V_d: (0.1 - 0.001)/(0.01 - 0.001) = 11). Plotted on separately "
            f"autoscaled axes the two look alike.")


# -- Fig. 4: Case II instantaneous power -----------------------------------------------------------


def _peak_ratio(d: Data, var: str, a: tuple[float, float, float], b: tuple[float, float, float]) -> float:
    ds = d["fig4"]
    za, va, fa = a
    zb, vb, fb = b
    return _val(ds, var, zeta=zb, vb=vb, fd=fb) / _val(ds, var, zeta=za, vb=va, fd=fa)


@claim(
    "case2_friction_level_leaves_damper_power",
    "fig4",
    (
        "when the magnitude of friction F_d increases from 0.02 to 0.04, the power dissipation by the viscous damping "
        "is not affected while the amplitude of the friction power flow increases"
    ),
)
def _case2_fd(d: Data) -> tuple[str, str]:
    r_dv = _peak_ratio(d, "peak_P_dv", (0.01, 0.01, 0.02), (0.01, 0.01, 0.04))
    r_f = _peak_ratio(d, "peak_P_f", (0.01, 0.01, 0.02), (0.01, 0.01, 0.04))
    # "not affected": within 1 %; "increases": P_f = F_d X' doubles with F_d, so more than halfway (x1.5)
    ok = abs(r_dv - 1.0) < 0.01 and r_f > 1.5
    return ("supported" if ok else "refuted",
            f"F_d 0.02 -> 0.04: peak damper power x{r_dv:.6f}, peak friction power x{r_f:.6f}. The motion "
            f"about X* = F_d does not depend on F_d (X - F_d obeys the same equation), and P_f = F_d X'.")


@claim(
    "case2_belt_speed_only_shifts_the_phase",
    "fig4",
    (
        "by changing the value of the conveyor belt speed V_b from 0.01 to 0.1, the figure shows only phase changes "
        "in the damping dissipated energy and the frictional power flows"
    ),
)
def _case2_vb(d: Data) -> tuple[str, str]:
    r_dv = _peak_ratio(d, "peak_P_dv", (0.01, 0.01, 0.02), (0.01, 0.1, 0.02))
    r_f = _peak_ratio(d, "peak_P_f", (0.01, 0.01, 0.02), (0.01, 0.1, 0.02))
    # "only phase changes" means x1; 3 ~ sqrt(11) is halfway (log scale) to the amplitude's x11
    return ("refuted" if r_dv > 3.0 and r_f > 3.0 else "supported",
            f"V_b 0.01 -> 0.1: peak damper power x{g(r_dv)}, peak friction power x{g(r_f)} -- the amplitude scales "
            f"with V_b - V_d, so P_f with it and P_dv with its square. Not a phase change.")


@claim(
    "case2_more_damping_less_power",
    "fig4",
    (
        "as the damping ratio increases from 0.01 to 0.03, amplitudes of the power flow magnitude of the viscous "
        "damper and the friction are further reduced"
    ),
)
def _case2_zeta(d: Data) -> tuple[str, str]:
    r_dv = _peak_ratio(d, "peak_P_dv", (0.01, 0.01, 0.02), (0.03, 0.01, 0.02))
    r_f = _peak_ratio(d, "peak_P_f", (0.01, 0.01, 0.02), (0.03, 0.01, 0.02))
    return ("supported" if r_dv < 1.0 and r_f < 1.0 else "refuted",
            f"zeta 0.01 -> 0.03 at the end of the run: peak damper power x{g(r_dv)}, peak friction power x{g(r_f)}: "
            f"reduced, by the faster decay exp(-zeta tau) of a transient, so the factor depends on the window.")


@claim(
    "case2_friction_puts_net_power_in",
    "fig4",
    (
        "the friction force also provides power input into the system but the positive part of the frictional power "
        "flow is slightly larger than the negative part through calculation. The reason is that the value of power "
        "dissipation by the viscous damper is small"
    ),
)
def _case2_net(d: Data) -> tuple[str, str]:
    ds = d["fig4"]
    c = select(ds, zeta=0.01, vb=0.01, fd=0.02).sel(solver="rk4")
    from_max, from_min = float(c.last_net_friction), float(c.last_net_friction_from_min)
    p_dv = float(c.last_P_dv)
    flips = from_max < 0.0 < from_min
    return ("refuted" if flips else "supported",
            f"Over the last cycle (zeta = 0.01, V_b = 0.01, F_d = 0.02) P_fin - P_df = {g(from_min)} when the cycle "
            f"runs from a minimum of X to the next, but {g(from_max)} from a maximum to the next (R_f = "
            f"{g(float(c.last_R_f_from_min), 4)} and {g(float(c.last_R_f), 4)}), while P_dv = {g(p_dv)}. In slip the "
            f"friction is the constant force F_d: its net work over a window is F_d times the change of X, which "
            f"goes into the spring, not into the damper; its sign is set by where the window starts, and it is "
            f"{g(abs(from_min) / p_dv, 2)} times the damper power. The balance P_fin = P_df + P_dv the paper invokes "
            f"holds only for periodic motion.")


@claim(
    "case2_damper_power_far_below_friction_power",
    "fig4",
    (
        "the value of power dissipation by the viscous damper is small being smaller than 1e-11. In contrast, the "
        "order of magnitude of frictional power flow is larger, 1e-6 in Fig. 4(d), (e) and (f)"
    ),
)
def _case2_magnitudes(d: Data) -> tuple[str, str]:
    ds, tr = d["fig4"], d["transient"]
    c = select(ds, zeta=0.01, vb=0.01, fd=0.02).sel(solver="rk4")
    t_end = float(ds.tau[-1])
    implied = {str(k): float(v) for k, v in zip(tr.paper_number.values, tr.implied_tau.values)}
    at_dv = implied.get("damper power below 1e-11", math.nan)
    at_f = implied.get("friction power of order 1e-6", math.nan)
    dv, f = _window_series(d, "peak_P_dv"), _window_series(d, "peak_P_f")
    reached = _reached(dv, _paper_value(d, "damper power below 1e-11"), below=True) and _reached(
        f, _paper_value(d, "friction power of order 1e-6"))
    verdict = _window_verdict(reached, _window_dependent(dv) or _window_dependent(f))
    return (verdict,
            f"At the end of our run (tau = {g(t_end)}) the peak damper power is {g(float(c.peak_P_dv))} and the peak "
            f"friction power {g(float(c.peak_P_f))} (zeta = 0.01, V_b = 0.01, F_d = 0.02): the paper's orders. But "
            f"they decay as exp(-2 zeta tau) and exp(-zeta tau): the paper's method reaches 1e-11 at tau = "
            f"{g(at_dv)} and 1e-6 at tau = {g(at_f)}, and any other value at another window. The numbers say where "
            f"the paper stopped integrating, not how the system behaves.")


# -- Fig. 5: dissipation ratios ----------------------------------------------------------------------


def _rc(d: Data, zeta: float, vb: float, fd: float, solver: str = "rk4") -> float:
    return float(d["sweep"].last_R_c.sel(solver=solver, vb=vb, fd=fd, zeta=zeta))


@claim(
    "rc_falls_with_friction",
    "fig5",
    (
        "the power dissipation ratio by the viscous damper R_c, decreases significantly with the increase of the "
        "magnitude of the friction from 0.02 to 0.04"
    ),
)
def _rc_fd(d: Data) -> tuple[str, str]:
    r1, r3 = _rc(d, 0.01, 0.01, 0.04) / _rc(d, 0.01, 0.01, 0.02), _rc(d, 0.03, 0.01, 0.04) / _rc(d, 0.03, 0.01, 0.02)
    # "decreases significantly": below 0.75, about halfway (log scale: 0.71) between x1 and the x0.5 of R_c ~ 1/F_d
    return ("supported" if r1 < 0.75 and r3 < 0.75 else "refuted",
            f"R_c(F_d = 0.04)/R_c(F_d = 0.02) = {g(r1, 4)} at zeta = 0.01 and {g(r3, 4)} at zeta = 0.03: "
            f"R_c ~ pi zeta A / F_d halves, at any window (A does not depend on F_d).")


@claim("rc_grows_slightly_with_damping", "fig5",
       "[R_c] increases slightly with the damping ratio from 0.01 to 0.03")
def _rc_zeta(d: Data) -> tuple[str, str]:
    r = _rc(d, 0.03, 0.01, 0.02) / _rc(d, 0.01, 0.01, 0.02)
    tr = d["transient"].sel(solver="rk4", cycle_start="max")
    low = tr.R_c.isel(case=0)
    high = tr.R_c.isel(case=1)
    up = (high > low).values
    t_cross = float(tr.tau_i.values[np.argmax(~up)]) if up.any() and not up.all() else math.nan
    return ("refuted" if r < 1.0 else "supported",
            f"R_c(zeta = 0.03)/R_c(zeta = 0.01) = {g(r)} over the last cycle before tau = "
            f"{g(float(d['fig4'].tau[-1]))}. R_c ~ pi zeta A/F_d with A ~ exp(-zeta tau), so the ratio is about "
            f"3 exp(-0.02 tau): above 1 only for windows that start before tau ~ ln(3)/0.02 = 55 (measured: R_c is "
            f"larger for zeta = 0.03 only for window positions below {g(t_cross)}).")


@claim(
    "rc_barely_changes_with_belt_speed",
    "fig5",
    (
        "When the feeding speed from the belt increases to 0.1, the figure shows little change in power flow "
        "quantities."
    ),
)
def _rc_vb(d: Data) -> tuple[str, str]:
    r = _rc(d, 0.01, 0.1, 0.02) / _rc(d, 0.01, 0.01, 0.02)
    # "little change": 3 ~ sqrt(11) is halfway (log scale) between x1 and R_c ~ A ~ V_b - V_d (x11)
    return ("refuted" if r > 3.0 else "supported",
            f"R_c(V_b = 0.1)/R_c(V_b = 0.01) = {g(r)} (zeta = 0.01, F_d = 0.02): R_c grows with the amplitude, which "
            f"grows with V_b - V_d.")


@claim("friction_dissipates_9999_percent", "fig5",
       "most of the power is dissipated by the friction, about 99.99%")
def _rf(d: Data) -> tuple[str, str]:
    tr = d["transient"].sel(solver="rk4").isel(case=0)
    rc = tr.R_c.sel(cycle_start="max")
    first, last = float(rc.dropna("tau_i")[0]), float(rc.dropna("tau_i")[-1])
    t_first, t_last = float(tr.window_start.sel(cycle_start="max").dropna("tau_i")[0]), float(
        tr.window_start.sel(cycle_start="max").dropna("tau_i")[-1])
    at = float(d["transient"].implied_tau.sel(paper_number="99.99 % dissipated by friction"))
    sw = d["sweep"].sel(solver="rk4", vb=0.01, fd=0.02, zeta=0.01)
    steady = d["sweep"].sel(solver="exact", vb=0.01, fd=0.02, zeta=0.01)
    # "about 99.99 %" is R_c = 1e-4 (the value the transient data set records for it)
    rcs = _window_series(d, "R_c")
    verdict = _window_verdict(_reached(rcs, _paper_value(d, "99.99 % dissipated by friction")), _window_dependent(rcs))
    return (verdict,
            f"R_c over one cycle (zeta = 0.01, V_b = 0.01, F_d = 0.02) falls from {g(first)} at tau = {g(t_first)} "
            f"to {g(last)} at tau = {g(t_last)}; it is 1e-4 (\"99.99 %\") at tau = {g(at)} and {g(float(sw.last_R_c))} "
            f"at our tau = {g(float(d['fig4'].tau[-1]))}. R_f over the same cycle is {g(float(sw.last_R_f), 4)} = "
            f"e^(pi zeta) (from a maximum of X; e^(-pi zeta) from a minimum), not 1 - R_c: the transient does not "
            f"balance. In the steady state (exact solver) nothing flows: P_fin = "
            f"{g(float(steady.steady_P_fin))}, so neither ratio exists.")


# -- Fig. 6: force transmissibility ----------------------------------------------------------------


def _trb(d: Data, zeta: float, vb: float, fd: float, var: str = "last_TR_B", solver: str = "rk4") -> float:
    return float(d["sweep"][var].sel(solver=solver, vb=vb, fd=fd, zeta=zeta))


@claim(
    "trb_case1_falls_with_friction",
    "fig6",
    (
        "It can be found that TR_B decreases with friction force increase from 0.02 to 0.04 due to frictional "
        "resistance."
    ),
)
def _trb_fd(d: Data) -> tuple[str, str]:
    a, b = _trb(d, 0.0, 0.01, 0.02, "steady_TR_B", "exact"), _trb(d, 0.0, 0.01, 0.04, "steady_TR_B", "exact")
    return ("supported" if b < a else "refuted",
            f"zeta = 0, V_b = 0.01: TR_B = {g(a, 6)} (F_d = 0.02) -> {g(b, 6)} (F_d = 0.04), i.e. "
            f"(F_d + V_b - V_d)/F_d: the cycle's size V_b - V_d does not change while F_d, the reference, doubles.")


@claim("trb_case1_grows_with_belt_speed", "fig6",
       "TR_B increases as the belt speed V_b increases from 0.01 to 0.1.")
def _trb_vb(d: Data) -> tuple[str, str]:
    a, b = _trb(d, 0.0, 0.01, 0.02, "steady_TR_B", "exact"), _trb(d, 0.0, 0.1, 0.02, "steady_TR_B", "exact")
    return ("supported" if b > a else "refuted", f"zeta = 0, F_d = 0.02: TR_B = {g(a, 6)} (V_b = 0.01) -> {g(b, 6)} "
            f"(V_b = 0.1).")


@claim(
    "trb_case2_barely_changes",
    "fig6",
    (
        "For case II considering the viscous damper, changes of the magnitude of friction force, damping ratio and "
        "feeding velocity can hardly affect the value of TR_B because of small change of the transmitted force"
    ),
)
def _trb_case2(d: Data) -> tuple[str, str]:
    sw = d["sweep"]
    steady = sw.steady_TR_B.sel(solver="exact").where(sw.zeta > 0, drop=True)
    lo, hi = float(steady.min()), float(steady.max())
    win = sw.last_TR_B.sel(solver="rk4", zeta=0.01)
    return ("supported" if hi - lo < STEADY_TOL else "refuted",
            f"Steady state (exact solver), every zeta > 0 and every V_b, F_d: TR_B = {g(lo, 12)} ... {g(hi, 12)} -- "
            f"the motion has died out and the wall carries the static force F_d. Over the paper's kind of window "
            f"(last cycle before tau = {g(float(d['fig4'].tau[-1]))}, zeta = 0.01) TR_B = {g(float(win.min()), 5)} "
            f"... {g(float(win.max()), 5)}. Supported, for that reason rather than a small change of F_tB.")


@claim(
    "trb_falls_with_damping",
    "fig6",
    (
        "Fig. 6 also shows that the force transmission to the wall has a downward trend with the increase of the "
        "damping ratio, resulting from smaller limit cycles in Fig. 3(a)."
    ),
)
def _trb_trend(d: Data) -> tuple[str, str]:
    z = d["sweep"].zeta.values
    small = float(z[z > 0].min())
    w0, w1 = _trb(d, 0.0, 0.01, 0.02), _trb(d, small, 0.01, 0.02)
    w2 = _trb(d, 0.01, 0.01, 0.02)
    s0, s1, s2 = (_trb(d, zeta, 0.01, 0.02, "steady_TR_B", "exact") for zeta in (0.0, small, 0.01))
    # the paper's trend is in its window; it is the limit cycles' only if the steady state falls with zeta too
    steady_trend = s0 > s1 + STEADY_TOL and s1 > s2 + STEADY_TOL
    verdict = "refuted" if not w0 > w1 > w2 else "supported" if steady_trend else "partly"
    return (verdict,
            f"V_b = 0.01, F_d = 0.02, last cycle before tau = {g(float(d['fig4'].tau[-1]))}: TR_B = {g(w0, 4)} "
            f"(zeta = 0), {g(w1, 4)} (zeta = {g(small)}), {g(w2, 5)} (zeta = 0.01) -- a downward trend, set by how "
            f"far each transient has decayed by then. In the steady state TR_B steps from {g(w0, 4)} at zeta = 0 to "
            f"{g(s1, 6)} for every zeta > 0: no limit cycles, no trend.")


@claim(
    "trb_friction_and_damping_matter_more_than_belt_speed",
    "fig6",
    (
        "Compared with the effects of the belt speed, variations in the level of dry friction and damping have a "
        "relatively large effect on the force transmissibility."
    ),
)
def _trb_compare(d: Data) -> tuple[str, str]:
    base = _trb(d, 0.0, 0.01, 0.02, "steady_TR_B", "exact")
    by_vb = _trb(d, 0.0, 0.1, 0.02, "steady_TR_B", "exact") - base
    by_fd = _trb(d, 0.0, 0.01, 0.04, "steady_TR_B", "exact") - base
    return ("refuted" if abs(by_vb) > abs(by_fd) else "supported",
            f"At zeta = 0 (the only case with a steady vibration) V_b 0.01 -> 0.1 changes TR_B by {g(by_vb, 4)}, "
            f"F_d 0.02 -> 0.04 by {g(by_fd, 4)}; for zeta > 0 none of them matters in the steady state (TR_B = 1).")
