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
from dataclasses import asdict, dataclass, field, fields
from typing import Any, ClassVar, Mapping

import numpy as np

from . import _validate as check
from .parameters import MODEL_MAX, Param, declare, dimensional_parameters, nonnegative_real, positive_real, resolve

ZETA = nonnegative_real("zeta", "zeta", "damping ratio", "oscillator", 0.0, upper=MODEL_MAX, sweepable=True)
VB = Param("vb", "V_b", "belt speed", "oscillator", 0.01, lower=-MODEL_MAX, upper=MODEL_MAX, sweepable=True,
           dimension="velocity", dimensional_name="v_b")
FEX = nonnegative_real("fex", "F_ex", "amplitude of the external force F_ex cos(Omega tau + phi)", "oscillator", 0.0,
                       upper=MODEL_MAX, sweepable=True, dimension="force", dimensional_name="f_ex")
OMEGA = positive_real("omega", "Omega", "angular frequency of the external force", "oscillator", 1.0, upper=MODEL_MAX,
                      sweepable=True, dimension="frequency", dimensional_name="w_ex")
PHI = Param("phi", "phi", "phase of the external force (rad)", "oscillator", 0.0, lower=-MODEL_MAX, upper=MODEL_MAX,
            sweepable=True, dimension="angle", dimensional_name="phi_ex")
VB_AMPLITUDE = nonnegative_real("vb_amplitude", "A_b", "amplitude of the belt speed's variation A sin(Omega_b tau + phi_b)",
                                "oscillator", 0.0, upper=MODEL_MAX, sweepable=True, dimension="velocity",
                                dimensional_name="v_b_amp")
VB_OMEGA = positive_real("vb_omega", "Omega_b", "angular frequency of the belt speed's variation", "oscillator", 1.0,
                         upper=MODEL_MAX, sweepable=True, dimension="frequency", dimensional_name="w_b")
VB_PHI = Param("vb_phi", "phi_b", "phase of the belt speed's variation (rad)", "oscillator", 0.0, lower=-MODEL_MAX,
               upper=MODEL_MAX, sweepable=True, dimension="angle", dimensional_name="phi_b")


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
        """Whether the flow depends on time (an external force or a moving belt)."""
        return self.forced or self.belt_varies

    @property
    def drive_period(self) -> float:
        """The stroboscopic section's spacing the solvers sample, 2 pi / Omega with an external force, else
        2 pi / Omega_b (a moving belt alone)."""
        if self.forced or not self.belt_varies:
            return self.forcing_period
        return 2.0 * math.pi / self.vb_omega

    def section_problem(self) -> str | None:
        """The one line refusing a stroboscopic classification without a common period (an external force and a
        moving belt at different frequencies); None when there is one."""
        if self.forced and self.belt_varies and self.omega != self.vb_omega:
            return (f"vb_omega={self.vb_omega:g} differs from omega={self.omega:g}: the external force and the moving "
                    "belt have no common period (the stroboscopic section's and the Lyapunov blocks'); "
                    "set vb_omega equal to omega")
        return None

    def refuse_moving_belt(self, what: str) -> None:
        """Raise the one line refusing a moving belt to ``what``, a path that runs a belt at constant speed only."""
        if self.belt_varies:
            raise ValueError(f"vb_amplitude must be 0 for {what} (a belt at constant speed), got {self.vb_amplitude:g}; "
                             "simulate a moving belt with solver=auto")

    def refuse_forcing(self, what: str) -> None:
        """Raise the one line refusing an external force to ``what``, a path of the autonomous system (its section
        X' = 0 and its equilibria are not the forced system's)."""
        if self.forced:
            raise ValueError(f"fex must be 0 for {what} (the autonomous system), got {self.fex:g}; a forced system's "
                             "orbits: forced-orbit and forced-continue (find_forced_orbit, continue_forced)")

    def belt_accel(self, t: Any) -> Any:
        """V_b'(tau) = A Omega_b cos(Omega_b tau + phi_b), on scalars or arrays."""
        return self.vb_amplitude * self.vb_omega * np.cos(self.vb_omega * np.asarray(t) + self.vb_phi)

    def external_force(self, t: Any) -> Any:
        """f(tau) = F_ex cos(Omega tau + phi), on scalars or arrays."""
        return self.fex * np.cos(self.omega * np.asarray(t) + self.phi)


declare(BeltOscillator.parameters)


def unit_of(dimension: str, m: float, k: float, l_0: float) -> float:
    """One non-dimensional unit of a quantity of ``dimension`` (:data:`~frictionflow.parameters.DIMENSIONS`) in
    the units of m, k and l_0: length l_0, force k l_0, time 1 / omega0 (omega0 = sqrt(k / m)), so velocity
    omega0 l_0, stiffness k, damping (force per velocity) k / omega0, frequency omega0."""
    w0 = math.sqrt(k / m)
    units = {"none": 1.0, "angle": 1.0, "force": k * l_0, "length": l_0, "velocity": w0 * l_0, "stiffness": k,
             "damping": k / w0, "frequency": w0}
    return units[dimension]


#: the scales of a ``dimensional`` table (no parameter's value: they set the units)
SCALE_KEYS = ("m", "c", "k", "l_0")


