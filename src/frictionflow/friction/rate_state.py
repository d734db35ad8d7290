"""Rate-and-state friction (Dieterich 1979, Ruina 1983): the friction coefficient remembers the contact's age."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core import stiff
from ..parameters import MODEL_MAX, Param, nonnegative_real, positive_real
from .registry import register
from .stateful import StatefulLaw

STATE_LAWS = ("aging", "slip")
#: e^(mu0 / a) must stay a float: the contact's stiffness at rest is N a e^(mu0 / a) / (2 V_0)
EXP_MAX = 700.0

NORMAL = positive_real("normal", "N", "normal load (rate-and-state law)", "law", 1.0, upper=MODEL_MAX, dimension="force",
                    sweepable=True)
MU0 = nonnegative_real("mu0", "mu_0", "friction coefficient sliding steadily at V_0 (rate-and-state law)", "law", 0.6,
                       upper=100.0, sweepable=True)
RS_A = positive_real("a", "a", "direct-effect coefficient (rate-and-state law)", "law", 0.01, upper=100.0, sweepable=True)
RS_B = nonnegative_real("b", "b", "evolution-effect coefficient (rate-and-state law)", "law", 0.015, upper=100.0, sweepable=True)
DC = positive_real("dc", "D_c", "characteristic slip distance (rate-and-state law)", "law", 0.01, upper=MODEL_MAX,
                   dimension="length", sweepable=True)
VREF = positive_real("vref", "V_0", "reference velocity (rate-and-state law)", "law", 0.01, upper=MODEL_MAX,
                     dimension="velocity", sweepable=True)
STATE_LAW = Param("state_law", "", "evolution of the state variable: aging (Dieterich) or slip (Ruina)", "law",
                  "aging", kind="choice", choices=STATE_LAWS)


@register
class RateState(StatefulLaw):
    """Rate-and-state friction on the normal load N, in its regularised form.

    ::

        F      = N a asinh(V_r / (2 V_0) exp((mu0 + b ln(V_0 theta / D_c)) / a))
        theta' = 1 - |V_r| theta / D_c                          (aging law)
        theta' = -(|V_r| theta / D_c) ln(|V_r| theta / D_c)      (slip law)

    The asinh makes F defined and smooth through V_r = 0 (F takes V_r's sign);
    where |V_r| is well above 2 V_0 exp(-(mu0 + b ln(V_0 theta / D_c)) / a) it
    is N (mu0 + a ln(V_r / V_0) + b ln(V_0 theta / D_c)) to a relative
    O(exp(-2 (mu0 + ...) / a)).  Sliding steadily at V, theta = D_c / V under
    both state laws and |F| = N (mu0 + (a - b) ln(V / V_0)) (to the same order):
    velocity weakening for b > a.

    The internal state is psi = ln(V_0 theta / D_c) (``internal_names``), not
    theta: psi' = theta' / theta keeps theta = (D_c / V_0) e^psi positive
    whatever the step, and psi is of order one where theta spans decades.
    The run starts from the steady state at the belt speed, theta = D_c / |V_b|
    (psi = ln(V_0 / |V_b|); theta = D_c / V_0 for a belt at rest).

    The contact stores no energy (E = 0): all of the friction's work on the
    relative motion, F V_r, is interface heat.

    Parameters
    ----------
    normal:
        Normal load N > 0 (nondimensional: / (k l_0)).
    mu0:
        Friction coefficient sliding steadily at V_0, >= 0.
    a, b:
        Direct-effect coefficient a > 0 and evolution-effect coefficient b >= 0 (mu0 / a <= 700).
    dc:
        Characteristic slip distance D_c > 0 (nondimensional: / l_0).
    vref:
        Reference velocity V_0 > 0 (nondimensional: / (omega_0 l_0)).
    state_law:
        ``"aging"`` (Dieterich) or ``"slip"`` (Ruina).
    """

    name = "rate_state"
    code = stiff.RATE_STATE
    parameters = (NORMAL, MU0, RS_A, RS_B, DC, VREF, STATE_LAW)
    record_names = ("normal", "mu0", "a", "b", "dc", "vref", "state_law_code")
    internal_names = ("psi",)
    stiff_at_rest = True  # N a e^(Omega / a) / (2 V_0) at V_r = 0: about 1e25 at the defaults

    def __init__(self, normal: float = 1.0, mu0: float = 0.6, a: float = 0.01, b: float = 0.015, dc: float = 0.01,
                 vref: float = 0.01, state_law: str = "aging") -> None:
        self._assign(normal=normal, mu0=mu0, a=a, b=b, dc=dc, vref=vref, state_law=state_law)

    def _check_values(self) -> None:
        if not self.mu0 / self.a <= EXP_MAX:
            raise ValueError(f"a must be >= mu0 / {EXP_MAX:g} = {self.mu0 / EXP_MAX:g} for friction={self.name} "
                             f"(exp(mu0 / a) overflows), got {self.a!r}")

    @property
    def state_law_code(self) -> float:
        """The state law in the engine's record (0 aging, 1 slip)."""
        return float(STATE_LAWS.index(self.state_law))

    @property
    def fd(self) -> float:
        """The friction force sliding steadily at V_0 (the level runs start from and scale by)."""
        return float(self.slip_magnitude(self.vref))

    @property
    def fs(self) -> float:
        """No static level of its own, so that of :attr:`fd`."""
        return self.fd

    def theta(self, psi: Any) -> np.ndarray:
        """The state variable theta = (D_c / V_0) e^psi from the internal state psi."""
        return self.dc / self.vref * np.exp(np.asarray(psi, dtype=float))

    def _coefficient(self, vr: Any, psi: Any) -> np.ndarray:
        """a asinh(V_r / (2 V_0) e^Omega) (signed), with the asinh from ln|x| so that e^Omega never overflows."""
        vr, psi = np.broadcast_arrays(np.asarray(vr, dtype=float), np.asarray(psi, dtype=float))
        with np.errstate(divide="ignore"):
            lx = np.log(np.abs(vr) / (2.0 * self.vref)) + (self.mu0 + self.b * psi) / self.a
        low = np.minimum(lx, 0.0)
        high = np.maximum(lx, 0.0)
        mag = np.where(lx > 0.0, high + np.log(1.0 + np.sqrt(1.0 + np.exp(-2.0 * high))), np.arcsinh(np.exp(low)))
        return np.sign(vr) * self.a * mag

    def force(self, vr: Any, z: np.ndarray) -> np.ndarray:
        return self.normal * self._coefficient(vr, np.asarray(z, dtype=float)[0])

    def rate(self, vr: Any, z: np.ndarray) -> np.ndarray:
        """psi' = theta' / theta."""
        speed = np.abs(np.asarray(vr, dtype=float))
        psi = np.asarray(z, dtype=float)[0]
        if self.state_law == "aging":
            return (self.vref * np.exp(-psi) / self.dc - speed / self.dc)[None]
        with np.errstate(divide="ignore", invalid="ignore"):
            slip = -speed / self.dc * (np.log(speed / self.vref) + psi)
        return np.where(speed > 0.0, slip, 0.0)[None]

    def stored_energy(self, z: np.ndarray) -> np.ndarray:
        return np.zeros_like(np.asarray(z, dtype=float)[0])

    def steady_state(self, speed: Any) -> np.ndarray:
        """psi sliding steadily at ``speed`` != 0: theta = D_c / |V| (both state laws)."""
        return np.log(self.vref / np.abs(np.asarray(speed, dtype=float)))

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        """|F| sliding steadily at ``speed``: N a asinh(|V| / (2 V_0) e^((mu0 + b ln(V_0 / |V|)) / a)),
        N (mu0 + (a - b) ln(|V| / V_0)) but for the regularisation; N a asinh(0) = 0 at rest."""
        s = np.abs(np.asarray(speed, dtype=float))
        with np.errstate(divide="ignore"):
            psi = np.where(s > 0.0, self.steady_state(np.where(s > 0.0, s, 1.0)), 0.0)
        return self.normal * self._coefficient(s, psi)

    def slip_slope(self, speed: float) -> float:
        """d|F|/dV sliding steadily: N (a - b) x / (V sqrt(1 + x^2)), x the asinh's argument (-> N (a - b) / V)."""
        s = abs(float(speed))
        lx = np.log(s / (2.0 * self.vref)) + (self.mu0 + self.b * float(self.steady_state(s))) / self.a
        return float(self.normal * (self.a - self.b) / (s * np.sqrt(1.0 + np.exp(-2.0 * lx))))

    def initial_state(self, vb: float | None = None) -> np.ndarray:
        """Steady sliding at the belt speed: psi = ln(V_0 / |V_b|); psi = 0 (theta = D_c / V_0) for a belt at rest
        or none given."""
        return np.array([0.0 if not vb else float(self.steady_state(vb))])

    def default_start(self, vb: float) -> tuple[float, float]:
        """X(0) = N mu0 (F_d), X'(0) = 0: sliding at the belt's speed with the state steady there
        (:meth:`initial_state`), the spring off steady sliding unless V_b = V_0.  The paper's start, X'(0) = V_b,
        is V_r = 0 exactly, where the contact's stiffness N a e^(Omega/a) / (2 V_0) (about 1e25 at the
        defaults) holds the mass to rounding of V_b in the belt frame: the run could not leave it."""
        return self.fd, 0.0

    def steady_internal(self, vr: float) -> np.ndarray:
        """psi* = ln(V_0 / |V_r|) (theta* = D_c / |V_r|), where both state laws' rates vanish: the closed form
        in place of the base class's Newton iteration."""
        return self.initial_state(vr)

    def internal_scale(self) -> np.ndarray:
        """psi moves F by N b per unit (N a through the asinh at most): F_d / (N max(a, b)) carries a force of F_d."""
        return np.array([max(self.mu0, self.a) / max(self.a, self.b)])

    def speed_scale(self) -> float:
        """V_0: the law's logarithms are written about it (no velocity scale of its own)."""
        return self.vref
