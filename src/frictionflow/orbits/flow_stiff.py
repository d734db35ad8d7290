"""The flow map of a law with internal state on its whole state, with the monodromy (:mod:`..core.stiff_flow`)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..core import stiff as kernel
from ..core import stiff_flow
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..solvers.base import kernel_params

#: steps one flow may take before it is given up
MAX_STEPS = 2_000_000
#: Phi's absolute tolerance: looser than the state's, since each crossing of V_r = 0 (in a LuGre stick phase the
#: bristles' ringing crosses it several times) ends a step whose Phi is first-order accurate
PHI_ATOL = 1e-8


class FlowEnd(NamedTuple):
    """Where a flow ends: the state, the Jacobian dy(t0 + T)/dy(t0) and the vector field there."""

    y: np.ndarray
    jacobian: np.ndarray
    field: np.ndarray


def check_stateful(model: BeltOscillator, law: FrictionLaw) -> None:
    """Refuse, with one line, a system the stiff flow map cannot run."""
    if not getattr(law, "internal_names", ()):
        raise ValueError(f"friction={law.name} has no internal state: its orbits are shot on the section map (find_orbit)")
    if model.belt_varies:
        raise ValueError("vb_amplitude must be 0 for orbits of friction with internal state (a varying belt is not run yet)")


class StiffFlow:
    """The flow of (model, law) on y = (X, X', z ...) by Rodas4 with its variational equations.

    ``rtol``, ``atol``: the relative tolerance and the absolute one on X and X' (the internal states'
    scaled by their sizes); ``phi_atol``: the absolute one on Phi's entries (scaled by the ratio of the sizes).
    """

    def __init__(self, model: BeltOscillator, law: FrictionLaw, rtol: float = 1e-10, atol: float = 1e-12,
                 max_step: float = 0.5, phi_atol: float = PHI_ATOL) -> None:
        check_stateful(model, law)
        self.model, self.law = model, law
        self.q = kernel_params(model, law)
        self.zeta, self.vb = float(model.zeta), float(model.vb)
        self.size = np.concatenate([[1.0, 1.0], law.internal_scale()])  # X, X' of order 1, z of its own scale
        self.tol = np.concatenate([atol * self.size, [rtol]])
        self.ptol = phi_atol * self.size[:, None] / self.size[None, :]
        self.steps = np.array([min(1e-5, max_step), max_step, float(MAX_STEPS)])

    @property
    def n(self) -> int:
        return 2 + len(self.law.internal_names)

    def field(self, y: np.ndarray, t: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """(y', J) at (t, y)."""
        return stiff_flow.field_at(self.q, self.zeta, self.vb, float(t), np.asarray(y, dtype=float))

    def run(self, y0: np.ndarray, duration: float, t0: float = 0.0) -> FlowEnd:
        """The state after ``duration`` from (t0, y0), its Jacobian and the field there; RuntimeError if it fails."""
        y0 = np.asarray(y0, dtype=float)
        if not (duration > 0.0 and np.isfinite(duration)):
            raise RuntimeError(f"a flow needs a positive finite duration, got {duration!r}")
        y, phi, status, _ = stiff_flow.flow_variational(self.q, self.zeta, self.vb, y0, float(t0), float(duration),
                                                        self.tol, self.ptol, self.size, self.steps)
        if status != kernel.DONE or not np.all(np.isfinite(phi)):
            why = "the step cap" if status == kernel.STEP_CAP else "a vanishing step"
            raise RuntimeError(f"the variational flow from X={y0[0]:.6g}, X'={y0[1]:.6g} stopped at {why}")
        return FlowEnd(y, phi, self.field(y, t0 + duration)[0])
