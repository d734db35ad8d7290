"""What every friction law provides.

A law is a small immutable object whose parameters are declared once
(:class:`~frictionflow.parameters.Param`, the class attribute ``parameters``)
and validated in ``__init__``.  It hands the compiled kernels a flat float
array (:meth:`FrictionLaw.kernel_params`, layout in
``frictionflow.core.layout``); the same mapping from parameter values to
kernel slots (:meth:`FrictionLaw.kernel_columns`) fills the per-point rows of a
sweep.  Kernels know nothing of these classes.

To add a law: one module with a subclass (its ``parameters``, ``kernel_slots``,
its capabilities -- ``stick_rule``, ``piecewise_constant``, ``compiled_slip`` --
and, for a smooth slip curve, compiled ``magnitude``/``slope`` functions),
decorated with :func:`~frictionflow.friction.registry.register`, imported in
``friction/__init__.py``; a compiled law also gets a code in
``frictionflow.core.layout`` and a line in each dispatcher of
``frictionflow.core.friction``.  Solvers, engines and messages read the
capabilities, never the law's name.
"""

from __future__ import annotations

from typing import Any, Callable, ClassVar, Mapping

import numpy as np

from ..core import layout
from ..core.friction import slip_magnitude_of
from ..parameters import MODEL_MAX, Param, Sealed, nonnegative_real, positive_real, resolve

STICK_FORCES = ("resultant", "spring")
#: what a law does at V_r = 0: Coulomb's set-valued switch, Karnopp's velocity band |V_r| <= V_d, or nothing
#: of its own: its internal state (LuGre's bristles) holds the mass (:mod:`.stateful`)
STICK_RULES = ("switch", "band", "state")
#: how messages name each stick rule
STICK_RULE_WORDS = {"switch": "Coulomb's stick rule", "band": "a velocity band", "state": "an internal state (no stick rule)"}

# Parameters several laws share: declared once here, listed by each law.
FD = nonnegative_real("fd", "F_d", "kinetic friction", "law", 0.02, upper=MODEL_MAX, sweepable=True,
                     dimension="force", dimensional_name="f_d")
FS = Param("fs", "F_s", "maximum static friction", "law", lambda v: v["fd"], default_text="F_d",
           lower=0.0, upper=MODEL_MAX, sweepable=True, dimension="force", dimensional_name="f_ms")
STICK_FORCE = Param("stick_force", "", "force held while sticking: resultant (X+2zeta X') or spring (X, the paper's)",
                    "law", "resultant", kind="choice", choices=STICK_FORCES)
RK4_BAND = positive_real("rk4_band", "", "stick band half width of fixed-step RK4 (other solvers ignore it)", "law", 1e-4,
                         upper=MODEL_MAX, report=False)


