"""What every friction law provides.

A law is a small immutable object that validates its parameters in
``__init__`` and can hand the compiled kernels a flat float array
(:meth:`FrictionLaw.kernel_params`, layout in
:mod:`frictionflow.core.friction`).  Kernels know nothing of these
classes.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any

import numpy as np

from .. import _validate as check
from ..core import friction as kf

STICK_FORCES = ("resultant", "spring")


class FrictionLaw(ABC):
    """Base class of friction laws F_c(X, X') acting on the mass.

    Attributes
    ----------
    fd:
        Kinetic (dynamic) friction level F_d >= 0.
    fs:
        Maximum static friction F_s >= F_d (defaults to F_d).
    stick_force:
        Which force the interface has to hold while sticking:
        ``"resultant"`` (X + 2 zeta X', the complete force; default) or
        ``"spring"`` (X only, the paper's F_e = X).
    """

    name: str = "abstract"
    code: int = -1
    #: True when the slip force is constant (the exact event-driven solver applies)
    piecewise_constant: bool = True

    def __init__(self, fd: float, fs: float | None, stick_force: str) -> None:
        self.fd = check.nonnegative("fd", fd)
        self.fs = self.fd if fs is None else check.at_least("fs", fs, self.fd, "fd")
        self.stick_force = check.choice("stick_force", stick_force, STICK_FORCES)

    # -- what the kernels see -------------------------------------------------
    @property
    def band(self) -> float:
        """Half-width of the velocity band that fixed-step RK4 treats as stick."""
        return self.vd  # type: ignore[attr-defined]

    def kernel_params(self) -> np.ndarray:
        """Flat float64 array in the layout of :mod:`~frictionflow.core.friction`."""
        p = np.zeros(kf.N_PARAMS)
        p[kf.LAW] = self.code
        p[kf.FD] = self.fd
        p[kf.FS] = self.fs
        p[kf.VD] = getattr(self, "band", 0.0)  # laws without a band (user laws) never reach RK4
        p[kf.RESULTANT] = 1.0 if self.stick_force == "resultant" else 0.0
        self._fill_kernel_params(p)
        return p

    def _fill_kernel_params(self, p: np.ndarray) -> None:
        """Laws with more parameters than F_d, F_s, V_d fill them in here."""

    # -- physics ---------------------------------------------------------------
    def slip_force(self, vr: Any) -> np.ndarray:
        """Friction force on the mass while slipping at relative velocity ``vr`` (signed)."""
        vr = np.asarray(vr, dtype=float)
        return np.sign(vr) * self.slip_magnitude(np.abs(vr))

    @abstractmethod
    def slip_magnitude(self, speed: Any) -> np.ndarray:
        """|F| while slipping at relative speed ``speed`` > 0."""

    def slip_slope(self, vr: float) -> float:
        """dF/dV_r of the slip law at ``vr`` > 0 (0 for constant laws)."""
        return 0.0

    def sliding_equilibrium(self, vb: float) -> float:
        """X* of steady sliding at belt speed ``vb`` (X* = F(V_b))."""
        return float(self.slip_force(vb))

    def stick_force_value(self, x: Any, v: Any, zeta: float) -> np.ndarray:
        """F_e, the force the interface must hold to keep the mass sticking."""
        x = np.asarray(x, dtype=float)
        if self.stick_force == "resultant":
            return x + 2.0 * zeta * np.asarray(v, dtype=float)
        return x

    def as_dict(self) -> dict[str, Any]:
        """Parameters for reports and JSON."""
        return {"friction": self.name, "fd": self.fd, "fs": self.fs, "stick_force": self.stick_force}

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items() if k != "friction")
        return f"{type(self).__name__}({args})"

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self.as_dict() == other.as_dict()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash(tuple(self.as_dict().items()))
