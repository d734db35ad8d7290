"""How a friction law reaches the compiled kernels: a float64 array ``p`` with this layout.

==============  ======================================================
``p[LAW]``      law code (below): which compiled slip force applies
``p[FD]``       kinetic friction level F_d (TR_B's reference force)
``p[FS]``       maximum static friction F_s
``p[VD]``       stick-band half width: Karnopp's V_d, for the other
                laws the band fixed-step RK4 uses
``p[RESULTANT]`` 1.0: F_e = X + 2 zeta X'; 0.0: F_e = X
``p[LAW_A..C]`` the law's own parameters (its ``kernel_slots``)
==============  ======================================================

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

LAW, FD, FS, VD, RESULTANT, LAW_A, LAW_B, LAW_C = range(8)
N_PARAMS = 8

#: friction mode codes recorded per sample by the solvers
SLIP_NEG = -1
STICK = 0
SLIP_POS = 1
