"""Trajectory's state and contact blocks (issue 19, item 3): nothing in the record assumes one mass or one contact."""

from __future__ import annotations

import numpy as np

from frictionflow import BeltOscillator, Coulomb, simulate
from frictionflow.trajectory import WORK_NAMES, Trajectory


def _two_mass(n: int = 50) -> Trajectory:
    t = np.linspace(0.0, 5.0, n)
    state = np.stack([np.sin(t), np.cos(t), 0.5 * np.sin(2 * t), np.cos(2 * t)])
    force = np.stack([0.1 * np.sign(np.cos(t)), -0.2 * np.ones(n)])
    modes = np.stack([np.sign(np.cos(t)), np.zeros(n)]).astype(np.int8)
    return Trajectory(t=t, state=state, force=force, modes=modes, dwork=np.zeros((n, len(WORK_NAMES))),
                      model=BeltOscillator(0.05, 0.01), friction=Coulomb(0.1, 0.2), solver={"name": "made-up"},
                      state_names=("q1", "p1", "q2", "p2"), contact_names=("left", "right"))


def test_a_four_state_two_contact_record_exports_every_row_by_name():
    traj = _two_mass()
    ds = traj.to_xarray(dense=False)
    for i, name in enumerate(traj.state_names):
        np.testing.assert_array_equal(ds[name].values, traj.state[i])
    for j, name in enumerate(traj.contact_names):
        np.testing.assert_array_equal(ds[f"F_c_{name}"].values, traj.force[j])
        np.testing.assert_array_equal(ds[f"mode_{name}"].values, traj.modes[j])
        assert list(ds[f"mode_{name}"].attrs["flag_values"]) == [-1, 0, 1]
    assert "X" not in ds and "F_c" not in ds


def test_the_single_mass_columns_are_views_of_the_blocks():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=30.0)
    assert traj.state.shape == (2, len(traj.t)) and traj.force.shape == traj.modes.shape == (1, len(traj.t))
    assert np.shares_memory(traj.x, traj.state) and np.shares_memory(traj.mode, traj.modes)
    assert traj.x.flags.c_contiguous and traj.v.flags.c_contiguous  # compiled analysis gets contiguous rows
    traj.v[3] = 123.0
    assert traj.state[1, 3] == 123.0
    ds = traj.to_xarray(dense=False)
    assert {"X", "V", "F_c", "mode"} <= set(ds.data_vars)


def test_dense_keeps_every_recorded_row_of_every_block():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=30.0)
    dense = traj.dense(points_per_period=200)
    keep = np.flatnonzero(dense.recorded)
    np.testing.assert_array_equal(dense.state[:, keep], traj.state)
    np.testing.assert_array_equal(dense.force[:, keep], traj.force)
    np.testing.assert_array_equal(dense.modes[:, keep], traj.modes)
