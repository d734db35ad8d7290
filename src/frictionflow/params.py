"""The mass-on-belt oscillator and its dimensional <-> non-dimensional conversion.

The model (paper Eq. 1-5) in non-dimensional form is::

    X'' + 2 zeta X' + X = F_c(V_r) + F_ex cos(Omega tau + phi),     V_r = V_b - X'

with time tau = omega0 t (paper Eq. 1's f_ex, harmonic; F_ex = 0 is the
paper's autonomous system).  The paper's Eq. 1 prints ``m x'' + 2c x' + k x``; its
Eq. 3-4 (zeta = c / (2 m omega0), ``X'' + 2 zeta X' + X``) only follow from the
standard form ``m x'' + c x' + k x = f_c``, which is the one used here.

The friction parameters (F_d, F_s, V_d, ...) belong to the friction law
(:mod:`frictionflow.friction`); :class:`BeltOscillator` holds the structure
(zeta), the belt (V_b) and the external force (F_ex, Omega, phi).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, ClassVar, Mapping

import numpy as np

from . import _validate as check
from .parameters import MODEL_MAX, Param, declare, nonnegative_real, positive_real, resolve

ZETA = nonnegative_real("zeta", "zeta", "damping ratio", "oscillator", 0.0, upper=MODEL_MAX, sweepable=True)
VB = Param("vb", "V_b", "belt speed", "oscillator", 0.01, lower=-MODEL_MAX, upper=MODEL_MAX, sweepable=True)
FEX = nonnegative_real("fex", "F_ex", "amplitude of the external force F_ex cos(Omega tau + phi)", "oscillator", 0.0,
                       upper=MODEL_MAX, sweepable=True)
OMEGA = positive_real("omega", "Omega", "angular frequency of the external force", "oscillator", 1.0, upper=MODEL_MAX,
                      sweepable=True)
PHI = Param("phi", "phi", "phase of the external force (rad)", "oscillator", 0.0, lower=-MODEL_MAX, upper=MODEL_MAX,
            sweepable=True)
VB_AMPLITUDE = nonnegative_real("vb_amplitude", "A_b", "amplitude of the belt speed's variation A sin(Omega_b tau + phi_b)",
                                "oscillator", 0.0, upper=MODEL_MAX, sweepable=True)
VB_OMEGA = positive_real("vb_omega", "Omega_b", "angular frequency of the belt speed's variation", "oscillator", 1.0,
                         upper=MODEL_MAX, sweepable=True)
VB_PHI = Param("vb_phi", "phi_b", "phase of the belt speed's variation (rad)", "oscillator", 0.0, lower=-MODEL_MAX,
               upper=MODEL_MAX, sweepable=True)


@dataclass(frozen=True)
class BeltOscillator:
    """Non-dimensional single-DOF oscillator on a belt.

    Parameters
    ----------
    zeta:
        Damping ratio c / (2 m omega0), >= 0 (0 is the paper's Case I).
    vb:
        Belt speed V_b = v_b / (omega0 l_0), any finite value.
    fex, omega, phi:
        The external force F_ex cos(Omega tau + phi): amplitude >= 0 (0, the
        default, is the paper's unforced system), angular frequency > 0 in
        units of the natural frequency, phase in radians.
    vb_amplitude, vb_omega, vb_phi:
        The belt speed's variation: V_b(tau) = V_b + A sin(Omega_b tau + phi_b),
        amplitude A >= 0 (0, the default: a belt at constant speed), angular
        frequency Omega_b > 0, phase phi_b in radians.
    """

    zeta: float = 0.0
    vb: float = 0.01
    fex: float = 0.0
    omega: float = 1.0
    phi: float = 0.0
    vb_amplitude: float = 0.0
    vb_omega: float = 1.0
    vb_phi: float = 0.0
    parameters: ClassVar[tuple[Param, ...]] = (ZETA, VB, FEX, OMEGA, PHI, VB_AMPLITUDE, VB_OMEGA, VB_PHI)

    def __post_init__(self) -> None:
        for key, value in resolve(self.parameters, asdict(self)).items():
            object.__setattr__(self, key, value)

    @classmethod
    def from_values(cls, values: Mapping[str, Any]) -> "BeltOscillator":
        """Build from a mapping of parameter values (missing or None: the defaults)."""
        return cls(**resolve(cls.parameters, values))

    def as_dict(self) -> dict[str, float]:
        return asdict(self)

    def report(self) -> dict[str, float]:
        """The parameters a run's report names: zeta and V_b, and the external force's when forced."""
        out = {"zeta": self.zeta, "vb": self.vb}
        if self.forced:
            out.update(fex=self.fex, omega=self.omega, phi=self.phi)
        if self.belt_varies:
            out.update(vb_amplitude=self.vb_amplitude, vb_omega=self.vb_omega, vb_phi=self.vb_phi)
        return out

    @property
    def forced(self) -> bool:
        """Whether an external force acts (F_ex > 0)."""
        return self.fex > 0.0

    @property
    def forcing_period(self) -> float:
        """2 pi / Omega (the stroboscopic section's spacing)."""
        return 2.0 * math.pi / self.omega

    @property
    def belt_varies(self) -> bool:
        """Whether the belt's speed varies in time (A > 0)."""
        return self.vb_amplitude > 0.0

    def belt_speed(self, t: Any) -> Any:
        """V_b(tau) = V_b + A sin(Omega_b tau + phi_b), on scalars or arrays."""
        return self.vb + self.vb_amplitude * np.sin(self.vb_omega * np.asarray(t) + self.vb_phi)

    @property
    def driven(self) -> bool:
        """Whether the flow depends on time: an external force or a moving belt."""
        return self.forced or self.belt_varies

    @property
    def drive_period(self) -> float:
        """The stroboscopic section's spacing the solvers sample: 2 pi / Omega with an external force, else
        2 pi / Omega_b (a moving belt alone)."""
        if self.forced or not self.belt_varies:
            return self.forcing_period
        return 2.0 * math.pi / self.vb_omega

    def section_problem(self) -> str | None:
        """The one line refusing a stroboscopic classification without a common period (an external force and a
        moving belt at different frequencies); None when there is one."""
        if self.forced and self.belt_varies and self.omega != self.vb_omega:
            return (f"vb_omega={self.vb_omega:g} differs from omega={self.omega:g}: the external force and the moving "
                    "belt have no common period to classify the run on; set vb_omega equal to omega")
        return None

    def refuse_moving_belt(self, what: str) -> None:
        """Raise the one line refusing a moving belt to ``what``, a path that runs a belt at constant speed only."""
        if self.belt_varies:
            raise ValueError(f"vb_amplitude must be 0 for {what} (a belt at constant speed), got {self.vb_amplitude:g}; "
                             "simulate a moving belt with solver=adaptive or rk4")

    def belt_accel(self, t: Any) -> Any:
        """V_b'(tau) = A Omega_b cos(Omega_b tau + phi_b), on scalars or arrays."""
        return self.vb_amplitude * self.vb_omega * np.cos(self.vb_omega * np.asarray(t) + self.vb_phi)

    def external_force(self, t: Any) -> Any:
        """f(tau) = F_ex cos(Omega tau + phi), on scalars or arrays."""
        return self.fex * np.cos(self.omega * np.asarray(t) + self.phi)


declare(BeltOscillator.parameters)


@dataclass(frozen=True)
class DimensionalParams:
    """Dimensional parameters (SI or any consistent units).

    :meth:`nondimensional` converts them by the paper's Eq. 3 (omega0 =
    sqrt(k/m), zeta = c / (2 m omega0), X = x / l_0, F = f / (k l_0),
    V = v / (omega0 l_0)).

    Parameters
    ----------
    m, c, k:
        Mass, viscous damping coefficient and spring stiffness (m x'' + c x' + k x = f).
    v_b:
        Belt speed.
    f_d:
        Kinetic (dynamic) friction force.
    f_ms:
        Maximum static friction force (default ``f_d``, the paper's choice).
    v_d:
        Karnopp's dead-zone half width (default: the paper's V_d = 1e-3 in
        non-dimensional units).
    l_0:
        The length scale of X = x / l_0.
    f_ex, w_ex, phi_ex:
        Amplitude, angular frequency (rad per unit time; default omega0) and
        phase of the external force f_ex cos(w_ex t + phi_ex).
    """


    m: float
    c: float
    k: float
    v_b: float
    f_d: float
    f_ms: float | None = None
    v_d: float | None = None
    l_0: float = 1.0
    f_ex: float = 0.0
    w_ex: float | None = None
    phi_ex: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "m", check.positive("m", self.m))
        object.__setattr__(self, "c", check.nonnegative("c", self.c))
        object.__setattr__(self, "k", check.positive("k", self.k))
        object.__setattr__(self, "v_b", check.finite("v_b", self.v_b))
        object.__setattr__(self, "f_d", check.nonnegative("f_d", self.f_d))
        object.__setattr__(self, "l_0", check.positive("l_0", self.l_0))
        if self.f_ms is None:
            object.__setattr__(self, "f_ms", self.f_d)
        object.__setattr__(self, "f_ms", check.at_least("f_ms", self.f_ms, self.f_d, "f_d"))
        if self.v_d is None:
            object.__setattr__(self, "v_d", 1e-3 * self.omega0 * self.l_0)
        object.__setattr__(self, "v_d", check.positive("v_d", self.v_d))
        object.__setattr__(self, "f_ex", check.nonnegative("f_ex", self.f_ex))
        if self.w_ex is None:
            object.__setattr__(self, "w_ex", self.omega0)
        object.__setattr__(self, "w_ex", check.positive("w_ex", self.w_ex))
        object.__setattr__(self, "phi_ex", check.finite("phi_ex", self.phi_ex))

    @property
    def omega0(self) -> float:
        """Undamped natural frequency sqrt(k/m)."""
        return math.sqrt(self.k / self.m)

    def nondimensional(self) -> dict[str, float]:
        """Eq. 3: zeta, V_b, F_d, F_s, V_d, the forcing F_ex, Omega, phi (and omega0 for the time scale tau = omega0 t)."""
        w0 = self.omega0
        force = self.k * self.l_0
        return {
            "zeta": self.c / (2.0 * self.m * w0),
            "vb": self.v_b / (w0 * self.l_0),
            "fd": self.f_d / force,
            "fs": float(self.f_ms) / force,
            "vd": float(self.v_d) / (w0 * self.l_0),
            "fex": self.f_ex / force,
            "omega": float(self.w_ex) / w0,
            "phi": self.phi_ex,
            "omega0": w0,
        }

    @classmethod
    def from_nondimensional(
        cls,
        *,
        zeta: float,
        vb: float,
        fd: float,
        fs: float | None = None,
        vd: float = 1e-3,
        m: float = 1.0,
        k: float = 1.0,
        l_0: float = 1.0,
    ) -> "DimensionalParams":
        """Inverse of :meth:`nondimensional` for a chosen mass, stiffness and length."""
        w0 = math.sqrt(check.positive("k", k) / check.positive("m", m))
        force = k * l_0
        return cls(
            m=m,
            c=2.0 * m * w0 * zeta,
            k=k,
            v_b=vb * w0 * l_0,
            f_d=fd * force,
            f_ms=(fd if fs is None else fs) * force,
            v_d=vd * w0 * l_0,
            l_0=l_0,
        )

    def as_dict(self) -> dict[str, float]:
        return asdict(self)
