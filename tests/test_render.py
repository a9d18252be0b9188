"""The PNG picture: z-buffer rasterizer, isolines per pixel, source markers hidden by nearer surfaces."""

import numpy as np
import pytest

import heatcore as hc
from heatcore.viz import render
from heatcore.viz.raster import rasterize

pytest.importorskip("matplotlib")


def grid(n, jitter=0.0, seed=0):
    """A triangulated (n+1) x (n+1) grid over [0, n]^2, interior vertices jittered."""
    x, y = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0), indexing="xy")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    inner = (V[:, 0] > 0) & (V[:, 0] < n) & (V[:, 1] > 0) & (V[:, 1] < n)
    V[inner, :2] += np.random.default_rng(seed).uniform(-jitter, jitter, (inner.sum(), 2))
    i = np.arange(n)[None, :] + (n + 1) * np.arange(n)[:, None]
    a, b, c, d = i.ravel(), i.ravel() + 1, i.ravel() + n + 1, i.ravel() + n + 2
    return V, np.concatenate([np.column_stack([a, b, d]), np.column_stack([a, d, c])])


def test_every_pixel_of_a_closed_region_is_covered_once_and_interpolates_exactly():
    V, F = grid(9, jitter=0.3)
    V[:, :2] *= 40 / 9  # 40 x 40 pixels
    V[:, 2] = 0.1 * V[:, 0] - 0.2 * V[:, 1]
    raster = rasterize(V, F, 40, 40)
    assert (raster.face >= 0).all()  # no cracks between neighboring faces
    rows, cols = np.divmod(raster.pixels, 40)
    x, y = cols + 0.5, rows + 0.5
    corners = F[raster.face.flat[raster.pixels]]
    assert raster.barycentric.min() > -1e-9 and np.allclose(raster.barycentric.sum(axis=1), 1.0)
    linear = 3.0 * V[:, 0] - 2.0 * V[:, 1] + 5.0
    interpolated = np.einsum("ij,ij->i", raster.barycentric, linear[corners])
    np.testing.assert_allclose(interpolated, 3.0 * x - 2.0 * y + 5.0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(raster.depth.ravel()[raster.pixels], 0.1 * x - 0.2 * y, atol=1e-9)


def test_nearest_surface_wins_against_a_brute_force_reference():
    rng = np.random.default_rng(3)
    P = rng.uniform(0, 24, (90, 3))
    F = np.arange(90).reshape(30, 3)
    raster = rasterize(P, F, 24, 24)
    for row in range(24):
        for col in range(24):
            x, y = col + 0.5, row + 0.5
            best = -np.inf
            for a, b, c in P[F]:
                det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
                b1 = ((x - a[0]) * (c[1] - a[1]) - (y - a[1]) * (c[0] - a[0])) / det
                b2 = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / det
                if min(b1, b2, 1 - b1 - b2) >= 0:
                    best = max(best, a[2] + b1 * (b[2] - a[2]) + b2 * (c[2] - a[2]))
            assert raster.depth[row, col] == pytest.approx(best, abs=1e-9)


def test_isolines_are_dark_exactly_where_the_field_crosses_a_level():
    V, F = grid(6)
    V[:, :2] /= 6  # the unit square, seen from the front
    d = V[:, 0].copy()  # distance = x, levels at j / 5
    levels = np.array([0.2, 0.4, 0.6, 0.8])
    scale = 300.0  # pixels per unit
    Q = V * scale
    raster = rasterize(Q, F, 300, 300)
    half_width = 2.0
    seen, index = np.unique(raster.face.flat[raster.pixels], return_inverse=True)
    rgb = np.ones((300 * 300, 3))
    paint = lambda v: hc.viz.colorize(v, "viridis", vmax=1.0)  # noqa: E731
    rgb[raster.pixels] = render._pixel_colors(Q, F, d, seen, index, raster.barycentric, paint, levels, half_width)
    rgb = rgb.reshape(300, 300, 3)
    x = np.arange(300) + 0.5
    gap = np.abs(x[:, None] / scale - levels[None, :]).min(axis=1) * scale  # pixels to the nearest level
    line = np.abs(rgb[150] - render.LINE_RGB).max(axis=1) < 1e-9
    assert line[gap < half_width - 0.5 - 1e-6].all() and not line[gap > half_width - 0.5 + 1e-6].any()
    assert line.sum() >= 4 * 3
    clear = gap >= half_width + 0.5
    np.testing.assert_allclose(rgb[150, clear], hc.viz.colorize(x[clear] / scale, "viridis", vmax=1.0), atol=1e-12)


def ico_sphere(subdivisions=3):
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=subdivisions)
    return np.asarray(sphere.vertices), np.asarray(sphere.faces)


def test_back_faces_are_skipped_only_on_closed_outward_surfaces():
    V, F = ico_sphere(2)
    assert render._closed_outward(V, F)
    assert not render._closed_outward(V, F[:, ::-1])  # turned inside out
    assert not render._closed_outward(V, F[1:])  # a hole
    flipped = F.copy()
    flipped[7] = flipped[7, ::-1]
    assert not render._closed_outward(V, flipped)  # one face the wrong way round
    assert not render._closed_outward(*grid(3))


