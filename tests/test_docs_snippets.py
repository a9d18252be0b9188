"""Every ```python block of README.md and docs/*.md runs, as written, in a fresh folder.

Snippets that write files write them in a temporary folder; snippets that
need a file make it first, so each block runs on its own. Blocks that need
Blender (``import bpy``) or PyMeshLab (``import pymeshlab``) say so in their
test id (``[bpy]``, ``[pymeshlab]``) and run where the module is installed;
elsewhere they are reported as skipped with the module named, never passed.

The Blender block runs in a subprocess with the add-on of this checkout
loaded under the name the installed extension has
(``bl_ext.user_default.heat_geodesics``) and, as the scene the block expects,
an ico sphere with one selected vertex as the active object.
"""

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
NEEDS = ("bpy", "pymeshlab")


def python_blocks(path):
    """(first line number, code) of each ```python block of a Markdown file."""
    text = path.read_text()
    return [(text[: m.start()].count("\n") + 2, m.group(1))
            for m in re.finditer(r"^```python\n(.*?)^```", text, re.M | re.S)]


def needs(code):
    return [m for m in NEEDS if re.search(rf"^\s*(import|from) {m}\b", code, re.M)]


SNIPPETS = [(path, line, code) for path in DOCS for line, code in python_blocks(path)]
IDS = [f"{p.relative_to(REPO)}:{line}" + "".join(f"[{m}]" for m in needs(code)) for p, line, code in SNIPPETS]

BLENDER_SCENE = f"""
import importlib.util, sys, types
import bpy

ADDON = {str(REPO / "blender_addon")!r}
for name in ("bl_ext", "bl_ext.user_default"):  # the packages Blender makes for installed extensions
    sys.modules[name] = types.ModuleType(name)
    sys.modules[name].__path__ = []
spec = importlib.util.spec_from_file_location(
    "bl_ext.user_default.heat_geodesics", ADDON + "/__init__.py", submodule_search_locations=[ADDON])
addon = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = addon
spec.loader.exec_module(addon)
addon.register()

bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
selected = [False] * len(bpy.context.object.data.vertices)
selected[5] = True
bpy.context.object.data.vertices.foreach_set("select", selected)
"""


def test_snippets_are_found():
    names = {p.relative_to(REPO).as_posix() for p, _, _ in SNIPPETS}
    assert {"README.md", "docs/accuracy-high.md", "docs/blender.md", "docs/meshlab.md", "docs/pointcloud.md",
            "docs/polygon.md", "docs/tet.md"} <= names
    assert len(SNIPPETS) >= 7
    marked = [i.split(":")[0] + i[i.index("["):] for i in IDS if "[" in i]
    assert marked == ["docs/blender.md[bpy]", "docs/meshlab.md[pymeshlab]"]


@pytest.mark.parametrize("path, line, code", SNIPPETS, ids=IDS)
def test_snippet_runs(path, line, code, tmp_path, monkeypatch):
    where = f"{path.relative_to(REPO)}:{line}"
    for module in needs(code):
        if importlib.util.find_spec(module) is None:
            pytest.skip(f"{where} needs {module}, which is not installed here")
    if "bpy" in needs(code):
        script = tmp_path / "snippet.py"
        script.write_text(BLENDER_SCENE + "\n# ---- the snippet\n" + code
                          + "\nimport numpy as np\nassert np.isfinite(result.distance).all() and result.distance.max() > 0\n")
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
        proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True,
                              timeout=300)
        assert proc.returncode == 0, f"{where} failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}"
        return
    monkeypatch.chdir(tmp_path)
    exec(compile(code, where, "exec"), {"__name__": "__snippet__"})
