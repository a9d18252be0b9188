"""Install the built extension zip into a fresh Blender user folder and run its operator.

Run by tests/test_blender.py in a subprocess whose ``sys.path`` holds only
bpy and numpy (``python -S`` with ``PYTHONPATH``) and whose
``BLENDER_USER_RESOURCES`` is a temporary folder, so that heatcore, scipy,
cholespy, qdldl (and cvxopt, pymetis where bundled) can only come from the installed extension. Runs
the operator (and cvxopt's CHOLMOD where bundled), then imports every module the extension carries.
Prints one JSON line.

Usage: python -S blender_install_check.py EXTENSION.zip [--install-only]

Tests call :func:`run_installed` (the subprocess) and :func:`verify` (what its answer must say).
"""

import importlib
import importlib.util
import json
import os
import pkgutil
import subprocess
import sys
from pathlib import Path

import bpy
import numpy as np


def install_only(zip_path):
    """Install ``zip_path`` and say only what Blender did: the operator's result, enabled, files there."""
    import addon_utils

    result = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    folder = Path(bpy.utils.user_resource("EXTENSIONS")) / "user_default"
    print(json.dumps({"install": sorted(result), "enabled": addon_utils.check("bl_ext.user_default.heat_geodesics")[1],
                      "installed": sorted(p.name for p in folder.glob("[!.]*"))}))


def main(zip_path):
    result = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    import addon_utils

    module = "bl_ext.user_default.heat_geodesics"
    addon = sys.modules.get(module)
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=2.0)
    obj = bpy.context.active_object
    n = len(obj.data.vertices)
    co = np.empty(3 * n)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    top = int(np.argmax(co[:, 2]))
    select = np.zeros(n, dtype=bool)
    select[top] = True
    obj.data.vertices.foreach_set("select", select)
    ran = bpy.ops.mesh.heat_geodesic_distance(isolines=4)
    values = np.empty(n, dtype=np.float32)
    obj.data.attributes["geodesic_distance"].data.foreach_get("value", values)
    exact = 2.0 * np.arccos(np.clip(co @ co[top] / 4.0, -1.0, 1.0))
    hc = sys.modules[module + "._vendor.heatcore"]
    import cholespy
    import qdldl
    import scipy

    try:
        import cvxopt
    except ImportError:  # not bundled on this platform
        cvxopt = None
    try:
        import pymetis
    except ImportError:  # not bundled on this platform
        pymetis = None
    supernodal, nested, sparse_forward = None, False, False
    if cvxopt is not None:  # the large-mesh backend works inside Blender's Python
        if pymetis is not None:  # with its nested dissection, used here on a small mesh
            hc.linalg.ordering.NESTED_DISSECTION_MIN_SIZE = 0
        faces = np.array([p.vertices[:] for p in obj.data.polygons])
        mesh = hc.TriangleMesh(co, faces)
        solver = hc.HeatSolver(mesh, backend="supernodal")
        supernodal = solver.distance([top]).tolist()
        sparse_forward = solver.heat_flow.neumann._sparse_forward is not None  # the bundled CHOLMOD's layout was read
        nested = isinstance(mesh.derived["nested", "supernodal"], hc.linalg.Ordering)

    loaded = sorted(m for m in sys.modules if m.startswith(module + "._vendor.heatcore"))
    imported, errors = import_everything(module)
    print(
        json.dumps(
            {
                "vendored_loaded": loaded,
                "imported": imported,
                "import_errors": errors,
                "faces": [list(p.vertices) for p in obj.data.polygons],
                "co": co.tolist(),
                "top": top,
                "install": sorted(result),
                "enabled": addon_utils.check(module)[1],
                "addon_file": getattr(addon, "__file__", None),
                "extensions_dir": bpy.utils.user_resource("EXTENSIONS"),
                "heatcore_file": hc.__file__,
                "scipy_file": scipy.__file__,
                "scipy_version": scipy.__version__,
                "cholespy_file": cholespy.__file__,
                "qdldl_file": qdldl.__file__,
                "cvxopt_file": getattr(cvxopt, "__file__", None),
                "pymetis_file": getattr(pymetis, "__file__", None),
                "supernodal_distance": supernodal,
                "nested_dissection_used": nested,
                "sparse_forward_used": sparse_forward,
                "operator": sorted(ran),
                "color_active": obj.data.color_attributes.active_color.name,
                "n": n,
                "distance": values.tolist(),
                "exact": exact.tolist(),
            }
        )
    )


