"""The choices the paper leaves open, made once and stated.

The paper integrates Eq. 4 with RK4 and Karnopp's law (F_e = X, F_s = F_d,
V_d = 1e-3, X(0) = F_d, X'(0) = V_b) but gives neither the step nor the
integration length nor where its averaging window sits.  We take:

* ``dt = 1e-3``: the stick band is resolved in every case of the paper
  (|X''| <= 0.22, so one step moves X' by at most 2.2e-4, about a fifth of
  V_d), and RK4's global error, of order dt^4, is far below anything shown:
  RK4 and the exact solver agree to ~1e-4 on every average.
* ``t_end = 600``: Case II never settles on a cycle (it decays at rate zeta),
  so every average depends on where the window sits.  Three of the paper's
  numbers -- damper power below 1e-11, friction power of order 1e-6 and
  "99.99 %" dissipated by friction -- each imply a window near
  tau = 500...600 for zeta = 0.01 (see :mod:`.transient`); we take the end
  of that range.  The averaging window is the last whole cycle (between the
  last two maxima of X) before ``t_end``: Eq. 9 averages over "one periodic
  cycle".
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import _validate as check
from ..parameters import declared

#: The paper's Karnopp band half-width (Sec. 4).
PAPER_VD = 1e-3


@dataclass(frozen=True)
class Settings:
    """How long, how fine and over which grids every study runs.

    Attributes
    ----------
    dt:
        RK4 step of the paper's method.
    t_end:
        Length of every run of Figs. 2-6; the averaging window is the last
        whole cycle before it.
    vd:
        Karnopp band half-width V_d.
    exact_dense_dt:
        Sampling step of the exact solver's closed form (for plots, files and
        the quadrature of windowed averages).
    shown_span, shown_dt:
        Length of the time histories and phase portraits shown (the end of
        each run), and their sampling step in the figures and files.
    zeta_grid:
        Damping ratios of the sweeps of Figs. 5 and 6 (0 is Case I).
    window_t_end, window_step:
        Length of the runs that show how the averages depend on the window,
        and the spacing of the window positions.
    band_vb, band_t_end:
        Belt speeds around V_d for the Karnopp-band study, and their run length.
    band_history_t_end:
        Length of the V_b = V_d runs (RK4 creeps for thousands of time units).
    """

    dt: float = 1e-3
    t_end: float = 600.0
    vd: float = PAPER_VD
    exact_dense_dt: float = 0.01
    shown_span: float = 20.0
    shown_dt: float = 0.02
    zeta_grid: tuple[float, ...] = (0.0, 0.001, 0.002, 0.003, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.025, 0.03)
    window_t_end: float = 1000.0
    window_step: float = 10.0
    band_vb: tuple[float, ...] = (0.0005, 0.0008, 0.001, 0.0012, 0.0015, 0.002, 0.003, 0.005, 0.01, 0.02, 0.05, 0.1)
    band_t_end: float = 1500.0
    band_history_t_end: float = 12000.0

    def __post_init__(self) -> None:
        for name in ("dt", "t_end", "vd", "exact_dense_dt", "shown_span", "shown_dt", "window_t_end", "window_step",
                     "band_t_end", "band_history_t_end"):
            check.positive(name, getattr(self, name))
        for name in ("dt", "t_end"):  # and within the ranges simulate's --dt and --t-end enforce (RK4's step, a run's)
            declared()[name].check(getattr(self, name))
        if self.shown_span >= self.t_end:  # named by t_end: what a command line can change (reproduce --t-end)
            raise ValueError(f"t_end must be > {self.shown_span:g} (shown_span: the end of each run the time histories "
                             f"and phase portraits show), got {self.t_end!r}")
        if self.window_t_end < self.t_end:
            raise ValueError(f"window_t_end must be >= t_end = {self.t_end:g}, got {self.window_t_end!r}")
        if not self.zeta_grid or any(z < 0 for z in self.zeta_grid) or 0.01 not in self.zeta_grid or 0.03 not in self.zeta_grid:
            raise ValueError(f"zeta_grid must hold values >= 0 including the paper's 0.01 and 0.03, got {self.zeta_grid!r}")
        if not self.band_vb or any(v <= 0 for v in self.band_vb) or PAPER_VD not in self.band_vb:
            raise ValueError(f"band_vb must hold belt speeds > 0 including V_d = {PAPER_VD:g}, got {self.band_vb!r}")

    @classmethod
    def quick(cls) -> Settings:
        """Reduced grids and shorter auxiliary runs for smoke tests (same method, same t_end)."""
        return cls(
            zeta_grid=(0.0, 0.005, 0.01, 0.03),
            window_t_end=700.0,
            window_step=50.0,
            band_vb=(0.0005, 0.001, 0.002, 0.01),
            band_t_end=1200.0,
            band_history_t_end=1500.0,
        )

    def describe(self) -> dict[str, object]:
        """The settings as plain values, for file attributes and the report."""
        from dataclasses import asdict

        return asdict(self)
