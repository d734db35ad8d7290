"""The cubic friction law: a falling-then-rising slip curve with a Hopf point and a stick-slip onset.

::

    F(V_r) = sgn(V_r) (mu_s - k_1 |V_r| + k_3 |V_r|^3)

a classic of the friction-oscillator literature (e.g. Thomsen & Fidlin,
Int. J. Non-Linear Mech. 38, 2003).  The slip force falls from the static
level mu_s = F_s at V_r -> 0 to its minimum F_min = mu_s - (2/3) k_1 v_m at
v_m = sqrt(k_1 / (3 k_3)) and rises after it; F_min is the law's kinetic level
F_d (TR_B's reference force and the default X(0)).  Steady sliding at V_b is
stable while 2 zeta + F'(V_b) = 2 zeta - k_1 + 3 k_3 V_b^2 > 0.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

from ..core import layout
from ..core.curve_cubic import magnitude, partial, slope  # noqa: F401  (the law's curve, re-exported)
from ..parameters import MODEL_MAX, nonnegative_real, positive_real
from .base import FS, RK4_BAND, STICK_FORCE, FrictionLaw
from .registry import register

MU_S = FS.with_default(0.04, None)
K1 = nonnegative_real("k1", "k_1", "cubic law's linear falling coefficient", "law", 0.3, upper=MODEL_MAX, sweepable=True)
K3 = positive_real("k3", "k_3", "cubic law's cubic rising coefficient", "law", 10.0, upper=MODEL_MAX ** 2, sweepable=True)


def minimum(mu_s: Any, k1: Any, k3: Any) -> Any:
    """F_min = mu_s - (2/3) k_1 sqrt(k_1 / (3 k_3)), the slip force's minimum (scalars or arrays)."""
    return mu_s - (2.0 / 3.0) * k1 * (k1 / (3.0 * k3)) ** 0.5


@register
class Cubic(FrictionLaw):
    """Coulomb's stick rule with the cubic slip curve mu_s - k_1 |V_r| + k_3 |V_r|^3.

    ``fd`` is not a parameter: it is the curve's minimum F_min (the kinetic level).

    Parameters
    ----------
    fs:
        Static friction mu_s = F_s = F(0+) >= 0.
    k1:
        Falling coefficient k_1 >= 0 (the initial slope is -k_1).
    k3:
        Rising coefficient k_3 > 0.  The slip force must stay >= 0:
        k_1 sqrt(k_1 / (3 k_3)) <= 1.5 mu_s.
    stick_force:
        ``"resultant"`` (default) or ``"spring"``.
    rk4_band:
        Stick band for the fixed-step RK4 solver only.
    """

    name = "cubic"
    code = layout.CUBIC
    parameters = (MU_S, STICK_FORCE, K1, K3, RK4_BAND)
    kernel_slots = {"rk4_band": layout.VD, "k1": layout.LAW_A, "k3": layout.LAW_B}
    piecewise_constant = False
    magnitude = staticmethod(magnitude)
    slope = staticmethod(slope)

    def __init__(self, fs: float = 0.04, k1: float = 0.3, k3: float = 10.0, stick_force: str = "resultant",
                 rk4_band: float = 1e-4) -> None:
        self._assign(fs=fs, k1=k1, k3=k3, stick_force=stick_force, rk4_band=rk4_band)

    def _check_values(self) -> None:
        self.fd = float(minimum(self.fs, self.k1, self.k3))
        if self.fd < 0.0:
            bound = 1.5 * self.fs / math.sqrt(1.0 / (3.0 * self.k3))
            raise ValueError(f"k1 must be <= {bound ** (2 / 3):.6g} for fs = {self.fs:g}, k3 = {self.k3:g} "
                             f"(a slip force >= 0 at every speed), got {self.k1!r}")

    @classmethod
    def kernel_columns(cls, v: Mapping[str, Any]) -> dict[int, Any]:
        return super().kernel_columns({**v, "fd": minimum(v["fs"], v["k1"], v["k3"])})

    def as_dict(self) -> dict[str, Any]:
        return {"friction": self.name, "fd": self.fd} | {k: v for k, v in super().as_dict().items() if k != "friction"}
