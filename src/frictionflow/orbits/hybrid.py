"""A stretch of motion as a hybrid system: smooth phases joined by switches.

The belt oscillator is smooth inside each friction mode (slip+, slip-,
stick, Karnopp's band modes) and switches between modes on surfaces
h(X, X') = 0.  The Jacobian of a flow map across a switch is not the product
of the phase Jacobians alone: a perturbed trajectory reaches the surface
earlier or later, and while the unperturbed one already follows the new
vector field the perturbed one still follows the old.  The *saltation
matrix* (Aizerman & Gantmacher 1958; Leine & Nijmeijer 2004, ch. 7)

    S = I + (f+ - f-) grad(h)^T / (grad(h) . f-)

accounts for that, so that the Jacobian of a flow map is

    Phi = Phi_n S_{n-1} Phi_{n-1} ... S_1 Phi_1 .

A switch into a mode that holds X' fixed (stick: X' = V_b; f+ has X'' = 0)
gives S = diag(1, 0): the stick phase forgets every perturbation of X'.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core import saltation as salt

#: the longest a flow runs unless told otherwise (its ``max_time``): every flow of shooting and continuation is
#: bounded by it
MAX_TIME = 1e4
#: friction modes a phase can be in, and whether the mass is held there
STICKING_MODES = ("stick", "band-sat+", "band-sat-", "edge-lo", "edge-hi")


@dataclass(frozen=True, eq=False)
class Phase:
    """One smooth piece of motion in one friction mode.

    Attributes
    ----------
    mode:
        The friction mode: ``slip+``, ``slip-`` (V_r = V_b - X' positive or
        negative), ``stick``, or one of Karnopp's band modes ``band-sat+``,
        ``band-sat-``, ``edge-lo``, ``edge-hi`` (``STICKING_MODES`` hold the mass).
    t0:
        When the phase starts, in dimensionless time tau from the start of
        its :class:`Segment`.
    duration:
        How long it lasts (tau).
    y0:
        The state (X, X') at its start, shape (2,).
    y1:
        The state (X, X') at its end, shape (2,).
    jacobian:
        d y1 / d y0 along this phase at fixed duration, 2 x 2 (no saltation:
        the switches' matrices are on the :class:`Switch` between phases).
    """

    mode: str
    t0: float
    duration: float
    y0: np.ndarray
    y1: np.ndarray
    jacobian: np.ndarray  # d y1 / d y0 along this phase (fixed duration)

    @property
    def sticking(self) -> bool:
        """The mass is held by the interface (V_r = 0 or inside Karnopp's band)."""
        return self.mode in STICKING_MODES


@dataclass(frozen=True, eq=False)
class Switch:
    """A mode change at state ``y`` and time ``t``, with its saltation matrix.

    Attributes
    ----------
    t:
        When it happens, in dimensionless time tau from the start of its
        :class:`Segment` (the end of the phase before it).
    y:
        The state (X, X') on the switching surface, shape (2,) (X' = V_b
        exactly on a switch into ``stick``).
    before:
        The friction mode before the switch (a :attr:`Phase.mode`).
    after:
        The friction mode after it.
    normal:
        A normal of the switching surface h(X, X') = 0 at ``y`` (grad h, up
        to its scale), shape (2,).
    f_before:
        The vector field (X', X'') of the mode before, at ``y``, shape (2,).
    f_after:
        The vector field (X', X'') of the mode after, at ``y``, shape (2,).
    saltation:
        The saltation matrix S = I + (f+ - f-) n^T / (n . f-), 2 x 2: how a
        perturbation just before the switch maps to one just after it.
    """

    t: float
    y: np.ndarray
    before: str
    after: str
    normal: np.ndarray  # grad h of the switching surface h(X, X') = 0
    f_before: np.ndarray
    f_after: np.ndarray
    saltation: np.ndarray

    @property
    def kind(self) -> str:
        """``stick onset``, ``slip onset``, ``slip reversal`` or ``band`` (inside Karnopp's band)."""
        held_before = self.before in STICKING_MODES
        held_after = self.after in STICKING_MODES
        if not held_before and held_after:
            return "stick onset"
        if held_before and not held_after:
            return "slip onset"
        if not held_before and not held_after:
            return "slip reversal"
        return "band"

    @property
    def transversality(self) -> float:
        """|grad h . f-| relative to |grad h| |f-|, near 0 when the switch is a grazing touch."""
        den = float(np.linalg.norm(self.normal) * np.linalg.norm(self.f_before))
        return abs(float(self.normal @ self.f_before)) / den if den > 0 else 0.0


def saltation(f_before: np.ndarray, f_after: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """S = I + (f+ - f-) n^T / (n . f-) for a transversal crossing of h = 0 with grad h = n (:mod:`..core.saltation`)."""
    S = salt.matrix(np.asarray(f_before, float), np.asarray(f_after, float), np.asarray(normal, float))
    if np.isnan(S).all():
        raise ZeroDivisionError("the trajectory touches the switching surface tangentially (grazing)")
    return S


@dataclass(eq=False)
class Segment:
    """Motion from ``y0`` to ``y1``: its phases and the switches between them.

    ``len(switches) == len(phases) - 1``; phase k ends where switch k happens.
    ``returns`` counts the crossings of the Poincare section X' = 0 (X'' < 0)
    on the way; a segment that stopped on the section ends exactly there.

    Attributes
    ----------
    y0:
        The start state (X, X'), shape (2,).
    y1:
        The end state (X, X'), shape (2,).
    duration:
        The time flowed from ``y0`` to ``y1`` (dimensionless tau).
    phases:
        The smooth phases, in order (:class:`Phase`).
    switches:
        The mode changes between consecutive phases, in order (:class:`Switch`).
    returns:
        The crossings of the section X' = 0 with X'' < 0 on the way.
    f_end:
        The vector field (X', X'') of the last phase's mode at ``y1``, shape
        (2,), for the projection onto the section (:meth:`section_jacobian`);
        None if not known.
    """

    y0: np.ndarray
    y1: np.ndarray
    duration: float
    phases: list[Phase] = field(default_factory=list)
    switches: list[Switch] = field(default_factory=list)
    returns: int = 0
    f_end: np.ndarray | None = None  # the vector field at y1 (for the section projection)

    def jacobian(self) -> np.ndarray:
        """d y1 / d y0 at fixed duration: phase Jacobians and saltation matrices in order."""
        if not self.phases:
            return np.eye(2)
        J = self.phases[0].jacobian
        for sw, ph in zip(self.switches, self.phases[1:], strict=True):
            J = ph.jacobian @ sw.saltation @ J
        return J

    def section_jacobian(self) -> np.ndarray:
        """d y1 / d y0 when the end time is the return to the section X' = 0.

        A perturbed start returns earlier or later; projecting along the flow
        onto the section (the saltation of a "switch" into the same field)
        gives (I - f e2^T / (e2 . f)) Phi.
        """
        J = self.jacobian()
        if self.f_end is None or self.f_end[1] == 0.0:
            return J
        e2 = np.array([0.0, 1.0])
        return (np.eye(2) - np.outer(self.f_end, e2) / self.f_end[1]) @ J

    @property
    def stick_time(self) -> float:
        """Time spent held by the interface."""
        return float(sum(p.duration for p in self.phases if p.sticking))

    @property
    def modes(self) -> tuple[str, ...]:
        """The sequence of friction modes, consecutive repeats merged."""
        out: list[str] = []
        for p in self.phases:
            if not out or out[-1] != p.mode:
                out.append(p.mode)
        return tuple(out)
