"""What each Blender extension zip weighs, wheel by wheel, and the table docs/blender-packaging.md shows.

A wheel is a zip: the extension zip stores it as it is (compressed once), and
Blender unpacks it on install. So each wheel costs its file size in the zip
and the sum of its members' sizes once installed.

Examples
--------
>>> b = Built("linux-x64", "3.11", ("4.2.0", "5.1.0"), Path("x.zip"), 40_000_000,
...           {"scipy-1.15.3-cp311-cp311-manylinux_2_17_x86_64.whl": (37_000_000, 110_000_000)},
...           (1_000_000, 3_000_000), ["pymetis"])
>>> b.blender_range, b.installed_bytes, round(b.zip_mb, 1)
('4.2 - 5.0', 113000000, 40.0)
>>> print(size_table([b]).splitlines()[2])
| linux-x64 | 4.2 - 5.0 | 3.11 | **40.0** | 113.0 | 37.0 (110.0) | - | - | - | - | - | 1.0 (3.0) | 0.0 (0.0) | pymetis |
"""

import re
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

#: The most an extension zip may weigh (issue 37).
MAX_ZIP_MB = 60.0

#: Columns of the size table: the bundled distributions, in this order.
COLUMNS = ["scipy", "cvxopt", "cholespy", "qdldl", "pymetis", "typing_extensions"]

BEGIN, END = "<!-- sizes: begin (scripts/build_blender_extension.py --docs) -->", "<!-- sizes: end -->"


def _mb(n):
    return n / 1e6


def previous_series(version):
    """``"5.1.0"`` -> ``"5.0"``: the last Blender series below an exclusive ``blender_version_max``."""
    major, minor = (int(x) for x in version.split(".")[:2])
    return f"{major}.{minor - 1}" if minor else f"{major - 1}.x"


@dataclass
class Built:
    """One extension zip: its target, and what it and each wheel in it weigh (bytes)."""

    platform: str
    python: str
    blender: tuple  # (blender_version_min, blender_version_max or None), max exclusive as in the manifest
    path: Path
    zip_bytes: int
    wheels: dict = field(default_factory=dict)  # wheel file name -> (bytes in the zip, bytes installed)
    sources: tuple = (0, 0)  # the add-on and vendored heatcore: (bytes in the zip, bytes installed)
    missing: list = field(default_factory=list)  # optional distributions without a wheel for this target
    before: dict = field(default_factory=dict)  # wheel file name -> (bytes, bytes installed) before pruning

    @property
    def blender_range(self):
        low = ".".join(self.blender[0].split(".")[:2])
        return f"{low} - {previous_series(self.blender[1])}" if self.blender[1] else f"{low} and newer"

    @property
    def installed_bytes(self):
        return self.sources[1] + sum(installed for _, installed in self.wheels.values())

    @property
    def zip_mb(self):
        return _mb(self.zip_bytes)

    @property
    def pruned_bytes(self):
        """``(bytes, bytes installed)`` that pruning took out of the wheels (:mod:`slim_wheels`)."""
        saved = [(b[0] - self.wheels[n][0], b[1] - self.wheels[n][1]) for n, b in self.before.items() if n in self.wheels]
        return tuple(sum(x) for x in zip(*saved)) if saved else (0, 0)

    def wheel_of(self, distribution):
        """``(bytes in the zip, bytes installed)`` of ``distribution``'s wheel, or None."""
        for name, sizes in self.wheels.items():
            if name.split("-")[0].lower() == distribution.lower():
                return sizes
        return None


def measure(platform, python, blender, path, missing=(), before=None):
    """Measure a built zip: the zip, each wheel in it (packed and unpacked), and the rest.

    ``before`` gives each wheel's ``(bytes, bytes installed)`` before it was pruned.

    Returns
    -------
    Built
    """
    wheels, packed, unpacked = {}, 0, 0
    with zipfile.ZipFile(path) as outer:
        for info in outer.infolist():
            if info.filename.endswith(".whl"):
                with outer.open(info) as f, zipfile.ZipFile(f) as wheel:
                    installed = sum(i.file_size for i in wheel.infolist())
                wheels[Path(info.filename).name] = (info.compress_size, installed)
            else:
                packed += info.compress_size
                unpacked += info.file_size
    return Built(platform, python, tuple(blender), Path(path), Path(path).stat().st_size, wheels,
                 (packed, unpacked), list(missing), dict(before or {}))


def _cell(sizes):
    return "-" if sizes is None else f"{_mb(sizes[0]):.1f} ({_mb(sizes[1]):.1f})"


def size_table(builds):
    """A markdown table: one row per zip, MB in the zip (installed) per wheel."""
    head = ["platform", "Blender", "Python", "zip MB", "installed MB", *COLUMNS, "add-on + heatcore", "pruned",
            "no wheel"]
    rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for b in builds:
        cells = [b.platform, b.blender_range, b.python, f"**{b.zip_mb:.1f}**", f"{_mb(b.installed_bytes):.1f}",
                 *(_cell(b.wheel_of(c)) for c in COLUMNS), _cell(b.sources), _cell(b.pruned_bytes),
                 ", ".join(b.missing) or "-"]
        rows.append("| " + " | ".join(cells) + " |")
    return "\n".join(rows)


def dropped_list(files):
    """Markdown bullets of the heatcore files left out of the extension, grouped by folder."""
    groups = {}
    for name in files:
        parts = name.split("/")
        folder = "/".join(parts[:2]) + "/" if len(parts) > 2 else name
        groups.setdefault(folder, []).append(name)
    return "\n".join(f"- `{folder}` ({len(names)} files)" if len(names) > 1 else f"- `{names[0]}`"
                     for folder, names in sorted(groups.items()))


def write_docs(path, builds, dropped, note=""):
    """Replace the text between the size markers of ``path`` by the table of ``builds`` and the dropped files."""
    text = Path(path).read_text()
    if BEGIN not in text or END not in text:
        raise ValueError(f"{path} has no size markers ({BEGIN!r} ... {END!r})")
    left_out = "Left out of every zip (heatcore files the add-on never imports):"
    parts = [BEGIN, note, size_table(builds), left_out, dropped_list(dropped), END]
    body = "\n\n".join(p for p in parts if p)
    Path(path).write_text(re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: body, text, flags=re.DOTALL))
