"""The documentation site (docs/conf.py, docs/api/, examples/): only where Sphinx is installed.

Install with ``pip install -e ".[docs]"``.  The default run checks the sources quickly:

* every gallery script ``examples/plot_*.py`` opens with a sphinx-gallery title docstring (a title line
  underlined with ``=``, then some explanation), and there are at least 12 of them;
* ``docs/conf.py`` points sphinx-gallery at ``examples/`` and the index links the generated gallery;
* the API reference (``docs/api/*.rst``) lists every public name: the lazy table of ``coinwall``
  (``coinwall/__init__.pyi``) and the ``__all__`` of each public module it documents.

``python -m pytest -m slow tests/test_docs_site.py`` also builds the whole site with ``-W`` (warnings are
errors) into a temporary folder and checks the gallery's thumbnails and the API reference's links.
"""

from __future__ import annotations

import ast
import importlib
import os
import re
import runpy
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("sphinx_gallery")

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))

# modules whose __all__ the API reference documents (docs/api/*.rst), besides coinwall's own lazy table
DOCUMENTED_MODULES = (
    "coinwall.forward",
    "coinwall.forward.dynamics",
    "coinwall.forward.formats",
    "coinwall.forward.quantum",
    "coinwall.cases.scan",
    "coinwall.inverse",
    "coinwall.inverse.export",
    "coinwall.inverse.fit",
    "coinwall.inverse.design",
    "coinwall.cases",
)


def test_gallery_has_enough_examples():
    assert len(EXAMPLES) >= 12, [p.name for p in EXAMPLES]


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_has_title_docstring(path):
    """sphinx-gallery takes the title from the docstring's first line, underlined with '='."""
    docstring = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")), clean=True)
    assert docstring, f"{path.name}: no module docstring"
    lines = docstring.splitlines()
    assert len(lines) >= 4, f"{path.name}: a title and a few lines of explanation"
    title, underline = lines[0].strip(), lines[1].strip()
    assert title and not title.startswith("="), f"{path.name}: the first line is the title"
    assert re.fullmatch(r"=+", underline) and len(underline) >= len(title), (
        f"{path.name}: the title must be underlined with '=' at least as long as it"
    )
    assert any(line.strip() for line in lines[2:]), f"{path.name}: no explanation under the title"


def test_example_makes_a_figure_with_the_library():
    for path in EXAMPLES:
        text = path.read_text(encoding="utf-8")
        assert re.search(r"^from coinwall[\w.]* import ", text, re.MULTILINE), f"{path.name}: uses no API"
        assert "matplotlib" in text, f"{path.name}: makes no figure"


def test_conf_lists_the_gallery():
    conf = runpy.run_path(str(DOCS / "conf.py"))
    gallery = conf["sphinx_gallery_conf"]
    examples = [(DOCS / d).resolve() for d in gallery["examples_dirs"]]
    assert (ROOT / "examples").resolve() in examples
    assert len(gallery["gallery_dirs"]) == len(gallery["examples_dirs"])
    assert "sphinx_gallery.gen_gallery" in conf["extensions"]
    for name in ("myst_parser", "numpydoc", "sphinx.ext.autosummary", "sphinx.ext.mathjax"):
        assert name in conf["extensions"]
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    for target in gallery["gallery_dirs"]:
        assert f"{target}/index" in index, f"docs/index.md does not link the gallery {target}"
    assert (ROOT / "examples" / "GALLERY_HEADER.rst").is_file()


def _documented_names():
    """Names listed in the autosummary tables and ``.. data::`` entries of docs/api/*.rst, by module."""
    names = {}
    for rst in sorted((DOCS / "api").glob("*.rst")):
        module = None
        in_summary = False
        for line in rst.read_text(encoding="utf-8").splitlines():
            found = re.match(r"\.\. (?:current)?module:: (\S+)", line)
            if found:
                module = found.group(1)
                continue
            data = re.match(r"\.\. data:: (\w+)", line)
            if data:
                names.setdefault(module, set()).add(data.group(1))
                continue
            if line.startswith(".. autosummary::"):
                in_summary = True
                continue
            if in_summary:
                if line and not line.startswith(" "):
                    in_summary = False
                elif line.strip() and not line.strip().startswith(":"):
                    names.setdefault(module, set()).add(line.strip().lstrip("~").split(".")[-1])
    return names


def test_api_reference_lists_every_public_name():
    import coinwall

    documented = _documented_names()
    everyday = documented.get("coinwall", set())
    top = set(coinwall.__all__) - {"__version__"}
    missing = sorted(top - everyday)
    assert not missing, f"docs/api/coinwall.rst misses {missing}"
    for module_name in DOCUMENTED_MODULES:
        module = importlib.import_module(module_name)
        # a re-exported everyday name is documented once, under coinwall.NAME
        public = {n for n in module.__all__ if n not in top}
        here = set().union(*(v for k, v in documented.items() if k and k.startswith(module_name)))
        # names that coinwall.forward re-exports from its dynamics and formats subpackages
        elsewhere = set().union(*(v for k, v in documented.items() if k and k.startswith("coinwall.forward")))
        missing = sorted(public - here - (elsewhere if module_name == "coinwall.forward" else set()))
        assert not missing, f"the API reference misses {module_name}: {missing}"


