"""``frictionflow reproduce`` end to end (quick settings), and its bad-input errors.

(The CLI test lives beside the other paper tests: tests/cli/ belongs to the CLI's owners.)
"""

import contextlib
import io
import json
import re

import pytest
import xarray as xr

from frictionflow.cli import main

STEMS = ("fig2", "fig3", "fig4", "fig5", "fig6")
EXTRA = ("case2_decay", "window_dependence", "karnopp_band")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One quick reproduction: (output directory, what it printed)."""
    d = tmp_path_factory.mktemp("repro") / "out"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["reproduce", "--out", str(d), "--quick", "--dpi", "120"])
    assert code == 0
    return d, printed.getvalue()


@pytest.fixture(scope="module")
def out(run):
    return run[0]


def test_writes_every_figure_as_png_and_pdf(out):
    for stem in STEMS + EXTRA:
        for ext in (".png", ".pdf"):
            p = out / f"{stem}{ext}"
            assert p.stat().st_size > 5_000, p


def test_the_figures_are_at_the_dpi_asked_for(out):
    from PIL import Image

    for stem in STEMS + EXTRA:
        with Image.open(out / f"{stem}.png") as im:
            assert im.info["dpi"] == pytest.approx((120, 120), abs=0.0254)  # pHYs: whole pixels per metre


def test_writes_the_data_of_every_figure_as_netcdf_with_units_and_csv(out):
    for stem in STEMS + ("case2_transient", "karnopp_band_sweep", "karnopp_band_history"):
        ds = xr.open_dataset(out / f"{stem}.nc")
        assert (out / f"{stem}.csv").stat().st_size > 0
        for var in ds.data_vars:
            assert ds[var].attrs.get("long_name"), (stem, var)
        assert ds.attrs["setting_t_end"] == 600.0


def test_report_is_self_contained_and_has_each_figure_with_its_caption_and_verdicts(out):
    html = (out / "report.html").read_text(encoding="utf-8")
    assert len(re.findall(r'<img [^>]*src="data:image/png;base64,', html)) == len(STEMS + EXTRA)
    assert not re.search(r'(src|href)="(https?:)?//', html)  # nothing to fetch: opens offline
    for n in range(2, 7):
        assert f"<h2>Fig. {n}</h2>" in html
    assert "Limit cycles on steady-state response for case II" in html  # the paper's caption of Fig. 3
    assert "Where the paper differs" in html
    claims = json.loads((out / "claims.json").read_text())
    assert all(f'class="verdict {c["verdict"]}"' in html for c in claims)


def test_prints_the_verdicts_and_where_the_report_is(run):
    printed = run[1]
    assert "case2_settles_on_a_limit_cycle" in printed and "refuted" in printed and "report.html" in printed


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--t-end", "-1"], r"^error: --t-end must be finite and in \(0, 1e\+12\], got -1\.0$"),
        (["--dt", "0"], r"^error: --dt must be finite and in \[1e-09, 1000\], got 0\.0$"),
        (["--workers", "0"], r"^error: --workers must be an integer and >= 1, got 0$"),
    ],
)
def test_bad_input_is_one_line_and_exit_2_before_any_work(tmp_path, capsys, args, message):
    target = tmp_path / "never"
    code = main(["reproduce", "--out", str(target), *args])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert re.match(message, err) and "\n" not in err
    assert not target.exists()


def test_out_must_be_a_directory_under_an_existing_parent(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["reproduce", "--out", str(f)]) == 2
    assert capsys.readouterr().err.startswith("error: --out must be a directory")
    assert main(["reproduce", "--out", str(tmp_path / "no" / "such")]) == 2
    assert "parent directory" in capsys.readouterr().err
