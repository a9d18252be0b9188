"""Time the add-on's first click (solver built) and cached clicks (solver reused), stage by stage.

Runs the real operator ``mesh.heat_geodesic_distance`` headless through
``bpy`` with every output on (distance attribute, colors with 10 isolines,
weight group), on meshes built in bpy: icospheres of 162 and 2,562 vertices
(refined to 40,962 solver vertices by default), a torus of 51,200 vertices
(quads) and Suzanne with five levels of Catmull-Clark subdivision (504,482
vertices, the size of the issue's 504k mesh), or OBJ files given with
``--mesh``. The first click is also timed as the button makes it (the modal
operator's logic, ``ModalRun``, driven by timer events every
``display.timer_step`` as Blender would): until the first answer is on
screen (a small mesh's preview, drawn at once; else the result) and until
the result is written. A cached click is a click with another selected vertex after the
first; the core query is ``solver.distance(src)`` on the cached solver with
the same source, timed right after each click. The cached click is split into
stages by timing the functions the add-on calls (whatever is left is
"other": the operator and ``bpy.ops`` around it, mode checks, the mesh
update). Prints one line per click and the Markdown tables of docs/blender-benchmarks.md.

Examples
--------
::

    python scripts/bench_blender_clicks.py
    python scripts/bench_blender_clicks.py --mesh ../shared/meshes/nefertiti.obj --clicks 5
    python scripts/bench_blender_clicks.py --no-weights      # distance and colors only
    python scripts/bench_blender_clicks.py --edit-mode       # clicks made in Edit Mode
    python scripts/bench_blender_clicks.py --polygons TRIANGULATE   # quads measured as loop triangles
"""

import argparse
import contextlib
import functools
import os
import statistics
import time
from collections import defaultdict
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon

#: Built-in meshes: name -> (label, maker).
MESHES = {
    "icosphere": ("icosphere, 3 subdivisions", lambda: _icosphere(3)),
    "icosphere5": ("icosphere, 5 subdivisions", lambda: _icosphere(5)),
    "torus": ("torus 256 x 200 (quads)", lambda: _torus()),
    "suzanne5": ("Suzanne, subdivision level 5", lambda: _suzanne(5)),
}

#: Stages of a click: (label, module attribute path relative to the add-on) timed by wrapping.
STAGES = [
    ("sources", "stages.resolve_sources"),
    ("topology", "adapters.topology"),
    ("shape", "stages.object_positions"),
    ("positions (key)", "adapters.vertex_positions"),
    ("cache lookup", "cache.SOLVERS.entry"),
    ("colorize", "outputs.colormaps.colorize"),
    ("write distance", "adapters.write_float_attribute"),
    ("write colors", "adapters.write_color_attribute"),
    ("weights", "outputs.weights.distance_weights"),
    ("write weights", "adapters.write_vertex_group"),
]


def _icosphere(subdivisions):
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions)
    return bpy.context.active_object


def _torus():
    bpy.ops.mesh.primitive_torus_add(major_segments=256, minor_segments=200)
    return bpy.context.active_object


def _suzanne(levels):
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    mod = obj.modifiers.new("subdivision", "SUBSURF")
    mod.levels = levels
    bpy.ops.object.modifier_apply(modifier=mod.name)
    return obj


