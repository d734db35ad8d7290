"""The documentation builds, warnings as errors, running every example of its gallery; what it shows is checked.

The build is the command the guide gives, on a copy of ``docs/`` (the gallery
and the command-line reference write their generated pages beside their
sources: a copy keeps the checkout clean), once for the module.  About a minute
on two cores, most of it the gallery.

The equations are typeset by a copy of MathJax shipped with the site
(``sphinx-mathjax-offline``).  A headless Chromium opens built pages with every
host name unresolvable and must find no raw TeX in the visible text.  pip cannot
provide that browser: the ``playwright`` wheel carries only a driver, and
``playwright install chromium`` downloads the browser from its own CDN, not from
PyPI (tried: it fails where only package registries are reachable).  Debian's
``chromium-headless-shell`` (or any Chromium or Chrome on the ``PATH``, or
``FRICTIONFLOW_CHROMIUM``) is used; without one the browser test is skipped,
saying so, and the non-browser checks (the pages load the bundled MathJax by a
relative path, nothing from the network, and the bundle with its fonts is in
the site) still run.
"""

from __future__ import annotations

import enum
import html.parser
import inspect
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("sphinx_gallery")
pytest.importorskip("myst_parser")
pytest.importorskip("sphinx-mathjax-offline")

import typer  # noqa: E402
from sphinx.ext.napoleon import Config, NumpyDocstring  # noqa: E402
from sphinx.pycode import ModuleAnalyzer  # noqa: E402

from frictionflow.cli import COMMAND_MODULES, app, load_commands  # noqa: E402
from frictionflow import quantities as Q  # noqa: E402
from frictionflow.analysis.structure import STRUCTURE_KINDS  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
GENERATED = ("_build", "auto_examples", "generated", "sg_execution_times.rst")
GUIDE = ("installation", "model", "models", "friction", "solvers", "steady_states", "power_flow", "forcing", "orbits",
         "lyapunov", "basins", "sweeps", "paper")
BROWSERS = ("chromium-headless-shell", "chromium", "chromium-browser", "google-chrome", "google-chrome-stable",
            "chrome", "headless_shell")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site built from a copy of ``docs/`` with ``-W``; its html directory."""
    tmp = tmp_path_factory.mktemp("docs")
    src = tmp / "docs"
    shutil.copytree(DOCS, src, ignore=shutil.ignore_patterns(*GENERATED))
    # CHANGELOG.md and CITATION.cff are included from the repository's root, one level up
    for name in ("CHANGELOG.md", "CITATION.cff"):
        shutil.copy(ROOT / name, tmp / name)
    out = tmp / "html"
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(src), str(out)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900, cwd=tmp)
    assert done.returncode == 0, done.stderr[-5000:]
    return out


class _Text(html.parser.HTMLParser):
    """The text a reader sees: no script, style or head, nor MathJax's hidden MathML for screen readers."""

    HIDDEN = {"script", "style", "head", "mjx-assistive-mml", "template"}

    def __init__(self) -> None:
        super().__init__()
        self.depth = 0
        self.parts: list[str] = []

    def handle_starttag(self, tag, attrs):  # noqa: ANN001
        if tag in self.HIDDEN or self.depth:
            self.depth += tag not in {"br", "img", "meta", "link", "input", "hr"}

    def handle_endtag(self, tag):  # noqa: ANN001
        if self.depth:
            self.depth -= 1

    def handle_data(self, data):  # noqa: ANN001
        if not self.depth:
            self.parts.append(data)


def visible_text(page: str) -> str:
    parser = _Text()
    parser.feed(page)
    return " ".join(parser.parts)


def test_docs_build_with_their_gallery_and_no_warning(site):
    examples = sorted(p.stem for p in (DOCS / "examples").glob("plot_*.py"))
    assert len(examples) >= 6
    for name in examples:  # every example ran and drew at least one figure
        assert (site / "auto_examples" / f"{name}.html").is_file()
        assert list((site / "_images").glob(f"sphx_glr_{name}_001.png")), f"{name} drew no figure"


def test_the_guide_has_every_page_in_its_table_of_contents(site):
    index = (site / "guide" / "index.html").read_text()
    for name in GUIDE:
        assert (site / "guide" / f"{name}.html").is_file(), name
        assert f'href="{name}.html"' in index, f"{name} is not in the guide's table of contents"
    for page in ("cli", "api/index", "contributing", "changelog", "citation"):
        assert f'href="{page}.html"' in (site / "index.html").read_text(), page
    changelog = visible_text((site / "changelog.html").read_text())
    assert "Unreleased" in changelog and "SwitchMode" in changelog  # CHANGELOG.md itself, rendered
    assert "cff-version" in (site / "citation.html").read_text()


