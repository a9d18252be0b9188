"""heatcore's module import graph, read statically: cycles and arrows that run up the layers.

Every ``import`` statement of ``heatcore/`` and ``blender_addon/`` is read with
:mod:`ast` (nothing is imported or executed): absolute and relative imports,
imports inside functions (they still close cycles at run time) and
``importlib.import_module`` calls whose name is written in the source. An
import ``from pkg import name`` is an arrow to the module ``pkg.name`` when
that module exists, else to ``pkg``. Importing a submodule also runs its
parents' ``__init__``; those implicit arrows are not counted.

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
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
ROOTS = ("heatcore", "blender_addon")

# Layers bottom to top: (layer, [(group, description, module patterns)]). Groups in one layer are
# siblings: neither imports the other. The flat names of the layout before 0d3c9d9 are listed
# too, so that an old revision is judged by the same rules.
LAYERS = [
    ("foundation", [("foundation", "errors, options, settings and progress: what every layer may raise, declare or report",
                     ["heatcore.errors", "heatcore.options", "heatcore.options.*", "heatcore.settings",
                      "heatcore.progress"])]),
    ("linalg", [("linalg", "sparse SPD factorizations, orderings; no geometry",
                 ["heatcore.linalg", "heatcore.linalg.*", "heatcore.sparse_rhs"])]),
    ("domains", [("domains", "what the heat method runs on: operators and source pins",
                  ["heatcore.domains", "heatcore.domains.*", "heatcore.domain", "heatcore.intrinsic",
                   "heatcore.operators", "heatcore.parts", "heatcore.pointcloud", "heatcore.polygon",
                   "heatcore.polygon_shape", "heatcore.refine", "heatcore.sources", "heatcore.tet",
                   "heatcore.triangle", "heatcore.validate", "heatcore.weld"])]),
    ("solver", [("solver", "the heat method and its family: paths, isolines, vector heat",
                 ["heatcore.heat", "heatcore.heat.*", "heatcore.steps", "heatcore.steps.*", "heatcore.eikonal",
                  "heatcore.eikonal.*", "heatcore.fast_marching", "heatcore.high_accuracy", "heatcore.vector_heat",
                  "heatcore.vector_heat.*", "heatcore.reference", "heatcore.contours", "heatcore.voronoi", "heatcore.paths", "heatcore.paths.*"])]),
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


@dataclass
class Graph:
    """Modules (name -> path), arrows (importer, imported) -> line numbers, external imports."""

    modules: dict = field(default_factory=dict)
    edges: dict = field(default_factory=dict)
    externals: dict = field(default_factory=dict)  # module -> {top-level external name: [lines]}
    lines: dict = field(default_factory=dict)  # module -> line count


def module_name(path):
    """Dotted module name of a source path: ``heatcore/io/__init__.py`` -> ``heatcore.io``.

    Examples
    --------
    >>> module_name("heatcore/domains/triangle.py"), module_name("heatcore/io/__init__.py")
    ('heatcore.domains.triangle', 'heatcore.io')
    """
    parts = list(Path(path).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def read_sources(rev=None, repo=REPO):
    """``{path: source}`` of every ``.py`` under ``heatcore/`` and ``blender_addon/``.

    With ``rev`` (a commit, tag or branch) the files are read through ``git show``,
    without touching the working tree.
    """
    if rev is None:
        return {
            p.relative_to(repo).as_posix(): p.read_text(encoding="utf-8")
            for root in ROOTS
            for p in sorted((repo / root).rglob("*.py"))
            if "_vendor" not in p.parts and "__pycache__" not in p.parts
        }
    names = subprocess.run(
        ["git", "-C", str(repo), "ls-tree", "-r", "--name-only", rev, "--", *ROOTS],
        check=True, capture_output=True, text=True,
    ).stdout.split()
    return {
        name: subprocess.run(
            ["git", "-C", str(repo), "show", f"{rev}:{name}"], check=True, capture_output=True, text=True
        ).stdout
        for name in names
        if name.endswith(".py") and "/_vendor/" not in name
    }


def _package_of(module, is_package):
    return module if is_package else module.rpartition(".")[0]


def _resolve_relative(module, is_package, level, name):
    base = _package_of(module, is_package).split(".")
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join(base + ([name] if name else []))


def _internal(name, modules):
    """The longest prefix of ``name`` that is one of ``modules`` (None when external)."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        candidate = ".".join(parts[:i])
        if candidate in modules:
            return candidate
    return None


