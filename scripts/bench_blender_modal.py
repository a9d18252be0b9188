"""How responsive Blender stays while the button builds a large mesh's solver in the background.

Drives the modal operator's logic (``ModalRun``, which the operator's ``modal``
calls on each event) headless through ``bpy``: the worker thread builds the
solver while the main thread runs a 10 ms ticker, as Blender's event loop
would, and delivers timer events as the add-on's display spaces them (``blender_addon.display.timer_step``).
Measured on the main thread:

- ``prepare``: the click itself (options checked, mesh read and hashed, cache looked up);
- ``longest stall``: the longest gap between two ticks while the worker builds: Python on the
  main thread (Blender's UI drawing, its timers) waits that long for the GIL;
- ``finish``: the timer event that queries the distance and writes the outputs;
- ``preview``: when the first answer was drawn (the coarse preview of a large mesh, :mod:`blender_addon.preview`),
  and how long the timer event that drew it took (``timer``, the longest timer event before ``finish``, includes it);

and the progress: stage updates, and the longest time between two of them.

Examples
--------
::

    python scripts/bench_blender_modal.py                    # Suzanne, 5 subdivision levels (504,482 vertices)
    python scripts/bench_blender_modal.py --backend qdldl --backend cholmod
    python scripts/bench_blender_modal.py --mesh ../shared/meshes/nefertiti.obj
"""

import argparse
import importlib
import time

import bpy
from bench_blender_clicks import largest_part, make_mesh
from blender_addon_loader import load_addon

TICK = 0.01


def measure(obj, backend):
    stages = importlib.import_module("blender_addon.stages")
    operator = importlib.import_module("blender_addon.operator")
    display = importlib.import_module("blender_addon.display")
    stages.SOLVERS.clear()

    class Display:  # the calls ModalRun makes on blender_addon.display.ProgressDisplay
        def progress(self, fraction, message):
            pass

        def end(self):
            pass

    t0 = time.perf_counter()
    source = int(largest_part(obj.data)[0])  # a click builds the part its source is on: the head, not an eye
    run = stages.prepare_run(obj, sources=[source], isolines=10, backend=backend)
    prepare = time.perf_counter() - t0
    modal = operator.ModalRun(run, Display(), lambda kind, text: print("   ", *kind, text))
    modal.start(obj)
    stall = handle_max = finish = 0.0
    shown = shown_event = None
    last = next_timer = time.perf_counter()
    while True:
        time.sleep(TICK)
        now = time.perf_counter()
        if not modal.finishing:
            stall = max(stall, now - last - TICK)
        if now >= next_timer:
            h0 = time.perf_counter()
            state = modal.handle(bpy.context, "TIMER")
            spent = time.perf_counter() - h0
            if shown is None and modal.preview is not None:
                shown, shown_event = time.perf_counter() - t0, spent
            if modal.result is not None or state != {"PASS_THROUGH"}:
                finish = spent
                break
            handle_max = max(handle_max, spent)
            next_timer = now + display.timer_step(now - t0)
        last = time.perf_counter()
    total = time.perf_counter() - t0
    updates = modal.build.updates
    times = [0.0] + [t for t, _, _ in updates] + [run.solver_seconds]
    gaps = [b - a for a, b in zip(times, times[1:])]
    worst = max(range(len(gaps) - 1), key=lambda i: gaps[i + 1])  # the gap after update i
    return {
        "backend": backend,
        "vertices": len(run.V),
        "build": run.solver_seconds,
        "total": total,
        "prepare": prepare,
        "stall": stall,
        "timer": handle_max,
        "finish": finish,
        "preview": shown,
        "preview_event": shown_event,
        "updates": len(updates),
        "gap": gaps[worst + 1],
        "gap_stage": updates[worst][2],
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesh", help="OBJ file (default: Suzanne subdivided)")
    parser.add_argument("--levels", type=int, default=5, help="subdivision levels of Suzanne (default 5)")
    parser.add_argument("--backend", action="append", help="factorization backend (repeatable; default auto)")
    args = parser.parse_args(argv)
    load_addon()
    obj = make_mesh(args.mesh, args.levels)
    print("| backend | vertices | build | preview drawn (its timer event) | click to result | prepare (main) "
          "| longest main-thread stall | longest timer event | finish (main) | progress updates "
          "| longest gap between updates |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for backend in args.backend or ["auto"]:
        r = measure(obj, backend)
        drawn = "none" if r["preview"] is None else f"{r['preview']:.2f} s ({r['preview_event'] * 1000:.0f} ms)"
        print(f"| {r['backend']} | {r['vertices']:,} | {r['build']:.1f} s | {drawn} | {r['total']:.1f} s | {r['prepare']:.2f} s "
              f"| {r['stall']:.2f} s | {r['timer'] * 1000:.0f} ms | {r['finish']:.2f} s | {r['updates']} "
              f"| {r['gap']:.1f} s ({r['gap_stage']}) |", flush=True)


if __name__ == "__main__":
    main()