def _commands() -> dict:
    load_commands(None)
    return typer.main.get_command(app).commands


def test_the_command_line_reference_has_every_command_and_every_option(site):
    page = (site / "cli.html").read_text()
    commands = _commands()
    assert set(commands) == set(COMMAND_MODULES)
    for name, command in commands.items():
        match = re.search(rf'<section id="frictionflow-{re.escape(name)}">(.*?)</section>', page, re.S)
        assert match, f"no section for {name}"
        text = visible_text(match.group(1))
        for param in command.params:
            for opt in param.opts:
                if opt.startswith("-"):
                    assert opt in text, f"{name}: {opt} missing from the reference"
            if param.help:  # the help text is the command's own, not a paraphrase
                assert " ".join(param.help.split())[:40] in " ".join(text.split()), f"{name} {param.name}"


def _api_objects() -> list[str]:
    """Every object the API pages document (their autofunction/autoclass directives)."""
    names = []
    for page in sorted((DOCS / "api").glob("*.rst")):
        names += re.findall(r"^\.\. auto(?:function|class):: (\S+)", page.read_text(), re.M)
    return names


def _resolve(name: str):  # noqa: ANN202
    module, _, attr = name.rpartition(".")
    while True:
        try:
            obj = __import__(module, fromlist=["_"])
            break
        except ImportError:
            module, _, head = module.rpartition(".")
            attr = f"{head}.{attr}"
    for part in attr.split("."):
        obj = getattr(obj, part)
    return obj


def test_the_api_reference_is_grouped_by_topic_and_public(site):
    topics = re.findall(r'class="reference internal" href="(\w+)\.html"', (site / "api" / "index.html").read_text())
    assert 8 <= len(set(topics)) <= 15, topics  # topics in the sidebar, not one entry per name
    names = _api_objects()
    assert len(names) >= 80 and len(set(names)) == len(names)
    for name in names:
        assert not any(part.startswith("_") for part in name.split(".")), name
        assert not name.startswith("frictionflow.core"), name
        _resolve(name)
    pages = {p.stem: p.read_text() for p in (site / "api").glob("*.html")}
    assert "frictionflow.simulate" in pages["simulation"] and "frictionflow.Trajectory" in pages["simulation"]
    for stem, page in pages.items():  # a summary is a sentence, not cut at an abbreviation
        for cell in re.findall(r'<td><p>(.*?)</p></td>', page, re.S):
            text = visible_text(cell).strip()
            assert not re.search(r"\b(Eq|Eqs|Fig|Figs)\.$", text), f"{stem}: summary cut: {text!r}"


def _documented(obj) -> set[str]:  # noqa: ANN001
    """Names a NumPy docstring describes (Parameters, Other Parameters, a class's Attributes), and ``#:`` fields."""
    lines = str(NumpyDocstring(inspect.getdoc(obj) or "", Config(napoleon_use_param=True), what="class"))
    names = set()
    if inspect.isclass(obj):  # a dataclass field documented by a "#:" comment is an attribute on the page
        for klass in (k for k in obj.__mro__ if k.__module__.startswith("frictionflow")):
            docs = ModuleAnalyzer.for_module(klass.__module__).find_attr_docs()
            names.update(attr for (scope, attr), doc in docs.items() if scope == klass.__qualname__ and "".join(doc).strip())
    for field in re.findall(r"^:param ([^:]+):", lines, re.M) + re.findall(r"^\.\. attribute:: (.+)$", lines, re.M):
        names.update(n.strip().lstrip("\\*") for n in field.split(","))
    return names


def _parameters(obj) -> list[str]:  # noqa: ANN001
    target = obj.__init__ if inspect.isclass(obj) else obj
    try:
        sig = inspect.signature(target)
    except (TypeError, ValueError):
        return []
    return [n for n, p in sig.parameters.items() if n not in ("self", "cls") and not n.startswith("_")
            and not (inspect.isclass(obj) and issubclass(obj, BaseException))]


