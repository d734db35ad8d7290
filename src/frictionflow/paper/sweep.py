"""The damping sweep behind Figs. 5 and 6: every (V_b, F_d, zeta) with both solvers.

For each point two kinds of numbers are kept:

* ``last_*``: Eq. 9 and Eq. 6 over the last whole cycle before t_end -- the
  paper's method and its averaging (the exact solver's values over the same
  kind of window are the cross-check);
* ``steady_*``: what :func:`~frictionflow.analysis.analyze` finds as the steady
  state (for the exact solver, for every zeta > 0, the sliding equilibrium:
  P_fin = 0, so R_c and R_f are undefined, and TR_B = 1).
"""

from __future__ import annotations

import numpy as np

from .._lazy import lazy_module
from .results import Runner
from .runs import SOLVERS, Point

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

VB = (0.01, 0.1)
FD = (0.02, 0.04)


#: quantities kept over the last cycle and in the steady state
LAST = ("P_dv", "P_fin", "P_df", "R_c", "R_f", "TR_B", "amplitude", "net_friction", "dE")
STEADY = ("P_dv", "P_fin", "P_df", "R_c", "R_f", "TR_B")


def dataset(runner: Runner, vbs: tuple[float, ...] = VB, fds: tuple[float, ...] = FD) -> xr.Dataset:
    """All sweep quantities over (solver, vb, fd, zeta)."""
    zetas = runner.settings.zeta_grid
    shape = (len(SOLVERS), len(vbs), len(fds), len(zetas))
    last = {k: np.full(shape, np.nan) for k in LAST}
    steady = {k: np.full(shape, np.nan) for k in STEADY}
    kind = np.full(shape, "", dtype=object)
    for i, s in enumerate(SOLVERS):
        for j, vb in enumerate(vbs):
            for k, fd in enumerate(fds):
                for m, z in enumerate(zetas):
                    r = runner.result(Point(z, vb, fd), s, decay=False)
                    for name in LAST:
                        last[name][i, j, k, m] = getattr(r.last, name)
                    for name in STEADY:
                        steady[name][i, j, k, m] = r.steady[name]
                    kind[i, j, k, m] = r.kind
    dims = ("solver", "vb", "fd", "zeta")
    data = {f"last_{k}": (dims, v) for k, v in last.items()}
    data.update({f"steady_{k}": (dims, v) for k, v in steady.items()})
    data["kind"] = (dims, kind.astype(str))
    return xr.Dataset(data, coords={"solver": list(SOLVERS), "vb": list(vbs), "fd": list(fds), "zeta": list(zetas)})
