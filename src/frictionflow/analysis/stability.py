"""Steady sliding of a structure with friction contacts: its equilibrium, linearisation and complex eigenvalues.

All contacts slip at their belt speeds (V_r,j = b_j, q' = 0).  With mu_j the
law's signed slip value sgn(b_j) |F|(|b_j|) and N_j = P_j + n_j . q the normal
load, the equilibrium q* solves

    (K - sum_j mu_j e_j n_j^T) q* = sum_j e_j mu_j P_j

and small motions about it obey M x'' + C_eff x' + K_eff x = 0 with

    C_eff = C + sum_j N_j* mu'_j e_j e_j^T      (mu'_j = d|F|/d|V_r| at |b_j|)
    K_eff = K - sum_j mu_j e_j n_j^T            (the circulatory part: not symmetric)

so that A = [[0, I], [-M^-1 K_eff, -M^-1 C_eff]].  A falling slip curve
(mu' < 0) makes C_eff lose definiteness (negative damping); a normal load that
follows the motion makes K_eff non-symmetric, and two modes can coalesce in
frequency and split in damping (mode coupling, flutter).  The single mass
(M = K = 1, C = 2 zeta, N = 1) gives 2 zeta + F'(V_b), the damping of
:mod:`.equilibrium`.

Along one parameter (:func:`stability_scan`) the eigenvalues are tracked from
value to value (nearest continuation of the eigenvalue, the mode shape's
overlap breaking ties) and every change of sign of a mode's real part is
located by ``brentq`` and classified by what feeds the mode just beyond it
(:meth:`SteadySliding.growth_parts`: the real part is the damping forces'
share plus the circulatory forces'): ``negative_damping`` where the damping's
share is the larger (C_eff feeds the mode; its frequency stays apart from the
others'), ``mode_coupling`` where the circulatory forces' is (typically two
frequencies coalesce there and the real parts split; with damping that is
not proportional the crossing can come before the frequencies meet, and C_eff
positive definite still feeds nothing), ``divergence`` for a real eigenvalue
through zero (no frequency).

Where steady sliding does not exist at a value -- a normal load N_j* <= 0 at
the equilibrium (the contact is lost) or K_eff singular (no isolated
equilibrium) -- the scan goes on: the value is marked
(:attr:`StabilityScan.lost`; its eigenvalues NaN, ``stable`` False), the
eigenvalues are tracked and the critical points searched on each connected
stretch of values where it exists, and the boundary between a stretch and
values where a contact is lost is located by ``brentq`` on the smallest
normal load at steady sliding, min_j N_j*, between the last value with
sliding and the first without: a ``contact_loss`` point (no mode: its
frequency is NaN, null in JSON; ``unstable_above`` True where the contact is
lost above it).  The load changes sign either through zero or through
infinity, where K_eff turns singular on the way (q* runs off to infinity
and comes back on the other side: that value is also a divergence, a real
eigenvalue through zero); the root is that value in both cases.  A run of
singular values alone (loads > 0 on both sides: a divergence that the grid
hit) is marked but not located.  A scan without steady sliding at any value
is refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from .. import _validate as check
from .._display import Row, Summarized, num
from .._json import jsonable
from .._figures import draw
from .._lazy import lazy_module
from ..core.assembly import Assembly
from ..core.friction import slip_magnitude_of, slip_slope_of
from ..core.layout import LAW, VD
from ..core.structure.pencil import refine
from ..estimate import SECONDS_PER, Estimate
from ..friction.base import FrictionLaw
from ..friction.registry import law_classes

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick

#: critical point kinds, in the order the docs list them (``contact_loss``: the end of the values where steady
#: sliding keeps every contact closed, no mode's crossing)
KINDS = ("mode_coupling", "negative_damping", "divergence", "contact_loss")
#: a real part below this times its root's modulus is taken as zero (undamped modes: rounding, not damping) ...
ZERO_REAL = 1e-8
#: ... and below this times the spectrum's size (the rounding of the roots of a decomposition of that norm)
ROUNDING_FLOOR = 1e3 * np.finfo(float).eps


def zero_tolerance(lam: np.ndarray) -> np.ndarray:
    """Per eigenvalue (``lam``: one spectrum per row of its last axis), the real part below which it is zero:
    :data:`ZERO_REAL` of its own modulus, never under :data:`ROUNDING_FLOOR` of the spectrum's size.  (Of the
    spectrum's size alone, a stiff element's rate hid every other mode: with a damper of 1e9 on a third dof the
    Hoffmann pair's growth rate 0.075 counted as zero.)"""
    size = np.abs(lam)
    with np.errstate(invalid="ignore"):
        return ZERO_REAL * size + ROUNDING_FLOOR * size.max(axis=-1, keepdims=True)
