"""How a friction law reaches the compiled kernels: a float64 array ``p`` with this layout.

==============  ======================================================
``p[LAW]``      law code (below): which compiled slip force applies
``p[FD]``       kinetic friction level F_d (TR_B's reference force)
``p[FS]``       maximum static friction F_s
``p[VD]``       stick-band half width: Karnopp's V_d, for the other
                laws the band fixed-step RK4 uses
``p[RESULTANT]`` 1.0: F_e = X + 2 zeta X'; 0.0: F_e = X
``p[LAW_A..C]`` the law's own parameters (its ``kernel_slots``)
``p[FEX]``      amplitude F_ex of the external force (0: unforced)
``p[OMEGA]``    its angular frequency Omega
``p[PHI]``      its phase phi: f(tau) = F_ex cos(Omega tau + phi)
``p[VB_AMP]``   amplitude A of the belt's speed variation (0: a belt at constant speed)
``p[VB_OMEGA]`` its angular frequency Omega_b
``p[VB_PHI]``   its phase phi_b: V_b(tau) = V_b + A sin(Omega_b tau + phi_b)
==============  ======================================================

The record holds every force on the mass besides the spring and the damper:
the interface's and the external one.  With forcing the equation of motion is
X'' = F_c + f(tau) - X - 2 zeta X', and the force the interface must hold
while sticking is F_e - f(tau) (F_e = X + 2 zeta V_b, or X).

Every registered law with a compiled slip force has a code here and a line
in each dispatcher of :mod:`.friction`.  This module imports nothing, so the
law modules can use it without importing the kernels.
"""

KARNOPP = 0
COULOMB = 1
STRIBECK = 2
CUBIC = 3
#: the codes with a compiled slip curve (batched RK4 compiles one loop for each)
SMOOTH_LAWS = (STRIBECK, CUBIC)
#: the codes by stick rule (each law's ``stick_rule``; tests/test_registries.py holds the two together):
#: Karnopp's velocity band, Coulomb's set-valued switch at V_r = 0
BAND_LAWS = (KARNOPP,)
SWITCH_LAWS = (COULOMB, *SMOOTH_LAWS)

LAW, FD, FS, VD, RESULTANT, LAW_A, LAW_B, LAW_C, FEX, OMEGA, PHI, VB_AMP, VB_OMEGA, VB_PHI = range(14)
N_PARAMS = 14

#: the work integrals every solver accumulates (columns of ``Trajectory.dwork``):
#: damper, friction in, friction out, interface heat, external force
W_DV, W_FIN, W_FOUT, W_HEAT, W_EX = range(5)
N_WORK = 5

#: friction mode codes recorded per sample by the solvers
SLIP_NEG = -1
STICK = 0
SLIP_POS = 1
