"""The steady-sliding equilibrium, its linear stability and its reported values.

Sliding at the belt speed, X' = 0 and X* = F(V_b), F the signed slip force.
Linearised about it, with F'(V_b) the slope of the slip law, perturbations
obey

    x'' + (2 zeta + F'(V_b)) x' + x = 0,   A = [[0, 1], [-1, -(2 zeta + F'(V_b))]]

so the equilibrium is stable when 2 zeta + F'(V_b) > 0 and loses stability
in a Hopf bifurcation where 2 zeta + F'(V_b) = 0 (a falling slip law,
F' < 0, feeds energy in: the negative-damping mechanism of friction-induced
vibration).  det A = 1 > 0: no eigenvalue crosses zero, so there is no fold
of equilibria either.

A law with internal states z (LuGre, ...) adds them to the state: the fixed
point is (X*, 0, z*) with z* where the states' rates vanish at V_r = V_b and
X* the law's force there, and its stability is that of the Jacobian of the
whole state, assembled from the law's exact derivatives (the stiff engine's,
:func:`frictionflow.core.stiff_flow.field_at`): stable when every
eigenvalue has a negative real part.  Stiff bristles (sigma0 |V_b| >> g)
give back the threshold 2 zeta + F'(V_b) = 0 of the static law.

This is the one definition: :func:`frictionflow.analyze`, the orbit
continuation (:mod:`frictionflow.orbits.equilibria`) and the batched sweep
kernels all use it, the values reported at the equilibrium through
:func:`frictionflow.core.sections.equilibrium_row`.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as check
from .. import quantities as Q
from ..core import sections as sec
from ..core import stiff_flow
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..solvers.base import kernel_params
from .power_flow import PowerFlow
from .transmissibility import amplitude_of


@dataclass(frozen=True)
class SlidingEquilibrium:
    """X* = F(V_b), its effective damping 2 zeta + F'(V_b) and what follows from it.

    Attributes
    ----------
    x:
        X* = F(V_b), the displacement at which the spring balances the slip
        force (NaN where the law holds the mass instead).
    damping:
        The effective damping 2 zeta + F'(V_b): > 0 stable, < 0 unstable
        (with internal states: of the steady-sliding force; the eigenvalues decide).
    eigenvalues:
        The eigenvalues of the slip vector field's Jacobian at X*: two, or
        with internal states one per state (X, X', z...).
    value:
        The parameter value it was computed at along a parameter
        (continuation), NaN otherwise.
    internal:
        The internal states z* at the equilibrium (empty for a static law).
    matrix:
        The whole state's Jacobian at (X*, 0, z*) for a law with internal
        states, else None (the 2 x 2 :attr:`jacobian` follows from ``damping``).
    """

    x: float
    damping: float
    eigenvalues: tuple[complex, ...]
    value: float = math.nan
    internal: tuple[float, ...] = ()
    matrix: np.ndarray | None = None

    @property
    def stability(self) -> str:
        growth = -self.damping if self.matrix is None else max(l.real for l in self.eigenvalues)
        if growth < 0:
            return "stable"
        if growth > 0:
            return "unstable"
        return "neutral"

    @property
    def decay_rate(self) -> float:
        """How fast perturbations decay, -max Re(lambda) (negative when they grow)."""
        return -max(l.real for l in self.eigenvalues)

    @property
    def jacobian(self) -> np.ndarray:
        """A, the slip vector field's Jacobian at X* (trace A = -damping; with internal states :attr:`matrix`)."""
        if self.matrix is not None:
            return self.matrix.copy()
        return np.array([[0.0, 1.0], [-1.0, -self.damping]])


def eigenvalues(damping: float) -> tuple[complex, complex]:
    """Roots of l^2 + c l + 1 = 0, c = ``damping`` (for |c| < 2 the one with Im > 0 first)."""
    root = cmath.sqrt(damping * damping / 4.0 - 1.0)
    return (-damping / 2.0 + root, -damping / 2.0 - root)


def sliding_equilibrium(model: BeltOscillator, friction: FrictionLaw, value: float = math.nan) -> SlidingEquilibrium:
    """The equilibrium of steady sliding at V_r = V_b and its linear stability.

    X* is NaN where the law holds the mass instead (inside Karnopp's band).

    Parameters
    ----------
    model:
        The oscillator (its zeta and V_b).
    friction:
        The friction law (its slip force and slope at V_b).
    value:
        A parameter value to record with the result (continuation); NaN
        by default.
    """
    check.instance("model", model, BeltOscillator, "a BeltOscillator")
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")

    c = 2.0 * model.zeta + friction.slip_slope(abs(model.vb))
    if friction.internal_names:
        return _with_internal_states(model, friction, c, value)
    return SlidingEquilibrium(x=friction.sliding_equilibrium(model.vb), damping=c, eigenvalues=eigenvalues(c), value=value)


def _with_internal_states(model: BeltOscillator, friction: FrictionLaw, damping: float,
                          value: float) -> SlidingEquilibrium:
    """The fixed point (X*, 0, z*) of a law with internal states and the eigenvalues of the whole state's
    Jacobian there (largest real part first)."""
    vb = float(model.vb)
    z = friction.steady_internal(vb)
    if not np.all(np.isfinite(z)):  # the states do not rest at V_b: no steady sliding
        nan = complex(math.nan, math.nan)
        return SlidingEquilibrium(x=math.nan, damping=damping, eigenvalues=(nan,) * (2 + len(z)), value=value,
                                  internal=tuple(float(v) for v in z))
    x = float(friction.force(vb, z))
    a = stiff_flow.field_at(kernel_params(model, friction), float(model.zeta), vb, 0.0, np.concatenate([[x, 0.0], z]))[1]
    lam = sorted((complex(l) for l in np.linalg.eigvals(a)), key=lambda l: (-l.real, -l.imag))
    return SlidingEquilibrium(x=x, damping=damping, eigenvalues=tuple(lam), value=value,
                              internal=tuple(float(v) for v in z), matrix=a)


def equilibrium_values(
    x: float, vb: float, fd: float, *, window: tuple[float, float], stick: float | None = 0.0, residual: float = 0.0
) -> tuple[PowerFlow, float, dict[str, float]]:
    """Power flow, TR_B and amplitudes of the equilibrium X* = ``x``, from the table's rules.

    ``stick`` (None: unknown) says whether the mass rests sliding or in a
    stick band; ``residual`` is the energy residual to report.
    """
    row = sec.equilibrium_row(float(x), float(vb), float(fd), math.nan if stick is None else float(stick), float(residual))
    return PowerFlow.from_row(window, row), float(row[Q.INDEX["TR_B"]]), amplitude_of(row)
