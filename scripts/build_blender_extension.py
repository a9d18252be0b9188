"""Build the Heat Geodesics Blender extension: zip(s) that users install from disk.

Steps:

1. stage ``blender_addon/`` and vendor heatcore's source as ``_vendor/heatcore``
   (a sub-package of the extension, so it cannot clash with other extensions);
2. download the binary wheels heatcore needs and Blender lacks (scipy,
   cholespy, qdldl; cvxopt and pymetis where they have wheels) for each platform and Python
   version, with ``pip download --only-binary=:all: --platform ... --python-version ...``;
3. write ``platforms`` and ``wheels`` into the staged ``blender_manifest.toml``;
4. build with Blender's own extension builder: ``blender --command extension
   build`` when ``--blender`` is given, else the same CLI bundled with the
   ``bpy`` module (``bl_pkg/cli/blender_ext.py``), one zip per platform.

Blender 4.2 - 5.0 run Python 3.11; Python 3.13 wheels are added where they
exist (Blender releases on 3.13 pick them; Blender picks the wheels of its own
Python and platform at install time).

Examples
--------
Every platform (four zips in dist/)::

    python scripts/build_blender_extension.py

Only this machine's platform and Blender 4.2 - 5.0's Python::

    python scripts/build_blender_extension.py --platform linux-x64 --python 3.11
"""

import argparse
import importlib.util
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
ADDON_DIR = REPO / "blender_addon"
HEATCORE_DIR = REPO / "heatcore"

#: Blender platform name -> pip ``--platform`` tags (any of them matches).
PLATFORMS = {
    "linux-x64": ["manylinux_2_28_x86_64", "manylinux_2_27_x86_64", "manylinux_2_17_x86_64", "manylinux2014_x86_64"],
    "macos-arm64": ["macosx_12_0_arm64", "macosx_11_0_arm64"],
    "macos-x64": ["macosx_11_0_x86_64", "macosx_10_15_x86_64", "macosx_10_14_x86_64", "macosx_10_13_x86_64"],
    "windows-x64": ["win_amd64"],
}

#: Python versions: 3.11 is required (Blender 4.2 - 5.0); the others are added when wheels exist.
REQUIRED_PYTHON = "3.11"
PYTHONS = ["3.11", "3.13"]

#: Pinned wheels. scipy 1.15 supports numpy 1.23.5 - 2.x, which covers the
#: numpy of every Blender from 4.2 on, and has wheels for Python 3.11 and 3.13.
REQUIREMENTS = ["scipy==1.15.3", "cholespy==2.2.0", "qdldl==0.1.9.post1"]
#: Groups bundled where wheels exist for the platform and Python (heatcore runs without them):
#: cvxopt's supernodal CHOLMOD prepares sculpt-sized meshes several times faster (GPL-3, as
#: Blender itself), and pymetis (with its one dependency), whose nested dissection makes the
#: Poisson factor of meshes from 500k vertices up a third smaller (MIT; no Windows wheel). None
#: needs numpy.
OPTIONAL_REQUIREMENTS = [["cvxopt==1.3.3"], ["pymetis==2025.2.2", "typing-extensions==4.16.0"]]
#: SPDX license of each bundled wheel, as its metadata states it (the libraries its binaries carry
#: are listed in docs/blender.md). blender_manifest.toml and docs/blender.md name every wheel with
#: its license; tests/test_blender_menus.py keeps them equal to this table and to the pins above.
WHEEL_LICENSES = {
    "scipy": "BSD-3-Clause",
    "cholespy": "BSD-3-Clause",
    "qdldl": "Apache-2.0",
    "cvxopt": "GPL-3.0-or-later",
    "pymetis": "MIT AND Apache-2.0",
    "typing-extensions": "PSF-2.0",
}


def current_platform():
    """The Blender platform name of this machine (for example ``linux-x64``)."""
    import platform

    system = {"Linux": "linux", "Darwin": "macos", "Windows": "windows"}[platform.system()]
    machine = platform.machine().lower()
    arch = "arm64" if machine in ("arm64", "aarch64") else "x64"
    return f"{system}-{arch}"


