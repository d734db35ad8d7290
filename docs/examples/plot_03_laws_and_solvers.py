r"""
Friction laws and solvers compared
==================================

Dry friction is discontinuous at V_r = 0: the force jumps from -F_d to +F_d,
and while the mass sticks it is whatever holds it, up to F_s.  A naive
integrator that evaluates ``F_d sign(V_r)`` at every step *chatters*: during
stick it flips the force from one side to the other every step.  This
example shows that chattering, the paper's remedy (a stick band :math:`|V_r| \le V_d`
inside fixed-step RK4) and the exact switching this package uses.
"""

# %%
# The slip laws
# -------------
# The force while slipping, against the slip speed :math:`|V_r|`.
import matplotlib.pyplot as plt
import numpy as np

from frictionflow import RK4, Adaptive, BeltOscillator, Coulomb, Cubic, Stribeck, simulate

laws = {
    "Coulomb": Coulomb(fd=0.02, fs=0.04),
    "Stribeck": Stribeck(fd=0.02, fs=0.04, vs=0.01),
    "Cubic": Cubic(fs=0.04, k1=0.3, k3=10.0),
}
speed = np.linspace(0.0, 0.1, 400)
fig, ax = plt.subplots(figsize=(6, 3.2), constrained_layout=True)
for name, law in laws.items():
    ax.plot(speed, law.slip_magnitude(speed), label=name)
ax.plot([0, 0], [0, 0.04], "k:", lw=0.8)
ax.set(xlabel="slip speed |V_r|", ylabel="|F_c|", title="slip force (static level F_s = 0.04 at rest)")
_ = ax.legend()

# %%
# A naive integrator chatters
# ---------------------------
# Classical RK4 on :math:`X'' + 2\zeta X' + X = \mathrm{sign}(V_r) F(|V_r|)` with the Stribeck
# law above: no stick rule at all.  Once the mass reaches the belt's speed,
# every step overshoots V_b and the force flips from +F_s to -F_s.
law = laws["Stribeck"]
model, dt, t_end = BeltOscillator(zeta=0.05, vb=0.01), 0.01, 40.0


def naive_rk4(x, v):
    def f(x, v):
        vr = model.vb - v
        return v, np.sign(vr) * float(law.slip_magnitude(abs(vr))) - x - 2 * model.zeta * v

    out = [(0.0, x, v, f(x, v)[1] + x + 2 * model.zeta * v)]
    for k in range(int(round(t_end / dt))):
        k1 = f(x, v)
        k2 = f(x + dt / 2 * k1[0], v + dt / 2 * k1[1])
        k3 = f(x + dt / 2 * k2[0], v + dt / 2 * k2[1])
        k4 = f(x + dt * k3[0], v + dt * k3[1])
        x += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        v += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        out.append(((k + 1) * dt, x, v, f(x, v)[1] + x + 2 * model.zeta * v))  # F_c = X'' + X + 2 zeta X'
    return np.array(out).T


tn, xn, vn, fcn = naive_rk4(0.0, 0.0)
switching = simulate(model, law, Adaptive(), t_end=t_end, x0=0.0, v0=0.0)
exact = switching.dense(256)  # the curve between its samples
banded = Stribeck(fd=0.02, fs=0.04, vs=0.01, rk4_band=1e-3)  # a band as wide as the paper's V_d
paper = simulate(model, banded, RK4(dt=dt), t_end=t_end, x0=0.0, v0=0.0)  # RK4 through the band

fig, ax = plt.subplots(2, 1, figsize=(8, 5), sharex=True, constrained_layout=True)
ax[0].plot(tn, fcn, lw=0.5, color="C3", label="naive RK4: sign(V_r) F(|V_r|)")
ax[0].plot(paper.t, paper.fc, lw=1.0, color="C1", label="RK4 through a stick band (the paper's remedy)")
ax[0].plot(exact.t, exact.fc, lw=1.4, color="k", ls="--", label="located switches")
ax[0].set(ylabel="F_c", title=f"friction force, dt = {dt}")
ax[0].legend(fontsize=7, loc="lower right")
ax[1].plot(tn, vn, lw=0.6, color="C3")
ax[1].plot(paper.t, paper.v, lw=1.0, color="C1")
ax[1].plot(exact.t, exact.v, lw=1.4, color="k", ls="--")
ax[1].axhline(model.vb, color="0.5", lw=0.6)
_ = ax[1].set(xlabel=r"$\tau$", ylabel="X'")

# %%
# Count the sign flips of the force: the naive run flips again and again
# where it should stick; the switching solver changes mode only where the
# motion does.
flips = int(np.count_nonzero(np.diff(np.sign(fcn))))
print(f"naive RK4: {flips} sign flips of F_c in {len(tn) - 1} steps")
print(f"located switches: {len(switching.events['t'])}")

# %%
# Zoom on one stick phase: the naive force is a square wave at the step
# frequency; the band gives a continuous holding force; with located
# switches the mass sticks with X' = V_b exactly and F_c = X + 2 zeta V_b.
stick = exact.t[(exact.mode == 0) & (exact.t > 15)]
t0 = stick[0] + 0.5
fig, ax = plt.subplots(figsize=(8, 3), constrained_layout=True)
for t, y, style in ((tn, fcn, dict(lw=0.8, color="C3", label="naive RK4")),
                    (paper.t, paper.fc, dict(color="C1", label="RK4 + band")),
                    (exact.t, exact.fc, dict(color="k", ls="--", label="located switches"))):
    near = (t > t0) & (t < t0 + 0.5)
    ax.plot(t[near], y[near], **style)
ax.set(xlabel=r"$\tau$", ylabel="F_c", title="inside a stick phase")
_ = ax.legend(fontsize=8)

# %%
# Smooth slip laws: the adaptive solver
# -------------------------------------
# The "located switches" run above is the adaptive Dormand-Prince solver: it
# integrates each slip phase with the slip direction fixed (no sign() inside,
# so nothing chatters), locates every switch on its dense output and holds
# X' = V_b exactly while the mass sticks.
switching

# %%
fig = switching.plot()
