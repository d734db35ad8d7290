"""Parameter sweeps: many simulations, one labelled dataset, resumable, local or on a Dask cluster."""

from .compute import KIND_NAMES, VARIABLES, compute_chunk
from .config import GRID_KEYS, SweepConfig, load_sweep, parse_sweep
from .model import ModelSweepConfig, load_model_sweep, parse_model_sweep
from .store import verify_sweep
from .plotting import plot_cut, plot_map
from .runner import repair_sweep, run_sweep

__all__ = [
    "GRID_KEYS",
    "KIND_NAMES",
    "ModelSweepConfig",
    "VARIABLES",
    "SweepConfig",
    "compute_chunk",
    "load_model_sweep",
    "load_sweep",
    "parse_model_sweep",
    "parse_sweep",
    "plot_cut",
    "plot_map",
    "repair_sweep",
    "run_sweep",
    "verify_sweep",
]
