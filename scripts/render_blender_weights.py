"""Render a Displace modifier driven by the add-on's geodesic weights (docs/blender.md).

A flat 2 x 2 grid (161 x 161 vertices) with a slit cut into it; the source
is a vertex left of the slit. ``compute_geodesic_distance(...,
weight_group=..., weight_radius=1.2, weight_falloff="SMOOTH")`` writes the
weights, and a Displace modifier lifts the grid by them: a hill whose
contours wrap around the end of the slit, as geodesic distance does (a
Euclidean falloff, such as the Vertex Weight Proximity modifier's, would
climb the far side of the slit too). Headless EEVEE render through ``bpy``
of the add-on's isoline material (isolines drawn per pixel from the distance
attribute, as Material Preview shows them).

Examples
--------
::

    python scripts/render_blender_weights.py docs/images/blender_weights_displace.png
"""

import argparse
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon
from blender_render_scene import camera_looking_at, render_still

REPO = Path(__file__).resolve().parents[1]


def slit_grid(n=161, slit_from=-0.35):
    """A 2 x 2 grid with the faces along x = 0 removed from y = ``slit_from`` to the top edge."""
    import bmesh  # after bpy

    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n - 1, y_subdivisions=n - 1, size=2.0)
    obj = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    half = 1.0 / (n - 1)
    cut = [f for f in bm.faces if abs(f.calc_center_median().x) < half and f.calc_center_median().y > slit_from]
    bmesh.ops.delete(bm, geom=cut, context="FACES_ONLY")
    bm.to_mesh(obj.data)
    bm.free()
    return obj


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", nargs="?", default=str(REPO / "docs" / "images" / "blender_weights_displace.png"))
    parser.add_argument("--size", type=int, nargs=2, default=[960, 600])
    args = parser.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon = load_addon()
    obj = slit_grid()
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    source = int(np.argmin(np.linalg.norm(co.reshape(-1, 3) - [-0.3, 0.45, 0.0], axis=1)))
    result = addon.compute_geodesic_distance(
        obj, sources=[source], isolines=16, weight_group="geodesic_weight", weight_radius=1.2,
        weight_falloff="SMOOTH", isoline_material=True, isoline_width=2.0,
    )
    displace = obj.modifiers.new("Displace", "DISPLACE")
    displace.vertex_group, displace.direction, displace.mid_level, displace.strength = "geodesic_weight", "Z", 0.0, 0.6
    bpy.ops.object.shade_smooth()

    camera_looking_at((2.6, -3.9, 3.1), (0.0, 0.1, 0.1))
    render_still(Path(args.output).resolve(), args.size, sun_degrees=(35, 15, 20))
    print(f"wrote {args.output}: max distance {result.max_distance:.3f}")
    addon.unregister()


if __name__ == "__main__":
    main()
