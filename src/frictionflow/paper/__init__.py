"""Reproduction of the reference paper: Figs. 2-6, their data, and where the paper holds.

>>> from frictionflow.paper import reproduce, Settings
>>> summary = reproduce("out", Settings.quick())      # doctest: +SKIP
>>> summary.counts()                                   # doctest: +SKIP
{'supported': ..., 'refuted': ..., 'partly': ...}

Every study runs with the paper's method (RK4 through Karnopp's band,
F_e = X, F_s = F_d, V_d = 1e-3, from X(0) = F_d, X'(0) = V_b) and with the
exact event-driven solver.  Modules: :mod:`.settings` (the step, length and
window chosen, and why), :mod:`.fig2` ... :mod:`.fig6` (data set and figure
of each), :mod:`.transient` (Case II decay and the window dependence),
:mod:`.band` (Karnopp's band at V_b <= V_d), :mod:`.claims` (the paper's
statements checked against the data), :mod:`.report` (report.html).
"""

from .claims import Claim, evaluate
from .pipeline import Summary, compute, reproduce
from .settings import Settings

__all__ = ["Claim", "Settings", "Summary", "compute", "evaluate", "reproduce"]