def make_mesh(path=None, levels=4):
    """A fresh scene holding one mesh object: an OBJ file, or Suzanne with ``levels`` of subdivision applied."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not path:
        return _suzanne(levels)
    bpy.ops.wm.obj_import(filepath=str(path))
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    return obj


def bench_mesh(spec):
    """(label, object) of a built-in mesh (``MESHES``) or an OBJ file, in a fresh scene."""
    if spec in MESHES:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        label, maker = MESHES[spec]
        return label, maker()
    return Path(spec).stem, make_mesh(spec)


class Stages:
    """Wraps the add-on's functions with timers; ``seconds`` holds the time of each in the last click."""

    def __init__(self, addon):
        self.seconds = defaultdict(float)
        self.solver = None
        self.query = 0.0
        for label, path in STAGES:
            self._wrap(addon, path, label)
        self._wrap_mode_switch(addon.adapters)

    def _wrap_mode_switch(self, adapters):
        """Time ``adapters.object_mode``'s switches to Object Mode and back (clicks in modes other than Object and Edit)."""
        inner = adapters.object_mode

        @contextlib.contextmanager
        def object_mode(obj):
            start = time.perf_counter()
            manager = inner(obj)
            manager.__enter__()
            self.seconds["mode switch"] += time.perf_counter() - start
            try:
                yield
            finally:
                start = time.perf_counter()
                manager.__exit__(None, None, None)
                self.seconds["mode switch"] += time.perf_counter() - start

        adapters.object_mode = object_mode

    def _wrap(self, addon, path, label):
        *parents, name = path.split(".")
        owner = addon
        for part in parents:
            owner = getattr(owner, part, None)
        if owner is None or not hasattr(owner, name):
            return  # the add-on no longer has it: its time falls into "other"
        inner = getattr(owner, name)

        @functools.wraps(inner)
        def timed(*args, **kwargs):
            start = time.perf_counter()
            try:
                result = inner(*args, **kwargs)
            finally:
                self.seconds[label] += time.perf_counter() - start
            if label == "cache lookup" and result is not None:
                self._time_queries(result[1])  # SolverCache.entry: (key, solver)
            return result

        setattr(owner, name, timed)

    def _time_queries(self, solver):
        """Time ``solver.distance`` as the click calls it (the stage "query")."""
        if getattr(solver, "_bench_timed", False):
            return
        inner = solver.distance

        def distance(*args, **kwargs):
            start = time.perf_counter()
            try:
                return inner(*args, **kwargs)
            finally:
                self.seconds["query"] += time.perf_counter() - start

        solver.distance, solver._bench_timed, self.solver = distance, True, solver
        self.core_query = inner

    def reset(self):
        self.seconds.clear()


def select(obj, vertex):
    """Select only ``vertex`` (in Edit Mode through bmesh)."""
    if obj.mode == "EDIT":
        import bmesh  # (importable once bpy is)

        bpy.ops.mesh.select_all(action="DESELECT")
        bm = bmesh.from_edit_mesh(obj.data)
        bm.verts.ensure_lookup_table()
        bm.verts[vertex].select_set(True)
        bmesh.update_edit_mesh(obj.data)
    else:
        mask = np.zeros(len(obj.data.vertices), dtype=bool)
        mask[vertex] = True
        obj.data.vertices.foreach_set("select", mask)
        obj.data.update()
    # The selection's own evaluation, which Blender makes when the user selects, before any click (in Edit
    # Mode it converts the edit mesh: 0.15 s at 504k vertices); bpy.ops would otherwise count it in the click.
    bpy.context.view_layer.update()


def click(obj, vertex, write_weights):
    select(obj, vertex)
    start = time.perf_counter()
    bpy.ops.mesh.heat_geodesic_distance(isolines=10, write_weights=write_weights, polygons=POLYGONS[0])
    return time.perf_counter() - start


class QuietDisplay:
    """The button's display (progress indicator, header, status bar), silent: headless Blender has none."""

    def progress(self, fraction, message):
        pass

    def end(self):
        pass


def button_click(addon, obj, vertex, write_weights):
    """The button's first click: seconds until a first answer is on screen, and until the result is written.

    The modal operator's logic (``ModalRun``) with timer events as
    ``display.timer_step`` spaces them; the first answer is the preview where the run
    draws one (:mod:`blender_addon.preview`), else the written result.
    """
    select(obj, vertex)
    weights = addon.properties.DEFAULT_WEIGHT_GROUP if write_weights else None
    start = time.perf_counter()
    run = addon.stages.prepare_run(obj, isolines=10, weight_group=weights, polygons=POLYGONS[0])
    modal = addon.operator.ModalRun(run, QuietDisplay(), lambda kind, text: None)
    modal.start(obj)
    shown = time.perf_counter() - start if modal.preview is not None else None  # drawn at once
    while True:  # Blender's first timer event comes one step after the click
        time.sleep(addon.display.timer_step(time.perf_counter() - start))
        state = modal.handle(bpy.context, "TIMER")
        if shown is None and modal.preview is not None:
            shown = time.perf_counter() - start  # drawn at this timer event
        if state != {"PASS_THROUGH"}:
            break
    written = time.perf_counter() - start
    return (written if shown is None else shown), written


#: The operator's ``polygons`` option for every click (``--polygons``).
POLYGONS = ["AUTO"]


def largest_part(mesh):
    """The vertices of the mesh's largest connected part (a click builds the part its source is on)."""
    from heatcore.domains.parts import vertex_components

    mesh.calc_loop_triangles()
    F = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", F)
    _, part = vertex_components(F.reshape(-1, 3), len(mesh.vertices))
    return np.flatnonzero(part == np.bincount(part).argmax())