#: evaluations a scan's estimate allows for locating its critical points (brentq: about 60 for each of two)
REFINE_EVALUATIONS = 120


class NoSteadySliding(ValueError):
    """Steady sliding does not exist: K_eff singular or a normal load <= 0 at the equilibrium.

    ``reason`` is ``"singular"`` or ``"contact_lost"``; the message is one line.  A ``ValueError``, as the
    other refusals of :func:`~frictionflow.steady_sliding`.
    """

    def __init__(self, message: str, reason: str) -> None:
        super().__init__(message)
        self.reason = reason


@dataclass(frozen=True, repr=False)
class SteadySliding(Summarized):
    """Steady sliding of every contact at its belt speed and the linearisation about it.

    Attributes
    ----------
    q:
        (n,) q*, the equilibrium displacements.
    normal:
        (k,) N_j* = P_j + n_j . q*, the normal loads there (> 0).
    mu:
        (k,) the signed slip values sgn(b_j) |F|(|b_j|).
    slope:
        (k,) d|F|/d|V_r| at |b_j|.
    mass:
        (n, n) M.
    stiffness, damping:
        (n, n) K_eff and C_eff.
    jacobian:
        (2n, 2n) A of the first-order system (state q then q').
    eigenvalues:
        (2n,) complex eigenvalues of A.
    eigenvectors:
        (2n, 2n) its eigenvectors, one per column, unit length.
    """

    q: np.ndarray
    normal: np.ndarray
    mu: np.ndarray
    slope: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    jacobian: np.ndarray
    eigenvalues: np.ndarray
    eigenvectors: np.ndarray

    @property
    def stable(self) -> bool:
        """No eigenvalue in the right half plane (a real part within ``zero_tolerance`` is zero: undamped modes
        count as stable, marginally)."""
        lam = self.eigenvalues
        return not bool(np.any(lam.real > zero_tolerance(lam)))

    def growth_parts(self) -> tuple[np.ndarray, np.ndarray]:
        """Each eigenvalue's real part split into what the damping and the circulatory forces contribute.

        With x the mode shape, m = x^H M x, c = x^H C_eff x and k = x^H K_eff x, the eigenvalue
        lambda = sigma + i omega solves lambda^2 m + lambda c + k = 0, whose imaginary part gives

            sigma = -c / (2 m) - Im(k) / (2 m omega)

        the first term the damping's share (positive only where C_eff feeds the mode: negative damping), the
        second the circulatory forces' (the antisymmetric part of K_eff: mode coupling).  NaN for a real
        eigenvalue (omega = 0).

        Returns
        -------
        (damping, circulatory):
            Two (2n,) arrays whose sum is the eigenvalues' real parts.
        """
        n = self.q.size
        x = self.eigenvectors[:n]
        m = np.einsum("ij,ik,kj->j", x.conj(), self.mass, x).real
        c = np.einsum("ij,ik,kj->j", x.conj(), self.damping, x).real
        k_im = np.einsum("ij,ik,kj->j", x.conj(), self.stiffness, x).imag
        omega = self.eigenvalues.imag
        with np.errstate(divide="ignore", invalid="ignore"):
            circulatory = np.where(omega != 0.0, -k_im / (2.0 * m * omega), np.nan)
        return -c / (2.0 * m), circulatory

    def _summary(self) -> tuple[str, list[Row]]:
        rows = [("q*", ", ".join(num(x, 6) for x in self.q)), ("N*", ", ".join(num(x, 6) for x in self.normal)),
                ("max Re(lambda)", num(float(np.max(self.eigenvalues.real)), 6)),
                ("stability", "stable" if self.stable else "not stable")]
        return "SteadySliding", rows


