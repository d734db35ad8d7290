"""User-defined slip laws: any function of the relative speed, with Coulomb's stick rule."""

from __future__ import annotations

import weakref
from typing import Any, Callable

import numpy as np
from llvmlite import ir
from numba import cfunc, njit, types
from numba.core.registry import CPUDispatcher
from numba.extending import intrinsic

from ..core import layout
from .base import FD, FS, STICK_FORCE, FrictionLaw
from .registry import register

#: the slot of the kernels' force record that carries the address of the user's compiled function (a user law
#: has no parameters of its own in the record)
ADDRESS = layout.LAW_A
#: the signature every user function is compiled to: |F| from the relative speed
SLIP_SIGNATURE = types.float64(types.float64)

#: func -> its compiled form, while func lives (the law holds func, and the compiled form too)
_COMPILED: "weakref.WeakKeyDictionary[Callable, Any]" = weakref.WeakKeyDictionary()


@intrinsic
def _call_at(typingctx, bits, speed):
    """Call the ``double(double)`` function whose address is the bit pattern of the float64 ``bits``."""
    def codegen(context, builder, signature, args):
        bits, speed = args
        function = ir.FunctionType(ir.DoubleType(), [ir.DoubleType()])
        address = builder.inttoptr(builder.bitcast(bits, ir.IntType(64)), function.as_pointer())
        return builder.call(address, [speed])

    return types.float64(types.float64, types.float64), codegen


@njit(cache=True)
def user_slip_force(p, speed):
    """The slip force of the user function whose address ``p[ADDRESS]`` holds (the kernels' ``(p, speed)``).

    One function for every user law: the kernels rebuilt around it are
    compiled once and cached (:mod:`frictionflow.core._rebind`), not once per user function.
    """
    return _call_at(p[ADDRESS], speed)


def compiled_function(func: Callable[[float], float]) -> Any | None:
    """``func`` compiled to a C callable ``double(double)`` (a numba ``cfunc``), or None if numba cannot compile it.

    Compiling a small function takes a fraction of a second; the result is
    kept while ``func`` lives.  An exception raised by ``func`` in compiled
    code cannot cross the C boundary: the call returns NaN instead, which
    ends the run.
    """
    try:
        return _COMPILED[func]
    except (KeyError, TypeError):
        pass
    try:
        compiled = cfunc(SLIP_SIGNATURE)(_guarded(func))
    except Exception:  # not numba-compilable (or no plain function: a partial, a callable object): run in Python
        compiled = None
    try:
        _COMPILED[func] = compiled
    except TypeError:  # not weakly referable: compiled again for the next law
        pass
    return compiled


def _guarded(func: Callable[[float], float]) -> Callable[[float], float]:
    """``func`` compiled, returning NaN where it raises (nothing can be raised through the C boundary);
    TypeError for a callable that is not a plain function."""
    jitted = func if isinstance(func, CPUDispatcher) else njit(func)

    def slip(speed):
        try:
            return jitted(speed)
        except Exception:  # noqa: BLE001
            return np.nan

    return slip


def address_bits(compiled: Any) -> float:
    """The address of a compiled function as the float64 with the same bits (what ``p[ADDRESS]`` holds)."""
    return float(np.array([compiled.address], dtype=np.int64).view(np.float64)[0])


@register
class SlipLaw(FrictionLaw):
    """A user-defined slip law with Coulomb's stick rule.

    Parameters
    ----------
    func:
        ``func(speed) -> float``: the friction magnitude while slipping at
        relative speed ``speed`` > 0.  A numba-compilable function (plain
        ``math``/``numpy`` code, or already ``numba.njit``-ed) runs compiled;
        anything else runs in the Python version of the adaptive solver.
        The adaptive solver's kernels for user laws are compiled on the
        first use (about 10 s of CPU) and kept in numba's cache like the
        built-in ones; each new function, in each process, then only
        compiles itself (about 0.1-0.4 s): they call the function whose
        address the law's force record carries.  An
        exception ``func`` raises in compiled code becomes NaN, which ends
        the run (no exception crosses compiled code).
    fs:
        Maximum static friction F_s (defaults to ``func(0)``).
    fd:
        Reference friction level used for TR_B and the default X(0) (defaults
        to ``func`` at 100 V_b-independent units, i.e. ``func(1e2)``).
    dfunc:
        Optional derivative of ``func`` (for the equilibrium's stability); by
        default a central difference.
    stick_force:
        The force held while sticking: ``resultant`` X + 2 zeta X' (default)
        or ``spring`` X (the paper's).
    """


    name = "user"
    code = layout.STRIBECK  # only the adaptive solver runs it, rebuilt around the user's function
    parameters = (FD, FS, STICK_FORCE)
    piecewise_constant = False
    configurable = False
    compiled_slip = False  # the kernels' dispatch by code cannot evaluate the user's function

    def __init__(
        self,
        func: Callable[[float], float],
        fs: float | None = None,
        fd: float | None = None,
        dfunc: Callable[[float], float] | None = None,
        stick_force: str = "resultant",
    ) -> None:
        if not callable(func):
            raise ValueError(f"func must be callable, got {func!r}")
        self.func = func
        self.dfunc = dfunc
        f0 = float(func(0.0))
        self._assign(fd=float(func(1e2)) if fd is None else fd, fs=f0 if fs is None else fs, stick_force=stick_force)

    def kernel_force(self) -> Callable[[np.ndarray, float], float] | None:
        """``user_slip_force`` (the same for every user law), or None if numba cannot compile ``func``."""
        return None if self._compiled() is None else user_slip_force

    def kernel_params(self) -> np.ndarray:
        """The force record, with the address of the compiled ``func`` in ``p[ADDRESS]`` (0 if not compiled)."""
        p = super().kernel_params()
        compiled = self._compiled()
        if compiled is not None:
            p[ADDRESS] = address_bits(compiled)
        return p

    def _compiled(self) -> Any | None:
        """The compiled ``func``, held by the law so that its address stays valid while the law is used."""
        if "_compiled_func" not in self.__dict__:
            self.__dict__["_compiled_func"] = compiled_function(self.func)
        return self.__dict__["_compiled_func"]

    def __getstate__(self) -> dict[str, Any]:
        # a compiled function and its address belong to this process: another compiles its own
        return {k: v for k, v in self.__dict__.items() if k != "_compiled_func"}

    @property
    def band(self) -> None:
        return None  # RK4 does not run user laws

    def slip_magnitude(self, speed: Any) -> np.ndarray:
        return np.vectorize(lambda s: float(self.func(float(s))), otypes=[float])(speed)

    def slip_slope(self, speed: float) -> float:
        if self.dfunc is not None:
            return float(self.dfunc(speed))
        h = 1e-6 * max(abs(speed), 1e-6)
        return (float(self.func(speed + h)) - float(self.func(speed - h))) / (2 * h)

    def as_dict(self) -> dict[str, Any]:
        return super().as_dict() | {"func": getattr(self.func, "__name__", repr(self.func))}

    def __hash__(self) -> int:
        return id(self)

    def __eq__(self, other: object) -> bool:
        return self is other
