"""Write the toolbar icon of the *Geodesic Probe* tool: ``blender_addon/icons/ops.mesh.heat_geodesic_probe.dat``.

The icon is a source point (an orange disc) with three isolines around it
(light rings, fading outwards): what the probe shows. It is written in
Blender's toolbar icon format (the ``.dat`` files of
``release/datafiles/blender_icons_geom``): the header ``VCO``, version 0,
the coordinate range (255, 255) and start (0, 0), then 6 bytes (x, y of three
corners, 0..255, counter-clockwise) per triangle, then 12 bytes (RGBA of
three corners) per triangle. Run it again after changing the drawing::

    python scripts/make_probe_icon.py
"""

import math
from pathlib import Path

OUT = Path(__file__).resolve().parents[1] / "blender_addon" / "icons" / "ops.mesh.heat_geodesic_probe.dat"
#: The source point: centre (in -1..1), radius, colour.
SOURCE = ((-0.35, -0.35), 0.22, (255, 140, 40, 255))
#: The isolines: (inner radius, outer radius, colour), around the source.
RINGS = ((0.42, 0.56, (235, 235, 235, 255)), (0.80, 0.94, (235, 235, 235, 200)), (1.18, 1.32, (235, 235, 235, 140)))
SEGMENTS = 48


def _byte(f):
    return min(max(round((f + 1.0) * 0.5 * 255), 0), 255)


def _inside(x, y):
    return -1.0 <= x <= 1.0 and -1.0 <= y <= 1.0


def triangles():
    """(corners, colour) of every triangle, in -1..1 coordinates, counter-clockwise."""
    (cx, cy), r, colour = SOURCE
    tris = []
    for k in range(SEGMENTS):
        a, b = 2 * math.pi * k / SEGMENTS, 2 * math.pi * (k + 1) / SEGMENTS
        tris.append((((cx, cy), (cx + r * math.cos(a), cy + r * math.sin(a)),
                      (cx + r * math.cos(b), cy + r * math.sin(b))), colour))
    for r0, r1, colour in RINGS:
        for k in range(SEGMENTS * 2):
            a, b = math.pi * k / SEGMENTS, math.pi * (k + 1) / SEGMENTS
            p = [(cx + r * math.cos(t), cy + r * math.sin(t)) for r, t in ((r0, a), (r1, a), (r1, b), (r0, b))]
            if all(_inside(*q) for q in p):  # the rings are cut by the icon's square
                tris += [((p[0], p[1], p[2]), colour), ((p[0], p[2], p[3]), colour)]
    return tris


def icon_bytes():
    """The ``.dat`` file's content."""
    coords, colours = bytearray(), bytearray()
    for corners, colour in triangles():
        xy = [(_byte(x), _byte(y)) for x, y in corners]
        (x0, y0), (x1, y1), (x2, y2) = xy
        if (x0 - x1) * (y1 - y2) + (y0 - y1) * (x2 - x1) <= 0:  # zero area once in bytes (or clockwise)
            continue
        for x, y in xy:
            coords += bytes((x, y))
        colours += bytes(colour) * 3
    return b"VCO\x00" + bytes((255, 255)) + bytes((0, 0)) + bytes(coords) + bytes(colours)


if __name__ == "__main__":
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_bytes(icon_bytes())
    print(f"wrote {OUT.name}: {(OUT.stat().st_size - 8) // 18} triangles")
