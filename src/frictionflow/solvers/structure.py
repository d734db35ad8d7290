"""The solvers of linear structures with friction contacts: :func:`run_assembly`, :func:`simulate_system`.

The exact engine runs the laws that are piecewise constant with the switch
stick rule (their slip force is a constant times the normal load, stuck is a
constraint); the adaptive one (:mod:`.structure_adaptive`) every switch-rule
law with a compiled slip curve.  Which solver runs structures, and with which
laws, each solver class declares (``structure_laws``); nothing here names a law.
"""

from __future__ import annotations

import math
import warnings
from typing import Any, Mapping

import numpy as np

from .. import _validate as check
from ..core import codes
from ..core.assembly import Assembly, natural_frequencies
from ..core.layout import LAW
from ..core.structure.run import run
from ..estimate import SECONDS_PER, Estimate
from ..friction.registry import law_classes
from ..motion import Motion
from ..system import System, assemble
from ..system.assemble import free_directions
from ..system.checks import independent
from . import structure_adaptive
from .base import DEFAULT_MAX_MEMORY
from .registry import solver_named, solver_names_where
from .structure_motion import buffers, first_capacity, memory_room, motion, row_bytes, run_growing, stopped

#: the solver's name in messages
NAME = "exact"
#: how each structure solver integrates (the CLI summary's heading)
HOW = {NAME: "located switches, closed-form phases", "adaptive": "located switches, Dormand-Prince 5(4) phases"}
#: the smallest first buffer size (samples and switches); :func:`.structure_motion.regrow` sizes a rerun
FIRST_CAP = 1024


def supported_laws(solver: str = NAME) -> dict[int, str]:
    """Law code -> name of the laws ``solver`` runs at a structure's contacts (its ``structure_laws``)."""
    test = _structure_solver(solver).structure_laws
    return {cls.code: cls.name for cls in law_classes() if cls.configurable and test(cls)}


def structure_solvers() -> tuple[str, ...]:
    """The names of the solvers that run structures."""
    return solver_names_where(lambda cls: cls.structure_laws is not None)


#: the solver name that picks one (:func:`structure_solver_for`)
AUTO = "auto"


def structure_solver_for(system: Any, solver: str = AUTO) -> str:
    """``solver``, or for ``"auto"`` the first structure solver (registry order) that runs every contact's law
    (and, where the structure has an undamped free motion, runs those: ``structure_free_motion``).

    Parameters
    ----------
    system:
        The structure (:class:`frictionflow.system.System`).
    solver:
        A name of :func:`structure_solvers` or ``"auto"``.
    """
    if solver != AUTO:
        _structure_solver(solver)
        return solver
    laws = [type(c.law) for c in system.contacts]
    free = free_directions(assemble(system), undamped=True).shape[1] > 0
    for name in structure_solvers():
        cls = solver_named(name)
        if all(cls.structure_laws(law) for law in laws) and (cls.structure_free_motion or not free):
            return name
    return NAME  # none runs them all: the exact solver's message names the contact


def solver_settings(solver: str, values: Mapping[str, Any]) -> dict[str, Any]:
    """The settings of structure solver ``solver`` given in ``values`` (its declared parameters, not None),
    each checked in its declared range (a one-line ValueError naming the parameter as given), by its
    keywords; ``dense_dt`` stays the run's."""
    cls = _structure_solver(solver)
    return {cls.keywords.get(p.name, p.name): p.check(values[p.name]) for p in cls.parameters
            if values.get(p.name) is not None and p.name != "dense_dt"}


def structure_parameters(solver: str | None = None) -> tuple[str, ...]:
    """The names of the declared parameters of structure solver ``solver`` (None: of every one)."""
    names = structure_solvers() if solver is None else (solver,)
    return tuple(dict.fromkeys(p.name for name in names for p in _structure_solver(name).parameters))


def _structure_solver(solver: Any) -> Any:
    cls = solver_named(solver)
    if cls is None or cls.structure_laws is None:
        raise ValueError(f"solver must be one of {', '.join(structure_solvers())} for a structure, got {solver!r}")
    return cls


def solvers_running(law: type) -> tuple[str, ...]:
    """The structure solvers that run the law class ``law`` at a structure's contacts (their ``structure_laws``)."""
    return solver_names_where(lambda cls: cls.structure_laws is not None and bool(cls.structure_laws(law)))


