"""The Blender extension's packaging: one zip per platform and Blender Python, each under 60 MB.

tests/test_blender.py installs this machine's zip (built offline) into Blender and runs it; here:
which Blender runs which Python, what is vendored and pruned, the measurements and the table of
docs/blender-packaging.md, and (with the network) the release zips of every platform built and weighed.
"""

import base64
import doctest
import hashlib
import importlib.metadata as md
import importlib.util
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
import tomllib

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = REPO / "scripts"
DOCS = REPO / "docs" / "blender-packaging.md"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, SCRIPTS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(name, module)
    spec.loader.exec_module(module)
    return sys.modules[name]


build = _load("build_blender_extension")
contents, sizes, slim, repacked = (_load(n) for n in ("extension_contents", "extension_sizes", "slim_wheels",
                                                       "installed_wheels"))


@pytest.mark.parametrize("module", [build, contents, sizes, slim, repacked], ids=lambda m: m.__name__)
def test_doctests(module, monkeypatch):
    # doctest keeps the objects whose inspect.getmodule is this module: another test may have loaded the script
    # again under the same name (tests/test_blender.py does), so this instance is made the registered one
    monkeypatch.setitem(sys.modules, module.__name__, module)
    result = doctest.testmod(module)
    assert result.attempted > 0 and result.failed == 0


def test_the_python_of_this_blender_picks_its_zip():
    """bpy 5.0.1 runs the Python its Blender series is mapped to; the series meet without a gap."""
    bpy = pytest.importorskip("bpy")
    version = ".".join(str(x) for x in bpy.app.version)
    here = f"{sys.version_info[0]}.{sys.version_info[1]}"
    key = lambda v: tuple(int(x) for x in v.split("."))
    matching = [py for py, (low, high) in build.BLENDER_PYTHONS.items()
                if key(low) <= key(version) and (high is None or key(version) < key(high))]
    assert matching == [here], (version, here)
    (low11, high11), (low13, high13) = build.BLENDER_PYTHONS["3.11"], build.BLENDER_PYTHONS["3.13"]
    assert (low11, high11, low13, high13) == ("4.2.0", "5.1.0", "5.1.0", None)


def test_targets_name_their_blender_versions():
    assert build.Target("linux-x64", "3.11").filename("0.1.0") == "heat_geodesics-0.1.0-blender-4.2-5.0-linux-x64.zip"
    assert build.Target("windows-x64", "3.13").filename("0.1.0") == (
        "heat_geodesics-0.1.0-blender-5.1-and-newer-windows-x64.zip")
    with pytest.raises(build.BuildError, match="unknown platform or Python '3.12'"):
        build.build(REPO / "dist" / "never", pythons=["3.12"])


def test_manifest_of_a_target(tmp_path):
    (tmp_path / "blender_manifest.toml").write_text((REPO / "blender_addon" / "blender_manifest.toml").read_text())
    wheels = [Path("scipy-1.15.3-cp313-cp313-win_amd64.whl"), Path("qdldl-0.1.9.post1-cp313-cp313-win_amd64.whl")]
    build.write_manifest(tmp_path, build.Target("windows-x64", "3.13"), wheels)
    manifest = tomllib.loads((tmp_path / "blender_manifest.toml").read_text())
    assert manifest["blender_version_min"] == "5.1.0" and "blender_version_max" not in manifest
    assert manifest["platforms"] == ["windows-x64"]
    assert manifest["wheels"] == ["./wheels/qdldl-0.1.9.post1-cp313-cp313-win_amd64.whl",
                                  "./wheels/scipy-1.15.3-cp313-cp313-win_amd64.whl"]
    assert manifest["maintainer"] == "heatcore developers" and "website" not in manifest  # the repo states none
    (tmp_path / "blender_manifest.toml").write_text((REPO / "blender_addon" / "blender_manifest.toml").read_text())
    build.write_manifest(tmp_path, build.Target("linux-x64", "3.11"), wheels[:1])
    manifest = tomllib.loads((tmp_path / "blender_manifest.toml").read_text())
    assert (manifest["blender_version_min"], manifest["blender_version_max"]) == ("4.2.0", "5.1.0")


def test_only_the_modules_the_addon_imports_are_vendored(tmp_path):
    shipped, dropped = contents.heatcore_modules()
    for front_end in ("heatcore.apps.cli", "heatcore.apps.meshlab", "heatcore.apps.batch.run", "heatcore.__main__"):
        assert front_end in dropped
    for needed in ("heatcore", "heatcore.heat", "heatcore.viz.colormap", "heatcore.paths", "heatcore.linalg.supernodal"):
        assert needed in shipped
    assert "heatcore/data/spot.obj" in contents.dropped_files()
    vendored_bytes = contents.stage_sources(tmp_path / "stage")
    vendored = sorted(p.relative_to(tmp_path / "stage" / "_vendor").as_posix()
                      for p in (tmp_path / "stage" / "_vendor" / "heatcore").rglob("*") if p.is_file())
    assert vendored == sorted([*shipped.values(), "heatcore/LICENSE"])
    assert vendored_bytes == sum((REPO / p).stat().st_size for p in shipped.values())
    assert (tmp_path / "stage" / "__init__.py").read_text() == (REPO / "blender_addon" / "__init__.py").read_text()


