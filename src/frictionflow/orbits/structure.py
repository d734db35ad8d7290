"""Periodic orbits of a structure with friction contacts: Newton on the Poincare return map, Floquet multipliers.

The section is the downward crossing of q_i' = 0 for one coordinate i (by
default the one whose velocity varies most over the transient's second
half, as :func:`frictionflow.analysis.structure.section_times` picks it).  A
point s of the section has q_i' = 0, and q_j' = b_j along every contact
stuck there; Newton runs on P(s) - s = 0 in the coordinates of that affine
set (an orthonormal basis B of its directions), with the Jacobian
B^T (DP - I) B from the exact monodromy (:mod:`.structure_flow`: phase
transition matrices from the closed forms, saltation at every switch).

At the fixed point the monodromy M over one period has the Floquet
multipliers as its eigenvalues: one is 1 (the flow's own direction: the
system is autonomous), a stuck contact contributes 0s (a stick phase forgets
the perturbations it holds), and the largest of the others in modulus
decides stability.

With harmonic forces (all of one frequency Omega) the section is
stroboscopic instead: P maps the state at t = 0 to the state at
t = m 2 pi / Omega (``returns`` = m forcing periods, m > 1 for a
subharmonic), Newton runs on P(s) - s = 0 within the stuck contacts'
constraints only, and no multiplier is trivial (the period is fixed by the
forcing, not by the flow).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, NamedTuple

import numpy as np

from .._display import Row, Summarized, num
from .._json import jsonable
from ..analysis.structure import certified_sliding, stick_fractions
from ..core.assembly import Assembly, natural_frequencies
from ..core.layout import LAW, STICK
from ..estimate import enforce, enforce_stage
from ..friction.registry import law_classes
from ..solvers.structure import check_switchable, run_estimate, solvers_running, supported_laws
from ..system import assemble
from . import floquet
from .shooting import ShootingError, check_shooting
from .structure_flow import Flow, Return, crossings, return_map
from .structure_transient import cycle_count, slow_hint, strobe_count, strobe_hint, transient_hint

#: Newton's default tolerance on |P(s) - s|, relative to the orbit's size (:func:`orbit_scales`)
DEFAULT_TOL = 1e-11
#: backtracking halvings before Newton gives up
MAX_HALVINGS = 12
#: a Newton trial must return to the section within this many current periods
RETURN_LIMIT = 4.0
#: largest |M f - f| / |f| (scaled units) of an autonomous orbit returned; rounding leaves 1e-15 to 1e-11
CARRIED_TOL = 1e-6


@dataclass(frozen=True, repr=False, eq=False)
class StructureOrbit(floquet.MultiplierStability, Summarized):
    """A periodic orbit of a structure, its Floquet multipliers and its power flow.

    Attributes
    ----------
    state:
        (2n,) the state (q, q') where the orbit crosses the section.
    period:
        The period.
    returns:
        How many section crossings make one period.
    section:
        The dof whose velocity's downward zero crossing is the section.
    monodromy:
        (2n, 2n) d y(T) / d y(0) over one period, saltation included.
    multipliers:
        Its eigenvalues, largest modulus first.
    stick_fraction:
        Per contact, the share of the period it spends stuck.
    elements:
        Element name -> its average powers over one period (:meth:`~frictionflow.motion.Motion.element_power`).
    energy_residual:
        The relative residual of the energy balance over one period.
    residual, iterations:
        max |P(s) - s| at the returned state, each component relative to its group's size (``orbit_scales``:
        positions, velocities), and Newton's iterations.
    motion:
        One period run from :attr:`state` by the exact engine.
    dof, contacts:
        The names of the coordinates and of the contacts.
    system:
        The model the orbit belongs to (None for an assembly).
    autonomous:
        False for a forced structure's stroboscopic orbit: its period is the forcing's and no multiplier is
        trivial.
    tangent:
        (2n,) the vector field at :attr:`state` (an autonomous orbit's; None when forced): M maps it to itself.
    scale:
        (2n,) per state component, the orbit's size in its units (``orbit_scales``), or None: the nontrivial
        multipliers are taken in these units.
    """

    state: np.ndarray
    period: float
    section: str
    returns: int
    monodromy: np.ndarray
    multipliers: np.ndarray
    stick_fraction: tuple[float, ...]
    elements: dict[str, dict[str, float]]
    energy_residual: float
    residual: float
    iterations: int
    motion: Any
    dof: tuple[str, ...]
    contacts: tuple[str, ...]
    system: Any = field(default=None)
    autonomous: bool = True
    tangent: np.ndarray | None = field(default=None)
    scale: np.ndarray | None = field(default=None)

    @property
    def nontrivial(self) -> np.ndarray:
        """The multipliers without the trivial one, largest modulus first.

        For an autonomous orbit the eigenvalues of B^T M B, B an orthonormal basis across :attr:`tangent` f.
        M f = f, so in the basis (f, B) M is block triangular and these are M's other eigenvalues, without
        saying which of two multipliers near 1 is the trivial one (a stiff damper's creep, 1 - k T / c, beside
        the trivial one moved by the monodromy's rounding: the one nearest 1 was dropped and the orbit called
        unstable).  In units of :attr:`scale` (D^-1 M D across D^-1 f): in the model's units M's position and
        velocity blocks part by the unit of time squared, and B^T M B rounded to 1e-4 in picoseconds."""
        if not self.autonomous or self.tangent is None:
            return super().nontrivial
        d = np.ones(len(self.tangent)) if self.scale is None else np.asarray(self.scale, dtype=float)
        B = _basis((self.tangent / d)[None, :])
        mu = np.linalg.eigvals(B.T @ (self.monodromy * d / d[:, None]) @ B).astype(complex)
        return mu[np.argsort(-np.abs(mu), kind="stable")]

    def _summary(self) -> tuple[str, list[Row]]:
        n = len(self.dof)
        rows = [
            ("period", num(self.period, 10) + (f" ({self.returns} {self._unit})" if self.returns > 1 else "")),
            ("section", self.section + ("' = 0; " if self.autonomous else "; ") + ", ".join(f"{d}={num(x, 8)}" for d, x in zip(self.dof, self.state[:n]))),
            ("stability", f"{self.stability}, largest nontrivial |multiplier| {num(abs(self.multiplier))}"),
            ("multipliers", ", ".join(num(m.real, 6) + (f"{m.imag:+.3g}j" if m.imag else "") for m in self.multipliers)),
            ("stick fraction", ", ".join(f"{c} {num(s, 4)}" for c, s in zip(self.contacts, self.stick_fraction))),
            ("energy residual", num(self.energy_residual, 3)),
            ("Newton", f"{self.iterations} iterations, residual {num(self.residual, 2)}"),
        ]
        return "StructureOrbit", rows

    @property
    def _unit(self) -> str:
        return "section crossings" if self.autonomous else "forcing periods"

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready report (NaN becomes None; multipliers as {re, im})."""
        n = len(self.dof)
        return jsonable({
            "period": self.period,
            "returns": self.returns,
            "section": self.section,
            "autonomous": self.autonomous,
            "state": {"q": dict(zip(self.dof, self.state[:n])), "v": dict(zip(self.dof, self.state[n:]))},
            "multipliers": [{"re": float(m.real), "im": float(m.imag)} for m in self.multipliers],
            "multiplier": {"re": self.multiplier.real, "im": self.multiplier.imag},
            "stable": self.stable,
            "stability": self.stability,
            "stick_fraction": list(self.stick_fraction),
            "elements": self.elements,
            "energy_residual": self.energy_residual,
            "monodromy": self.monodromy,
            "newton": {"iterations": self.iterations, "residual": self.residual},
        })


class Setup(NamedTuple):
    """What the shooting works on: the flow and the names."""

    flow: Flow
    dof: tuple[str, ...]
    contacts: tuple[str, ...]
    system: Any


def _setup(system_or_assembly: Any) -> Setup:
    """The :class:`Setup` of a model or an assembly; one line if it cannot have an autonomous orbit."""
    if isinstance(system_or_assembly, Assembly):
        asm, system = system_or_assembly, None
        dof = tuple(f"q{i}" for i in range(len(asm.q0)))
        contacts = tuple(f"contact.{j}" for j in range(len(asm.belt)))
    elif hasattr(system_or_assembly, "dof") and hasattr(system_or_assembly, "contact_names"):
        system = system_or_assembly
        asm, dof, contacts = assemble(system), tuple(system.dof), tuple(system.contact_names)
    else:
        raise TypeError("system_or_assembly must be a frictionflow.system.System or a core.assembly.Assembly, "
                        f"got {type(system_or_assembly).__name__}")
    if len(asm.belt) == 0:
        raise ValueError("find_structure_orbit: the model has no contact (a linear structure has no isolated orbit)")
    _check_laws(asm, contacts)
    check_switchable(asm, contacts)
    return Setup(Flow(asm, {"dof": dof}), dof, contacts, system)


def _check_laws(asm: Assembly, contacts: tuple[str, ...]) -> None:
    """One line when a contact's law is not the exact engine's: the shooting and its monodromy are that engine's."""
    runs = supported_laws()
    classes = {cls.code: cls for cls in sorted(law_classes(), key=lambda cls: cls.configurable)}  # a built-in's
    for contact, code in zip(contacts, np.asarray(asm.law)[:, LAW]):
        if int(code) not in runs:
            cls = classes[int(code)]
            others = solvers_running(cls)
            where = f"simulate runs it on the {' or '.join(others)} solver" if others else "no structure solver runs it"
            raise ValueError(f"a structure's periodic orbits are shot with the exact engine, which runs contacts with "
                             f"the laws {', '.join(runs.values())}; {contact} has friction={cls.name} ({where})")


def _row(flow: Flow, motion: Any, section: Any, dof: tuple[str, ...]) -> int:
    """The state row of the section's velocity: the dof named or indexed, or the one moving most."""
    n = flow.n
    if section is None:
        t0, t1 = float(motion.t[0]), float(motion.t[-1])
        grid = np.linspace(t0 + 0.5 * (t1 - t0), t1, 512)
        velocities = flow.states(motion, grid)[:, n:]
        return n + int(np.argmax(np.ptp(velocities, axis=0)))
    if isinstance(section, str):
        if section not in dof:
            raise ValueError(f"section must be one of the dof ({', '.join(dof)}), got {section!r}")
        return n + dof.index(section)
    if isinstance(section, (int, np.integer)) and not isinstance(section, bool) and 0 <= section < n:
        return n + int(section)
    raise ValueError(f"section must be a dof name or an index in [0, {n - 1}], got {section!r}")


def _constraints(flow: Flow, modes: np.ndarray, row: int | None) -> tuple[np.ndarray, np.ndarray]:
    """(A, c): the section and the stuck contacts as A y = c (q'_row = 0 unless ``row`` is None, stroboscopic;
    e_j . q' = b_j for stuck j)."""
    n, asm = flow.n, flow.assembly
    stuck = np.flatnonzero(np.asarray(modes) == STICK)
    first = 0 if row is None else 1
    A = np.zeros((first + len(stuck), 2 * n))
    c = np.zeros(first + len(stuck))
    if row is not None:
        A[0, row] = 1.0
    for i, j in enumerate(stuck):
        A[first + i, n:] = asm.contact_dir[j]
        c[first + i] = asm.belt[j]
    return A, c


def _basis(A: np.ndarray) -> np.ndarray:
    """An orthonormal basis of A's null space (the directions Newton moves in)."""
    if A.shape[0] == 0:
        return np.eye(A.shape[1])
    _, sv, vt = np.linalg.svd(A, full_matrices=True)
    rank = int(np.sum(sv > 1e-12 * sv.max()))
    return vt[rank:].T.copy()


def _project(y: np.ndarray, A: np.ndarray, c: np.ndarray, row: int | None) -> np.ndarray:
    """The point of {A y = c} nearest ``y``, with the section's row exactly 0 (``row`` None: stroboscopic)."""
    if A.shape[0] == 0:
        return y.copy()
    out = y - A.T @ np.linalg.lstsq(A @ A.T, A @ y - c, rcond=None)[0]
    if row is not None:
        out[row] = 0.0
    return out


def on_section(flow: Flow, motion: Any, t: float, row: int | None) -> np.ndarray:
    """The state of ``motion`` at ``t`` put on the section (q'_row = 0; ``row`` None: stroboscopic) and on the
    constraints of the contacts stuck there (e_j . q' = b_j), so that a run from it starts in the same modes.

    The crossing is located to rounding, not exactly, and zeroing q'_row alone moves V_r of a stuck contact
    along that dof by that rounding, past the engine's test for V_r = 0: the run would start the contact
    slipping.  Where its held force lies between F_d N and F_s N that slip is self-consistent and never comes
    back, so the map's point would not continue the motion it came from, and Newton could converge on that
    branch to a "fixed point" ending stuck where it began slipping.
    """
    i = int(np.searchsorted(motion.t, t, side="right")) - 1
    A, c = _constraints(flow, np.asarray(motion.modes)[:, max(i, 0)], row)
    return _project(flow.states(motion, np.array([t]))[0], A, c, row)


def _residual(ret: Return) -> np.ndarray:
    return ret.end - ret.start


def _step(flow: Flow, ret: Return, row: int | None, again: Callable[[np.ndarray, Return], Return],
          scale: np.ndarray) -> Return:
    """One Newton step from ``ret`` with backtracking on max |P(s) - s| / ``scale`` (per component: positions'
    and velocities' own sizes); ShootingError if it stalls.

    ``again(s, ret)``: the map from the trial point ``s`` (RuntimeError if it does not return); ``row``: the
    section's state row (None: stroboscopic, no row pinned).
    """
    A, c = _constraints(flow, ret.modes, row)
    # Newton's linear step in units of each component's size: in the model's units the monodromy's
    # position-velocity blocks part by the unit of time squared (1e24 in picoseconds: a step of rounding)
    B = _basis(A * scale)
    r = _residual(ret)
    J = B.T @ (ret.jacobian * scale / scale[:, None] - np.eye(len(r))) @ B
    try:
        step = scale * (B @ np.linalg.solve(J, -(B.T @ (r / scale))))
    except np.linalg.LinAlgError:
        raise ShootingError("the return map's Jacobian minus I is singular: Newton cannot proceed "
                            "(a fold, or a family of neutral orbits)") from None
    size = float(np.max(np.abs(r) / scale))
    end = on_section(flow, ret.motion, ret.time, row)
    # far from the orbit the stuck set at P(s) may differ from s's, which Newton's coordinates cannot follow:
    # after the halvings, one plain return (s -> P(s)) still gets closer to an attracting orbit
    trials = [_project(ret.start + 0.5 ** i * step, A, c, row) for i in range(MAX_HALVINGS)] + [end]
    for s in trials:
        try:  # a trial that does not return within a few periods is not closer
            new = again(s, ret)
        except RuntimeError:
            continue
        if float(np.max(np.abs(_residual(new)) / scale)) < size:
            return new
    raise ShootingError(f"Newton stalled at residual {size:.3g} (of the orbit's size): no periodic orbit near "
                        "this start")


def _newton(flow: Flow, ret: Return, row: int | None, again: Callable[[np.ndarray, Return], Return],
            tol: tuple[float, np.ndarray], max_iter: int) -> tuple[Return, int]:
    """Newton on P(s) - s = 0 from ``ret`` (``again``: the map, as :func:`_step`) until every component is within
    ``tol`` = (relative tolerance, per-component scale) of its size; the return and the iterations."""
    rel, scale = tol
    for it in range(max_iter + 1):
        if float(np.max(np.abs(_residual(ret)) / scale)) <= rel:
            return ret, it
        if it < max_iter:
            ret = _step(flow, ret, row, again, scale)
    raise ShootingError(f"Newton did not converge in {max_iter} iterations "
                        f"(residual {float(np.max(np.abs(_residual(ret)) / scale)):.3g} of the orbit's size)")


def _start(setup: Setup, guess: np.ndarray, t_transient: float, section: Any,
           returns: int | None) -> tuple[Return, int, Any, int]:
    """The first return map: from the transient's last section crossing (or the guess's first), the row, the
    transient's run (None without one) and the crossings per period (``returns``; None: the count of the cycle
    the transient settles on or nears, :func:`cycle_count`, else 1)."""
    flow = setup.flow
    slow = 2.0 * math.pi / flow.omega_min
    length = t_transient if t_transient > 0 else 2.0 * slow * ((returns or 1) + 1)
    motion = _transient(flow, guess, length)
    if t_transient > 0 and certified_sliding(motion):  # proven: no switch after it, a spiral into steady sliding
        raise ShootingError(f"the motion settles on the steady-sliding equilibrium (certified from t={length:.6g} on, "
                            "as simulate --model finds it): no periodic orbit to shoot for from this start")
    row = _row(flow, motion, section, setup.dof)
    if returns is None:
        found = cycle_count(flow, motion, row) if t_transient > 0 else None
        returns = min(max(found[1], 1), 64) if found is not None else 1
    times = crossings(flow, motion, row, 0.5 * length if t_transient > 0 else 0.0)
    if len(times) == 0:
        raise ShootingError(f"the motion does not cross the section {setup.dof[row - flow.n]}' = 0 downwards "
                            f"in t={length:.6g} (it settled on an equilibrium, or the transient is too short)")
    tc = float(times[-1] if t_transient > 0 else times[0])
    gap = float(np.diff(times)[-1]) if len(times) > 1 else slow
    s = on_section(flow, motion, tc, row)
    try:
        ret = return_map(flow, s, row, returns, 1.5 * returns * gap)
        return ret, row, motion if t_transient > 0 else None, returns
    except RuntimeError as e:
        raise ShootingError(f"from the section point at t={tc:.6g}: {e}") from None


#: flows per Newton iteration counted by the shooting's estimate (the step, one backtracking halving), each
#: bounded by 4 periods (a trial return that takes longer is rejected)
SHOOTING_FLOWS = 2


def find_structure_orbit(
    system_or_assembly: Any,
    guess_state: Any = None,
    *,
    t_transient: float = 300.0,
    tol: float | None = None,
    returns: int | None = None,
    section: Any = None,
    max_iter: int = 40,
) -> StructureOrbit:
    """A periodic orbit of a structure by Newton shooting on its return map, with its Floquet multipliers.

    Parameters
    ----------
    system_or_assembly:
        A :class:`frictionflow.system.System` or a :class:`frictionflow.core.assembly.Assembly`; contacts
        with a piecewise-constant law (the exact engine's).  With harmonic forces (one frequency Omega for
        all) the orbit is the stroboscopic map's fixed point at t = 0 (the module's docstring).
    guess_state:
        (2n,) start state (q, q'); default the model's initial state.
    t_transient:
        Simulate this long first and shoot from the last section crossing of its second half (> 0: an
        attracting orbit); 0 shoots from the guess's first crossing (an unstable orbit near the guess).
    tol:
        Newton's tolerance on |P(s) - s| relative to the orbit's size, positions' and velocities' each
        (``orbit_scales``); default 1e-11, at most 1e-3.
    returns:
        Section crossings per period (2 for a period-2 orbit), 1 to 64; forced, forcing periods per period.
        Default: the count of the cycle the transient settles on (its section states repeat to 1e-6, as
        simulate's analysis finds it) or nears (to 1e-3), so that the orbit is that cycle
        rather than another one Newton reaches from its crossing; 1 without a transient or a cycle.
    section:
        The dof (name or index) whose velocity's downward zero crossing is the section; default the one
        whose velocity varies most over the transient's second half.  Forced: None (the section is
        stroboscopic).
    max_iter:
        Newton iterations before :class:`~frictionflow.orbits.ShootingError`.
    """
    check_shooting(t_transient, tol, 1 if returns is None else returns, max_iter, "t_transient")
    setup = _setup(system_or_assembly)
    flow, n = setup.flow, setup.flow.n
    asm = flow.assembly
    guess = np.concatenate((asm.q0, asm.v0)) if guess_state is None else np.asarray(guess_state, dtype=float)
    if guess.shape != (2 * n,) or not np.all(np.isfinite(guess)):
        raise ValueError(f"guess_state must be {2 * n} finite numbers (q then q'), got shape {guess.shape}")
    if len(asm.force_amp):
        return _forced_orbit(setup, guess, float(t_transient), section, (tol, returns, int(max_iter)))
    slow = 2.0 * math.pi / flow.omega_min
    transient = float(t_transient) if t_transient > 0 else 2.0 * slow * ((returns or 1) + 1)
    enforce(lambda: run_estimate(asm, transient), open_stage="shooting")
    ret, row, transient_run, returns = _start(setup, guess, float(t_transient), section, returns)
    enforce_stage("shooting", lambda: run_estimate(asm, SHOOTING_FLOWS * (int(max_iter) + 1) * 4.0 * ret.time))
    scale = orbit_scales(flow, ret.start)
    def again(s: np.ndarray, last: Return) -> Return:
        return return_map(flow, s, row, int(returns), 1.5 * last.time, limit=RETURN_LIMIT * last.time)

    try:
        ret, iterations = _newton(flow, ret, row, again, (DEFAULT_TOL if tol is None else tol, scale), int(max_iter))
    except ShootingError as e:
        hint = slow_hint(asm, float(t_transient)) or transient_hint(flow, setup.dof, transient_run, row, int(returns))
        raise ShootingError(f"{e}{hint}") from None
    return _orbit(setup, ret, row, int(returns), iterations, scale)


def forcing_period(assembly: Assembly) -> float:
    """2 pi / Omega of a structure's harmonic forces; one line if their frequencies differ."""
    omega = np.unique(assembly.force_omega)
    if len(omega) != 1:
        raise ValueError("find_structure_orbit: the forces' frequencies differ "
                         f"({', '.join(f'{w:g}' for w in omega)}): a stroboscopic orbit needs one forcing frequency")
    return 2.0 * math.pi / float(omega[0])


def strobe(flow: Flow, start: np.ndarray, T: float) -> Return:
    """The stroboscopic map over ``T`` (a whole number of forcing periods) from ``start`` at t = 0, with its
    exact monodromy (the section does not move, so the map's Jacobian is the monodromy)."""
    motion = flow.run(start, T)
    if motion.status != "ok":
        raise RuntimeError(f"{motion.lost[0]} lost its normal load at t={motion.lost[1]:.6g}")
    M = flow.monodromy(motion, T)
    end = flow.states(motion, np.array([T]))[0]
    return Return(np.array(start, dtype=float), T, end, M, M, motion, np.asarray(motion.modes[:, 0]).copy())


def _forced_orbit(setup: Setup, guess: np.ndarray, t_transient: float, section: Any,
                  settings: tuple[float | None, int | None, int]) -> StructureOrbit:
    """Newton on the stroboscopic map of a forced structure: (tol, forcing periods, max_iter) in ``settings``;
    forcing periods None: the period of the cycle the transient settles on or nears, in forcing periods
    (:func:`strobe_count`), else 1."""
    tol, periods, max_iter = settings
    if section is not None:
        raise ValueError(f"section must be None for a forced structure (its section is stroboscopic), got {section!r}")
    flow, asm = setup.flow, setup.flow.assembly
    forcing = forcing_period(asm)
    motion = None
    if periods is None:  # the transient to whole forcing periods, counted; rerun below only if m does not divide it
        length = math.ceil(t_transient / forcing) * forcing
        enforce(lambda: run_estimate(asm, 2.0 * length + 2.0 * forcing), open_stage="shooting")
        motion = _transient(flow, guess, length)
        counted = None if motion is None else strobe_count(motion, forcing)
        periods = 1 if counted is None else counted
    T = periods * forcing
    settle = math.ceil(t_transient / T) * T  # a whole number of periods: the map's phase
    enforce(lambda: run_estimate(asm, settle + T), open_stage="shooting")
    if motion is None or float(motion.t[-1]) != settle:
        motion = _transient(flow, guess, settle)
    start = guess if motion is None else flow.states(motion, np.array([settle]))[0]
    try:
        ret = strobe(flow, start, T)
    except RuntimeError as e:
        raise ShootingError(f"from the start: {e}") from None
    enforce_stage("shooting", lambda: run_estimate(asm, SHOOTING_FLOWS * (max_iter + 1) * T))
    scale = orbit_scales(flow, ret.start)
    try:
        ret, iterations = _newton(flow, ret, None, lambda s, last: strobe(flow, s, T),
                                  (DEFAULT_TOL if tol is None else tol, scale), max_iter)
    except ShootingError as e:
        raise ShootingError(f"{e}{strobe_hint(motion, forcing, periods)}") from None
    return _orbit(setup, ret, None, periods, iterations, scale)


def _transient(flow: Flow, guess: np.ndarray, length: float) -> Any:
    """The run from ``guess`` over ``length`` (None for 0); ShootingError if it loses a contact."""
    if length <= 0:
        return None
    motion = flow.run(guess, length)
    if motion.status != "ok":
        raise ShootingError(f"{motion.lost[0]} lost its normal load at t={motion.lost[1]:.6g} in the transient")
    return motion


def orbit_scales(flow: Flow, state: np.ndarray) -> np.ndarray:
    """Per state component, the orbit's size in its own units: the largest |q| for positions (at least the
    velocities' over the fastest natural or forcing frequency), the largest of |q'| and the belt speeds for
    velocities.
    One scale over both made Newton's tolerance and the difference step depend on the unit of time (in
    microseconds the belt's speed set the positions' tolerance: the period off by 1.3e-7)."""
    n, asm = flow.n, flow.assembly
    v = max(float(np.max(np.abs(state[n:]))), float(np.max(np.abs(asm.belt), initial=0.0)), 1e-300)
    omega = max(float(natural_frequencies(asm).max(initial=0.0)), float(np.max(np.abs(asm.force_omega), initial=0.0)))
    q = max(float(np.max(np.abs(state[:n]))), v / omega if omega > 0.0 else 0.0, 1e-300)
    return np.repeat([q, v], n)


def _orbit(setup: Setup, ret: Return, row: int | None, returns: int, iterations: int,
           scale: np.ndarray) -> StructureOrbit:
    """The :class:`StructureOrbit` of a converged return (``row`` None: stroboscopic); ShootingError if it is
    an equilibrium."""
    flow, T = setup.flow, ret.time
    # the stroboscopic map's run is exactly one period from the start; a return map's runs past it
    one = ret.motion if row is None else flow.run(ret.start, T)
    if row is not None and np.all(np.ptp(flow.states(one, np.linspace(0.0, T, 65)), axis=0) <= 1e-9 * scale):
        raise ShootingError("shooting converged onto an equilibrium: no periodic orbit near this start")
    tangent = None if row is None else flow.field(ret.modes, ret.start, 0.0)
    if tangent is not None:
        _check_carried(ret.monodromy, tangent, scale)
    return StructureOrbit(
        state=ret.start.copy(), period=T, section="stroboscopic" if row is None else setup.dof[row - flow.n],
        returns=returns, autonomous=row is not None,
        monodromy=ret.monodromy, multipliers=floquet.multipliers(ret.monodromy),
        stick_fraction=stick_fractions(one, (0.0, T)), elements=one.element_power(0.0, T),
        energy_residual=one.energy_residual, residual=float(np.max(np.abs(_residual(ret)) / scale)),
        iterations=iterations, motion=one, dof=setup.dof, contacts=setup.contacts, system=setup.system,
        tangent=tangent, scale=scale,
    )


def _check_carried(monodromy: np.ndarray, tangent: np.ndarray, scale: np.ndarray) -> None:
    """ShootingError unless the monodromy carries the vector field f at the start to itself (M f = f, each
    component in units of ``scale``, to :data:`CARRIED_TOL` of |f|).

    Along a periodic orbit of an autonomous system this holds exactly; it fails where the run from the start
    is not the motion that ends there -- a run beginning in other contact modes than the period ends in
    (the return map's fixed point is then one of a branch the motion does not follow).
    """
    f = tangent / scale
    drift = float(np.linalg.norm((monodromy @ tangent - tangent) / scale) / max(float(np.linalg.norm(f)), 1e-300))
    if not drift <= CARRIED_TOL:
        raise ShootingError(f"Newton's fixed point is not a periodic orbit: the monodromy carries the vector field "
                            f"at its start {drift:.3g} of its size away from itself (M f = f on an orbit), so the "
                            "run from it is not the motion that ends there")


def fd_deviation(system_or_assembly: Any, orbit: StructureOrbit, fd: np.ndarray) -> float:
    """max |(M_fd - M) B| over B, an orthonormal basis of the perturbations that keep the contacts stuck at the
    orbit's start stuck (e_j . dq' = 0).

    Across such a constraint the two differ by convention, not error: the exact monodromy holds the contact, the
    differences start it slipping or (a full mass matrix) spread the velocity kick to the other dof by M^-1.
    """
    A, _ = _constraints(_setup(system_or_assembly).flow, orbit.motion.modes[:, 0], None)
    return float(np.max(np.abs((np.asarray(fd) - orbit.monodromy) @ _basis(A))))


def fd_structure_monodromy(system_or_assembly: Any, state: Any, period: float, eps: float | None = None) -> np.ndarray:
    """The monodromy by central differences of the time-``period`` map, each end from a run of the exact engine.

    Independent of the phase matrices and the saltation: a check on them (its columns for velocity
    perturbations across a stuck contact's constraint start that contact slipping, so they differ there).

    Parameters
    ----------
    system_or_assembly:
        The structure.
    state:
        (2n,) the state at the start of the period.
    period:
        The time the map integrates over.
    eps:
        The difference step (default 1e-6 of each component's scale, ``orbit_scales``).
    """
    flow = _setup(system_or_assembly).flow
    y = np.asarray(state, dtype=float)
    steps = 1e-6 * orbit_scales(flow, y) if eps is None else np.full(len(y), float(eps))
    cols = []
    for h, e in zip(steps, np.eye(len(y))):
        ends = [flow.run(y + sign * h * e, float(period)).state[:, -1] for sign in (1.0, -1.0)]
        cols.append((ends[0] - ends[1]) / (2.0 * h))
    return np.column_stack(cols)
