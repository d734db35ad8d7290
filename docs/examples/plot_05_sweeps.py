"""
Sweeps: from a laptop to a Dask cluster
=======================================

A sweep runs ``simulate``'s analysis at every point of a grid of parameters
and returns one labelled :class:`xarray.Dataset`.  The grid is cut into
chunks, each computed by compiled kernels in parallel and committed to the
output as it finishes: kill a sweep and run the same call again, and it
recomputes only what is missing.
"""

# %%
# A small sweep on this machine
# -----------------------------
# The config is what a TOML file would hold: ``simulate``'s settings plus a
# ``grid``.  Here: Coulomb friction with F_s = 2 F_d, damping against belt
# speed.
import tempfile
import time
from pathlib import Path

from frictionflow.sweep import plot_cut, plot_map, run_sweep

config = {
    "friction": "coulomb",
    "fd": 0.02,
    "fs": 0.04,
    "t_end": 300.0,
    "grid": {
        "zeta": {"start": 0.0, "stop": 0.12, "num": 13},
        "vb": {"start": 0.004, "stop": 0.04, "num": 8, "scale": "log"},
    },
}
out = Path(tempfile.mkdtemp()) / "sweep.zarr"
start = time.perf_counter()
ds = run_sweep(config, out)
print(f"{ds.sizes} in {time.perf_counter() - start:.1f} s")
ds

# %%
# Every variable carries its units and meaning; ``kind`` says what each point
# settled into (0 periodic, 1 equilibrium, 2 not settled, 3 diverged).
print(ds.R_c.attrs["long_name"])
print(ds.kind.values)

# %%
# A map and a cut
# ---------------
# The share of the friction input the damper dissipates, R_c = P_dv / P_fin,
# over the grid (blank where the motion settled onto the sliding
# equilibrium, which has no vibration).
fig = plot_map(ds, "R_c", "zeta", "vb", log=(False, True))

# %%
# The force reaching the wall, TR_B, against damping, one line per belt speed.
fig = plot_cut(ds.isel(vb=slice(0, 8, 2)), "TR_B", "zeta", hue="vb")

# %%
# Resuming
# --------
# The output records which chunks are done: the same call again finds them
# all and computes nothing.
start = time.perf_counter()
again = run_sweep(config, out)
print(f"second call: {time.perf_counter() - start:.2f} s, identical: {again.identical(ds)}")

# %%
# On a Dask cluster
# -----------------
# The same sweep runs on a cluster by giving the scheduler's address (or a
# ``dask.distributed.Client``); each chunk is one task, whose worker returns
# its results to the process that called ``run_sweep`` (the driver), which
# commits each chunk to the output as it arrives: workers never write.  Not
# run here, as it needs a cluster:
#
# .. code-block:: python
#
#    from dask.distributed import Client
#
#    client = Client("tcp://scheduler.example:8786")
#    ds = run_sweep("sweep.toml", "/shared/results.zarr", client=client)
#
# or from the shell:
#
# .. code-block:: bash
#
#    frictionflow sweep sweep.toml --out /shared/results.zarr --scheduler tcp://scheduler.example:8786
#
# The output path is on the machine running ``run_sweep`` (or ``frictionflow
# sweep``): it need not be shared with the workers.  ``pip install
# "frictionflow[dask]"`` on every machine brings the Dask dependencies.
