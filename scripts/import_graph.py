"""heatcore's module import graph, read statically: cycles, arrows that run up the layers, private names.

The graph is read by :mod:`import_reader`: every ``import`` statement of
``heatcore/`` and ``blender_addon/``, function-level ones included, and every
``importlib.import_module`` call whose name the source spells (relative ones
too; a computed name that cannot be read is listed, not guessed). This module
holds the rules and reports what breaks them: import cycles, arrows up the
layers or between siblings, fence breaches, modules in no layer, and uses of
another module's private names (``from m import _name``, ``m._name``).

The layers, bottom to top (an arrow may point down or within its group,
never up and never sideways to a sibling group):

    front ends   apps/ (and heatcore.__main__)  |  blender_addon/
    api          heatcore/__init__.py
    io | viz     io/ (file readers and writers)  |  viz/ (colormaps, renderer)  |  weights.py
    solver       heat.py, eikonal.py, fast_marching.py, high_accuracy.py, reference.py, contours.py, voronoi.py
    domains      domains/
    linalg       linalg/ (knows no geometry)
    foundation   errors.py, options.py, progress.py

plus fences: domains import no linalg backend (only the ``linalg.factor``
interface), and ``ctypes`` is imported only under ``heatcore/linalg/``.

Usage::

    python scripts/import_graph.py                  # the working tree
    python scripts/import_graph.py --rev d03b81d    # a commit, read through git show
    python scripts/import_graph.py --draw docs/images/layers.png
    python scripts/import_graph.py --json

Examples
--------
>>> graph = build_graph({"heatcore/__init__.py": "from . import heat",
...                      "heatcore/heat.py": "def f():\\n    import heatcore\\n"})
>>> sorted(graph.edges)
[('heatcore', 'heatcore.heat'), ('heatcore.heat', 'heatcore')]
>>> find_cycles(graph)
[['heatcore', 'heatcore.heat']]
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import json
import sys
from pathlib import Path

if str(Path(__file__).resolve().parent) not in sys.path:  # loaded by path (tests): find its neighbours
    sys.path.insert(0, str(Path(__file__).resolve().parent))

from import_reader import build_graph, module_name, read_sources

# Layers bottom to top: (layer, [(group, description, module patterns)]). Groups in one layer are
# siblings: neither imports the other. The flat names of the layout before 0d3c9d9 are listed
# too, so that an old revision is judged by the same rules.
LAYERS = [
    ("foundation", [("foundation", "what every layer may raise, declare or report",
                     ["heatcore.errors", "heatcore.options", "heatcore.options.*", "heatcore.settings",
                      "heatcore.progress"])]),
    ("linalg", [("linalg", "sparse SPD factorizations, orderings, the optional libraries and numba; no geometry",
                 ["heatcore.linalg", "heatcore.linalg.*", "heatcore.sparse_rhs", "heatcore.compiled"])]),
    ("domains", [("domains", "what the heat method runs on: operators and source pins",
                  ["heatcore.domains", "heatcore.domains.*", "heatcore.domain", "heatcore.intrinsic",
                   "heatcore.operators", "heatcore.parts", "heatcore.pointcloud", "heatcore.polygon",
                   "heatcore.polygon_shape", "heatcore.refine", "heatcore.sources", "heatcore.tet",
                   "heatcore.triangle", "heatcore.validate", "heatcore.weld"])]),
    ("solver", [("solver", "the heat method and its family: paths, isolines, vector and signed heat",
                 ["heatcore.heat", "heatcore.heat.*", "heatcore.steps", "heatcore.steps.*", "heatcore.eikonal",
                  "heatcore.eikonal.*", "heatcore.fast_marching", "heatcore.high_accuracy", "heatcore.vector_heat",
                  "heatcore.vector_heat.*", "heatcore.reference", "heatcore.contours", "heatcore.voronoi", "heatcore.paths", "heatcore.paths.*",
                  "heatcore.preview", "heatcore.signed_heat", "heatcore.signed_heat.*"])]),
    ("io | viz", [("io", "reading and writing files; raises core errors",
                   ["heatcore.io", "heatcore.io.*", "heatcore.domain_io", "heatcore.ply",
                    "heatcore.pointcloud_io", "heatcore.polygon_io", "heatcore.tet_io"]),
                  ("viz", "colormaps and the software renderer",
                   ["heatcore.viz", "heatcore.viz.*", "heatcore.colormap", "heatcore.render"]),
                  ("weights", "distance to weights in [0, 1] for modifiers (Blender's falloff curves)",
                   ["heatcore.weights"])]),
    ("api", [("api", "the public API: heatcore/__init__.py", ["heatcore"])]),
    ("front ends", [("apps", "command line, batch, MeshLab filter",
                     ["heatcore.apps", "heatcore.apps.*", "heatcore.__main__", "heatcore.cli",
                      "heatcore.inputs", "heatcore.outputs", "heatcore.meshlab", "heatcore.batch",
                      "heatcore.batch_*"]),
                    ("blender_addon", "the Blender add-on", ["blender_addon", "blender_addon.*"])]),
]

# Arrows forbidden although they point down: (from patterns, to patterns, allowed targets, why).
FENCES = [
    (["heatcore.domains", "heatcore.domains.*"], ["heatcore.linalg", "heatcore.linalg.*"],
     ["heatcore.linalg.factor"], "domains import no linalg backend (only the linalg.factor interface)"),
]

# External modules only some of heatcore may import: (module, allowed importer patterns).
FENCED_EXTERNALS = [("ctypes", ["heatcore.linalg", "heatcore.linalg.*"])]


def strongly_connected(graph):
    """Strongly connected components of more than one module (Tarjan), each sorted."""
    succ = {m: [] for m in graph.modules}
    for a, b in graph.edges:
        succ[a].append(b)
    index, low, stack, on_stack, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(succ[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))
    for v in sorted(succ):
        if v not in index:
            visit(v)
    return sorted(out)


def find_cycles(graph, limit=100):
    """Elementary import cycles (each as a list of modules, smallest first), at most ``limit``.

    Examples
    --------
    >>> g = build_graph({"heatcore/a.py": "from . import b", "heatcore/b.py": "from . import a",
    ...                  "heatcore/__init__.py": ""})
    >>> find_cycles(g)
    [['heatcore.a', 'heatcore.b']]
    """
    cycles = []
    for comp in strongly_connected(graph):
        members = set(comp)
        succ = {m: sorted(b for (a, b) in graph.edges if a == m and b in members) for m in comp}
        for start in comp:  # cycles whose smallest module is ``start``
            path, stack = [start], [iter(succ[start])]
            while stack:
                for w in stack[-1]:
                    if w == start:
                        cycles.append(list(path))
                        if len(cycles) >= limit:
                            return cycles
                    elif w > start and w not in path:
                        path.append(w)
                        stack.append(iter(succ[w]))
                        break
                else:
                    stack.pop()
                    path.pop()
    return sorted(cycles, key=lambda c: (len(c), c))


def _matches(name, patterns):
    return any(fnmatch.fnmatchcase(name, p) for p in patterns)


def layer_of(module):
    """``(rank, layer, group)`` of a module, or None when no layer claims it.

    Examples
    --------
    >>> layer_of("heatcore.domains.triangle")
    (2, 'domains', 'domains')
    >>> layer_of("blender_addon.api")
    (6, 'front ends', 'blender_addon')
    """
    for rank, (layer, groups) in enumerate(LAYERS):
        for group, _, patterns in groups:
            if _matches(module, patterns):
                return rank, layer, group
    return None


def upward_arrows(graph):
    """Arrows that point up the layers or sideways to a sibling group, and fence breaches.

    Returns a sorted list of ``(importer, imported, lines, why)``.
    """
    out = []
    for (a, b), lines in sorted(graph.edges.items()):
        la, lb = layer_of(a), layer_of(b)
        if la is None or lb is None:
            continue  # reported by unlayered()
        if lb[0] > la[0]:
            out.append((a, b, lines, f"{la[2]} ({la[1]}) imports {lb[2]} ({lb[1]}), a layer above"))
        elif lb[0] == la[0] and lb[2] != la[2]:
            out.append((a, b, lines, f"{la[2]} imports its sibling {lb[2]}"))
        else:
            for src, dst, allowed, why in FENCES:
                if _matches(a, src) and _matches(b, dst) and not _matches(b, allowed):
                    out.append((a, b, lines, why))
    return out


def fenced_externals(graph):
    """``(module, external, lines)`` for each fenced external module imported outside its fence."""
    out = []
    for module, externals in sorted(graph.externals.items()):
        for external, allowed in FENCED_EXTERNALS:
            if external in externals and not _matches(module, allowed):
                out.append((module, external, externals[external]))
    return out


def unlayered(graph):
    """Modules that no layer claims (a new top-level module must be given a layer)."""
    return sorted(m for m in graph.modules if layer_of(m) is None)


def summary(graph):
    """A dict of the figures: modules, edges, cycles, upward arrows, fence breaches, private-name
    imports, and the ``import_module`` calls whose name the source does not spell."""
    return {
        "modules": len(graph.modules),
        "edges": len(graph.edges),
        "cycles": find_cycles(graph),
        "upward": [
            {"from": a, "to": b, "lines": lines, "why": why} for a, b, lines, why in upward_arrows(graph)
        ],
        "fenced_externals": [
            {"module": m, "imports": e, "lines": lines} for m, e, lines in fenced_externals(graph)
        ],
        "unlayered": unlayered(graph),
        "private": [{"module": m, "imports": f"{o}.{n}", "line": line} for m, o, n, line in graph.private],
        "dynamic": [{"module": m, "line": line, "call": call} for m, line, call in graph.dynamic],
    }


def report(graph, title):
    """The figures as text."""
    s = summary(graph)
    out = [(f"{title}: {s['modules']} modules, {s['edges']} import arrows, "
            f"{len(s['cycles'])} cycles, {len(s['upward'])} upward arrows, "
            f"{len(s['private'])} private-name imports, {len(s['dynamic'])} import_module calls not read")]
    out.append("cycles:" if s["cycles"] else "cycles: none")
    out += ["  " + " -> ".join(c + [c[0]]) for c in s["cycles"]]
    out.append("upward arrows:" if s["upward"] else "upward arrows: none")
    out += [f"  {u['from']} -> {u['to']} (line {', '.join(map(str, u['lines']))}): {u['why']}"
            for u in s["upward"]]
    if s["fenced_externals"]:
        out.append("fenced external imports:")
        out += [f"  {f['module']} imports {f['imports']} (line {', '.join(map(str, f['lines']))})"
                for f in s["fenced_externals"]]
    if s["unlayered"]:
        out.append("modules in no layer: " + ", ".join(s["unlayered"]))
    out.append("private names of other modules:" if s["private"] else "private names of other modules: none")
    out += [f"  {p['module']} (line {p['line']}) uses {p['imports']}" for p in s["private"]]
    if s["dynamic"]:
        out.append("import_module calls whose module the source does not spell (no arrow drawn):")
        out += [f"  {d['module']} (line {d['line']}): {d['call']}" for d in s["dynamic"]]
    return "\n".join(out)


def module_table(sources):
    """Markdown rows ``| path | layer | first line of the module docstring |``, by layer, top first."""
    rows = []
    for path, text in sources.items():
        name = module_name(path)
        where = layer_of(name)
        doc = ast.get_docstring(ast.parse(text)) or ""
        summary_line = doc.strip().split("\n\n")[0].replace("\n", " ")
        rows.append(((-where[0], where[2]) if where else (1, "?"), path, where[2] if where else "?", summary_line))
    rows.sort()
    return ["| module | layer | concept |", "|---|---|---|"] + [
        f"| `{path}` | {group} | {line} |" for _, path, group, line in rows
    ]


def main(argv=None):
    """Command line: print the figures (or JSON), optionally draw the diagram."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rev", help="read the files of this git revision (git show), not the working tree")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    parser.add_argument("--edges", action="store_true", help="also list every import arrow")
    parser.add_argument("--draw", metavar="PNG", help="draw the layer diagram to this file")
    parser.add_argument("--table", action="store_true", help="print a markdown table module -> layer -> docstring")
    args = parser.parse_args(argv)
    sources = read_sources(args.rev)
    graph = build_graph(sources)
    if args.table:
        print("\n".join(module_table(sources)))
        return 0
    title = f"revision {args.rev}" if args.rev else "working tree"
    if args.json:
        print(json.dumps(summary(graph), indent=1))
    else:
        print(report(graph, title))
    if args.edges:
        for (a, b), lines in sorted(graph.edges.items()):
            print(f"  {a} -> {b}  ({', '.join(map(str, lines))})")
    if args.draw:
        from layer_diagram import draw  # matplotlib: only for the picture

        print("drew", draw(graph, args.draw))
    s = summary(graph)
    return 1 if (s["cycles"] or s["upward"] or s["fenced_externals"] or s["unlayered"] or s["private"]) else 0


if __name__ == "__main__":
    sys.exit(main())
