"""What each kernel's mode codes mean as public :class:`~frictionflow.modes.SwitchMode` values, and each exact mode's motion.

The compiled kernels record the mode entered at each switch in their own
codes (the exact kernel's SLIP_POS ... STICK = 1 ... 8, the adaptive
kernel's -1/0/+1).  The tables are stated here, in the rules layer, because
two layers above read them: the solvers, which translate a run's events
(:func:`frictionflow.solvers.events.switch_modes`), and the closed-form
interpolant (:mod:`frictionflow._continuous`), which evaluates the phase
that follows each event with the exact kernel's own motion
(:func:`exact_motion`).
"""

from __future__ import annotations

from collections.abc import Mapping

from ..modes import SwitchMode
from . import exact as ke
from . import layout as kl

#: the exact event-driven kernel (:mod:`frictionflow.core.exact`)
EXACT_EVENT_MODES: Mapping[int, SwitchMode] = {
    ke.SLIP_POS: SwitchMode.SLIP_POSITIVE,
    ke.SLIP_NEG: SwitchMode.SLIP_NEGATIVE,
    ke.STICK: SwitchMode.STICK,
    ke.HOLD: SwitchMode.BAND_HOLD,
    ke.SAT_POS: SwitchMode.BAND_SATURATED_POSITIVE,
    ke.SAT_NEG: SwitchMode.BAND_SATURATED_NEGATIVE,
    ke.EDGE_LO: SwitchMode.BAND_EDGE_LOWER,
    ke.EDGE_HI: SwitchMode.BAND_EDGE_UPPER,
}

#: the Dormand-Prince kernel (:mod:`frictionflow.core.dopri`): slip direction or stick
ADAPTIVE_EVENT_MODES: Mapping[int, SwitchMode] = {
    kl.SLIP_POS: SwitchMode.SLIP_POSITIVE,
    kl.SLIP_NEG: SwitchMode.SLIP_NEGATIVE,
    kl.STICK: SwitchMode.STICK,
}

#: SwitchMode -> the exact kernel's code
EXACT_CODES: Mapping[SwitchMode, int] = {mode: code for code, mode in EXACT_EVENT_MODES.items()}


def exact_motion(mode: SwitchMode, zeta: float, fd: float, fs: float, resultant: bool) -> tuple[int, float]:
    """(motion type, OSC centre F) of a phase in ``mode``, as the exact kernel integrates it.

    Parameters
    ----------
    mode : SwitchMode
        The phase's mode (one the exact kernel records).
    zeta, fd, fs : float
        Damping ratio, kinetic and static friction levels.
    resultant : bool
        The interface holds F_e = X + 2 zeta X' (else X, the spring alone).

    Returns
    -------
    tuple of (int, float)
        :data:`~frictionflow.core.closed_form.OSC`, ``LIN`` or ``EXP`` and
        the constant force an OSC phase oscillates about (0.0 otherwise):
        :func:`frictionflow.core.exact.dynamics` of the mode's kernel code,
        run as Python (a table read, nothing to compile).
    """
    dyn, force, _ = ke.dynamics.py_func(EXACT_CODES[mode], zeta, fd, fs, resultant)
    return dyn, force


def held_modes(stick_rule: str) -> tuple[SwitchMode, ...]:
    """The modes in which the exact kernel holds the mass (no slip) under ``stick_rule``, in SwitchMode order.

    Parameters
    ----------
    stick_rule : str
        The law's declared stick rule, ``"switch"`` (Coulomb's) or ``"band"`` (Karnopp's).

    Returns
    -------
    tuple of SwitchMode
        The modes :func:`~frictionflow.core.exact.select_mode` chooses from
        for the rule's closed-form law (:func:`~frictionflow.core.exact.mode_order`)
        less those that slip: STICK alone for the switch, the band's own for the band.
    """
    code = kl.KARNOPP if stick_rule == "band" else kl.COULOMB  # the closed forms' law of each rule
    order = ke.mode_order.py_func(code)
    return tuple(sorted(EXACT_EVENT_MODES[int(c)] for c in order if ke.FRICTION_MODE[int(c)] == 0))