@dataclass(frozen=True)
class DimensionalParams:
    """Dimensional parameters (SI or any consistent units).

    :meth:`nondimensional` converts them by the paper's Eq. 3 (omega0 =
    sqrt(k/m), zeta = c / (2 m omega0), X = x / l_0, F = f / (k l_0),
    V = v / (omega0 l_0)), each parameter by the dimension it declares
    (:attr:`~frictionflow.parameters.Param.dimension`, units in :meth:`unit`).

    Parameters
    ----------
    m, c, k:
        Mass, viscous damping coefficient and spring stiffness (m x'' + c x' + k x = f).
    v_b:
        Belt speed.
    f_d:
        Kinetic (dynamic) friction force (None: the law has none, or it keeps its default).
    f_ms:
        Maximum static friction force (default: the law's own, ``f_d`` for Coulomb and Karnopp, the paper's
        choice; ``2 f_d`` for Stribeck).
    v_d:
        Karnopp's dead-zone half width (default: the paper's V_d = 1e-3 in
        non-dimensional units).
    l_0:
        The length scale of X = x / l_0.
    f_ex, w_ex, phi_ex:
        Amplitude, angular frequency (rad per unit time; default omega0) and
        phase of the external force f_ex cos(w_ex t + phi_ex).
    v_b_amp, w_b, phi_b:
        The belt speed's variation v_b_amp sin(w_b t + phi_b): amplitude (a velocity, default 0), angular
        frequency (default omega0) and phase.
    law:
        Any other parameter with a dimension, by its key (``sigma0``, ``sigma1``, ``dc``, ``normal``, ...;
        ``frictionflow.parameters.dimensional_parameters``).
    """

    m: float
    c: float
    k: float
    v_b: float
    f_d: float | None = None
    f_ms: float | None = None
    v_d: float | None = None
    l_0: float = 1.0
    f_ex: float = 0.0
    w_ex: float | None = None
    phi_ex: float = 0.0
    v_b_amp: float = 0.0
    w_b: float | None = None
    phi_b: float = 0.0
    law: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name, rule in (("m", check.positive), ("c", check.nonnegative), ("k", check.positive),
                           ("v_b", check.finite), ("l_0", check.positive), ("f_ex", check.nonnegative),
                           ("phi_ex", check.finite), ("v_b_amp", check.nonnegative), ("phi_b", check.finite)):
            object.__setattr__(self, name, rule(name, getattr(self, name)))
        if self.f_d is not None:
            object.__setattr__(self, "f_d", check.nonnegative("f_d", self.f_d))
            if self.f_ms is not None:  # unset: the law's own default (F_d for Coulomb and Karnopp, 2 F_d for Stribeck)
                object.__setattr__(self, "f_ms", check.at_least("f_ms", self.f_ms, self.f_d, "f_d"))
        elif self.f_ms is not None:
            raise ValueError(f"f_ms needs f_d (f_ms >= f_d), got f_ms={self.f_ms!r} alone")
        object.__setattr__(self, "v_d", check.positive("v_d", 1e-3 * self.omega0 * self.l_0 if self.v_d is None
                                                       else self.v_d))
        for name in ("w_ex", "w_b"):  # the frequencies default to the natural one
            object.__setattr__(self, name, check.positive(name, self.omega0 if getattr(self, name) is None
                                                          else getattr(self, name)))
        object.__setattr__(self, "law", self._law_values(self.law))

    @staticmethod
    def _law_values(law: Mapping[str, Any]) -> dict[str, float]:
        known = dimensional_parameters()
        own = {f.name for f in fields(DimensionalParams)}
        for key in law:
            if key not in known or key in own:
                allowed = ", ".join(k for k in known if k not in own)
                raise ValueError(f"dimensional: unknown law key {key!r}; allowed: {allowed}")
        return {key: check.finite(key, value) for key, value in law.items()}

    @classmethod
    def from_table(cls, table: Mapping[str, Any]) -> "DimensionalParams":
        """From one flat table (a config's ``dimensional``): the fields by name, every other key a law's."""
        own = {f.name for f in fields(cls)} - {"law"}
        return cls(**{k: v for k, v in table.items() if k in own}, law={k: v for k, v in table.items() if k not in own})

    @property
    def omega0(self) -> float:
        """Undamped natural frequency sqrt(k/m)."""
        return math.sqrt(self.k / self.m)

    def unit(self, dimension: str) -> float:
        """What one non-dimensional unit of a quantity of ``dimension`` is in these units (``unit_of``)."""
        return unit_of(dimension, self.m, self.k, self.l_0)

    def nondimensional(self) -> dict[str, float]:
        """zeta, every parameter given (V_b, F_d, F_s, V_d, the forcing F_ex, Omega, phi, the belt's variation,
        the law's), each divided by the unit of its dimension, and omega0 for the time scale tau = omega0 t."""
        known = dimensional_parameters()
        given = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in (*SCALE_KEYS, "law")}
        out = {"zeta": self.c / (2.0 * self.m * self.omega0)}
        for key, value in {**given, **self.law}.items():
            if value is not None:
                p = known[key]
                out[p.name] = float(value) / self.unit(p.dimension)
        return out | {"omega0": self.omega0}

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