class FrictionLaw(Sealed):
    """Base class of friction laws F_c(X, X') acting on the mass.

    Class attributes a law sets
    ---------------------------
    name:
        Registry name (``--friction NAME``).
    code:
        Law code of its compiled slip force (``frictionflow.core.layout``).
    parameters:
        Its parameters, in the order of the JSON ``params``.
    kernel_slots:
        Kernel slot of each parameter beyond F_d, F_s and the stick force.
    piecewise_constant:
        The slip force is constant (the exact event-driven solver applies).
    stick_rule:
        One of ``STICK_RULES``: ``"band"`` (Karnopp's velocity band) or ``"switch"``
        (Coulomb's set-valued rule at V_r = 0).
    compiled_slip:
        The kernels' own force dispatch (``frictionflow.core.friction``, by ``code``) evaluates its
        slip force.  False for a user's function: only the adaptive kernel, rebuilt around it, runs it.
    internal_names:
        Names of its internal states; a law with any (:class:`~frictionflow.friction.stateful.StatefulLaw`)
        runs only in the solvers that integrate them.
    has_tangent_kernel (derived unless a law sets it)
        Coulomb's stick rule and a compiled slip force: the tangent and flow-map kernels
        (Lyapunov exponents, forced orbits, the compiled orbit engine) run it.
    """

    name: ClassVar[str] = "abstract"
    code: ClassVar[int] = -1
    parameters: ClassVar[tuple[Param, ...]] = (FD, FS, STICK_FORCE)
    kernel_slots: ClassVar[dict[str, int]] = {}
    piecewise_constant: ClassVar[bool] = True
    stick_rule: ClassVar[str] = "switch"
    compiled_slip: ClassVar[bool] = True
    has_tangent_kernel: ClassVar[bool] = True
    #: names of its internal states, ``("z",)`` for LuGre; empty for a static law F(V_r)
    internal_names: ClassVar[tuple[str, ...]] = ()
    #: buildable by name from a config (user laws need a function)
    configurable: ClassVar[bool] = True
    #: compiled (fd, fs, a, b, c, speed) -> |F| and its slope, for smooth laws
    magnitude: ClassVar[Callable[..., float] | None] = None
    slope: ClassVar[Callable[..., float] | None] = None

    fd: float
    fs: float
    stick_force: str
    #: a user's slip function (the adaptive kernel is rebuilt around it); None for built-in laws
    func: Callable[[float], float] | None = None

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.stick_rule not in STICK_RULES:
            raise ValueError(f"{cls.__name__}.stick_rule must be one of {', '.join(STICK_RULES)}, got {cls.stick_rule!r}")
        if "has_tangent_kernel" not in cls.__dict__:  # derived from what the law declares
            cls.has_tangent_kernel = cls.stick_rule == "switch" and cls.compiled_slip

    def _assign(self, **given: Any) -> None:
        """Validate and set every declared parameter (defaults from the declarations)."""
        self._assign_checked(resolve(self.parameters, given))

    def _assign_checked(self, values: Mapping[str, Any]) -> None:
        """Set every parameter from ``values`` (each checked against its range), then the rules between them."""
        for key, value in values.items():
            setattr(self, key, value)
        self._check_values()
        self._seal()  # its kernel parameters are computed once (kernel_params): no value may change after

    def _check_values(self) -> None:
        """Rules between parameters (F_s >= F_d)."""
        if self.fs < self.fd:
            raise ValueError(f"fs must be >= fd = {self.fd!r}, got {self.fs!r}")

    @classmethod
    def from_values(cls, values: Mapping[str, Any], ranges: tuple[Param, ...] | None = None) -> "FrictionLaw":
        """Build from a mapping of parameter values (missing or None: the defaults).

        ``ranges``: the parameters' declarations to check the values against in place of the law's own (the
        same names; a structure's contacts take values in the model's units: ``frictionflow.system``)."""
        if ranges is None:
            return cls(**{p.name: values.get(p.name) for p in cls.parameters if values.get(p.name) is not None})
        law = cls.__new__(cls)
        law._assign_checked(resolve(ranges, {k: v for k, v in values.items() if v is not None}))
        return law

    def values(self) -> dict[str, Any]:
        """Every declared parameter's value, in declaration order."""
        return {p.name: getattr(self, p.name) for p in self.parameters}

    # -- what the kernels see -------------------------------------------------
    @property
    def band(self) -> float | None:
        """Half-width of the velocity band that fixed-step RK4 treats as stick (None if RK4 cannot run the law)."""
        return getattr(self, "rk4_band", None)

    @classmethod
    def kernel_columns(cls, v: Mapping[str, Any]) -> dict[int, Any]:
        """Kernel slot -> value from resolved parameter values (scalars, or per-point arrays of a sweep)."""
        cols = {layout.LAW: cls.code, layout.FD: v["fd"], layout.FS: v["fs"],
                layout.RESULTANT: 1.0 if v["stick_force"] == "resultant" else 0.0}
        cols.update({slot: v[name] for name, slot in cls.kernel_slots.items()})
        return cols

    def kernel_params(self) -> np.ndarray:
        """Flat float64 array in the layout of ``frictionflow.core.layout`` (a copy: the law is immutable)."""
        p = self.__dict__.get("_kernel_params")
        if p is None:
            p = np.zeros(layout.N_PARAMS)
            for slot, value in self.kernel_columns(self.values()).items():
                p[slot] = value
            self.__dict__["_kernel_params"] = p
        return p.copy()

    # -- physics ---------------------------------------------------------------
    def kernel_force(self) -> Callable[[np.ndarray, float], float] | None:
        """The compiled ``(p, speed) -> |F|`` the kernels use for this law (None: it cannot be compiled)."""
        return slip_magnitude_of

    def slip_force(self, vr: Any) -> np.ndarray:
        """Friction force on the mass while slipping at relative velocity ``vr`` (signed)."""
        vr = np.asarray(vr, dtype=float)
        return np.sign(vr) * self.slip_magnitude(np.abs(vr))

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        """|F| while slipping at relative speed ``speed`` >= 0 (the compiled law, element by element)."""
        s = np.asarray(speed, dtype=float)
        if self.magnitude is None:
            return np.full_like(s, self.fd)
        args = self._kernel_args()
        return np.vectorize(lambda u: self.magnitude(*args, u), otypes=[float])(s)

    def slip_slope(self, speed: float) -> float:
        """d|F|/d|V_r| at ``speed`` > 0 (the limit from above at 0; 0 for constant laws)."""
        if self.slope is None:
            return 0.0
        return float(self.slope(*self._kernel_args(), float(speed)))

    def _kernel_args(self) -> tuple[float, ...]:
        p = self.kernel_params()
        return (p[layout.FD], p[layout.FS], p[layout.LAW_A], p[layout.LAW_B], p[layout.LAW_C])

    def resolvable(self) -> bool:
        """Whether its slip curve changes on a velocity scale adaptive steps can resolve in floating point
        (cost estimates assume a run of one that cannot goes to its step cap)."""
        return True

    def hopf_damping(self, vb: float) -> float:
        """zeta at which steady sliding at belt speed ``vb`` changes stability: 2 zeta + F'(V_b) = 0."""
        return -0.5 * self.slip_slope(abs(vb))

    def start(self, vb: float, x0: float | None = None, v0: float | None = None) -> tuple[float, float]:
        """A run's initial state (X(0), X'(0)): the values given, else the law's :meth:`default_start`."""
        dx, dv = self.default_start(vb)
        return (dx if x0 is None else x0), (dv if v0 is None else v0)

    def default_start(self, vb: float) -> tuple[float, float]:
        """The start when none is given: the paper's X(0) = F_d, X'(0) = V_b (the mass moving with the belt)."""
        return self.fd, vb

    def stick_speed(self) -> float:
        """|V_r| below which a sample counts as stuck; 0: the law's stick is a mode of its own (V_r = 0 held by
        the stick rule), not a threshold on a continuous motion."""
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
        return {"friction": self.name} | {p.name: getattr(self, p.name) for p in self.parameters if p.report}

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.values().items())
        return f"{type(self).__name__}({args})"

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self.values() == other.values()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self), tuple(self.values().items())))