def _law_message(solver: str, contact: str, law: str) -> str:
    """One line: ``solver`` does not run ``law`` at ``contact``; the structure solvers that would."""
    runs = tuple(dict.fromkeys(name for c in law_classes() if c.name == law for name in solvers_running(c)))
    use = f"; use solver={' or '.join(runs)}" if runs else ""
    return (f"solver={solver} runs structures whose contacts' laws are {', '.join(supported_laws(solver).values())}; "
            f"{contact} has friction={law}{use}")


def _names(assembly: Assembly, names: Mapping[str, Any] | None) -> dict[str, tuple[str, ...]]:
    """The dof and element names (given, or ``q0``... and ``kind.i``)."""
    names = dict(names or {})
    counts = {"spring": len(assembly.spring_k), "damper": len(assembly.damper_c), "force": len(assembly.force_amp),
              "contact": len(assembly.belt)}
    out = {"dof": tuple(names.get("dof", (f"q{i}" for i in range(len(assembly.q0)))))}
    for kind, count in counts.items():
        out[kind] = tuple(names.get(kind, (f"{kind}.{i}" for i in range(count))))
    return out


def _check(assembly: Assembly, t_end: float, dense_dt: float | None, contacts: tuple[str, ...], solver: str) -> None:
    """One-line errors for a run that cannot be made."""
    if not isinstance(assembly, Assembly):
        raise TypeError(f"assembly must be a frictionflow.core.assembly.Assembly, got {type(assembly).__name__}")
    if not (isinstance(t_end, (int, float)) and math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"t_end must be a finite number > 0, got {t_end!r}")
    if dense_dt is not None and not (math.isfinite(dense_dt) and dense_dt > 0):
        raise ValueError(f"dense_dt must be a finite number > 0 (or None), got {dense_dt!r}")
    laws = supported_laws(solver)
    for j, code in enumerate(assembly.law[:, LAW].astype(int)):
        if code not in laws:
            known = {cls.code: cls.name for cls in law_classes() if cls.configurable}
            raise ValueError(_law_message(solver, contacts[j], known.get(code, f"(law code {code})")))
    check_switchable(assembly, contacts)


def check_switchable(assembly: Assembly, contacts: tuple[str, ...]) -> None:
    """Refuse contacts along dependent directions, naming them: the switching engines hold stuck contacts as
    constraints, and along dependent directions their forces are indeterminate (the model itself is fine: steady
    sliding and its eigenvalues need no stick)."""
    if not contacts:  # a linear structure: nothing to switch
        return
    rows = np.asarray(assembly.contact_dir, dtype=float).reshape(len(contacts), -1)
    independent(list(zip(contacts, rows)), "the switching engines cannot hold contacts along dependent directions")


def _channels(names: dict[str, tuple[str, ...]]) -> tuple[str, ...]:
    return (*names["spring"], *names["damper"], *names["force"],
            *(f"{c}.belt" for c in names["contact"]), *(f"{c}.heat" for c in names["contact"]))


def run_assembly(assembly: Assembly, t_end: float, *, dense_dt: float | None = None,
                 names: Mapping[str, Any] | None = None, system: Any = None, solver: str = NAME,
                 settings: Mapping[str, Any] | None = None, max_memory: float = DEFAULT_MAX_MEMORY) -> Motion:
    """Run the structure ``assembly`` from t = 0 to ``t_end`` with the exact event-driven engine (or ``solver``).

    Parameters
    ----------
    assembly:
        The structure (:class:`~frictionflow.core.assembly.Assembly`).
    t_end:
        The end time, > 0.
    dense_dt:
        Also sample every ``dense_dt`` (None: the start, the switches and the end only).
    names:
        Optional names: ``dof`` and per kind (``spring``, ``damper``, ``contact``, ``force``) the element
        names; default ``q0``, ... and ``spring.0``, ....
    system:
        The model object the assembly came from, kept on the result.
    solver:
        A solver that runs structures (:func:`structure_solvers`): ``"exact"`` (Coulomb's law) or
        ``"adaptive"`` (every switch-rule law with a compiled slip curve).
    settings:
        The solver's own settings by keyword (the adaptive one's ``rtol``, ``atol``, ``max_steps``).
    max_memory:
        GiB the run's records may take: a run sampled too densely is refused before it starts, one whose
        switches outgrow it when its records would (as the single mass's ``max_memory``).
    """
    nm = _names(assembly, names)
    cls = _structure_solver(solver)
    _check(assembly, t_end, dense_dt, nm["contact"], solver)
    check.positive("max_memory", check.number("max_memory", max_memory))
    if solver != NAME:
        # the solver's own checks are the single mass's (nondimensional time); a structure's sampling step is
        # checked above in its own units and handed over apart
        settings = cls(**(settings or {}))
        return structure_adaptive.run(assembly, (t_end, dense_dt), settings, nm, _channels(nm), system, max_memory)
    if settings:
        raise ValueError(f"solver={NAME} takes no settings, got {', '.join(sorted(settings))}")
    room = memory_room(assembly, (float(t_end), dense_dt), max_memory)
    minv = np.linalg.inv(assembly.mass)

    def attempt(cap: int) -> tuple:
        records = buffers(assembly, cap)
        return run(assembly, minv, float(t_end), float(dense_dt or 0.0), *records), *records

    omega = fastest_bound(assembly, minv)
    first = first_capacity(assembly, samples_bound(assembly, t_end, dense_dt, omega), FIRST_CAP)
    seconds = switch_bound(assembly, t_end, omega) * SECONDS_PER["structure_switch"]
    try:
        res, *records = run_growing(float(t_end), first, attempt, seconds, room)
    except ValueError as e:
        raise in_model_terms(e, assembly, nm) from None
    if res.status not in (codes.OK, codes.CONTACT_LOST):
        raise RuntimeError(stopped(res, records, nm, NAME, assembly))
    return motion(res, records, assembly, nm, _channels(nm), system)


