"""The cost of ``accuracy="high"`` is stated once (issue 38): :data:`heatcore.options.HIGH_ACCURACY_COST`.

The figure comes from ``scripts/bench_high_cost.py``; the option's help is
generated from it, and every document that states the cost says the same.
"""

import re
from pathlib import Path

import pytest

import heatcore as hc
from heatcore import options
from heatcore.apps import cli

REPO = Path(__file__).resolve().parents[1]


def flat(text):
    return " ".join(text.split())


def test_the_sentence_comes_from_the_figures():
    low, high = options.HIGH_ACCURACY_COST["numba"]
    slow_low, slow_high = options.HIGH_ACCURACY_COST["vectorized"]
    assert 1 <= low <= high < slow_low <= slow_high  # numba's pass is the cheaper one
    assert f"{low:g}-{high:g} smooth ones" in options.HIGH_ACCURACY_COST_TEXT
    assert f"{slow_low:g}-{slow_high:g} without it" in options.HIGH_ACCURACY_COST_TEXT


def test_help_says_it(capsys):
    for name in ("distance", "batch", "path", "logmap"):
        assert cli.main([name, "--help"]) == 0
        assert options.HIGH_ACCURACY_COST_TEXT in flat(capsys.readouterr().out), name
    assert options.HIGH_ACCURACY_COST_TEXT in flat(hc.geodesic_distance.__doc__)


@pytest.mark.parametrize("path", ["README.md", "docs/meshlab.md", "docs/accuracy-high.md", "pyproject.toml"])
def test_documents_say_the_same(path):
    assert options.HIGH_ACCURACY_COST_TEXT in flat((REPO / path).read_text()), path


def test_no_other_figure_for_the_cost():
    old = re.compile(r"2-3 smooth|2-3x the smooth|10-40|1\.3-2\.7|\b5-14\b|4\.6-14|2-40 times|2 to 40 times")
    files = [REPO / "README.md", REPO / "pyproject.toml", *sorted((REPO / "docs").glob("*.md")),
             *sorted((REPO / "heatcore").rglob("*.py")), *sorted((REPO / "blender_addon").rglob("*.py"))]
    stale = [f"{p.relative_to(REPO)}: {m.group(0)}" for p in files for m in old.finditer(p.read_text())]
    assert stale == []
    slow = "-".join(f"{x:g}" for x in options.HIGH_ACCURACY_COST["vectorized"])
    assert f"vectorized pass, {slow} times a smooth query" in (REPO / "docs" / "blender.md").read_text()