def import_everything(package):
    """Import every module of the installed extension (the add-on and what it vendors).

    Returns
    -------
    imported : list of str
        The modules imported.
    errors : dict
        Module -> the error importing it raised (empty when every module imports).
    """
    root = sys.modules[package]
    imported, errors = [], {}
    for info in pkgutil.walk_packages(root.__path__, package + ".", onerror=lambda name: errors.setdefault(name, "walk")):
        try:
            importlib.import_module(info.name)
            imported.append(info.name)
        except Exception as exc:  # noqa: BLE001 - every failure is reported, by module
            errors[info.name] = f"{type(exc).__name__}: {exc}"
    return sorted(imported), errors


def run_installed(zip_path, workdir, only_install=False):
    """Run this script on ``zip_path`` in a Python that sees only bpy and numpy; its JSON answer.

    The Blender user folder (``BLENDER_USER_RESOURCES``) is ``workdir/blender``, so the extension
    is installed into ``workdir/blender/extensions/user_default``. With ``only_install``, the
    answer of :func:`install_only`.
    """
    lite = Path(workdir) / "site"
    lite.mkdir()
    for name in ("bpy", "numpy"):
        src = Path(next(iter(importlib.util.find_spec(name).submodule_search_locations)))
        for path in src.parent.glob(name + "*"):
            if path.name in (name, name + ".libs"):
                (lite / path.name).symlink_to(path)
    env = {**os.environ, "PYTHONPATH": str(lite), "BLENDER_USER_RESOURCES": str(Path(workdir) / "blender")}
    args = [sys.executable, "-S", __file__, str(zip_path), *(["--install-only"] if only_install else [])]
    proc = subprocess.run(args, cwd=workdir, env=env,
                          capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def verify(out, workdir, platform, shipped):
    """Assert what :func:`run_installed` answered: installed, enabled, run, the core's distances.

    ``shipped`` names the heatcore modules the zip vendors (``extension_contents.heatcore_modules``).
    """
    import heatcore as hc
    from heatcore.reference import mean_relative_error

    installed = Path(out["extensions_dir"]).resolve()
    assert installed == (Path(workdir) / "blender" / "extensions").resolve()
    assert out["install"] == ["FINISHED"] and out["enabled"] and out["operator"] == ["FINISHED"]
    for key in ("addon_file", "heatcore_file", "scipy_file", "cholespy_file", "qdldl_file"):
        assert Path(out[key]).resolve().is_relative_to(installed), (key, out[key])
    assert "_vendor" in out["heatcore_file"] and out["color_active"] == "geodesic_distance_color"
    # Every module the extension carries imports inside Blender, without the heatcore files left out.
    assert out["import_errors"] == {}
    prefix = "bl_ext.user_default.heat_geodesics."
    assert {m for m in out["imported"] if m.startswith(prefix + "_vendor.")} == {prefix + "_vendor." + m for m in shipped}
    addon = Path(__file__).resolve().parents[1] / "blender_addon"
    assert {prefix + p.stem for p in addon.glob("*.py") if p.stem != "__init__"} <= set(out["imported"])
    assert out["vendored_loaded"] and set(out["vendored_loaded"]) <= {prefix + "_vendor." + m for m in shipped}
    d, exact = np.array(out["distance"]), np.array(out["exact"])
    assert len(d) == out["n"] == 162
    core = hc.geodesic_distance(np.array(out["co"]), np.array(out["faces"]), [out["top"]])
    np.testing.assert_allclose(d, core, rtol=1e-5, atol=1e-6)  # the core's numbers (float32 attribute)
    assert mean_relative_error(d, exact) < 0.02
    if platform in ("linux-x64", "windows-x64"):  # where cvxopt has wheels: bundled, and it runs
        assert Path(out["cvxopt_file"]).resolve().is_relative_to(installed)
        np.testing.assert_allclose(out["supernodal_distance"], core, rtol=1e-6, atol=1e-6)
        assert out["sparse_forward_used"]
    if platform in ("linux-x64", "macos-x64", "macos-arm64"):  # where pymetis has wheels
        assert Path(out["pymetis_file"]).resolve().is_relative_to(installed)
    if platform == "linux-x64":  # both: the Poisson factor was ordered by METIS inside Blender
        assert out["nested_dissection_used"]


if __name__ == "__main__":
    (install_only if "--install-only" in sys.argv[2:] else main)(sys.argv[1])
