"""Install the built extension zip into a fresh Blender user folder and run its operator.

Run by tests/test_blender.py in a subprocess whose ``sys.path`` holds only
bpy and numpy (``python -S`` with ``PYTHONPATH``) and whose
``BLENDER_USER_RESOURCES`` is a temporary folder, so that heatcore, scipy,
cholespy, qdldl (and cvxopt, pymetis where bundled) can only come from the installed extension. Runs
the operator (and cvxopt's CHOLMOD where bundled), then imports every module the extension carries.
Prints one JSON line.

Usage: python -S blender_install_check.py EXTENSION.zip
"""

import importlib
import json
import pkgutil
import sys

import bpy
import numpy as np


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


if __name__ == "__main__":
    main(sys.argv[1])
