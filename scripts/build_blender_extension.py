"""Build the Heat Geodesics Blender extension: one zip per platform and Blender Python version.

Each zip is built on its own (:func:`build_one`):

1. stage ``blender_addon/`` and vendor, as ``_vendor/heatcore``, only the
   heatcore modules the add-on imports (:mod:`extension_contents`);
2. download the binary wheels of that one platform and Python (scipy,
   cholespy, qdldl; cvxopt and pymetis where they have wheels) with
   ``pip download --only-binary=:all: --platform ... --python-version ...``,
   or, with ``--from-installed``, rebuild them from the packages installed here
   (:mod:`installed_wheels`: offline, this machine's platform and Python only),
   and prune from them what Blender never loads (:mod:`slim_wheels`);
3. write ``platforms``, ``wheels`` and the Blender versions that run that
   Python (:data:`BLENDER_PYTHONS`) into the staged ``blender_manifest.toml``;
4. build with Blender's own extension builder: ``blender --command extension
   build`` when ``--blender`` is given, else the same CLI bundled with the
   ``bpy`` module (``bl_pkg/cli/blender_ext.py``);
5. measure the zip and each wheel in it (:mod:`extension_sizes`); ``--docs``
   writes the table into docs/blender-packaging.md.

Examples
--------
Every platform and Python (eight zips in dist/), and the size table::

    python scripts/build_blender_extension.py --docs

This machine's platform, Blender 4.2 - 5.0, offline::

    python scripts/build_blender_extension.py --from-installed --python 3.11
"""

import argparse
import importlib.util
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

if str(Path(__file__).resolve().parent) not in sys.path:  # loaded by path (tests): find its neighbours
    sys.path.insert(0, str(Path(__file__).resolve().parent))

from extension_contents import dropped_files, heatcore_modules, stage_sources
from extension_sizes import MAX_ZIP_MB, measure, previous_series, write_docs
from installed_wheels import NotRepackable, repack
from slim_wheels import prune

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs" / "blender-packaging.md"

#: Blender platform name -> pip ``--platform`` tags (any of them matches).
PLATFORMS = {
    "linux-x64": ["manylinux_2_28_x86_64", "manylinux_2_27_x86_64", "manylinux_2_17_x86_64", "manylinux2014_x86_64"],
    "macos-arm64": ["macosx_12_0_arm64", "macosx_11_0_arm64"],
    "macos-x64": ["macosx_11_0_x86_64", "macosx_10_15_x86_64", "macosx_10_14_x86_64", "macosx_10_13_x86_64"],
    "windows-x64": ["win_amd64"],
}

#: Blender's Python -> the Blender versions that run it: (``blender_version_min``, ``blender_version_max``,
#: exclusive as Blender reads it; None: open). The ``bpy`` wheels on PyPI say so: 4.2.0 - 5.0.1 are
#: cp311 only (``Requires-Python ==3.11.*``), 5.1.2, 5.2.3 and 5.3.0 cp313 only (``==3.13.*``).
BLENDER_PYTHONS = {"3.11": ("4.2.0", "5.1.0"), "3.13": ("5.1.0", None)}
PYTHONS = list(BLENDER_PYTHONS)
#: The Python whose zips must build; the others are skipped with a note when a wheel is missing.
REQUIRED_PYTHON = "3.11"

#: Pinned wheels. scipy 1.15 supports numpy 1.23.5 - 2.x, which covers the
#: numpy of every Blender from 4.2 on, and has wheels for Python 3.11 and 3.13.
REQUIREMENTS = ["scipy==1.15.3", "cholespy==2.2.0", "qdldl==0.1.9.post1"]
#: Groups bundled where wheels exist for the platform and Python (heatcore runs without them):
#: cvxopt's supernodal CHOLMOD prepares sculpt-sized meshes several times faster (GPL-3, as
#: Blender itself), and pymetis with typing-extensions, which pymetis imports, whose nested
#: dissection makes the Poisson factor of meshes from 500k vertices up a third smaller (MIT; no
#: Windows wheel). A group goes in whole or not at all. None needs numpy.
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


__all__ = ["BLENDER_PYTHONS", "PLATFORMS", "BuildError", "Target", "build", "heatcore_modules", "installed_wheels",
           "pip_download"]


class BuildError(RuntimeError):
    """An extension zip could not be built (a wheel missing, the builder failing)."""


@dataclass(frozen=True)
class Target:
    """One zip: a Blender platform and the Python of the Blender versions it is for.

    Examples
    --------
    >>> t = Target("macos-arm64", "3.11")
    >>> t.blender, t.filename("0.1.0")
    (('4.2.0', '5.1.0'), 'heat_geodesics-0.1.0-blender-4.2-5.0-macos-arm64.zip')
    >>> Target("linux-x64", "3.13").filename("0.1.0")
    'heat_geodesics-0.1.0-blender-5.1-and-newer-linux-x64.zip'
    """

    platform: str
    python: str

    @property
    def blender(self):
        return BLENDER_PYTHONS[self.python]

    def filename(self, version):
        low, high = self.blender
        series = f"{low.rsplit('.', 1)[0]}-{previous_series(high)}" if high else f"{low.rsplit('.', 1)[0]}-and-newer"
        return f"heat_geodesics-{version}-blender-{series}-{self.platform}.zip"


