"""Basins of attraction and basin stability of the friction oscillator.

>>> from frictionflow.basins import basins
>>> b = basins(friction="stribeck", fd=0.02, fs=0.04, vs=0.05, delta=1.0, zeta=0.03, vb=0.12,
...            t_end=300.0, x0=(-0.3, 0.35), v0=(-0.3, 0.3), sample=500, seed=1)   # doctest: +SKIP
>>> b.fractions                                                                       # doctest: +SKIP
{'equilibrium': 0.09, 'stick_slip_cycle': 0.91, 'not_settled': 0.0, 'diverged': 0.0}

The initial states are a sweep (:mod:`frictionflow.sweep`: chunked,
resumable, local or Dask); the attractors are labelled afterwards over the
whole dataset (:mod:`.labels`).
"""

import sys
import types
import warnings

from .labels import DIVERGED, NOT_SETTLED, Attractor, Tolerances, label_attractors
from .plotting import plot_basins
from .study import Basins, SweepOptions, basins, write_dataset

__all__ = ["DIVERGED", "NOT_SETTLED", "Attractor", "Basins", "Tolerances", "basins", "label_attractors", "plot_basins", "SweepOptions", "write_dataset"]


class _CallableModule(types.ModuleType):
    """The subpackage, still callable as the function it used to be at top level (for one release).

    ``from frictionflow import basins; basins(...)`` gave the function until
    ``frictionflow.basins`` became this subpackage; the call goes on working,
    with a DeprecationWarning naming the new spelling.
    """

    def __call__(self, *args, **kwargs):
        warnings.warn("calling the module frictionflow.basins is deprecated: use frictionflow.basins.basins(...) "
                      "or frictionflow.compute_basins(...)", DeprecationWarning, stacklevel=2)
        return basins(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