def _dynamic_name(call, bindings):
    """The module name of ``importlib.import_module(...)`` when the source spells it, else None."""
    func = call.func
    named = (isinstance(func, ast.Attribute) and func.attr == "import_module") or (
        isinstance(func, ast.Name) and func.id == "import_module"
    )
    if not named or not call.args:
        return None
    arg = call.args[0]
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        return arg.value
    # pkg.__name__ + ".sub": the module bound to ``pkg`` by an import in this file, plus ".sub"
    if (
        isinstance(arg, ast.BinOp)
        and isinstance(arg.op, ast.Add)
        and isinstance(arg.right, ast.Constant)
        and isinstance(arg.right.value, str)
        and isinstance(arg.left, ast.Attribute)
        and arg.left.attr == "__name__"
        and isinstance(arg.left.value, ast.Name)
        and arg.left.value.id in bindings
    ):
        return bindings[arg.left.value.id] + arg.right.value
    return None


def _note(externals, name, line):
    lines = externals.setdefault(name, [])
    if line not in lines:
        lines.append(line)


def build_graph(sources):
    """The import graph of ``{path: source}`` (see :func:`read_sources`).

    Examples
    --------
    >>> g = build_graph({"heatcore/__init__.py": "", "heatcore/a.py": "from . import b\\nimport numpy",
    ...                  "heatcore/b.py": "from .a import x"})
    >>> sorted(g.edges), g.externals["heatcore.a"]
    ([('heatcore.a', 'heatcore.b'), ('heatcore.b', 'heatcore.a')], {'numpy': [2]})
    """
    graph = Graph()
    trees = {}
    for path, text in sorted(sources.items()):
        name = module_name(path)
        graph.modules[name] = path
        graph.lines[name] = len(text.splitlines())
        trees[name] = (ast.parse(text, filename=path), Path(path).name == "__init__.py")

    def add(src, dst, line):
        if dst != src:
            lines = graph.edges.setdefault((src, dst), [])
            if line not in lines:
                lines.append(line)

    for name, (tree, is_package) in trees.items():
        externals = graph.externals.setdefault(name, {})
        bindings = {}  # local name -> internal module it was bound to by an import
        nodes = list(ast.walk(tree))
        for node in nodes:
            if isinstance(node, ast.Import):
                for alias in node.names:
                    top = alias.name.split(".")[0]
                    target = _internal(alias.name, graph.modules) if top in ROOTS else None
                    if target is None:
                        _note(externals, top, node.lineno)
                        continue
                    add(name, target, node.lineno)
                    bindings[alias.asname or top] = target if alias.asname else top
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = _resolve_relative(name, is_package, node.level, node.module)
                else:
                    base = node.module
                if base not in graph.modules:
                    if base.split(".")[0] not in ROOTS:
                        _note(externals, base.split(".")[0], node.lineno)
                    continue  # a module not in the tree (blender_addon._vendor: the bundled copy)
                for alias in node.names:
                    full = f"{base}.{alias.name}"
                    add(name, full if full in graph.modules else base, node.lineno)
                    if full in graph.modules:
                        bindings[alias.asname or alias.name] = full
        for node in nodes:  # after the imports: names bound anywhere in the file are known
            if isinstance(node, ast.Call):
                dynamic = _dynamic_name(node, bindings)
                if dynamic is not None:
                    target = _internal(dynamic, graph.modules)
                    if target is not None:
                        add(name, target, node.lineno)
                    else:
                        _note(externals, dynamic.split(".")[0], node.lineno)
    return graph


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
    """A dict of the figures: modules, edges, cycles, upward arrows, fence breaches."""
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
    }


def report(graph, title):
    """The figures as text."""
    s = summary(graph)
    out = [(f"{title}: {s['modules']} modules, {s['edges']} import arrows, "
            f"{len(s['cycles'])} cycles, {len(s['upward'])} upward arrows")]
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
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# the layer diagram

def _short(path, group):
    """A module's file name inside its group's box: ``heatcore/domains/pointcloud/__init__.py``
    -> ``pointcloud/__init__.py`` in the ``domains`` box."""
    parts = Path(path).parts
    if group in FOLDERS:
        folder = ("blender_addon",) if group == "blender_addon" else ("heatcore", group)
        if parts[: len(folder)] == folder:
            return "/".join(parts[len(folder):])
        return path  # heatcore/__main__.py among the front ends
    return "/".join(parts[1:])