# ---------------------------------------------------------------------------------------------- the build
@pytest.mark.slow
def test_site_builds_without_warnings(tmp_path):
    """The whole site, examples run, warnings as errors; then the gallery and the API links are looked at."""
    source = tmp_path / "src"
    shutil.copytree(DOCS, source / "docs", ignore=shutil.ignore_patterns("_build", "generated", "auto_examples"))
    shutil.copytree(ROOT / "examples", source / "examples")
    html = tmp_path / "html"
    run = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(source / "docs"), str(html)],
        check=False, capture_output=True, text=True, timeout=1200, cwd=tmp_path,
    )
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-4000:]

    gallery = (html / "auto_examples" / "index.html").read_text(encoding="utf-8")
    thumbnails = re.findall(r'class="sphx-glr-thumbcontainer"', gallery)
    assert len(thumbnails) >= 12 and len(thumbnails) == len(EXAMPLES)
    for path in EXAMPLES:
        page = html / "auto_examples" / f"{path.stem}.html"
        assert page.is_file(), page
        assert re.search(r'<img [^>]*src="[^"]*sphx_glr_' + re.escape(path.stem) + r'_\d+\.png"',
                         page.read_text(encoding="utf-8")), f"{page.name} shows no figure"

    checked = 0
    for page in sorted((html / "api").rglob("*.html")):
        for href in re.findall(r'href="([^"]+)"', page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", href) or href.startswith("#"):
                continue
            target = (page.parent / href.split("#")[0].split("?")[0]).resolve()
            assert target.exists(), f"{page.relative_to(html)} links to a missing {href}"
            checked += 1
    assert checked > 100
    for name in ("coinwall.solve_body", "coinwall.Wall", "coinwall.forward.quantum.Spectrum"):
        assert (html / "api" / "generated" / f"{name}.html").is_file(), name


# ---------------------------------------------------------------------------------------------- in a browser
_BUILT = os.environ.get("COINWALL_DOCS_HTML")


# the browser reaches no network: every host name fails to resolve and every request goes to a closed proxy
_OFFLINE = ("--proxy-server=http://127.0.0.1:9", "--proxy-bypass-list=<-loopback>",
            "--host-resolver-rules=MAP * ~NOTFOUND")


def _offline_browser():
    """Headless Chromium with no network (skips where selenium, chromium or chromedriver are missing)."""
    pytest.importorskip("selenium")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    driver_path = shutil.which("chromedriver") or "/usr/bin/chromedriver"
    if not (os.path.exists(chromium) and os.path.exists(driver_path)):
        pytest.skip("headless browser tests need chromium and chromedriver")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1366,900",
                     *_OFFLINE):
        options.add_argument(argument)
    return webdriver.Chrome(service=Service(driver_path), options=options)


@pytest.mark.skipif(not _BUILT, reason="set COINWALL_DOCS_HTML to a built site (.ci/run builds it and sets it)")
def test_math_renders_offline_in_a_browser():
    """A page with math shows typeset math, not LaTeX, in a browser that reaches no network: MathJax is part of
    the site (sphinx-mathjax-offline copies it into _static/mathjax), not fetched from a CDN."""
    import time
    from pathlib import Path

    html = Path(_BUILT).resolve()
    page = html / "coin3d.html"
    source = page.read_text(encoding="utf-8")
    scripts = re.findall(r'<script[^>]*src="([^"]*mathjax[^"]*)"', source, re.I)
    assert scripts and all(not re.match(r"[a-z]+:", src) for src in scripts), scripts  # a path in the site
    assert all((page.parent / src.split("?")[0]).is_file() for src in scripts), scripts  # (Sphinx adds ?v=HASH)
    driver = _offline_browser()
    try:
        # the browser really is offline: a CDN request fails
        fetched = driver.execute_script("return fetch('https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-chtml.js')"
                                        ".then(() => 'loaded', () => 'failed')")
        assert fetched == "failed"
        driver.get(page.as_uri())
        end = time.monotonic() + 30
        while time.monotonic() < end:
            typeset = driver.execute_script("return document.querySelectorAll('mjx-container').length")
            if typeset:
                break
            time.sleep(0.1)
        spans = driver.execute_script("return document.querySelectorAll('.math').length")
        assert spans >= 3 and typeset == spans, (spans, typeset)  # every formula of the page typeset
        text = driver.execute_script("return document.body.innerText")
        for raw in ("\\frac", "\\mathcal", "\\dot", "$$"):
            assert raw not in text, f"raw LaTeX {raw!r} shown on {page.name}"
        glyphs = driver.execute_script("return document.querySelectorAll('mjx-container mjx-c').length")
        assert glyphs > 50  # the formulas are drawn glyph by glyph (MathJax's CommonHTML output)
    finally:
        driver.quit()


