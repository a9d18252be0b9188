"""What the Blender extension carries of heatcore: the modules the add-on imports, and nothing else.

The add-on (``blender_addon/``) reaches heatcore through imports that
:mod:`import_reader` reads statically: every ``import`` statement, those
inside functions too, and every ``importlib.import_module`` whose name the
source spells. The modules reachable from the add-on along those arrows (with
the ``__init__`` of each package above them, which Python runs first) are
vendored into the extension; the rest of heatcore (the command line, the
MeshLab filters, the batch runner, the bundled demo mesh, ...) stays out.

Examples
--------
>>> shipped, dropped = heatcore_modules()
>>> "heatcore.heat" in shipped and "heatcore.apps.cli" in dropped
True
>>> sorted(set(shipped) & set(dropped))
[]
"""

import shutil
import sys
from pathlib import Path

if str(Path(__file__).resolve().parent) not in sys.path:  # loaded by path (tests): find its neighbours
    sys.path.insert(0, str(Path(__file__).resolve().parent))

from import_reader import build_graph, read_sources

REPO = Path(__file__).resolve().parents[1]
ADDON = "blender_addon"


def reachable(graph, roots):
    """Modules of ``graph`` reachable from ``roots`` by import arrows, with their parent packages.

    Examples
    --------
    >>> g = build_graph({"heatcore/__init__.py": "", "heatcore/a/__init__.py": "",
    ...                  "heatcore/a/b.py": "", "heatcore/c.py": "from .a import b",
    ...                  "heatcore/d.py": ""})
    >>> sorted(reachable(g, ["heatcore.c"]))
    ['heatcore', 'heatcore.a', 'heatcore.a.b', 'heatcore.c']
    """
    arrows = {}
    for importer, imported in graph.edges:
        arrows.setdefault(importer, set()).add(imported)
    seen, todo = set(), list(roots)
    while todo:
        module = todo.pop()
        if module in seen or module not in graph.modules:
            continue
        seen.add(module)
        parts = module.split(".")
        todo += [".".join(parts[:i]) for i in range(1, len(parts))]
        todo += sorted(arrows.get(module, ()))
    return seen


def heatcore_modules(sources=None):
    """heatcore's modules split into those the add-on imports and those it does not.

    Parameters
    ----------
    sources : dict, optional
        ``{path: source}`` as :func:`import_reader.read_sources` returns (default: this checkout).

    Returns
    -------
    shipped, dropped : dict
        ``{module name: path relative to the repository}`` each.
    """
    graph = build_graph(read_sources() if sources is None else sources)
    roots = [m for m in graph.modules if m == ADDON or m.startswith(ADDON + ".")]
    needed = reachable(graph, roots)
    heatcore = {m: p for m, p in graph.modules.items() if m == "heatcore" or m.startswith("heatcore.")}
    shipped = {m: p for m, p in heatcore.items() if m in needed}
    dropped = {m: p for m, p in heatcore.items() if m not in needed}
    return shipped, dropped


def dropped_files(repo=REPO):
    """Files under ``heatcore/`` left out of the extension (paths relative to ``repo``), sorted."""
    shipped, _ = heatcore_modules()
    keep = set(shipped.values())
    return sorted(
        p.relative_to(repo).as_posix()
        for p in (repo / "heatcore").rglob("*")
        if p.is_file() and "__pycache__" not in p.parts and p.relative_to(repo).as_posix() not in keep
    )


def stage_sources(stage, repo=REPO):
    """Copy the add-on into ``stage`` and vendor the heatcore modules it imports as ``_vendor/heatcore``.

    Returns
    -------
    int
        Bytes of the heatcore sources vendored.
    """
    shutil.copytree(repo / ADDON, stage, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor"))
    vendor = stage / "_vendor"
    vendor.mkdir()
    (vendor / "__init__.py").write_text('"""Packages bundled with the extension (heatcore)."""\n')
    shipped, _ = heatcore_modules()
    size = 0
    for path in shipped.values():
        target = vendor / path
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(repo / path, target)
        size += target.stat().st_size
    shutil.copy(repo / "LICENSE", vendor / "heatcore" / "LICENSE")  # MIT travels with it
    return size


if __name__ == "__main__":
    if len(sys.argv) != 2 or Path(sys.argv[1]).exists():
        raise SystemExit("usage: python scripts/extension_contents.py NEW_FOLDER  (stages the add-on with its slim heatcore)")
    print(f"staged {stage_sources(Path(sys.argv[1]))} bytes of heatcore into {sys.argv[1]}/_vendor/heatcore")
