"""Compiled kernels on plain floats and arrays (numba, ``cache=True``).

Nothing here knows about dataclasses, xarray or the CLI: the solver façades in
:mod:`frictionflow.solvers` turn parameter objects into floats and the arrays
returned here into :class:`~frictionflow.trajectory.Trajectory` objects.
"""

from ._cache import refresh as _refresh_kernel_cache

_refresh_kernel_cache()
