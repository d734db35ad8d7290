"""
Power flow on one cycle
=======================

Multiplying the equation of motion X'' + 2 zeta X' + X = F_c by X' gives the
power balance

    K' + P_dv + U' = P_f,   P_dv = 2 zeta X'^2,   P_f = X' F_c,

with K = X'^2/2 and U = X^2/2.  Over a period K and U return to their
values, so the friction's net input equals the damper's dissipation.  Here
we follow the terms through one stick-slip cycle.
"""

# %%
# The cycle
# ---------
# The stable periodic orbit of a damped oscillator with Coulomb friction,
# found by Newton shooting on the Poincare map.
import matplotlib.pyplot as plt
import numpy as np

from frictionflow import BeltOscillator, Coulomb, instantaneous_power
from frictionflow.orbits import find_orbit

orbit = find_orbit(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04))
orbit

# %%
# One period as a trajectory, drawn densely (the solver's exact closed form
# between its samples).  Friction puts energy in where P_f > 0 (the belt
# drags the mass along) and takes it out where P_f < 0; the damper only
# takes.  The belt delivers P_belt = F_c V_b; what does not reach the mass is
# heat at the interface, P_heat = F_c V_r, zero while sticking.
cycle = orbit.trajectory().dense(points_per_period=2000)
p = instantaneous_power(cycle)
stick = cycle.mode == 0

fig, ax = plt.subplots(3, 1, figsize=(8, 7.5), sharex=True, constrained_layout=True)
ax[0].plot(cycle.t, cycle.x, label="X")
ax[0].plot(cycle.t, cycle.v, label="X'")
ax[0].fill_between(cycle.t, -0.03, 0.05, where=stick, color="0.9", label="stick")
ax[0].set(ylim=(-0.03, 0.05), title=f"one period, T = {orbit.period:.5f}")
ax[0].legend(fontsize=8, ncol=3)

ax[1].fill_between(cycle.t, p["P_f"], 0, where=p["P_f"] > 0, color="C2", alpha=0.5, label="friction in")
ax[1].fill_between(cycle.t, p["P_f"], 0, where=p["P_f"] < 0, color="C1", alpha=0.5, label="friction out")
ax[1].plot(cycle.t, p["P_dv"], color="C0", label=r"damper $P_{dv}$")
ax[1].set(ylabel="power")
ax[1].ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
ax[1].legend(fontsize=8, ncol=3)

ax[2].plot(cycle.t, p["P_belt"], color="C4", label=r"belt $P_{belt}$")
ax[2].plot(cycle.t, p["P_heat"], color="C3", label=r"heat $P_{heat}$")
ax[2].plot(cycle.t, p["P_f"], color="k", lw=0.8, label=r"$P_f = P_{belt} - P_{heat}$")
ax[2].set(xlabel=r"$\tau$", ylabel="power")
ax[2].ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
_ = ax[2].legend(fontsize=8, ncol=3)

# %%
# The balance, integrated
# -----------------------
# The solver integrates the work of each term itself; over the cycle the
# change of K + U is what friction put in minus what friction and the damper
# took out.
W = cycle.work  # W_dv, W_fin, W_fout, W_heat, running from the cycle's start
energy = cycle.energy - cycle.energy[0]
fig, ax = plt.subplots(figsize=(8, 3.5), constrained_layout=True)
ax.plot(cycle.t, W[:, 1], color="C2", label=r"$W_{fin}$")
ax.plot(cycle.t, W[:, 2] + W[:, 0], color="C1", label=r"$W_{fout} + W_{dv}$")
ax.plot(cycle.t, energy, color="k", label=r"$\Delta(K+U)$")
ax.plot(cycle.t, W[:, 1] - W[:, 2] - W[:, 0], "w:", lw=1.5, label=r"$W_{fin} - W_{fout} - W_{dv}$")
ax.set(xlabel=r"$\tau$", ylabel="work", title="energy balance through the cycle")
ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
ax.legend(fontsize=8)
print(f"largest imbalance along the cycle: {np.abs(energy - (W[:, 1] - W[:, 2] - W[:, 0])).max():.1e}")

# %%
# The averages
# ------------
# Divided by the period: P_fin = P_df + P_dv, so R_c + R_f = 1.
av = orbit.measures.averages()
for k in ("P_fin", "P_df", "P_dv", "R_c", "R_f", "P_belt", "P_heat"):
    print(f"{k:7s} {av[k]:.6g}")
print(f"P_fin - P_df - P_dv = {av['P_fin'] - av['P_df'] - av['P_dv']:.1e}")