def contact_slip(assembly: Assembly, laws: Sequence[FrictionLaw] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Each contact's signed slip value mu_j and slope mu'_j at its belt speed.

    Parameters
    ----------
    assembly:
        The structure (its ``belt`` and ``law`` rows).
    laws:
        The contacts' law objects (a user's slip function is only reachable so); None: the kernel rows.

    Raises
    ------
    ValueError
        A belt speed of 0 (no sliding direction) or one inside a law's stick band.
    """
    belt = np.asarray(assembly.belt, dtype=float)
    rows = np.asarray(assembly.law, dtype=float)
    if laws is not None and len(laws) != len(belt):
        raise ValueError(f"laws must give one law per contact ({len(belt)}), got {len(laws)}")
    mu, slope = np.empty(len(belt)), np.empty(len(belt))
    for j, b in enumerate(belt):
        if not (math.isfinite(b) and b != 0.0):
            raise ValueError(f"contact.{j}.belt must be nonzero and finite for steady sliding, got {b:g}")
        speed = abs(b)
        if laws is None:
            cls = next((c for c in law_classes() if c.code == int(rows[j, LAW])), None)
            _check_band(j, None if cls is None else cls.stick_rule, rows[j, VD], speed)
            mu[j], slope[j] = slip_magnitude_of(rows[j], speed), slip_slope_of(rows[j], speed)
        else:
            _check_band(j, laws[j].stick_rule, laws[j].band, speed)
            mu[j], slope[j] = float(laws[j].slip_magnitude(speed)), laws[j].slip_slope(speed)
        mu[j] *= math.copysign(1.0, b)
    return mu, slope


def _check_band(j: int, stick_rule: str | None, band: float | None, speed: float) -> None:
    """Refuse a belt speed inside the stick band of a law with one (it holds the contact there, no sliding)."""
    if stick_rule == "band" and band is not None and speed <= band:
        raise ValueError(f"contact.{j}.belt = {speed:g} is inside the law's stick band |V_r| <= {band:g}: "
                         "the contact is held there, no steady sliding")


def steady_sliding(assembly: Assembly, laws: Sequence[FrictionLaw] | None = None) -> SteadySliding:
    """The steady-sliding equilibrium of ``assembly`` and the complex eigenvalues of its linearisation.

    Parameters
    ----------
    assembly:
        The structure (:class:`~frictionflow.core.assembly.Assembly`).
    laws:
        The contacts' law objects; None: the slip values from the kernel rows.

    Raises
    ------
    ValueError
        One line: a belt at rest, a belt inside a stick band;
        :class:`~frictionflow.analysis.stability.NoSteadySliding` (a ``ValueError``) for K_eff singular (no
        isolated equilibrium) or a normal load <= 0 at the equilibrium (the contact is lost).
    """
    check.instance("assembly", assembly, Assembly, "an Assembly (frictionflow.system.assemble(system))")
    mass = np.asarray(assembly.mass, dtype=float)
    e, _, _ = _contacts(assembly)
    mu, slope = contact_slip(assembly, laws)
    k_eff = effective_stiffness(assembly, mu)
    if np.linalg.cond(k_eff) * np.finfo(float).eps > 1e-6:
        raise NoSteadySliding("no steady-sliding equilibrium: K_eff = K - sum_j mu_j e_j n_j^T is singular "
                              "(a direction without stiffness, or the friction cancels it)", "singular")
    q, loads = _equilibrium(assembly, mu, k_eff)
    lost = np.flatnonzero(~(loads > 0.0))
    if lost.size:
        j = int(lost[0])
        raise NoSteadySliding(f"contact.{j}: the normal load at steady sliding is N = {loads[j]:g} <= 0: "
                              "the contact is lost", "contact_lost")
    c_eff = np.asarray(assembly.damping, dtype=float) + (e * (loads * slope)[:, None]).T @ e
    a = first_order(mass, c_eff, k_eff)
    lam, vec = _refined(mass, c_eff, k_eff, a, *np.linalg.eig(a))
    return SteadySliding(q, loads, mu, slope, mass, k_eff, c_eff, a, lam, vec)


def _refined(mass: np.ndarray, c_eff: np.ndarray, k_eff: np.ndarray, a: np.ndarray, lam: np.ndarray,
             vec: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``eig``'s roots and unit eigenvectors with those a stiff element's rate left ~its rate x EPS off refined on
    the pencil (``core.structure.pencil.refine``, right vectors only); a real spectrum stays real."""
    # the layouts the engine's combination builder passes (eig's vectors in Fortran order): one compiled refine
    lam_c, vec_c = lam.astype(complex), np.asfortranarray(vec, dtype=complex)
    if not refine(mass, c_eff, k_eff, a, lam_c, vec_c, np.zeros((0, 0), dtype=complex)):
        return lam, vec
    vec_c /= np.linalg.norm(vec_c, axis=0)
    return (lam_c, vec_c) if np.iscomplexobj(lam) else (lam_c.real, vec_c.real)


