"""The layer diagram of heatcore's import graph (``python scripts/import_graph.py --draw PNG``).

One box per group of :data:`import_graph.LAYERS`, top layer first, listing its
modules, and one arrow per pair of groups that import each other. Needs
matplotlib; the graph itself is read by :mod:`import_graph`.

Examples
--------
>>> from import_graph import build_graph
>>> graph = build_graph({"heatcore/__init__.py": "from . import errors", "heatcore/errors.py": ""})
>>> draw(graph, "layers.png")  # doctest: +SKIP
PosixPath('layers.png')
"""

import sys
from pathlib import Path

if str(Path(__file__).resolve().parent) not in sys.path:  # loaded by path (pytest): find its neighbour
    sys.path.insert(0, str(Path(__file__).resolve().parent))

from import_graph import LAYERS, layer_of, summary, upward_arrows


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
            f"{len(s['upward'])} upward arrows, {len(s['private'])} private-name imports", fontsize=9.5, ha="right", va="top", color="#333333")
    ax.text(-2.05, bottom - 0.2, "Each importing group has one coloured lane on the right; its arrows point at the "
            "groups it imports, the number counts module-to-module imports\n(imports inside functions and importlib.import_module "
            "calls included). Imports run down the layers only; "
            "siblings do not import each other.\nAn arrow up or sideways would be red and dashed. "
            "Fences: domains import no linalg backend (only linalg/factor.py); ctypes is imported only in linalg/.",
            fontsize=8.5, color="#444444", va="top", linespacing=1.4)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight", facecolor="white")
    plt.close(fig)
    return path

