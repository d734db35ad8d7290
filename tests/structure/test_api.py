"""run_assembly's refusals (one line naming the parameter) and the result's names."""

from __future__ import annotations

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly, supported_laws

from .builders import single_mass


def test_only_piecewise_constant_switch_laws_are_supported():
    assert set(supported_laws().values()) == {"coulomb"}
    asm = single_mass(0.05, 0.1, ff.Stribeck(fd=0.02, fs=0.04, vs=0.05), 0.0, 0.0)
    with pytest.raises(ValueError, match=r"^solver=exact runs structures whose contacts' laws are coulomb; "
                                         r"contact\.0 has friction=stribeck; use solver=adaptive$"):
        run_assembly(asm, 10.0)


@pytest.mark.parametrize("kw, match", [({"t_end": 0.0}, "t_end must be"), ({"t_end": float("nan")}, "t_end must be"),
                                       ({"t_end": 1.0, "dense_dt": -1.0}, "dense_dt must be")])
def test_bad_settings_are_refused_in_one_line(kw, match):
    asm = single_mass(0.05, 0.1, ff.Coulomb(fd=0.02), 0.0, 0.0)
    with pytest.raises(ValueError, match=match):
        run_assembly(asm, **kw)


def test_names_label_the_result():
    asm = single_mass(0.05, 0.01, ff.Coulomb(fd=0.02, fs=0.04), 0.02, 0.01)
    motion = run_assembly(asm, 20.0, names={"dof": ["x"], "contact": ["pad"]})
    assert motion.dof == ("x",) and motion.contacts == ("pad",)
    assert motion.channels == ("spring.0", "damper.0", "pad.belt", "pad.heat")
    ds = motion.to_xarray()
    assert list(ds.dof.values) == ["x"] and list(ds.contact.values) == ["pad"]
    np.testing.assert_array_equal(ds["q"].values[:, 0], motion.state[0])
    assert set(motion.element_power(1.0, 2.0)) == {"spring.0", "damper.0", "pad"}
    with pytest.raises(ValueError, match="t must be in"):
        motion.at(25.0)