def _hash(data):
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def _records(wheel):
    with zipfile.ZipFile(wheel) as z:
        record = next(n for n in z.namelist() if n.endswith(".dist-info/RECORD"))
        rows = [line.split(",") for line in z.read(record).decode().splitlines()]
    return {name: (digest, size) for name, digest, size in rows if name != record}


def test_pruning_drops_tests_and_keeps_a_valid_record(tmp_path):
    wheel = tmp_path / "scipy-1.0-cp311-cp311-linux_x86_64.whl"
    members = {"scipy/__init__.py": b"x = 1\n", "scipy/sparse/tests/test_a.py": b"def test(): pass\n" * 50,
               "scipy/sparse/_base.py": b"y = 2\n" * 10, "scipy-1.0.dist-info/RECORD": b""}
    with zipfile.ZipFile(wheel, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in members.items():
            z.writestr(name, data)
    before = (wheel.stat().st_size, sum(len(d) for d in members.values()))
    assert slim.prune(wheel) == before
    rows = _records(wheel)
    assert sorted(rows) == ["scipy/__init__.py", "scipy/sparse/_base.py"]
    with zipfile.ZipFile(wheel) as z:
        for name, (digest, size) in rows.items():
            assert (digest, int(size)) == (_hash(z.read(name)), len(z.read(name)))
    assert slim.pruned(["cvxopt/glpk.cp311-win_amd64.pyd", "cvxopt/cholmod.cp311-win_amd64.pyd",
                        "cvxopt.libs/libgsl-b64c76bc.so.23.1.0", "cvxopt.libs/libcholmod-8f6cf142.so.3.0.6"],
                       "cvxopt") == ["cvxopt/glpk.cp311-win_amd64.pyd", "cvxopt.libs/libgsl-b64c76bc.so.23.1.0"]


def test_a_repacked_wheel_holds_the_installed_files(tmp_path):
    wheel = repacked.repack("qdldl", tmp_path)
    dist = md.distribution("qdldl")
    assert wheel.name.startswith(f"qdldl-{dist.version}-cp{sys.version_info[0]}{sys.version_info[1]}-")
    rows = _records(wheel)
    with zipfile.ZipFile(wheel) as z:
        for name, (digest, size) in rows.items():
            data = z.read(name)
            assert data == Path(dist.locate_file(name)).read_bytes(), name
            assert (digest, int(size)) == (_hash(data), len(data))
    with pytest.raises(repacked.NotRepackable, match="not installed"):
        repacked.repack("no-such-distribution-here", tmp_path)


def test_measure_counts_each_wheel_packed_and_unpacked(tmp_path):
    inner = tmp_path / "qdldl-1-cp311-cp311-linux_x86_64.whl"
    with zipfile.ZipFile(inner, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("qdldl.so", b"\0" * 100_000)
        z.writestr("qdldl-1.dist-info/RECORD", b"")
    outer = tmp_path / "ext.zip"
    with zipfile.ZipFile(outer, "w", zipfile.ZIP_DEFLATED) as z:
        z.write(inner, "wheels/" + inner.name, compress_type=zipfile.ZIP_STORED)
        z.writestr("__init__.py", b"a = 1\n" * 1000)
    built = sizes.measure("linux-x64", "3.11", ("4.2.0", "5.1.0"), outer, ["cvxopt"], {inner.name: (200_000, 300_000)})
    assert built.wheels == {inner.name: (inner.stat().st_size, 100_000)}
    assert built.sources[1] == 6000 and built.installed_bytes == 106_000
    assert built.zip_bytes == outer.stat().st_size
    assert built.pruned_bytes == (200_000 - inner.stat().st_size, 200_000)
    row = sizes.size_table([built]).splitlines()[2]
    assert row.startswith("| linux-x64 | 4.2 - 5.0 | 3.11 |") and row.endswith("| 0.2 (0.2) | cvxopt |")


def _docs_rows():
    text = DOCS.read_text()
    table = text[text.index(sizes.BEGIN):text.index(sizes.END)]
    return [[c.strip() for c in line.strip("|").split("|")] for line in table.splitlines()
            if line.startswith("| ") and not line.startswith("| platform")]


def test_the_docs_table_measured_every_zip_under_60_mb():
    rows = _docs_rows()
    assert sorted((r[0], r[2]) for r in rows) == sorted((p, py) for p in build.PLATFORMS for py in build.PYTHONS)
    weights = {(r[0], r[2]): float(r[3].strip("*")) for r in rows}
    assert max(weights.values()) <= sizes.MAX_ZIP_MB, weights
    text = DOCS.read_text()
    pins = build.REQUIREMENTS + [r for group in build.OPTIONAL_REQUIREMENTS for r in group]
    assert f"with {', '.join(pins)}." in text  # measured with the wheels pinned now
    assert sizes.dropped_list(contents.dropped_files()) in text  # and the files left out now


def _pip_reaches_the_index(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--no-deps", "--only-binary=:all:",
                           "--platform", "win_amd64", "--python-version", "3.11", "--dest", str(tmp_path),
                           "qdldl==0.1.9.post1"], capture_output=True, text=True, check=False, timeout=120)
    return proc.returncode == 0, proc.stderr.strip().splitlines()[-1:] or ["no message"]


def _runs_on(wheel, python):
    """Whether ``wheel``'s tags let it run on CPython ``python`` (its own ABI, the stable ABI, or pure)."""
    _, _, py_tags, abi, _ = wheel[:-len(".whl")].split("-")
    minor = int(python.split(".")[1])
    for tag in py_tags.split("."):
        if tag == "py3" and abi == "none":
            return True
        if tag == f"cp3{minor}" or (abi == "abi3" and tag.startswith("cp3") and int(tag[3:]) <= minor):
            return True
    return False


def test_wheel_tags_for_a_python():
    assert _runs_on("cholespy-2.2.0-cp312-abi3-manylinux_2_28_x86_64.whl", "3.13")
    assert not _runs_on("cholespy-2.2.0-cp312-abi3-manylinux_2_28_x86_64.whl", "3.11")
    assert not _runs_on("scipy-1.15.3-cp313-cp313-win_amd64.whl", "3.11")
    assert _runs_on("typing_extensions-4.16.0-py3-none-any.whl", "3.11")


@pytest.mark.slow
def test_release_zips_are_built_and_under_60_mb(tmp_path):
    """With the network: pip downloads each platform's pinned wheels; every zip weighs 60 MB or less;
    this machine's zip (pinned wheels, pruned) installs into Blender and runs."""
    pytest.importorskip("bpy", reason="the zips are built with Blender's extension builder (the 'blender' extra)")
    online, why = _pip_reaches_the_index(tmp_path / "probe")
    if not online:
        pytest.skip(f"pip cannot download wheels here (offline?): {why[0]}")
    builds = build.build(tmp_path / "dist", log=lambda *a: None)
    assert sorted((b.platform, b.python) for b in builds) == sorted(
        (p, py) for p in build.PLATFORMS for py in build.PYTHONS)
    weights = {b.path.name: round(b.zip_mb, 1) for b in builds}
    assert max(weights.values()) <= sizes.MAX_ZIP_MB, weights
    for b in builds:
        with zipfile.ZipFile(b.path) as z:
            manifest = tomllib.loads(z.read("blender_manifest.toml").decode())
            names = z.namelist()
            for wheel in (n for n in names if n.endswith(".whl")):
                with z.open(wheel) as f, zipfile.ZipFile(f) as w:
                    assert slim.pruned(w.namelist(), slim.distribution(wheel)) == [], wheel
        assert not any(re.search(r"heatcore/apps/|spot\.obj|heatcore/reference\.py", n) for n in names)
        assert manifest["platforms"] == [b.platform]
        assert manifest["blender_version_min"] == build.BLENDER_PYTHONS[b.python][0]
        assert all(_runs_on(Path(w).name, b.python) for w in manifest["wheels"]), manifest["wheels"]
        assert ("cvxopt" in b.missing) == b.platform.startswith("macos")
        assert ("pymetis" in b.missing) == (b.platform == "windows-x64")
        assert ("typing-extensions" in b.missing) == (b.platform == "windows-x64")  # only with pymetis
    here = [b for b in builds if (b.platform, b.python) == (build.current_platform(), f"3.{sys.version_info[1]}")]
    assert len(here) == 1
    import blender_install_check  # imports bpy: the test extras have it

    workdir = tmp_path / "install"
    workdir.mkdir()
    out = blender_install_check.run_installed(here[0].path, workdir)
    blender_install_check.verify(out, workdir, here[0].platform, contents.heatcore_modules()[0])
    pinned = dict(req.split("==") for req in build.REQUIREMENTS)
    assert out["scipy_version"] == pinned["scipy"]  # the zip's scipy, not this Python's
    # The zip of the other Python is refused by this Blender: its manifest's versions exclude it.
    (other,) = [b for b in builds if b.platform == here[0].platform and b.python != here[0].python]
    answers = {}
    for b in (here[0], other):
        workdir = tmp_path / f"only-{b.python}"
        workdir.mkdir()
        answers[b.python] = blender_install_check.run_installed(b.path, workdir, only_install=True)
    assert answers[here[0].python]["installed"] == ["heat_geodesics"] and answers[here[0].python]["enabled"]
    assert answers[other.python]["installed"] == [] and not answers[other.python]["enabled"], answers