def test_the_winding_of_the_faces_does_not_change_the_picture(tmp_path):
    from PIL import Image

    V, F = ico_sphere(3)
    d = np.linalg.norm(V - V[0], axis=1)
    mixed = F.copy()
    flip = np.random.default_rng(1).random(len(F)) < 0.3
    mixed[flip] = mixed[flip, ::-1]
    for name, faces in (("out.png", F), ("in.png", F[:, ::-1]), ("mixed.png", mixed)):
        render.render_distance(tmp_path / name, V, faces, d, sources=[0], size=(3, 3), dpi=60)
    out = np.asarray(Image.open(tmp_path / "out.png").convert("RGB"), float)
    for name in ("in.png", "mixed.png"):  # inside out; 30% of the faces the wrong way round
        other = np.asarray(Image.open(tmp_path / name).convert("RGB"), float)
        assert np.abs(out - other).mean() < 0.5  # a few edge pixels may differ by rounding


def test_a_source_behind_the_surface_is_not_marked():
    V, F = ico_sphere()
    R = render.camera_rotation(0, 0)  # looking from +z
    P = (V - V.mean(axis=0)) @ R.T
    box = render._image_box(P, 200, 200)
    Q = (P - [box.x0, box.y0, 0.0]) * box.scale
    raster = rasterize(Q, F, box.width, box.height, cull_back=render._closed_outward(P, F))
    front, back = int(np.argmax(P[:, 2])), int(np.argmin(P[:, 2]))
    rim = int(np.argmin(np.abs(P[:, 2]) - 1e-3 * P[:, 0]))  # on the silhouette
    assert render._visible_sources(Q, F, raster, np.array([front, back, rim])).tolist() == [front, rim]


def test_an_open_surface_hides_a_source_on_a_surface_behind_it():
    V, F = grid(4)
    near, far = V + [0, 0, 1.0], V.copy()
    P = np.concatenate([near, far])
    F2 = np.concatenate([F, F + len(V)])
    box = render._image_box(P, 100, 100)
    Q = (P - [box.x0, box.y0, 0.0]) * box.scale
    source = len(V) + 12  # the far grid's centre, behind the near grid
    assert render._visible_sources(Q, F2, rasterize(Q, F2, box.width, box.height), np.array([source])).size == 0
    P[: len(V), 0] += 10.0  # move the near grid aside
    box = render._image_box(P, 100, 100)
    Q = (P - [box.x0, box.y0, 0.0]) * box.scale
    visible = render._visible_sources(Q, F2, rasterize(Q, F2, box.width, box.height), np.array([source]))
    assert visible.tolist() == [source]


def test_picture_size_and_unreachable_gray(tmp_path):
    from PIL import Image

    V, F = ico_sphere(2)
    d = np.where(V[:, 0] > 0.3, np.inf, np.linalg.norm(V - V[0], axis=1))
    path = tmp_path / "d.png"
    render.render_distance(path, V, F, d, sources=[0], size=(4, 3), dpi=50)
    image = np.asarray(Image.open(path).convert("RGB"))
    assert image.shape == (150, 200, 3)
    gray = np.round(np.asarray(hc.viz.UNREACHABLE_COLOR) * 255)
    assert (np.abs(image.astype(float) - gray).max(axis=2) < 40).sum() > 100  # the unreachable cap, shaded
    render.render_distance(tmp_path / "all.png", V, F, np.full(len(V), np.inf), size=(2, 2), dpi=30)


def test_bad_input_is_refused_with_a_typed_error(tmp_path):
    V, F = ico_sphere(1)
    with pytest.raises(hc.errors.InvalidMeshError, match="face indices 0..41"):
        render.render_distance(tmp_path / "x.png", V[:20], F, np.zeros(20))
    with pytest.raises(hc.errors.InvalidOptionError, match="one distance per vertex: 3 distances for 42"):
        render.render_distance(tmp_path / "x.png", V, F, np.zeros(3))
    assert not (tmp_path / "x.png").exists()


def test_the_default_picture_faces_the_source(tmp_path):
    """Issue 38: the default camera faced one side whatever the source; now it faces the (first) source."""
    from heatcore.viz.render import camera_rotation
    from heatcore.viz.view import MAX_ELEVATION, view_facing

    V, F = hc.io.load_demo_mesh()
    centre = V.mean(axis=0)
    for vertex in (int(np.argmin(V[:, 2])), int(np.argmax(V[:, 2])), int(np.argmin(V[:, 0])), int(np.argmin(V[:, 1]))):
        view = view_facing(V, F, vertex)
        towards = camera_rotation(view["elevation"], view["azimuth"])[2]  # from the mesh to the camera
        outward = V[vertex] - centre
        assert towards @ outward / np.linalg.norm(outward) > 0.3, vertex  # seen from its own side
        assert abs(view["elevation"]) <= MAX_ELEVATION
    flat = view_facing(np.c_[np.eye(3)[:, :2], np.zeros(3)], [[0, 1, 2]], 0, up="y")  # a flat triangle in z = 0
    assert flat == {"azimuth": 25.0, "elevation": 15.0}  # facing +z, its normal, three-quarter
    loose = np.r_[V, [[9.0, 9.0, 9.0]]]  # a vertex no face uses: the render's default camera
    assert view_facing(loose, F, len(V)) == {}


def test_distance_png_faces_a_source_on_the_back(tmp_path):
    from heatcore.apps.cli import main
    from heatcore.io import demo_mesh_path

    V, _ = hc.io.load_demo_mesh()
    back = int(np.argmax(V[:, 2]))  # spot faces -z: its tail end, hidden from the old default view
    png = tmp_path / "back.png"
    assert main(["distance", str(demo_mesh_path()), "-s", str(back), "--png", str(png), "--refine", "0", "-q"]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
