"""The documentation builds, warnings as errors, running every example of its gallery.

The build is the README's command, on a copy of ``docs/`` (the gallery
writes its generated pages beside its sources: a copy keeps the checkout
clean).  About a minute on two cores.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("sphinx_gallery")

DOCS = Path(__file__).resolve().parent.parent / "docs"
GENERATED = ("_build", "auto_examples", "generated", "sg_execution_times.rst")


def test_docs_build_with_their_gallery_and_no_warning(tmp_path):
    src = tmp_path / "docs"
    shutil.copytree(DOCS, src, ignore=shutil.ignore_patterns(*GENERATED))
    out = tmp_path / "html"
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(src), str(out)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-5000:]
    examples = sorted(p.stem for p in (src / "examples").glob("plot_*.py"))
    assert len(examples) >= 6
    for name in examples:  # every example ran and drew at least one figure
        assert (out / "auto_examples" / f"{name}.html").is_file()
        assert list((out / "_images").glob(f"sphx_glr_{name}_001.png")), f"{name} drew no figure"
    api = (out / "api.html").read_text()
    assert "frictionflow.simulate" in api and "frictionflow.Trajectory" in api
    assert (out / "generated" / "frictionflow.Trajectory.html").is_file()
