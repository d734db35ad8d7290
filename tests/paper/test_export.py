"""Units and long names on every quantity; NetCDF and CSV files."""

import pandas as pd
import pytest
import xarray as xr

from frictionflow.paper.export import annotate, long_name, write_dataset


@pytest.mark.parametrize("name", ["fig2", "fig3", "fig4", "fig5", "fig6", "transient", "band_sweep", "band_history"])
def test_every_variable_and_coordinate_has_a_long_name_and_numbers_have_units(data, name):
    ds = annotate(data[name].copy(), "t")
    for var in list(ds.data_vars) + list(ds.coords):
        assert ds[var].attrs.get("long_name"), (name, var)
        if ds[var].dtype.kind in "fiu":
            assert ds[var].attrs.get("units") == "1", (name, var)


def test_prefixed_names_spell_out_the_window():
    assert long_name("last_R_c").startswith("over the last whole cycle before t_end: ")
    assert long_name("steady_TR_B").startswith("in the steady state")
    with pytest.raises(KeyError, match="no long name for 'mystery'"):
        long_name("mystery")


def test_netcdf_round_trips_and_csv_has_one_table_per_set_of_dimensions(data, tmp_path):
    ds = annotate(data["fig2"].copy(), "Fig. 2")
    paths = write_dataset(ds, tmp_path, "fig2")
    assert {p.name for p in paths} == {"fig2.nc", "fig2.csv", "fig2_solver-case.csv", "fig2_case.csv"}
    back = xr.open_dataset(tmp_path / "fig2.nc")
    xr.testing.assert_allclose(back.P_f, ds.P_f)
    assert back.P_f.attrs["long_name"].startswith("instantaneous friction power")
    table = pd.read_csv(tmp_path / "fig2.csv")
    assert {"solver", "case", "tau", "P_f", "X", "V"} <= set(table.columns)
    assert len(table) == ds.sizes["solver"] * ds.sizes["case"] * ds.sizes["tau"]
