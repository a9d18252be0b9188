"""A missing optional package is a skip, never an error (issue 38, pins and skips row).

``pip install -e ".[test]"`` leaves out the ``blender`` extra: the Blender test modules must be
reported skipped, not fail at collection. gdist 2.1.0's wheels are built against numpy 1: under
numpy 2 its import raises ``ValueError`` ("numpy.dtype size changed"), which
``pytest.importorskip`` does not catch. Both are reproduced here in a child pytest whose
``PYTHONPATH`` starts with stand-ins: a ``bpy`` that is not installed and a ``gdist`` that
fails as the numpy-1 wheel does under numpy 2.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from heatcore.reference import import_gdist

REPO = Path(__file__).resolve().parents[1]
BROKEN_GDIST = 'raise ValueError("numpy.dtype size changed, may indicate binary incompatibility")\n'
NO_BPY = 'raise ModuleNotFoundError("No module named \'bpy\'", name="bpy")\n'


@pytest.fixture
def stand_ins(tmp_path):
    (tmp_path / "gdist.py").write_text(BROKEN_GDIST)
    (tmp_path / "bpy.py").write_text(NO_BPY)
    return tmp_path


def child_pytest(stand_ins, *args):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(stand_ins), str(REPO)]))
    done = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", "-rs", *args],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=300, check=False)
    return done.returncode, done.stdout + done.stderr


def test_a_gdist_built_for_another_numpy_is_an_import_error(stand_ins, monkeypatch):
    monkeypatch.syspath_prepend(str(stand_ins))
    monkeypatch.delitem(sys.modules, "gdist", raising=False)
    with pytest.raises(ImportError, match=r"gdist cannot be imported with numpy .*install numpy<2"):
        import_gdist()


def test_blender_modules_are_skipped_without_bpy(stand_ins):
    # the modules that need bpy to be imported (tests/test_blender_packaging.py collects without it: its few
    # tests that run Blender skip on their own)
    modules = sorted(p.name for p in (REPO / "tests").glob("test_blender*.py")
                     if "import blender_required" in p.read_text()) + ["concave_meshes.py"]
    assert len(modules) >= 26
    code, out = child_pytest(stand_ins, "--collect-only", *(f"tests/{m}" for m in modules))
    assert "error" not in out.lower(), out
    assert f"SKIPPED [{len(modules)}] tests/blender_required.py:10: Blender's bpy is not installed" in out, out
    assert code == 5, out  # pytest's "no tests collected": every module skipped, none failed
    code, out = child_pytest(stand_ins, "--collect-only", "tests/test_blender_packaging.py")
    assert code == 0 and "error" not in out.lower(), out


def test_reference_doctests_skip_with_a_broken_gdist(stand_ins):
    code, out = child_pytest(stand_ins, "heatcore/reference.py")
    assert code == 0, out
    assert out.count("gdist cannot be imported with numpy") == 2, out  # exact_distance, exact_directions
    assert "4 passed, 2 skipped" in out, out
