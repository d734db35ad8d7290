"""The output quantities of a steady state: one table, read by every report.

Each :class:`Quantity` names one number the package reports about a steady
state -- its name (the JSON key, the sweep variable, the dataclass field),
units and long name (the sweep dataset's attributes), where
``frictionflow simulate --json`` reports it, whether sweeps store it, and its
value at the sliding equilibrium.  The table's order is the one order of
every consumer:

* the kernels' layout (:mod:`frictionflow.core.sections`: window averages,
  window summaries and :func:`~frictionflow.core.sections.equilibrium_row`
  hold the quantities at their table positions, :data:`INDEX`), whose first
  :data:`NR` entries are the batched kernels' result row
  (:mod:`frictionflow.core.batch`: ``R_*``, ``NR``);
* the sweep datasets' variables and their attributes
  (:data:`frictionflow.sweep.compute.VARIABLES`, :mod:`frictionflow.sweep.store`);
* the JSON objects of ``simulate --json`` (``averages``, ``amplitude`` and
  where ``TR_B`` and ``energy_residual`` sit among them), and the fields of
  :class:`~frictionflow.analysis.power_flow.PowerFlow` (:func:`table_fields`);
* the equilibrium's values, one rule per quantity (:data:`EQUILIBRIUM_RULES`).

Adding a quantity
-----------------
1. Add a :class:`Quantity` to :data:`TABLE` where it should appear.  Swept
   quantities (``swept=True``) come first: the kernels' result row is the
   table's first :data:`NR` entries; a quantity sweeps do not store goes
   after them.
2. Compute it where its kind of value is computed: a window average in
   :func:`frictionflow.core.sections.averages`, an extreme or a ratio in
   :func:`~frictionflow.core.sections.window_summary` (at
   ``INDEX[name]``), and, if it is reported in ``amplitude``, in
   :func:`frictionflow.analysis.transmissibility.amplitude`.
3. Nothing to clear by hand: the kernels' numba cache is dropped whenever
   this table or any kernel source changes (:mod:`frictionflow.core._cache`).
4. If the sweep output changes, record the golden outputs again
   (``python -m tests.golden.record``) and say so in the CHANGELOG.
"""

from __future__ import annotations

from dataclasses import dataclass

#: the steady-state kinds, by code (the ``kind`` variable's flag meanings)
#: (``diverged``: the state left the floating-point range; nothing else is reported;
#: ``quasi_periodic`` and ``chaotic`` only occur with an external force: :mod:`frictionflow.analysis.forced`)
KINDS = ("periodic", "equilibrium", "not_settled", "diverged", "quasi_periodic", "chaotic")

#: how a quantity's value at the sliding equilibrium X* follows from X*,
#: V_b, F_d, the stick fraction and the energy residual
#: (:func:`frictionflow.core.sections.equilibrium_row` evaluates them):
#:
#: ``kind``  the code of ``"equilibrium"``;  ``nan``  undefined;  ``zero``  no motion, no vibration power;
#: ``x``  X*;  ``belt``  X* V_b while sliding, 0 resting in a stick band (stick fraction >= 1/2);
#: ``trb``  |X*| / F_d (NaN for F_d = 0);  ``stick``  the stick fraction;  ``resid``  the residual given
EQUILIBRIUM_RULES = ("kind", "nan", "zero", "x", "belt", "trb", "stick", "resid")


@dataclass(frozen=True)
class Quantity:
    """One reported quantity.

    ``report`` is the key of the ``simulate --json`` object it appears in (or
    under, when it is the quantity's own key); ``at_equilibrium`` one of
    :data:`EQUILIBRIUM_RULES`; ``dtype`` and ``flags`` its sweep variable's
    storage type and flag meanings.
    """

    name: str
    long_name: str
    report: str
    at_equilibrium: str
    swept: bool = True
    units: str = "1"
    dtype: str = "f8"
    flags: tuple[str, ...] = ()
    #: reported only for runs with an external force (the autonomous system's reports keep their keys)
    forced_only: bool = False


