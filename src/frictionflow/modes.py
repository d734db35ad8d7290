"""The public names of the friction modes a run switches into.

Every solver that locates switches records, for each switch, the mode the
motion enters; ``Trajectory.events["mode"]`` holds these as
:class:`SwitchMode` values, whatever codes the solver's kernel uses
internally (the translation tables are in :mod:`frictionflow.core.event_modes`).

This module depends on nothing else in the package, so that any layer
(trajectory, solvers, analysis) can import it without a cycle.
"""

from __future__ import annotations

from enum import IntEnum


class SwitchMode(IntEnum):
    """The friction mode a switch enters (V_r = V_b - X' is the relative velocity).

    =========================== ==== ===========================================
    member                      int  the mode
    =========================== ==== ===========================================
    ``SLIP_NEGATIVE``           -1   slip with V_r < 0 (the mass outruns the
                                     belt), beyond the stick band if there is
                                     one; F_c = -F(|V_r|)
    ``STICK``                    0   ideal (Coulomb-type) stick: X' = V_b held
                                     while |F_e| < F_s; F_c = X + 2 zeta V_b
    ``SLIP_POSITIVE``            1   slip with V_r > 0 (the mass lags the
                                     belt); F_c = +F(|V_r|)
    ``BAND_HOLD``                2   Karnopp: inside the stick band
                                     |V_r| <= V_d with |F_e| < F_s, the
                                     interface holds the mass; F_c = F_e
    ``BAND_SATURATED_POSITIVE``  3   Karnopp: inside the band with F_e >= F_s;
                                     F_c = +F_s
    ``BAND_SATURATED_NEGATIVE``  4   Karnopp: inside the band with F_e <= -F_s;
                                     F_c = -F_s
    ``BAND_EDGE_LOWER``          5   Karnopp: sliding along the band's lower
                                     edge X' = V_b - V_d (V_r = +V_d), where
                                     the band pushes the mass out and slip+
                                     pushes it back (Filippov sliding; seen
                                     with F_e = X and zeta > 0)
    ``BAND_EDGE_UPPER``          6   the same on the upper edge
                                     X' = V_b + V_d (V_r = -V_d) against slip-
    =========================== ==== ===========================================

    The values -1, 0, +1 agree with the per-sample codes of
    ``Trajectory.mode`` where they mean the same thing; samples report every
    band mode as 0 (stick), events tell them apart.  An event array is a
    plain ``int8`` array of these values, so ``modes == SwitchMode.STICK``
    works elementwise and ``SwitchMode(m)`` turns an element into its member.
    """

    SLIP_NEGATIVE = -1
    STICK = 0
    SLIP_POSITIVE = 1
    BAND_HOLD = 2
    BAND_SATURATED_POSITIVE = 3
    BAND_SATURATED_NEGATIVE = 4
    BAND_EDGE_LOWER = 5
    BAND_EDGE_UPPER = 6