GROUP_COLORS = {  # (box fill, arrow colour)
    "foundation": ("#ececec", "#6b6b6b"), "linalg": ("#dce9f7", "#2a6bb0"), "domains": ("#dff2df", "#2e8b3a"),
    "solver": ("#fde9cf", "#d07a00"), "io": ("#efe1f5", "#8a4fb0"), "viz": ("#fbe0e6", "#c2456a"),
    "weights": ("#e6f4ea", "#3b7d4f"),
    "api": ("#fff6c4", "#a08a00"), "apps": ("#dff1f3", "#1f8a96"), "blender_addon": ("#f3ecdc", "#8a6a2e"),
}
FOLDERS = {"linalg", "domains", "io", "viz", "apps", "blender_addon"}


def draw(graph, path, title="heatcore: modules by layer"):
    """Draw the layer diagram: one box per group listing its modules, top layer first, and one
    arrow per pair of groups that import each other, routed in a lane on the right (one lane per
    importing group, in its colour); the number on an arrow counts the module-to-module imports.
    An arrow that runs up or between siblings is drawn red and dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch, Rectangle

    members = {}
    for m in graph.modules:
        where = layer_of(m)
        members.setdefault(where[2] if where else "unlayered", []).append(m)

    # rows: groups top to bottom (top layer first); siblings on consecutive rows
    rows = []
    for rank, (layer, groups) in reversed(list(enumerate(LAYERS))):
        for group, desc, _ in groups:
            if members.get(group):
                rows.append({"group": group, "desc": desc, "layer": layer, "rank": rank,
                             "names": sorted((_short(graph.modules[m], group) for m in members[group]),
                                             key=lambda s: (s != "__init__.py", s.startswith("heatcore/"), s))})
    if members.get("unlayered"):
        rows.append({"group": "unlayered", "desc": "no layer claims these modules", "layer": "?", "rank": -1,
                     "names": sorted(members["unlayered"])})

    counts = {}
    for a, b in graph.edges:
        la, lb = layer_of(a), layer_of(b)
        ga, gb = (la[2] if la else "unlayered"), (lb[2] if lb else "unlayered")
        if ga != gb:
            counts[(ga, gb)] = counts.get((ga, gb), 0) + 1
    bad = set()
    for a, b, _, _ in upward_arrows(graph):
        bad.add((layer_of(a)[2], layer_of(b)[2]))

    box_x, box_w, row_h, head_h, pad, gap = 0.0, 9.2, 0.28, 0.62, 0.12, 0.34
    fan_in = {}
    for _, gb in counts:
        fan_in[gb] = fan_in.get(gb, 0) + 1
    y = 0.0
    char_w = 0.108  # width of a monospace character at the names' font size, in axis units
    for r in rows:  # as many columns as fit, each as wide as its longest name
        for ncols in range(5, 0, -1):
            nrows = -(-len(r["names"]) // ncols)
            columns = [r["names"][k:k + nrows] for k in range(0, len(r["names"]), nrows)]
            widths = [max(map(len, c)) * char_w + 0.45 for c in columns]
            if sum(widths) <= box_w - 0.4:
                break
        r["columns"], r["widths"] = columns, widths
        r["h"] = max(head_h + nrows * row_h + pad, 0.27 * (fan_in.get(r["group"], 0) + 1))
        r["top"] = -y
        r["y"] = -y - r["h"]
        y += r["h"] + gap
    bottom = -y + gap
    index = {r["group"]: r for r in rows}

    sources = [r["group"] for r in rows if any(ga == r["group"] for ga, _ in counts)]
    lane_gap = 0.34
    lane_x = {g: box_x + box_w + 0.35 + lane_gap * (len(sources) - 1 - i) for i, g in enumerate(sources)}
    right = box_x + box_w + 0.35 + lane_gap * len(sources) + 0.1

    fig_h = (-bottom) * 0.55 + 1.4
    fig, ax = plt.subplots(figsize=(12.5, fig_h))
    ax.set_xlim(-2.1, right + 0.1)
    ax.set_ylim(bottom - 0.45, 0.75)
    ax.axis("off")

    # layer bands and labels (a band holds the rows of one layer)
    layers_seen = []
    for r in rows:
        if not layers_seen or layers_seen[-1][0] != r["layer"]:
            layers_seen.append([r["layer"], r["top"], r["y"]])
        else:
            layers_seen[-1][2] = r["y"]
    for k, (layer, top, low) in enumerate(layers_seen):
        ax.add_patch(Rectangle((-2.05, low - 0.1), box_w + 2.1, top - low + 0.2, fc="#f7f7f7" if k % 2 else "white",
                               ec="none", zorder=0))
        siblings = sum(1 for r in rows if r["layer"] == layer) > 1
        ax.text(-1.95, (top + low) / 2, layer + ("\n(siblings)" if siblings else ""), fontsize=10.5, ha="left",
                va="center", fontweight="bold", color="#333333", linespacing=1.3)

    for r in rows:
        fill, _ = GROUP_COLORS.get(r["group"], ("#ffdddd", "#cc0000"))
        ax.add_patch(FancyBboxPatch((box_x, r["y"]), box_w, r["h"], boxstyle="round,pad=0,rounding_size=0.1",
                                    fc=fill, ec="#555555", lw=1.1, zorder=2))
        header = r["group"] + ("/" if r["group"] in FOLDERS else "")
        ax.text(box_x + 0.15, r["top"] - 0.08, header, fontsize=11, fontweight="bold", va="top", ha="left", zorder=3)
        ax.text(box_x + box_w - 0.15, r["top"] - 0.1, r["desc"], fontsize=8.5, va="top",
                ha="right", color="#444444", style="italic", zorder=3)
        x = box_x + 0.3
        for column, w in zip(r["columns"], r["widths"]):
            for q, name in enumerate(column):
                ax.text(x, r["top"] - head_h - q * row_h, name, fontsize=8.6,
                        family="monospace", va="center", ha="left", zorder=3)
            x += w

    # arrows: out of the importer's right side into its lane, down (or up) the lane, into the target
    entries = {}
    for src in sources:
        for (ga, gb) in counts:
            if ga == src:
                entries.setdefault(gb, []).append(src)
    for importers in entries.values():  # entry points spread along the target's right edge, far lanes lowest
        importers.sort(key=lambda s: lane_x[s])
    for src in sources:
        R = index[src]
        _, color = GROUP_COLORS.get(src, ("", "#cc0000"))
        x = lane_x[src]
        y0 = R["y"] + min(0.16, R["h"] / 4)
        targets = [gb for (ga, gb) in counts if ga == src]
        ys = []
        for gb in targets:
            T = index[gb]
            k, n = entries[gb].index(src), len(entries[gb])
            ys.append(T["top"] - T["h"] * (k + 1) / (n + 1))
        ax.plot([box_x + box_w, x], [y0, y0], color=color, lw=1.6, zorder=4, solid_capstyle="round")
        ax.plot([x, x], [min(ys + [y0]), max(ys + [y0])], color=color, lw=1.6, zorder=4)
        for gb, ty in zip(targets, ys):
            up = (src, gb) in bad or index[gb]["rank"] > R["rank"]
            c = "#cc0000" if up else color
            ax.annotate("", xy=(box_x + box_w + 0.02, ty), xytext=(x, ty),
                        arrowprops={"arrowstyle": "-|>", "color": c, "lw": 1.4, "mutation_scale": 11,
                                    "linestyle": "--" if up else "-", "shrinkA": 0, "shrinkB": 0}, zorder=5)
            ax.text(box_x + box_w + 0.2, ty + 0.045, str(counts[(src, gb)]), fontsize=7.5, color=c,
                    ha="center", va="bottom", zorder=6)

    s = summary(graph)
    ax.text(-2.05, 0.65, title, fontsize=14, fontweight="bold", va="top")
    ax.text(right, 0.62, f"{s['modules']} modules, {s['edges']} import arrows, {len(s['cycles'])} cycles, "
            f"{len(s['upward'])} upward arrows", fontsize=9.5, ha="right", va="top", color="#333333")
    ax.text(-2.05, bottom - 0.2, "Each importing group has one coloured lane on the right; its arrows point at the "
            "groups it imports, the number counts module-to-module imports.\nImports run down the layers only; "
            "siblings do not import each other. An arrow up or sideways would be red and dashed.\n"
            "Fences: domains import no linalg backend (only linalg/factor.py); ctypes is imported only in linalg/.",
            fontsize=8.5, color="#444444", va="top", linespacing=1.4)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight", facecolor="white")
    plt.close(fig)
    return path


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
        print("drew", draw(graph, args.draw))
    s = summary(graph)
    return 1 if (s["cycles"] or s["upward"] or s["fenced_externals"] or s["unlayered"]) else 0


if __name__ == "__main__":
    sys.exit(main())