def test_every_public_parameter_is_described():
    missing = {}
    for name in _api_objects():
        obj = _resolve(name)
        if inspect.isclass(obj) and (obj.__init__ is object.__init__ or issubclass(obj, enum.Enum)):
            continue
        lacking = set(_parameters(obj)) - _documented(obj)
        if lacking:
            missing[name] = sorted(lacking)
    assert not missing, f"parameters without a description: {missing}"


def test_the_equations_use_the_mathjax_shipped_with_the_site(site):
    bundle = site / "_static" / "mathjax"
    assert (bundle / "tex-chtml.js").stat().st_size > 100_000
    assert list((bundle / "output" / "chtml" / "fonts" / "woff-v2").glob("MathJax_Main-Regular.woff"))
    for page in [site / "guide" / "model.html", site / "guide" / "power_flow.html", site / "index.html"]:
        text = page.read_text()
        assert 'class="math' in text, f"{page.name} has no equation to check"
        scripts = re.findall(r'<script[^>]*\bsrc="([^"]+)"', text)
        assert any(s.endswith("_static/mathjax/tex-chtml.js") and not s.startswith(("http:", "https:", "//"))
                   for s in scripts), scripts
        assert not [s for s in scripts if s.startswith(("http:", "https:", "//"))], scripts


def _browser() -> str | None:
    given = os.environ.get("FRICTIONFLOW_CHROMIUM")
    if given:
        return given
    for name in BROWSERS:
        if path := shutil.which(name):
            return path
    for path in sorted(Path.home().glob(".cache/ms-playwright/*/*/chrome*")):  # a playwright install, if any
        if path.is_file() and os.access(path, os.X_OK):
            return str(path)
    return None


def test_equations_render_offline_in_headless_chromium(site):
    browser = _browser()
    if browser is None:
        pytest.skip("no headless Chromium (pip cannot install one; Debian: apt-get install chromium-headless-shell)")
    for page in ("guide/model.html", "guide/power_flow.html", "index.html"):
        source = (site / page).read_text()
        equations = source.count('class="math notranslate nohighlight"')
        assert equations > 0
        cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
               "--host-resolver-rules=MAP * ~NOTFOUND",  # no network: every host name fails
               "--virtual-time-budget=30000", "--dump-dom", (site / page).as_uri()]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr[-2000:]
        dom = done.stdout
        text = visible_text(dom)
        for raw in ("\\(", "\\)", "\\[", "\\begin", "$$"):
            assert raw not in text, f"{page}: raw TeX {raw!r} in the visible text"
        assert dom.count("<mjx-container") == equations, f"{page}: not every equation typeset"


def test_the_readme_is_a_landing_page_whose_links_resolve():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) < 80  # the long content lives in the guide
    for command in ("pip install . && frictionflow simulate --fd 0.02 --vb 0.01 --zeta 0 --plot case1.png",
                    'pip install ".[test]" && python -m pytest'):
        assert command in readme
    links = re.findall(r"\]\(([^)#]+)\)", readme)
    assert len(links) >= 15
    for link in links:
        if not link.startswith(("http:", "https:")):
            assert (ROOT / link).exists(), f"README links to a missing {link}"


def test_the_citation_file_is_complete_and_names_this_version():
    yaml = pytest.importorskip("yaml")
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    for key in ("cff-version", "message", "title", "authors", "version", "license"):  # CFF 1.2.0 requires the first four
        assert cff.get(key), key
    assert all(a.get("name") or a.get("family-names") for a in cff["authors"])
    project = re.search(r'^version = "([^"]+)"', (ROOT / "pyproject.toml").read_text(), re.M).group(1)
    assert str(cff["version"]) == project


def test_the_sweep_guide_lists_every_kind_code_a_dataset_holds():
    """The codes of ``kind`` as docs/guide/sweeps.md lists them, for the single mass and for a model sweep, are the
    datasets' own (``flag_meanings``: the kinds in code order)."""
    text = " ".join((Path(__file__).parents[1] / "docs" / "guide" / "sweeps.md").read_text().split())
    listed = [re.findall(r"(\d) ([a-z-]+(?: [a-z]+)?)", m) for m in re.findall(r"`kind` \(([^)]*)\)", text)]
    assert len(listed) == 2, listed
    for pairs, kinds in zip(listed, (Q.KINDS, STRUCTURE_KINDS)):
        names = [name.replace(" ", "_").replace("-", "_") for _, name in pairs]
        assert [int(code) for code, _ in pairs] == list(range(len(kinds)))
        assert names == list(kinds), (names, kinds)
