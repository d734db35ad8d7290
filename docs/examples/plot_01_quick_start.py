"""
Quick start
===========

Simulate the mass-on-belt oscillator, find its steady state, read its power
flow, and look at the motion.  Everything here is the package's public API.
"""

# %%
# One run
# -------
# A damped oscillator (zeta = 0.05) on a belt moving at V_b = 0.01, with
# Coulomb friction whose static level F_s = 0.04 exceeds the kinetic
# F_d = 0.02: the classic stick-slip cycle.  The exact solver (the default for
# this law) goes from switch to switch in closed form.
from frictionflow import BeltOscillator, Coulomb, analyze, simulate

model = BeltOscillator(zeta=0.05, vb=0.01)
traj = simulate(model, Coulomb(fd=0.02, fs=0.04), t_end=100)
traj

# %%
# The trajectory keeps only what the analysis needs: the switches, the zeros
# and extremes of X'.  Between them the motion is known exactly, and the
# trajectory evaluates it at any time:
x, v = traj(12.5)
print(f"X(12.5) = {x:.12f}, X'(12.5) = {v:.12f}")
xs, vs = traj([20.0, 20.5, 21.0])  # arrays too
print(xs)

# %%
# Steady state and power flow
# ---------------------------
# :func:`~frictionflow.analyze` finds the steady state (here a stable
# periodic orbit) and averages the power flow over whole periods of it.
result = analyze(traj)
result

# %%
# The numbers are attributes too:
ss = result.steady_state
print(ss.kind, ss.period, ss.stick_fraction)
print(result.power.P_fin, result.power.R_c, result.TR_B, result.energy_residual)

# %%
# The figure of a run
# -------------------
# Time history, phase portrait, the power at the end of the window and the
# averages.  The curves are the true motion between the samples, not straight
# lines between switches.
fig = result.plot()

# %%
# A labelled dataset
# ------------------
# ``to_xarray`` gives the motion on a dense grid (at least 64 points per
# natural period) with the solver's own samples and the switches marked.
ds = traj.to_xarray()
print(ds.sizes["tau"], "points,", int(ds.is_sample.sum()), "of them samples,", int(ds.switch.sum()), "switches")
switches = ds.where(ds.switch, drop=True)
ax = ds.X.plot(figsize=(8, 3), lw=0.8)
ax[0].axes.plot(switches.tau, switches.X, "k.", ms=4, label="switches")
_ = ax[0].axes.legend()
