"""
Periodic orbits and continuation
================================

A steady stick-slip cycle is a periodic orbit.  Instead of simulating until
the transient dies, :func:`~frictionflow.orbits.find_orbit` solves for it by
Newton shooting on the Poincare map of the section X' = 0, and reports its
Floquet multipliers.  :func:`~frictionflow.orbits.continuation` then follows
equilibria and orbits as a parameter changes, and finds where they are born,
fold or change character.
"""

# %%
# One orbit
# ---------
from frictionflow import BeltOscillator, Coulomb, Stribeck
from frictionflow.orbits import continuation, find_orbit

orbit = find_orbit(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04))
orbit

# %%
# With a stick phase the Poincare map is locally constant: the nontrivial
# multiplier is 0 and the orbit attracts in one turn.
print("multipliers:", orbit.multipliers)
fig = orbit.plot()

# %%
# Continuation in the damping
# ---------------------------
# With a Stribeck law the friction force falls with the slip speed, and the
# sliding equilibrium loses stability where 2 zeta + F'(V_b) = 0 (a Hopf
# point).  On the tail of the Stribeck curve the Hopf bifurcation is
# subcritical: unstable cycles are born there and turn back at a fold, where
# they meet the stable stick-slip cycles.
law = Stribeck(fd=0.02, fs=0.04, vs=0.01)
result = continuation(BeltOscillator(zeta=0.3, vb=0.016), law, "zeta", 0.2, 0.4, seeds=("hopf",), n_equilibria=21)
result

# %%
# Solid lines are stable, dashed unstable; the amplitude panel marks the
# bifurcations found.
fig = result.plot()

# %%
# Every point of a branch carries its power flow and transmissibility:
branch = result.branches[1]
for point in branch.points[:: max(1, len(branch.points) // 6)]:
    print(f"zeta={point.value:.4f} {point.stability:9s} amplitude={point.amplitude:.4g} "
          f"R_c={point.measures.averages()['R_c']:.3f} TR_B={point.measures.TR_B:.3f}")
