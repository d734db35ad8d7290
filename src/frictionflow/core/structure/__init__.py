"""Exact event-driven motion of a linear structure with piecewise-constant friction contacts (issue 22).

The record :class:`~frictionflow.core.assembly.Assembly` describes the
structure.  In each combination of contact modes the motion is linear with
constant coefficients: a stuck contact is a constraint e_j . q' = b_j that
removes its direction, a slipping one a constant force +-F_d N_j(q) (a
q-dependent normal load adds a constant stiffness term), harmonic forces
are particular solutions.  The modules:

============  =============================================================
``spectral``  the integrals of e^{lambda (tau - s)} times 1, s, e^{mu s}
              (phi-functions, stable at resonance and at lambda = 0)
``combo``     one mode combination: the reduced (null-space) equations,
              their eigen-decomposition and the event functions' maps
``sparsity``  the nonzeros of a combination's Z and R (the phase's sums
              through them follow the nonzeros)
``phase``     a phase: its modal coordinates, the state and the event
              functions at any time of it, bounds on their derivatives
``events``    the certified walk to the first event of a phase
``stick``     held forces and the per-contact stick rule (active set)
``work``      the work of each element over a stretch of a phase
``run``       the run loop
============  =============================================================
"""
