"""Every relative link of README.md and docs/*.md resolves: the file exists and, for a Markdown
file, the ``#anchor`` is one of its headings (GitHub's slugs). Sections moved between pages (the
Blender page split into blender.md, blender-benchmarks.md and blender-tests.md) leave no dead link.
"""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
LINK = re.compile(r"\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#+\s+(.*)$", re.MULTILINE)


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens.

    >>> slug("Install (Blender 4.2 or later)")
    'install-blender-42-or-later'
    >>> slug("In Blender: *Isoline Curves*")
    'in-blender-isoline-curves'
    """
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(page):
    text = re.sub(r"^```.*?^```", "", page.read_text(), flags=re.MULTILINE | re.DOTALL)  # no code comments
    return {slug(h) for h in HEADING.findall(text)}


def links(page):
    for link in LINK.findall(page.read_text()):
        if not re.match(r"[a-z]+:", link):  # http:, https:, mailto: are not checked here
            yield link


def test_the_slugs_are_githubs():
    assert slug("Geodesic UV Map: a decal placed with the least distortion") == \
        "geodesic-uv-map-a-decal-placed-with-the-least-distortion"
    assert "use" in anchors(REPO / "docs" / "blender.md")


@pytest.mark.parametrize("page", PAGES, ids=[p.relative_to(REPO).as_posix() for p in PAGES])
def test_every_relative_link_resolves(page):
    dead = []
    for link in links(page):
        path, _, anchor = link.partition("#")
        target = (page.parent / path).resolve() if path else page
        if not target.exists():
            dead.append(f"{link} (no such file)")
        elif anchor and target.suffix == ".md" and anchor not in anchors(target):
            dead.append(f"{link} (no such heading)")
    assert dead == []
