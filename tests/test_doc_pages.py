"""The documentation: generated pages match the code, the built site needs no network."""

import re
import subprocess
import sys

import pytest

from .doc_pages import DOCS, PAGES

ROOT = DOCS.parent


@pytest.mark.parametrize("name", sorted(PAGES))
def test_generated_page_is_up_to_date(name):
    assert (DOCS / name).read_text() == PAGES[name]() + "\n", f"docs/{name} is stale: run python -m tests.doc_pages --write"


def test_generated_pages_are_in_the_navigation():
    nav = (ROOT / "mkdocs.yml").read_text().split("\nnav:\n", 1)[1]
    for name in PAGES:
        assert f": {name}\n" in nav


def test_no_resource_comes_from_the_network():
    """MathJax is served with the site (vendored), the theme loads no web fonts."""
    config = (ROOT / "mkdocs.yml").read_text()
    assert "font: false" in config
    scripts = re.findall(r"^extra_javascript:\n((?:  - .*\n)+)", config, re.M)[0]
    assert "http" not in scripts
    for script in re.findall(r"- (\S+)", scripts):
        assert (DOCS / script).is_file(), script
    mathjax = DOCS / "javascripts" / "mathjax"
    assert (mathjax / "LICENSE").read_text().lstrip().startswith("Apache License")
    assert len(list((mathjax / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))) >= 20


def test_built_site_loads_nothing_from_the_network(tmp_path):
    """Build the site and look at every script, style sheet, image and font it loads."""
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(tmp_path / "site")],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    pages = list((tmp_path / "site").rglob("*.html"))
    assert len(pages) > 20
    remote = re.compile(r"""<(?:script|img|source|iframe)[^>]*\ssrc=["']https?://|<link[^>]*\shref=["']https?://[^"']*["'][^>]*>""")
    for page in pages:
        text = page.read_text()
        found = [m.group(0) for m in remote.finditer(text)]
        assert not found, f"{page.name} loads {found}"
        if "arithmatex" in text:
            assert "javascripts/mathjax/tex-chtml-full.js" in text
