"""The stated choices of step, length and grids, and their validation."""

import dataclasses

import pytest

from frictionflow.cli import main
from frictionflow.paper import Settings


def test_published_choices_are_the_paper_method_with_stated_step_and_length():
    s = Settings()
    assert (s.dt, s.t_end, s.vd) == (1e-3, 600.0, 1e-3)
    assert 0.01 in s.zeta_grid and 0.03 in s.zeta_grid and 0.0 in s.zeta_grid


def test_quick_keeps_the_method_and_only_thins_the_grids():
    q, s = Settings.quick(), Settings()
    assert (q.dt, q.t_end, q.vd, q.exact_dense_dt) == (s.dt, s.t_end, s.vd, s.exact_dense_dt)
    assert len(q.zeta_grid) < len(s.zeta_grid)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"dt": 0.0}, r"^dt must be finite and > 0, got 0\.0$"),
        ({"t_end": -5.0}, r"^t_end must be finite and > 0"),
        ({"t_end": 15.0}, r"^t_end must be > 20 \(shown_span: the end of each run the time histories .*\), got 15\.0$"),
        ({"shown_span": 700.0}, r"^t_end must be > 700 \(shown_span: .*\), got 600\.0$"),
        ({"t_end": 2000.0}, r"^window_t_end must be >= t_end = 2000"),
        ({"zeta_grid": (0.0, 0.02)}, r"^zeta_grid must hold .* 0\.01 and 0\.03"),
        ({"band_vb": (0.002,)}, r"^band_vb must hold belt speeds > 0 including V_d"),
    ],
)
def test_bad_settings_fail_with_one_line_naming_the_parameter(change, message):
    with pytest.raises(ValueError, match=message) as err:
        dataclasses.replace(Settings(), **change)
    assert "\n" not in str(err.value)


def test_reproduce_with_a_run_shorter_than_the_span_shown_names_the_option_given(tmp_path, capsys):
    """``--t-end 20`` is refused naming t_end, the option the user gave, not the setting it meets (shown_span)."""
    assert main(["reproduce", "--t-end", "20", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --t-end must be > 20 (shown_span: ") and err.count("\n") == 1, err
    assert not (tmp_path / "out").exists()