@pytest.mark.skipif(not _BUILT, reason="set COINWALL_DOCS_HTML to a built site (.ci/run builds it and sets it)")
def test_built_site_in_a_browser():
    """The built site as a reader's browser shows it (headless Chromium): the gallery page shows a loaded
    thumbnail for every example, and every link of the API index leads to a page that exists."""
    from pathlib import Path
    from urllib.parse import unquote, urlparse

    from selenium.webdriver.common.by import By

    html = Path(_BUILT).resolve()
    driver = _offline_browser()
    try:
        driver.get((html / "auto_examples" / "index.html").as_uri())
        images = driver.find_elements(By.CSS_SELECTOR, ".sphx-glr-thumbcontainer img")
        loaded = [img for img in images
                  if driver.execute_script("return arguments[0].complete && arguments[0].naturalWidth > 0", img)]
        assert len(loaded) >= 12 and len(loaded) == len(EXAMPLES), (len(images), len(loaded))
        driver.get((html / "api" / "index.html").as_uri())
        links = [a.get_attribute("href") for a in driver.find_elements(By.CSS_SELECTOR, "article a[href]")]
        local = [link for link in links if link.startswith("file://")]
        assert len(local) > 20
        for link in local:
            path = Path(unquote(urlparse(link).path))
            assert path.exists(), f"the API index links to a missing {link}"
    finally:
        driver.quit()


# the API pages a reader opens first, each with the sections its docstring has (tests/test_api_docs.py)
_API_PAGES = {
    "coinwall.solve_body": ("Parameters", "Returns", "Raises"),
    "coinwall.Wall": ("Attributes",),
    "coinwall.forward.dynamics.basin_map": ("Parameters", "Returns", "Raises"),
    "coinwall.forward.dynamics.toss_outcomes": ("Parameters", "Returns"),
    "coinwall.inverse.design.design": ("Parameters", "Returns", "Raises"),
}


@pytest.mark.skipif(not _BUILT, reason="set COINWALL_DOCS_HTML to a built site (.ci/run builds it and sets it)")
def test_api_pages_show_examples_in_a_browser():
    """The API pages of solve_body, Wall, the toss (basin_map, toss_outcomes) and design, as a browser shows them:
    an Examples heading followed by a visible doctest block of ``>>>`` lines, the numpydoc sections, and on
    solve_body's page its formulas typeset by the bundled MathJax (no network), not raw LaTeX."""
    import time
    from pathlib import Path

    from selenium.webdriver.common.by import By

    html = Path(_BUILT).resolve()
    driver = _offline_browser()
    try:
        for name, sections in _API_PAGES.items():
            page = html / "api" / "generated" / f"{name}.html"
            assert page.is_file(), page
            driver.get(page.as_uri())
            article = driver.find_element(By.CSS_SELECTOR, "article")
            headings = [p.text.strip() for p in article.find_elements(By.CSS_SELECTOR, "p.rubric")]
            assert "Examples" in headings, (name, headings)
            # the doctest block after the Examples heading: shown, with prompts and printed results
            blocks = driver.execute_script(
                "const rubric = [...document.querySelectorAll('article p.rubric')]"
                ".find(p => p.textContent.trim() === 'Examples');"
                "const found = []; for (let n = rubric.nextElementSibling; n && !n.matches('p.rubric');"
                " n = n.nextElementSibling) { if (n.matches('div.doctest')) found.push(n); } return found;")
            assert blocks, f"{name}: no doctest block under Examples"
            text = "\n".join(block.text for block in blocks)
            assert all(block.is_displayed() for block in blocks), name
            assert text.count(">>>") >= 2 and any(line and not line.startswith((">>>", "...")) for line in
                                                  text.splitlines()), f"{name}: {text[:200]!r}"
            fields = [dt.text.strip().rstrip(":") for dt in article.find_elements(By.CSS_SELECTOR, "dl.field-list > dt")]
            for section in sections:
                assert section in fields + headings, (name, section, fields, headings)
        # the API index by task: a table per group, every summary in view at 1366 px (no table scrolls sideways)
        driver.get((html / "api" / "index.html").as_uri())
        tables = driver.find_elements(By.CSS_SELECTOR, "article table.autosummary")
        assert len(tables) >= 8, len(tables)
        wide = driver.execute_script("return [...document.querySelectorAll('article table.autosummary')]"
                                     ".filter(t => t.parentElement.scrollWidth > t.parentElement.clientWidth + 1)"
                                     ".map(t => t.closest('section').querySelector('h3').textContent)")
        assert not wide, f"API index tables wider than the page: {wide}"
        # solve_body's formulas: typeset by MathJax from the site itself, every one of them
        driver.get((html / "api" / "generated" / "coinwall.solve_body.html").as_uri())
        end = time.monotonic() + 30
        spans = driver.execute_script("return document.querySelectorAll('article .math').length")
        typeset = 0
        while time.monotonic() < end and typeset < spans:
            typeset = driver.execute_script("return document.querySelectorAll('article mjx-container').length")
            time.sleep(0.1)
        assert spans >= 3 and typeset == spans, (spans, typeset)
        shown = driver.find_element(By.CSS_SELECTOR, "article").text
        for raw in ("\\theta", "\\min", "\\ge", "\\("):
            assert raw not in shown, f"raw LaTeX {raw!r} shown on solve_body's page"
    finally:
        driver.quit()
