"""A ``--config`` key that the command takes no option for is refused in one line, as the sweeps refuse theirs: it
was ignored without a word (``orbit`` with ``window``, ``dt`` and ``ode_rtol``, ``response`` with ``t_end`` and with
``omega``, which its ``--vary`` sets)."""

from __future__ import annotations

import pytest

from frictionflow.cli.options import command_config

from .processes import in_process, one_line

CASES = [
    ("orbit", [], "window = \"0:1\"\n", "window"),
    ("orbit", [], "dt = 0.5\n", "dt"),
    ("forced-orbit", ["--fex", "0.1"], "t_end = 0.001\n", "t_end"),
    ("response", ["--fex", "0.1", "--vary", "omega=0.8:1.2:3"], "omega = 0.8\n", "omega"),
    ("response", ["--fex", "0.1", "--vary", "omega=0.8:1.2:3"], "t_end = 50.0\n", "t_end"),
    ("map", ["--x", "vb=0.01:0.03", "--y", "zeta=0:0.5"], "window = \"0:1\"\n", "window"),
    ("lyapunov", [], "rtol = 1e-6\n", "rtol"),
    # a command's own options (not the model's) are not config keys: the message said a config took them
    ("orbit", [], "tol = 1e-10\n", "tol"),
    ("lyapunov", [], "t_transient = 5.0\n", "t_transient"),
]


@pytest.mark.parametrize("command, args, text, key", CASES, ids=[f"{c[0]}-{c[3]}" for c in CASES])
def test_a_config_key_the_command_does_not_take_is_refused(tmp_path, command, args, text, key):
    config = tmp_path / "c.toml"
    config.write_text('friction = "coulomb"\nfd = 0.02\nfs = 0.04\n' + text)
    code, out, err, _ = in_process(command, *args, "--config", str(config), "--json")
    assert code == 2 and out == ""
    one_line(err, f"--config: key {key!r} is not used by {command}", "holds the model's options",
             f"frictionflow {command} --help")


def test_a_config_of_the_command_s_own_keys_runs_as_the_options_do(tmp_path):
    config = tmp_path / "c.toml"
    config.write_text('friction = "coulomb"\nfd = 0.02\nfs = 0.04\nzeta = 0.05\nvb = 0.01\n')
    by_file = in_process("orbit", "--config", str(config), "--json")
    by_options = in_process("orbit", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--zeta", "0.05", "--vb",
                            "0.01", "--json")
    assert by_file[0] == 0 and by_file[1] == by_options[1]


def test_the_settings_a_command_reads_from_a_config_alone_are_kept(tmp_path):
    """lyapunov's max_memory and response's rtol have no option but are read from a config: they stay allowed."""
    config = tmp_path / "c.toml"
    config.write_text("max_memory = 100.0\nrtol = 1e-7\n")
    assert command_config("lyapunov", config, {"friction": None}, config_only=("max_memory", "rtol")).max_memory == 100.0
    with pytest.raises(ValueError, match=r"key 'rtol' is not used by lyapunov"):
        command_config("lyapunov", config, {"friction": None}, config_only=("max_memory",))