#: how the engine (``core.structure.combo.decompose``) refuses a mode combination whose eigenvectors double
#: precision cannot resolve
DEFECTIVE = "structure: a mode combination's matrix is defective"
#: ... and one with a (nearly) defective double root, resolved only to ~1e-8
REPEATED = "structure: a mode combination has a repeated root"
#: the rates of a structure whose defective combination is blamed on its stiffest element span at least this
#: much; closer rates mean a double root (equal modes coupled through a normal load)
RATES_SPREAD = 1e4


def in_model_terms(error: ValueError, assembly: Assembly, nm: dict[str, tuple[str, ...]]) -> ValueError:
    """The engine's refusal of an unresolvable mode combination, said in the model's terms where it can be.

    With no direction free of every spring and damper (an undamped rigid mode: the engine's own message), the
    cause is the structure's rates spanning too far: an element far stiffer than the masses (a damper of 2e10
    on unit masses: rates 5e-11 to 2e10).  The line names the fastest element (its rate alone:
    c e.M^-1.e for a damper, sqrt(k e.M^-1.e) for a spring) and, where K is invertible, the slowest rate (the
    largest root of the reversed problem mu^2 K + mu C + M: the forward one gets the smallest only to rounding
    of the largest)."""
    if str(error).startswith(REPEATED):
        return ValueError(repeated_message())
    if not str(error).startswith(DEFECTIVE):
        return error
    free = free_directions(assembly, undamped=True)
    if free.shape[1]:
        return ValueError(_free_motion_message(free, nm["dof"]))
    k, c = np.asarray(assembly.stiffness, dtype=float), np.asarray(assembly.damping, dtype=float)
    n = len(k)
    minv = np.linalg.inv(assembly.mass)
    on = [float(e @ minv @ e) for e in np.asarray(assembly.damper_dir, dtype=float).reshape(-1, n)]
    rates = [(nm["damper"][i], cv * on[i]) for i, cv in enumerate(np.asarray(assembly.damper_c, dtype=float))]
    on = [float(e @ minv @ e) for e in np.asarray(assembly.spring_dir, dtype=float).reshape(-1, n)]
    rates += [(nm["spring"][i], math.sqrt(kv * on[i])) for i, kv in enumerate(np.asarray(assembly.spring_k, dtype=float))]
    if not rates:  # nothing stiff to name
        return error
    name, fastest = max(rates, key=lambda r: r[1])
    slowest = ""
    if np.linalg.matrix_rank(k) == n:
        kinv = np.linalg.inv(k)
        reversed_ = np.block([[np.zeros((n, n)), np.eye(n)], [-kinv @ assembly.mass, -kinv @ c]])
        rate = 1.0 / float(np.abs(np.linalg.eigvals(reversed_)).max())
        if fastest < RATES_SPREAD * rate:  # nothing stiff: a double root without a basis of modes
            return ValueError(repeated_message())
        slowest = f" beside its slowest rate {rate:.3g}"
    return ValueError(f"structure: {name}'s rate {fastest:.3g} (alone){slowest} spans more than one "
                      "double-precision mode basis resolves; soften it, or leave out the motion it holds")