def _equilibrium(assembly: Assembly, mu: np.ndarray, k_eff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q*, N*): the steady-sliding displacements K_eff^-1 sum_j e_j mu_j P_j and the normal loads P_j + n_j . q*."""
    e, preload, coef = _contacts(assembly)
    q = np.linalg.solve(k_eff, e.T @ (mu * preload))
    return q, preload + coef @ q


def _contacts(assembly: Assembly) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e, P, n): the contacts' directions (k, n), preloads (k,) and normal-load coefficients (k, n)."""
    n = np.asarray(assembly.mass).shape[0]
    e = np.asarray(assembly.contact_dir, dtype=float).reshape(-1, n)
    normal = np.asarray(assembly.normal, dtype=float).reshape(len(e), n + 1)
    return e, normal[:, 0], normal[:, 1:]


def effective_stiffness(assembly: Assembly, mu: np.ndarray) -> np.ndarray:
    """K_eff = K - sum_j mu_j e_j n_j^T, with ``mu`` the contacts' signed slip values (:func:`contact_slip`)."""
    e, _, coef = _contacts(assembly)
    return np.asarray(assembly.stiffness, dtype=float) - (e * np.asarray(mu)[:, None]).T @ coef


def first_order(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """A = [[0, I], [-M^-1 K, -M^-1 C]], the first-order form of M x'' + C x' + K x = 0 (state x then x')."""
    n = mass.shape[0]
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -np.linalg.solve(mass, stiffness)
    a[n:, n:] = -np.linalg.solve(mass, damping)
    return a


# -- along one parameter ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Critical:
    """A value of the parameter where a mode's real part changes sign, or where steady sliding loses a contact.

    Attributes
    ----------
    value:
        The parameter value (refined by ``brentq``).
    kind:
        ``mode_coupling``, ``negative_damping``, ``divergence`` or ``contact_loss`` (``KINDS``).
    frequency:
        The mode's frequency Im(lambda) there (0 for a divergence, NaN for a contact loss: no mode).
    unstable_above:
        True where the mode is unstable on the side of larger values; for a contact loss, where the contact
        is lost (no steady sliding) on the side of larger values.
    """

    value: float
    kind: str
    frequency: float
    unstable_above: bool

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: value, kind, frequency (null for a contact loss), unstable_above."""
        return {"value": self.value, "kind": self.kind, "frequency": jsonable(float(self.frequency)),
                "unstable_above": self.unstable_above}


@dataclass(frozen=True, repr=False)
class StabilityScan(Summarized):
    """The eigenvalues of steady sliding along one parameter, tracked, and where stability changes.

    Attributes
    ----------
    param:
        The parameter's name (a model entry such as ``contact.0.belt``).
    values:
        (P,) its values.
    eigenvalues:
        (P, 2n) complex; column i is one eigenvalue followed from value to value (within each stretch of
        values with steady sliding; every stretch starts in the same order: upper half plane first, by
        frequency).  NaN + NaN j on the whole row at a value without steady sliding (:attr:`lost`).
    critical:
        The values where a mode's real part changes sign, and the ``contact_loss`` boundaries, in the order
        of ``values``.
    """

    param: str
    values: np.ndarray
    eigenvalues: np.ndarray
    critical: tuple[Critical, ...] = field(default=())

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``param``, ``values``, ``eigenvalues`` (per value a list of {re, im}; null at a value
        without steady sliding), ``lost`` (per value: no steady sliding there) and ``critical``."""
        return {"param": self.param, "values": [float(v) for v in self.values],
                "eigenvalues": [[{"re": jsonable(float(z.real)), "im": jsonable(float(z.imag))} for z in row]
                                for row in self.eigenvalues],
                "lost": self.lost.tolist(), "critical": [c.to_dict() for c in self.critical]}

    @property
    def lost(self) -> np.ndarray:
        """Per value (shape (P,), bool), whether steady sliding is missing there; its eigenvalues are then NaN
        (a normal load <= 0 at the equilibrium: the contact is lost; or K_eff singular: no isolated equilibrium)."""
        return np.all(np.isnan(self.eigenvalues), axis=1)

    @property
    def stable(self) -> np.ndarray:
        """Per value (shape (P,), bool), no eigenvalue in the right half plane there (a real part within
        ``zero_tolerance`` is zero: undamped modes count as stable, marginally, as for the critical points);
        False where steady sliding does not exist (:attr:`lost`)."""
        lam = self.eigenvalues
        with np.errstate(invalid="ignore"):
            unstable = np.any(lam.real > zero_tolerance(lam), axis=1)
        return ~unstable & ~self.lost

    def plot(self, path: Any = None, **kwargs: Any) -> Any:
        """The eigenvalue loci (:func:`frictionflow.stability_plot.plot_stability`); saved to ``path`` if given."""
        return draw(self, path, **kwargs)

    def _summary(self) -> tuple[str, list[Row]]:
        span = f"{num(self.values[0])} .. {num(self.values[-1])} ({len(self.values)} values)"
        rows = [(self.param, span), ("stable at", f"{int(np.sum(self.stable))} of {len(self.values)} values (Re <= 0)")]
        lost = int(np.sum(self.lost))
        if lost:
            rows.append(("no steady sliding at", f"{lost} of {len(self.values)} values (a contact lost, N* <= 0, "
                         "or K_eff singular)"))
        rows += [(f"critical {num(c.value, 8)}", f"{c.kind}, contact lost {'above' if c.unstable_above else 'below'}"
                  if c.kind == "contact_loss" else f"{c.kind}, frequency {num(c.frequency, 6)}, unstable "
                  f"{'above' if c.unstable_above else 'below'}") for c in self.critical]
        if not self.critical:
            rows.append(("critical", "none in the range"))
        return "StabilityScan", rows


def check_ends(assembly_at: Callable[[float], Assembly], values: Sequence[float], param: str,
               laws_at: Callable[[float], Sequence[FrictionLaw]] | None = None) -> None:
    """Refuse bad ``values`` (:func:`stability_scan`'s rules) or a range whose first or last value is no valid
    model (ValueError naming that value), before any value between is computed: a scan to 1e20 was refused at
    the first point past the model's bounds."""
    _Spectrum(assembly_at, laws_at, param).ends(_checked_values(values))


class _Spectrum:
    """value -> eigenvalues of steady sliding there, errors naming the value."""

    def __init__(self, assembly_at: Callable[[float], Assembly], laws_at: Callable[[float], Sequence[FrictionLaw]] | None,
                 param: str) -> None:
        self.assembly_at, self.laws_at, self.param = assembly_at, laws_at, param

    def attempt(self, value: float) -> SteadySliding | NoSteadySliding:
        """:meth:`sliding` at ``value``, or why there is none (a point of a scan like any other)."""
        try:
            return self.sliding(value)
        except NoSteadySliding as e:
            return e

    def ends(self, vals: np.ndarray) -> dict[int, SteadySliding | NoSteadySliding]:
        """:meth:`attempt` at the first and last of ``vals``, by index: a bad end raises before any value
        between is computed."""
        return {i: self.attempt(float(vals[i])) for i in (0, len(vals) - 1)}

    def sliding(self, value: float) -> SteadySliding:
        try:
            laws = None if self.laws_at is None else self.laws_at(value)
            return steady_sliding(self.assembly_at(value), laws)
        except NoSteadySliding as e:
            raise NoSteadySliding(f"{self.param} = {float(value)!r}: {e}", e.reason) from None
        except ValueError as e:
            raise ValueError(f"{self.param} = {float(value)!r}: {e}") from None  # the value checked, every digit

    def smallest_load(self, value: float) -> float:
        """min_j N_j* at steady sliding at ``value``, whether or not it is > 0 (0 where K_eff is exactly singular:
        the equilibrium's loads change sign through infinity there)."""
        laws = None if self.laws_at is None else self.laws_at(value)
        assembly = self.assembly_at(value)
        mu = contact_slip(assembly, laws)[0]
        try:
            loads = _equilibrium(assembly, mu, effective_stiffness(assembly, mu))[1]
        except np.linalg.LinAlgError:
            return 0.0
        return float(np.min(loads)) if loads.size else math.inf

    def __call__(self, value: float) -> np.ndarray:
        return self.sliding(value).eigenvalues

    def stiffness_det(self, value: float) -> float:
        """det K_eff at ``value``: where a real eigenvalue passes zero it does too (no equilibrium needed)."""
        laws = None if self.laws_at is None else self.laws_at(value)
        assembly = self.assembly_at(value)
        return float(np.linalg.det(effective_stiffness(assembly, contact_slip(assembly, laws)[0])))


def stability_scan(assembly_at: Callable[[float], Assembly], values: Sequence[float], *, param: str = "parameter",
                   laws_at: Callable[[float], Sequence[FrictionLaw]] | None = None) -> StabilityScan:
    """Eigenvalues of steady sliding along one parameter, tracked, with the critical values located and classified.

    Parameters
    ----------
    assembly_at:
        value -> the :class:`~frictionflow.core.assembly.Assembly` at that value of the parameter.
    values:
        The parameter's values, strictly increasing or decreasing (at least 2).
    param:
        The parameter's name, for the result and the messages.
    laws_at:
        value -> the contacts' law objects there; None: the slip values from the kernel rows.

    Returns
    -------
    StabilityScan
        The tracked eigenvalues and the critical points (see the module's docstring); values without steady
        sliding marked (:attr:`StabilityScan.lost`) and the boundaries where a contact is lost located.

    Raises
    ------
    ValueError
        One line: bad values, a value where a contact cannot slide (a belt at rest or inside a stick band),
        or no steady sliding at any value (nothing to show).
    """
    vals = _checked_values(values)
    spectrum = _Spectrum(assembly_at, laws_at, param)
    ends = spectrum.ends(vals)
    slides: list[SteadySliding | None] = []
    reasons: list[str | None] = []
    first: NoSteadySliding | None = None
    for i, v in enumerate(vals):
        got = ends[i] if i in ends else spectrum.attempt(float(v))
        if isinstance(got, NoSteadySliding):
            slides.append(None)
            reasons.append(got.reason)
            first = first or got
        else:
            slides.append(got)
            reasons.append(None)
    found = [s for s in slides if s is not None]
    if not found:
        raise ValueError(f"{first}; and at every other value of the scan ({len(vals)} from {vals[0]:g} to "
                         f"{vals[-1]:g}): no steady sliding to analyse")
    if len({s.eigenvalues.size for s in found}) != 1:
        raise ValueError(f"{param}: the number of degrees of freedom changes along the values")
    lam = np.full((len(vals), found[0].eigenvalues.size), complex(math.nan, math.nan))
    critical: list[Critical] = []
    for run in _stretches([s is not None for s in slides]):
        lam[run] = _track(vals[run], [slides[i] for i in run])
        critical += _critical_points(vals[run], lam[run], spectrum)
    critical += _contact_losses(vals, reasons, spectrum)
    critical.sort(key=lambda c: c.value if vals[-1] > vals[0] else -c.value)
    return StabilityScan(param, vals, lam, tuple(critical))


def _stretches(valid: Sequence[bool]) -> list[list[int]]:
    """The runs of consecutive indices where ``valid`` is True."""
    runs: list[list[int]] = []
    for i, ok in enumerate(valid):
        if ok:
            if runs and runs[-1][-1] == i - 1:
                runs[-1].append(i)
            else:
                runs.append([i])
    return runs


def _contact_losses(values: np.ndarray, reasons: Sequence[str | None], spectrum: _Spectrum) -> list[Critical]:
    """The ``contact_loss`` points: on each side of a run of values without steady sliding that borders one with
    it, the root of the smallest normal load between that neighbour and the nearest value of the run where a
    load is <= 0 (none if the run's values are all singular ones)."""
    out = []
    for run in _stretches([r is not None for r in reasons]):
        loads_lost = [i for i in run if reasons[i] == "contact_lost"]
        if not loads_lost:
            continue
        for valid, lost in ((run[0] - 1, loads_lost[0]), (run[-1] + 1, loads_lost[-1])):
            if not 0 <= valid < len(values):
                continue
            a, b = float(values[valid]), float(values[lost])
            root = _root(spectrum.smallest_load, a, b)
            if root is not None:  # always: N > 0 at a and <= 0 at b
                out.append(Critical(float(root), "contact_loss", math.nan, bool(b > a)))
    return out


def scan_estimate(n: int, points: int) -> Estimate:
    """What :func:`stability_scan` of a structure with ``n`` dof over ``points`` values costs, before it starts.

    Parameters
    ----------
    n:
        Degrees of freedom (the eigenvalue problem is 2n x 2n).
    points:
        Values of the parameter.
    """
    evaluations = points + REFINE_EVALUATIONS
    each = SECONDS_PER["structure_point"] + SECONDS_PER["eig_cube"] * (2.0 * n) ** 3
    return Estimate(evaluations, f"eigenvalue problems of size {2 * n}", evaluations * each,
                    memory=points * 2 * n * 16.0 + (2 * n) ** 2 * 16.0 * 4)


def _checked_values(values: Sequence[float]) -> np.ndarray:
    try:  # text, booleans, None or a ragged list are not the parameter's values
        vals = None if isinstance(values, (str, bytes)) else np.asarray(values)
    except (TypeError, ValueError):
        vals = None
    if vals is None or vals.dtype.kind not in "iuf" or vals.ndim != 1:
        raise ValueError(f"values must be a sequence of at least 2 finite numbers, got {values!r}")
    vals = vals.astype(float)
    if vals.size < 2 or not np.all(np.isfinite(vals)):
        raise ValueError(f"values must be at least 2 finite numbers, got {vals.size}: {values!r}")
    step = np.diff(vals)
    if not (np.all(step > 0) or np.all(step < 0)):
        raise ValueError("values must be strictly increasing or strictly decreasing")
    return vals


def _shapes(s: SteadySliding) -> np.ndarray:
    """The eigenvectors' displacement parts, unit length: what tells two modes of close eigenvalue apart."""
    n = s.q.size
    x = s.eigenvectors[:n]
    return x / np.maximum(np.linalg.norm(x, axis=0), np.finfo(float).tiny)


def _track(values: np.ndarray, slides: list[SteadySliding]) -> np.ndarray:
    """(P, 2n) eigenvalues, column i one eigenvalue followed from value to value.

    Matched to a linear prediction from the two values before (nearest continuation), a mode shape's overlap
    breaking ties (a small weight: where two frequencies cross, the shapes tell the modes apart).  The first
    value's order: upper half plane first, by frequency.
    """
    lam0 = slides[0].eigenvalues
    order = np.lexsort((lam0.real, np.abs(lam0.imag), lam0.imag < 0))
    out, shape = [lam0[order]], _shapes(slides[0])[:, order]
    for i in range(1, len(values)):
        pred = out[-1]
        if i >= 2:
            pred = out[-1] + (out[-1] - out[-2]) * (values[i] - values[i - 1]) / (values[i - 1] - values[i - 2])
        lam, new_shape = slides[i].eigenvalues, _shapes(slides[i])
        scale = max(float(np.abs(out[-1]).max()), np.finfo(float).tiny)
        overlap = np.abs(shape.conj().T @ new_shape)
        cost = np.abs(pred[:, None] - lam[None, :]) / scale + 1e-3 * (1.0 - overlap)
        _, cols = optimize.linear_sum_assignment(cost)
        out.append(lam[cols])
        shape = new_shape[:, cols]
    return np.array(out)


@dataclass(frozen=True)
class _Bracket:
    """Two neighbouring values where tracked eigenvalue ``k`` is stable at one and unstable at the other."""

    stable: float
    unstable: float
    lam_s: np.ndarray
    lam_u: np.ndarray
    k: int
    tol: float

    def interp(self, value: float) -> np.ndarray:
        """Every tracked eigenvalue at ``value``, interpolated between the ends (to recognise them there)."""
        t = (value - self.stable) / (self.unstable - self.stable)
        return self.lam_s + t * (self.lam_u - self.lam_s)


def _critical_points(values: np.ndarray, lam: np.ndarray, spectrum: _Spectrum) -> list[Critical]:
    """Each change of sign of a tracked eigenvalue's real part in the upper half plane, located and classified.

    A real part within ``zero_tolerance`` is zero (an undamped mode): stable, marginally.
    """
    tol = np.maximum(zero_tolerance(lam), np.finfo(float).tiny)
    unstable = lam.real > tol
    found = []
    for i in range(len(values) - 1):
        flips = np.flatnonzero(unstable[i] != unstable[i + 1])
        for k in flips:
            t = max(tol[i, k], tol[i + 1, k])
            s, u = (i, i + 1) if unstable[i + 1, k] else (i + 1, i)
            if lam[u, k].imag < -t or (lam[s, k].imag < -t and _conjugate_flips(lam[s], k, flips)):
                continue  # the conjugate of a mode of the upper half plane: counted there (also where the pair is
                # two real roots at the unstable end, as steep negative damping makes it: it crosses once)
            found.append(_locate(_Bracket(values[s], values[u], lam[s], lam[u], int(k), t), spectrum))
    return found


def _conjugate_flips(lam: np.ndarray, k: int, flips: np.ndarray) -> bool:
    """Whether the conjugate of ``lam[k]`` (the tracked eigenvalue nearest it) also changes stability (``flips``)."""
    j = int(np.argmin(np.abs(lam - np.conj(lam[k]))))
    return j != k and j in flips


def _partner(b: _Bracket) -> int | None:
    """The mode ``b.k`` coalesced with: not unstable at the stable end (a mode already in the right half plane
    there is another instability), nearest in frequency at the unstable end, their frequencies closer than
    their real parts there (merged), and its real part falling while ``b.k``'s rises (split); None if none."""
    others = [l for l in range(b.lam_u.size) if l != b.k and min(b.lam_s[l].imag, b.lam_u[l].imag) >= -b.tol
              and b.lam_s[l].real <= b.tol]
    if not others:
        return None
    u = b.lam_u
    l = min(others, key=lambda m: abs(u[m].imag - u[b.k].imag))
    merged = abs(u[l].imag - u[b.k].imag) <= abs(u[l].real - u[b.k].real)
    split = u[l].real - b.lam_s[l].real < 0.0 < u[b.k].real - b.lam_s[b.k].real
    return l if merged and split else None


def _pick(lam: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """The eigenvalues of ``lam`` nearest to ``targets``, one each, in the targets' order."""
    rows, cols = optimize.linear_sum_assignment(np.abs(targets[:, None] - lam[None, :]))
    return lam[cols[np.argsort(rows)]]


def _locate(b: _Bracket, spectrum: _Spectrum) -> Critical:
    """Refine the crossing in ``b``, classify it by what feeds the mode just beyond, and its frequency there
    (a coalesced pair's mean: each of the two is only known to ~sqrt(eps) at the coalescence, their mean to
    rounding)."""
    above = bool(b.unstable > b.stable)
    if abs(b.lam_u[b.k].imag) <= b.tol:
        # a real eigenvalue through 0 changes the sign of det A = det(M^-1 K_eff): K_eff is singular there,
        # where the equilibrium itself does not exist
        value = _root(spectrum.stiffness_det, b.stable, b.unstable)
        if value is not None:
            return Critical(float(value), "divergence", 0.0, above)
    partner = _partner(b)
    modes = [b.k] if partner is None else [b.k, partner]
    value = _refine(b, modes, spectrum)
    at = _pick(spectrum(value), b.interp(value)[modes])
    beyond = value + 0.5 * (b.unstable - value)
    kind = _mechanism(spectrum.sliding(beyond), b.interp(beyond)[modes])
    return Critical(float(value), kind, float(np.mean(np.abs(at.imag))), above)


def _mechanism(s: SteadySliding, targets: np.ndarray) -> str:
    """``mode_coupling`` where the circulatory forces feed the growing mode more than the damping forces do,
    ``negative_damping`` otherwise (:meth:`SteadySliding.growth_parts`); the growing mode: of the eigenvalues
    nearest to ``targets``, the one with the largest real part."""
    lam = s.eigenvalues
    _, cols = optimize.linear_sum_assignment(np.abs(targets[:, None] - lam[None, :]))
    i = cols[np.argmax(lam[cols].real)]
    damping, circulatory = s.growth_parts()
    return "mode_coupling" if circulatory[i] > damping[i] else "negative_damping"


def _refine(b: _Bracket, modes: list[int], spectrum: _Spectrum) -> float:
    """The critical value in ``b`` by ``brentq`` on a smooth indicator that changes sign there.

    The largest real part of ``modes`` where it is clearly negative at the stable end (a damped mode); for an
    undamped pair, whose real parts are zero up to rounding until they coalesce, the discriminant
    Re[(lambda_k^2 - lambda_l^2)^2]: (omega_l^2 - omega_k^2)^2 > 0 apart, -16 a^2 omega^2 < 0 once split.
    Bisection of the unstable flag if neither changes sign.
    """
    def real_part(v: float) -> float:
        return float(np.max(_pick(spectrum(v), b.interp(v)[modes]).real))

    def discriminant(v: float) -> float:
        lk, ll = _pick(spectrum(v), b.interp(v)[modes])
        return float(((lk * lk - ll * ll) ** 2).real)

    if real_part(b.stable) < -b.tol:
        root = _root(real_part, b.stable, b.unstable)
    elif len(modes) == 2:
        root = _root(discriminant, b.stable, b.unstable)
    else:
        root = None
    if root is not None:
        return root
    lo, hi = b.stable, b.unstable
    for _ in range(200):  # the unstable flag, halved until the ends are neighbouring floats
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (lo, mid) if real_part(mid) > b.tol else (mid, hi)
    return 0.5 * (lo + hi)


def _root(f: Callable[[float], float], a: float, b: float) -> float | None:
    """brentq's root of ``f`` between ``a`` and ``b`` to a few ulps; None if ``f`` has one sign at both."""
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if not (math.isfinite(fa) and math.isfinite(fb)) or (fa > 0) == (fb > 0):
        return None
    lo, hi = min(a, b), max(a, b)
    return float(optimize.brentq(f, lo, hi, xtol=1e-15 * max(abs(lo), abs(hi)), rtol=4 * np.finfo(float).eps))