TABLE = (
    Quantity("kind", "steady state: 0 periodic, 1 equilibrium, 2 not settled, 3 diverged, 4 quasi-periodic, 5 chaotic", "steady_state", "kind", dtype="i1", flags=KINDS),
    Quantity("period", "period of the periodic steady state (tau units; NaN unless periodic)", "steady_state", "nan"),
    Quantity("P_dv", "time-averaged power dissipated by the damper", "averages", "zero"),
    Quantity("P_df", "time-averaged power taken out by friction (magnitude of the negative part of X' F_c)", "averages", "zero"),
    Quantity("P_fin", "time-averaged power put in by friction (positive part of X' F_c)", "averages", "zero"),
    Quantity("R_c", "power dissipation ratio of the damper P_dv / P_fin", "averages", "nan"),
    Quantity("R_f", "power dissipation ratio of friction P_df / P_fin", "averages", "nan"),
    Quantity("P_belt", "time-averaged power delivered by the belt F_c V_b", "averages", "belt"),
    Quantity("P_heat", "time-averaged heat generated at the interface F_c V_r", "averages", "belt"),
    Quantity("TR_B", "force transmissibility max|X + 2 zeta X'| / F_ex (Eq. 6; F_ex = F_d unforced)", "TR_B", "trb"),
    Quantity("X_min", "minimum displacement over the steady-state window", "amplitude", "x"),
    Quantity("X_max", "maximum displacement over the steady-state window", "amplitude", "x"),
    Quantity("V_min", "minimum velocity over the steady-state window", "amplitude", "zero"),
    Quantity("V_max", "maximum velocity over the steady-state window", "amplitude", "zero"),
    Quantity("stick_fraction", "share of the steady-state window spent sticking", "steady_state", "stick"),
    Quantity("energy_residual", "relative residual of the power balance over the window", "energy_residual", "resid"),
    # stored by every sweep (0 without a force), so that a forced point's balance closes from the dataset:
    # P_dv + P_df = P_fin + P_ex over whole periods; simulate --json reports it for forced runs only
    Quantity("P_ex", "time-averaged power put in by the external force X' F_ex cos(Omega tau + phi)", "averages", "zero",
             forced_only=True),
    # not stored by sweeps: over whole periods it equals P_dv - P_ex
    Quantity("P_f", "time-averaged net power of friction X' F_c = P_belt - P_heat", "averages", "zero", swept=False),
)

NAMES = tuple(q.name for q in TABLE)
#: position of each quantity in the kernels' layout
INDEX = {name: i for i, name in enumerate(NAMES)}
NQ = len(TABLE)
#: the quantities sweeps store: the kernels' result row, in this order
SWEPT = tuple(q for q in TABLE if q.swept)
NR = len(SWEPT)
#: the ``simulate --json`` keys the table's quantities sit in (or under), in order of first appearance
REPORTS = tuple(dict.fromkeys(q.report for q in TABLE))


def reported_in(report: str, forced: bool = False) -> tuple[str, ...]:
    """Names of the quantities ``simulate --json`` reports in ``report`` (of a ``forced`` run), in table order."""
    return tuple(q.name for q in TABLE if q.report == report and (forced or not q.forced_only))


AVERAGES = reported_in("averages")
#: with an external force: P_ex too, after the others (the fields of PowerFlow, the forced JSON's order)
FORCED_AVERAGES = AVERAGES + tuple(n for n in reported_in("averages", forced=True) if n not in AVERAGES)
AMPLITUDE = reported_in("amplitude")
#: the orbit and continuation reports list the averages in the paper's order
#: (Eq. 9: P_fin, P_df, P_dv), as their recorded outputs do
PAPER_AVERAGES = ("P_fin", "P_df", "P_dv") + tuple(n for n in AVERAGES if n not in ("P_fin", "P_df", "P_dv"))


def index(name: str) -> int:
    """Position of quantity ``name`` in the kernels' layout (KeyError names the unknown quantity)."""
    return INDEX[name]


def table_fields(names: tuple[str, ...], *, after: str):
    """Class decorator, applied below ``@dataclass``: float fields ``names`` inserted after field ``after``.

    The dataclass then has the table's quantities as fields in the table's
    order, however many the table holds.
    """

    def add(cls):
        own = dict(cls.__dict__.get("__annotations__", {}))
        if after not in own:
            raise TypeError(f"{cls.__name__} has no field {after!r} to put the quantities after")
        merged = {}
        for key, ann in own.items():
            merged[key] = ann
            if key == after:
                merged.update({n: "float" for n in names})
        cls.__annotations__ = merged
        return cls

    return add


def _check() -> None:
    """The invariants the consumers rely on."""
    assert len(INDEX) == NQ, "quantity names must be unique"
    assert SWEPT == TABLE[:NR], "swept quantities must come first (the result row is the table's first NR entries)"
    for q in TABLE:
        assert q.at_equilibrium in EQUILIBRIUM_RULES, f"{q.name}: unknown equilibrium rule {q.at_equilibrium!r}"


_check()