def repeated_message() -> str:
    """One line: the exact engine does not resolve a combination with a (nearly) defective double root; the
    solvers that integrate the motion instead of summing its modes."""
    runs = free_motion_solvers()
    return (f"{REPEATED_SAID} (a critically damped mode, or equal modes coupled through a normal load), whose modes "
            "double precision resolves only to ~1e-8" + (f"; use solver={' or '.join(runs)}" if runs else ""))


#: how :func:`repeated_message` begins
REPEATED_SAID = f"solver={NAME}: a combination of contact modes has a repeated root"


def is_repeated_root(error: Exception) -> bool:
    """Whether ``error`` is the exact engine's refusal of a repeated root (:func:`repeated_message`)."""
    return str(error).startswith(REPEATED_SAID)


def free_direction_text(free: np.ndarray, dof: tuple[str, ...]) -> str:
    """``free``'s first column (a direction over ``dof``) as text, its largest coefficient 1: ``x1 + x2``."""
    d = free[:, 0] / free[np.argmax(np.abs(free[:, 0])), 0]
    terms = [(f"{abs(x):.3g} " if not math.isclose(abs(x), 1.0) else "") + name
             for x, name in zip(d, dof) if abs(x) > 1e-9]
    signs = ["-" if x < 0 else "+" for x in d if abs(x) > 1e-9]
    return ("-" if signs[0] == "-" else "") + terms[0] + "".join(f" {sign} {term}"
                                                                for sign, term in zip(signs[1:], terms[1:]))


def free_motion_solvers() -> tuple[str, ...]:
    """The structure solvers that run an undamped free motion (``structure_free_motion``)."""
    return solver_names_where(lambda cls: cls.structure_laws is not None and cls.structure_free_motion)


def is_free_motion(error: Exception) -> bool:
    """Whether ``error`` is the exact engine's refusal of an undamped free motion (raw, or said by
    :func:`in_model_terms`)."""
    return str(error).startswith(DEFECTIVE) or FREE_MOTION in str(error)


#: what the refusal of an undamped free motion says
FREE_MOTION = "an undamped free motion"


def _free_motion_message(free: np.ndarray, dof: tuple[str, ...]) -> str:
    """One line: the exact engine does not run the undamped free motion along ``free``'s first column (named
    over ``dof``); the structure solvers that do."""
    runs = free_motion_solvers()
    return (f"solver={NAME} runs structures whose every motion a spring, damper or normal load holds; along "
            f"{free_direction_text(free, dof)} none does ({FREE_MOTION}: polynomial in time, not a sum "
            "of its modes)" + (f"; use solver={' or '.join(runs)}" if runs else ""))


#: switches per natural period per contact assumed by :func:`run_estimate`: a stick-slip cycle has two,
#: chattering near a grazing a few more (a bound for the estimate, not a count: the motion decides)
SWITCHES_PER_PERIOD = 4.0


def switch_bound(assembly: Assembly, t_end: float, omega: float) -> float:
    """:data:`SWITCHES_PER_PERIOD` switches per contact per period of ``omega`` (the fastest mode's) up to ``t_end``."""
    return SWITCHES_PER_PERIOD * max(len(assembly.belt), 1) * (t_end * max(omega, 1e-6) / (2.0 * math.pi) + 1.0)


def samples_bound(assembly: Assembly, t_end: float, dense_dt: float | None, omega: float) -> float:
    """The samples a run writes by :func:`switch_bound`, with its dense grid's."""
    return switch_bound(assembly, t_end, omega) + (0.0 if not dense_dt else t_end / dense_dt)


def fastest_bound(assembly: Assembly, minv: np.ndarray) -> float:
    """sqrt(||M^-1 K||_inf) >= the fastest undamped natural frequency, without an eigenvalue solve (the first
    records' size takes it: an eigenvalue solve costs a 100-mass chain's short run several per cent)."""
    return math.sqrt(float(np.abs(minv @ assembly.stiffness).sum(axis=1).max(initial=0.0)))


#: samples per period of the fastest mode when a file wants the curve (:func:`file_dense_dt`)
FILE_SAMPLES_PER_PERIOD = 200


