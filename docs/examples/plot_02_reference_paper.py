"""
The reference paper: figures and verdicts
=========================================

:func:`frictionflow.paper.reproduce` recomputes Figs. 2-6 of the reference
paper with its own method (fixed-step RK4 through Karnopp's stick band, F_e =
X, F_s = F_d) and with the exact event-driven solver, writes every figure and
the data behind it, and checks each of the paper's claims against the data.

The quick settings used here keep the paper's step and run length but use
smaller grids (a smoke test: ``frictionflow reproduce --quick``); the
published figures come from ``Settings()``.
"""

# %%
# Run every study
# ---------------
import tempfile
from pathlib import Path

from frictionflow.paper import Settings, reproduce
from frictionflow.paper import fig2, fig3, fig5

out = Path(tempfile.mkdtemp()) / "paper"
summary = reproduce(out, Settings.quick(), workers=1)
print(summary.counts(), f"in {summary.seconds:.0f} s;", len(summary.files), "files, report:", summary.report.name)

# %%
# The verdicts
# ------------
# Each claim of the paper, quoted, with the evidence found.  "refuted" claims
# are mostly about Case II (zeta > 0, F_s = F_d), whose "limit cycles" are a
# spiral decaying onto the sliding equilibrium.
for claim in summary.claims:
    print(f"{claim.figure:5s} {claim.verdict:9s} {claim.key}")

# %%
# The first refuted claim in full:
c = next(claim for claim in summary.claims if claim.verdict == "refuted")
print(f"[{c.verdict}] {c.quote}\n\n{c.evidence}")

# %%
# Fig. 2: friction power in Case I
# --------------------------------
# Solid lines are the paper's method, dashed the exact solver.
fig = fig2.plot(summary.data["fig2"])

# %%
# Fig. 3: Case II phase portraits
# -------------------------------
fig = fig3.plot(summary.data["fig3"])

# %%
# Fig. 5: dissipation ratios against damping
# ------------------------------------------
# Dots joined by lines are the paper's method, crosses the exact solver over
# the same window.
fig = fig5.plot(summary.data["fig5"], summary.settings.t_end)