def stage_sources(stage):
    """Copy the add-on and vendor heatcore's source into ``stage``."""
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor")
    shutil.copytree(ADDON_DIR, stage, ignore=ignore)
    vendor = stage / "_vendor"
    vendor.mkdir()
    (vendor / "__init__.py").write_text('"""Packages bundled with the extension (heatcore)."""\n')
    shutil.copytree(HEATCORE_DIR, vendor / "heatcore", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    shutil.copy(HEATCORE_DIR.parent / "LICENSE", vendor / "heatcore" / "LICENSE")  # MIT travels with it


def download_wheels(dest, platform, python, requirements=REQUIREMENTS, pip=None):
    """Download the binary wheels of ``requirements`` for one Blender platform and Python version.

    Returns
    -------
    list of Path
        The wheels downloaded (empty when some requirement has no wheel there).
    """
    tmp = Path(tempfile.mkdtemp(prefix="wheels-", dir=dest))
    cmd = [*(pip or [sys.executable, "-m", "pip"]), "download", "--quiet", "--no-deps", "--only-binary=:all:"]
    for tag in PLATFORMS[platform]:
        cmd += ["--platform", tag]
    cmd += ["--python-version", python, "--dest", str(tmp), *requirements]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wheels = sorted(tmp.glob("*.whl"))
    if proc.returncode != 0 or len(wheels) != len(requirements):
        shutil.rmtree(tmp)
        return [], proc.stderr.strip()
    for w in wheels:
        shutil.move(str(w), dest / w.name)
    tmp.rmdir()
    return [dest / w.name for w in wheels], ""


def write_manifest(stage, platforms, wheels):
    """Insert ``platforms`` and ``wheels`` into the staged manifest (before its first table)."""
    path = stage / "blender_manifest.toml"
    lines = path.read_text().splitlines()
    first_table = next((i for i, line in enumerate(lines) if line.startswith("[")), len(lines))
    insert = [
        "platforms = [" + ", ".join(f'"{p}"' for p in platforms) + "]",
        "wheels = [",
        *[f'  "./wheels/{w.name}",' for w in wheels],
        "]",
        "",
    ]
    path.write_text("\n".join(lines[:first_table] + insert + lines[first_table:]) + "\n")


def blender_ext_cli():
    """Path of ``blender_ext.py``, the extension builder bundled with the bpy module."""
    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        raise SystemExit("the bpy module is not installed: pass --blender /path/to/blender, or pip install bpy")
    root = Path(list(spec.submodule_search_locations)[0])
    found = sorted(root.glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
    if not found:
        raise SystemExit(f"no bl_pkg/cli/blender_ext.py under {root}")
    return found[-1]


def build(output_dir, platforms=None, pythons=None, blender=None, log=print):
    """Build one extension zip per platform.

    Parameters
    ----------
    output_dir : path
        Where the zips go (created if needed).
    platforms : list of str, optional
        Blender platform names (keys of :data:`PLATFORMS`); default all.
    pythons : list of str, optional
        Python versions; default :data:`PYTHONS`. Wheels for
        :data:`REQUIRED_PYTHON` must exist; others are skipped with a note.
    blender : path, optional
        A Blender executable; default: the builder bundled with ``bpy``.

    Returns
    -------
    list of Path
        The zips built.
    """
    platforms = list(platforms or PLATFORMS)
    pythons = list(pythons or PYTHONS)
    for p in platforms:
        if p not in PLATFORMS:
            raise SystemExit(f"unknown platform {p!r}; choose from {sorted(PLATFORMS)}")
    output_dir = Path(output_dir).resolve()
    output_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="heat_geodesics-") as tmp:
        stage = Path(tmp) / "heat_geodesics"
        stage_sources(stage)
        wheel_dir = stage / "wheels"
        wheel_dir.mkdir()
        wheels = []
        for platform in platforms:
            for python in pythons:
                got, error = download_wheels(wheel_dir, platform, python)
                if not got:
                    if python == REQUIRED_PYTHON:
                        raise SystemExit(f"no wheels of {REQUIREMENTS} for {platform}, Python {python}:\n{error}")
                    log(f"note: skipping Python {python} on {platform} (no wheels): {error.splitlines()[-1:]}")
                    continue
                for optional in OPTIONAL_REQUIREMENTS:
                    extra, _ = download_wheels(wheel_dir, platform, python, optional)
                    got += extra
                wheels += got
                log(f"{platform} py{python}: {', '.join(w.name for w in got) or '-'}")
        write_manifest(stage, platforms, sorted(set(wheels)))
        if blender:
            cmd = [str(blender), "--factory-startup", "--command", "extension", "build"]
        else:
            cmd = [sys.executable, str(blender_ext_cli()), "build"]
        cmd += ["--source-dir", str(stage), "--output-dir", str(output_dir)]
        if len(platforms) > 1:
            cmd.append("--split-platforms")
        started = time.time() - 1.0
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode != 0:
            raise SystemExit(f"extension build failed ({' '.join(cmd)}):\n{proc.stdout}")
        zips = sorted(z for z in output_dir.glob("*.zip") if z.stat().st_mtime >= started)
    for z in zips:
        log(f"built {z} ({z.stat().st_size / 1e6:.1f} MB)")
    return zips


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output-dir", default=str(REPO / "dist"), help="where the zips go (default: dist/)")
    parser.add_argument(
        "--platform",
        action="append",
        choices=sorted(PLATFORMS),
        help="Blender platform to build for (repeatable; default: all). 'current' is not accepted: "
        f"this machine is {current_platform()}",
    )
    parser.add_argument("--python", action="append", help=f"Python version(s) for wheels (default: {PYTHONS})")
    parser.add_argument("--blender", help="Blender executable to build with (default: the bpy module's builder)")
    args = parser.parse_args(argv)
    build(args.output_dir, args.platform, args.python, args.blender)


if __name__ == "__main__":
    main()