def file_dense_dt(assembly: Assembly) -> float:
    """The dense grid's step when a run is written to a file and none was asked for: 200 samples per period of
    the fastest mode (bounded by :func:`fastest_bound`; 2 pi / 200 without springs), as the single mass's 2 pi / 200."""
    omega = fastest_bound(assembly, np.linalg.inv(assembly.mass))
    return 2.0 * math.pi / (FILE_SAMPLES_PER_PERIOD * (omega if omega > 0.0 else 1.0))


def run_estimate(assembly: Assembly, t_end: float, dense_dt: float | None = None, solver: str = NAME) -> Estimate:
    """What a run of ``assembly`` to ``t_end`` costs, before it starts: switches (steps), CPU seconds and memory.

    The switches are bounded by :data:`SWITCHES_PER_PERIOD` per contact and
    per period of the fastest undamped mode; each costs the engine's
    declared seconds (:data:`frictionflow.estimate.SECONDS_PER`).  The
    adaptive solver's steps: :func:`.structure_adaptive.step_estimate`.
    """
    if solver != NAME:
        return structure_adaptive.step_estimate(assembly, t_end, dense_dt)
    n = assembly.mass.shape[0]
    omega = float(natural_frequencies(assembly).max(initial=0.0))
    switches, samples = switch_bound(assembly, t_end, omega), samples_bound(assembly, t_end, dense_dt, omega)
    each = SECONDS_PER["structure_switch"] + SECONDS_PER["structure_switch_cube"] * float(n) ** 3
    return Estimate(switches, f"switches of a {n}-dof structure", switches * each, memory=samples * row_bytes(assembly))


def simulate_system(system: Any, t_end: float, *, dense_dt: float | None = None, solver: str = NAME,
                    max_memory: float = DEFAULT_MAX_MEMORY, **settings: Any) -> Motion:
    """Run the model ``system`` to ``t_end``: assemble it, then :func:`~frictionflow.solvers.structure.run_assembly`.

    Parameters
    ----------
    system:
        The structure (:class:`frictionflow.system.System`, from a model file or built in Python).
    t_end:
        The end of the run (> 0); the run starts at t = 0 from the system's initial state.
    dense_dt:
        Also sample every ``dense_dt`` (None: the switches and the ends only; between samples
        :meth:`~frictionflow.motion.Motion.at` evaluates the exact motion anyway).
    solver:
        ``"exact"`` (the default; Coulomb's law), ``"adaptive"`` for every switch-rule law with a
        compiled slip curve (Stribeck, cubic, Coulomb): see :func:`structure_solvers`; or ``"auto"``:
        :func:`structure_solver_for`'s choice, and when the exact engine meets a repeated root it does not
        resolve, the run made again with the first solver that integrates the motion (a warning says so).
    max_memory:
        GiB the run's records may take (4 by default): a run sampled too densely is refused before it starts.
    settings:
        The solver's settings, e.g. ``rtol=1e-10, atol=1e-13`` for the adaptive solver.
    """
    check.instance("system", system, System, "a frictionflow.system.System (load_system, System.from_dict)")
    if solver == AUTO:
        return _auto(system, t_end, dense_dt, max_memory, settings)
    test = _structure_solver(solver).structure_laws
    for contact, name in zip(system.contacts, system.contact_names):
        if not test(type(contact.law)):
            raise ValueError(_law_message(solver, name, contact.law.name))
    return run_assembly(assemble(system), t_end, dense_dt=dense_dt, names={"dof": system.dof}, system=system,
                        solver=solver, settings=settings, max_memory=max_memory)


def _auto(system: System, t_end: float, dense_dt: float | None, max_memory: float,
          settings: Mapping[str, Any]) -> Motion:
    """:func:`simulate_system` with ``solver="auto"``: on :func:`structure_solver_for`'s choice, and again on the
    first solver that integrates the motion where the exact engine met a repeated root (found only running: the
    combinations a run enters are not known before)."""
    solver = structure_solver_for(system)
    try:
        return simulate_system(system, t_end, dense_dt=dense_dt, solver=solver, max_memory=max_memory, **settings)
    except ValueError as e:
        if solver != NAME or not is_repeated_root(e):
            raise
        said = str(e).split("; use")[0].removeprefix(f"solver={NAME}: ")
    other = free_motion_solvers()[0]
    warnings.warn(f"solver=auto ran the model with solver={other} (with solver={NAME}, {said})")
    return simulate_system(system, t_end, dense_dt=dense_dt, solver=other, max_memory=max_memory)