def bench(addon, stages, spec, clicks, write_weights, rng, edit_mode=False):
    label, obj = bench_mesh(spec)
    n = len(obj.data.vertices)
    on = largest_part(obj.data)  # every click there: the first builds it, the others reuse it
    if edit_mode:
        bpy.ops.object.mode_set(mode="EDIT")
    addon.SOLVERS.clear()
    stages.reset()
    first = click(obj, int(on[0]), write_weights)
    build = bpy.context.window_manager.heat_geodesic_stats.solver_seconds
    print(f"{label}: {n:,} vertices; first click {first:.3f} s (solver built in {build:.3f} s)", flush=True)
    addon.SOLVERS.clear()
    shown, written = button_click(addon, obj, int(on[0]), write_weights)
    print(f"  button: first answer {shown:.3f} s, result written {written:.3f} s", flush=True)
    cached, queries, breakdown = [], [], defaultdict(list)
    for k in range(clicks):
        vertex = int(rng.choice(on))
        stages.reset()
        cached.append(click(obj, vertex, write_weights))
        assert bpy.context.window_manager.heat_geodesic_stats.cached, "the solver was not reused"
        parts = dict(stages.seconds)
        parts["other"] = cached[-1] - sum(parts.values())
        for key, value in parts.items():
            breakdown[key].append(value)
        start = time.perf_counter()
        stages.core_query([vertex])
        queries.append(time.perf_counter() - start)
        print(f"  cached click {k + 1}: {cached[-1]:.3f} s, core query {queries[-1]:.3f} s", flush=True)
    med = statistics.median
    return {
        "label": label, "n": n, "first": first, "build": build, "shown": shown, "written": written,
        "cached": med(cached), "query": med(queries),
        "stages": {key: med(values) for key, values in breakdown.items()},
    }


def tables(rows, clicks, write_weights, edit_mode=False):
    outputs = "distance, colors (10 isolines), weights" if write_weights else "distance, colors (10 isolines)"
    outputs += "; clicks in Edit Mode" if edit_mode else "; clicks in Object Mode"
    lines = [
        f"| mesh | vertices | first click | solver build | button: first answer shown | button: result written "
        f"| cached click (median of {clicks}) | core query | cached / query |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['label']} | {r['n']:,} | {r['first']:.2f} s | {r['build']:.2f} s | {r['shown']:.3f} s | "
                     f"{r['written']:.2f} s | {r['cached']:.3f} s | {r['query']:.3f} s | {r['cached'] / r['query']:.2f} |")
    keys = ["query"] + [label for label, _ in STAGES] + ["mode switch", "other"]
    keys = [k for k in keys if any(r["stages"].get(k, 0.0) >= 5e-5 for r in rows)]
    lines += ["", f"Cached click by stage (median seconds; outputs: {outputs}):", "",
              "| stage | " + " | ".join(f"{r['n']:,} vertices" for r in rows) + " |",
              "|---|" + "---|" * len(rows)]
    for key in keys:
        lines.append(f"| {key} | " + " | ".join(f"{r['stages'].get(key, 0.0):.4f}" for r in rows) + " |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesh", action="append",
                        help=f"OBJ file or one of {', '.join(MESHES)} (repeatable; default: torus and suzanne5)")
    parser.add_argument("--clicks", type=int, default=5, help="cached clicks to time on each mesh")
    parser.add_argument("--no-weights", dest="weights", action="store_false", help="no weight-group output")
    parser.add_argument("--edit-mode", action="store_true", help="click in Edit Mode (default: Object Mode)")
    parser.add_argument("--markdown", help="also write the tables to this file")
    parser.add_argument("--polygons", choices=("AUTO", "TRIANGULATE"), default="AUTO",
                        help="the operator's Polygons option (AUTO: quad meshes measured as polygons)")
    args = parser.parse_args(argv)
    POLYGONS[0] = args.polygons

    addon = load_addon()
    stages = Stages(addon)
    rng = np.random.default_rng(0)
    rows = [bench(addon, stages, spec, args.clicks, args.weights, rng, args.edit_mode)
            for spec in args.mesh or list(MESHES)]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    text = tables(rows, args.clicks, args.weights, args.edit_mode)
    text += f"\n\n({os.cpu_count()} CPU cores; load average {load:.2f} at the end of the run.)\n"
    print()
    print(text)
    if args.markdown:
        Path(args.markdown).write_text(text)
    addon.unregister()


if __name__ == "__main__":
    main()