def current_platform():
    """The Blender platform name of this machine (for example ``linux-x64``)."""
    import platform

    system = {"Linux": "linux", "Darwin": "macos", "Windows": "windows"}[platform.system()]
    machine = platform.machine().lower()
    arch = "arm64" if machine in ("arm64", "aarch64") else "x64"
    return f"{system}-{arch}"


def pip_download(dest, target, requirements, pip=None):
    """Download the binary wheels of ``requirements`` for ``target`` into ``dest``.

    Returns
    -------
    wheels : list of Path
        The wheels downloaded (empty when some requirement has no wheel there).
    error : str
        pip's message when it found none.
    """
    tmp = Path(tempfile.mkdtemp(prefix="wheels-", dir=dest))
    cmd = [*(pip or [sys.executable, "-m", "pip"]), "download", "--quiet", "--no-deps", "--only-binary=:all:"]
    for tag in PLATFORMS[target.platform]:
        cmd += ["--platform", tag]
    cmd += ["--python-version", target.python, "--dest", str(tmp), *requirements]
    proc = subprocess.run(cmd, check=False, capture_output=True, text=True)
    wheels = sorted(tmp.glob("*.whl"))
    if proc.returncode != 0 or len(wheels) != len(requirements):
        shutil.rmtree(tmp)
        return [], proc.stderr.strip() or f"pip found {len(wheels)} wheels for {len(requirements)} requirements"
    for w in wheels:
        shutil.move(str(w), dest / w.name)
    tmp.rmdir()
    return [dest / w.name for w in wheels], ""


def installed_wheels(dest, target, requirements):
    """Like :func:`pip_download`, from the packages installed in this Python (any version of each)."""
    here = Target(current_platform(), f"{sys.version_info[0]}.{sys.version_info[1]}")
    if target != here:
        return [], f"the installed packages are for {here.platform}, Python {here.python}"
    with tempfile.TemporaryDirectory(prefix="wheels-", dir=dest) as tmp:  # all of them, or none in dest
        try:
            wheels = [repack(req.split("==")[0], Path(tmp)) for req in requirements]
        except NotRepackable as exc:
            return [], str(exc)
        return [Path(shutil.move(str(w), dest / w.name)) for w in wheels], ""


def write_manifest(stage, target, wheels):
    """Write the target's platform, wheels and Blender versions into the staged manifest."""
    path = stage / "blender_manifest.toml"
    lines = path.read_text().splitlines()
    low, high = target.blender
    lines = [f'blender_version_min = "{low}"' if line.startswith("blender_version_min") else line for line in lines]
    first_table = next((i for i, line in enumerate(lines) if line.startswith("[")), len(lines))
    insert = [
        *([f'blender_version_max = "{high}"'] if high else []),
        f'platforms = ["{target.platform}"]',
        "wheels = [",
        *[f'  "./wheels/{w.name}",' for w in sorted(wheels)],
        "]",
        "",
    ]
    path.write_text("\n".join(lines[:first_table] + insert + lines[first_table:]) + "\n")


def gather_wheels(dest, target, fetch):
    """The required wheels and each optional group that has wheels for ``target``.

    Returns
    -------
    wheels : list of Path
    missing : list of str
        Distributions of the optional groups left out (no wheel there).
    """
    wheels, error = fetch(dest, target, REQUIREMENTS)
    if not wheels:
        raise BuildError(f"no wheels of {REQUIREMENTS} for {target.platform}, Python {target.python}:\n{error}")
    missing = []
    for group in OPTIONAL_REQUIREMENTS:
        extra, _ = fetch(dest, target, group)
        wheels += extra
        missing += [] if extra else [req.split("==")[0] for req in group]
    return wheels, missing


