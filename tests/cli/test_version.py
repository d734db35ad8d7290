"""``frictionflow --version``, the command list's help texts, and shell completion."""

from __future__ import annotations

import os
import subprocess
import sys
from importlib.metadata import version

import pytest

from frictionflow.cli import SHORT_HELP, main


def test_version_prints_the_installed_version(capsys):
    assert main(["--version"]) == 0
    out, _ = capsys.readouterr()
    assert out.strip() == f"frictionflow {version('frictionflow')}"


def test_version_works_as_a_program():
    done = subprocess.run([sys.executable, "-m", "frictionflow", "--version"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.startswith("frictionflow ")


def test_the_command_list_shows_every_help_text_whole(capsys):
    assert main(["--help"]) == 0
    out, _ = capsys.readouterr()
    words = " ".join(out.split())  # the same whatever the terminal's width
    for name, text in SHORT_HELP.items():
        assert f"{name} {text}" in words  # whole, not cut at a period or with "..."
    assert "..." not in out.split("Commands:")[1]
    assert "Reproduce Figs. 2-6" in out


@pytest.mark.parametrize("words, expected", [("frictionflow si", "simulate"), ("frictionflow simulate --fri", "--friction")])
def test_shell_completion_completes_commands_and_options(words, expected):
    # what the script installed by --install-completion asks the program (the README documents it)
    env = dict(os.environ, _FRICTIONFLOW_COMPLETE="complete_bash", COMP_WORDS=words, COMP_CWORD=str(len(words.split()) - 1))
    code = "import sys; sys.argv[0] = 'frictionflow'; from frictionflow.cli import run; run()"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    assert expected in done.stdout.split()