def builder_command(blender=None):
    """The extension builder: ``blender --command extension build``, else the one bundled with bpy."""
    if blender:
        return [str(blender), "--factory-startup", "--command", "extension", "build"]
    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        raise BuildError("the bpy module is not installed: pass --blender /path/to/blender, or pip install bpy")
    root = Path(next(iter(spec.submodule_search_locations)))
    found = sorted(root.glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
    if not found:
        raise BuildError(f"no bl_pkg/cli/blender_ext.py under {root}")
    return [sys.executable, str(found[-1]), "build"]


def build_one(target, sources, output_dir, fetch=pip_download, blender=None):
    """Build the zip of one target from the staged ``sources`` folder.

    Returns
    -------
    extension_sizes.Built
        The zip and what it weighs.
    """
    with tempfile.TemporaryDirectory(prefix="heat_geodesics-") as tmp:
        stage = Path(tmp) / "heat_geodesics"
        shutil.copytree(sources, stage)
        (stage / "wheels").mkdir()
        wheels, missing = gather_wheels(stage / "wheels", target, fetch)
        before = {w.name: prune(w) for w in wheels}
        write_manifest(stage, target, wheels)
        version = next(line.split('"')[1] for line in (stage / "blender_manifest.toml").read_text().splitlines()
                       if line.startswith("version"))
        out = Path(output_dir) / target.filename(version)
        cmd = [*builder_command(blender), "--source-dir", str(stage), "--output-filepath", str(out)]
        proc = subprocess.run(cmd, check=False, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode != 0 or not out.is_file():
            raise BuildError(f"extension build failed ({' '.join(cmd)}):\n{proc.stdout}")
    return measure(target.platform, target.python, target.blender, out, missing, before)


def build(output_dir, platforms=None, pythons=None, blender=None, log=print, fetch=pip_download):
    """Build one extension zip per platform and Python version.

    Parameters
    ----------
    output_dir : path
        Where the zips go (created if needed).
    platforms : list of str, optional
        Blender platform names (keys of :data:`PLATFORMS`); default all.
    pythons : list of str, optional
        Python versions (keys of :data:`BLENDER_PYTHONS`); default all. A target of
        :data:`REQUIRED_PYTHON` must build; others are skipped with a note when a wheel is missing.
    blender : path, optional
        A Blender executable; default: the builder bundled with ``bpy``.
    fetch : callable, optional
        ``fetch(dest, target, requirements) -> (wheels, error)``: :func:`pip_download` (default)
        or :func:`installed_wheels`.

    Returns
    -------
    list of extension_sizes.Built
        The zips built, measured.
    """
    platforms, pythons = list(platforms or PLATFORMS), list(pythons or PYTHONS)
    for value, known in [(p, PLATFORMS) for p in platforms] + [(p, BLENDER_PYTHONS) for p in pythons]:
        if value not in known:
            raise BuildError(f"unknown platform or Python {value!r}; choose from {sorted(known)}")
    output_dir = Path(output_dir).resolve()
    output_dir.mkdir(parents=True, exist_ok=True)
    builds = []
    with tempfile.TemporaryDirectory(prefix="heat_geodesics-src-") as tmp:
        sources = Path(tmp) / "src"
        stage_sources(sources)
        for target in (Target(p, py) for p in platforms for py in pythons):
            try:
                built = build_one(target, sources, output_dir, fetch, blender)
            except BuildError as exc:
                if target.python == REQUIRED_PYTHON:
                    raise
                log(f"note: no zip for {target.platform}, Python {target.python}: {str(exc).splitlines()[-1]}")
                continue
            builds.append(built)
            flag = "" if built.zip_mb <= MAX_ZIP_MB else f"  OVER {MAX_ZIP_MB:g} MB"
            log(f"built {built.path.name}: {built.zip_mb:.1f} MB, {built.installed_bytes / 1e6:.1f} MB installed{flag}")
    return builds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output-dir", default=str(REPO / "dist"), help="where the zips go (default: dist/)")
    parser.add_argument("--platform", action="append", choices=sorted(PLATFORMS),
                        help=f"Blender platform to build for (repeatable; default: all; this machine is {current_platform()})")
    parser.add_argument("--python", action="append", choices=PYTHONS, help=f"Blender's Python (default: {PYTHONS})")
    parser.add_argument("--blender", help="Blender executable to build with (default: the bpy module's builder)")
    parser.add_argument("--from-installed", action="store_true",
                        help="offline: wheels rebuilt from the packages installed here (this platform and Python only)")
    parser.add_argument("--docs", action="store_true", help=f"write the size table into {DOCS.relative_to(REPO)}")
    args = parser.parse_args(argv)
    if args.docs and (args.platform or args.python or args.from_installed):
        parser.error("--docs measures the release zips: every platform and Python, the pinned wheels downloaded")
    platforms = args.platform or ([current_platform()] if args.from_installed else None)
    pythons = args.python or ([f"{sys.version_info[0]}.{sys.version_info[1]}"] if args.from_installed else None)
    fetch = installed_wheels if args.from_installed else pip_download
    try:
        builds = build(args.output_dir, platforms, pythons, args.blender, fetch=fetch)
    except BuildError as exc:
        raise SystemExit(str(exc)) from None
    if args.docs:
        pins = ", ".join(REQUIREMENTS + [r for group in OPTIONAL_REQUIREMENTS for r in group])
        note = f"Measured by `scripts/build_blender_extension.py --docs` with {pins}. MB in the zip (MB installed)."
        write_docs(DOCS, builds, dropped_files(), note)
    over = [b.path.name for b in builds if b.zip_mb > MAX_ZIP_MB]
    if over:
        raise SystemExit(f"over {MAX_ZIP_MB:g} MB: {', '.join(over)}")


if __name__ == "__main__":
    main()
