"""Wheels rebuilt from the packages installed in this Python: an extension built offline.

``pip download`` needs the network; a package installed from a wheel keeps
every file it brought in its ``RECORD`` and its tag in its ``WHEEL`` file,
which is all a wheel is. :func:`repack` writes those files back into a
``.whl`` so that ``scripts/build_blender_extension.py --from-installed``
builds the zip for this machine's platform and Python with what is installed
here (their installed versions, not the pinned ones).

Examples
--------
>>> import tempfile, zipfile
>>> with tempfile.TemporaryDirectory() as tmp:
...     wheel = repack("qdldl", Path(tmp))
...     names = zipfile.ZipFile(wheel).namelist()
>>> wheel.name.startswith("qdldl-") and any(n.endswith(".dist-info/RECORD") for n in names)
True
"""

import base64
import hashlib
import importlib.metadata as md
import zipfile
from pathlib import Path


class NotRepackable(RuntimeError):
    """An installed distribution that cannot be written back into a wheel."""


def _tag(dist):
    """The one wheel tag (``cp311-cp311-manylinux_2_17_x86_64``) an installed distribution was built for."""
    text = dist.read_text("WHEEL")
    if text is None:
        raise NotRepackable(f"{dist.metadata['Name']} was not installed from a wheel (no WHEEL file)")
    tags = [line.split(":", 1)[1].strip() for line in text.splitlines() if line.startswith("Tag:")]
    if not tags:
        raise NotRepackable(f"{dist.metadata['Name']}: its WHEEL file names no tag")
    pythons, abis, platforms = (sorted({t.split("-")[i] for t in tags}) for i in range(3))
    return "-".join(".".join(part) for part in (pythons, abis, platforms))


def record_line(name, data):
    """The ``RECORD`` line of a wheel member: its name, sha256 (urlsafe base64, no padding) and size."""
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def repack(name, dest):
    """Write the installed distribution ``name`` as a wheel into ``dest``.

    Parameters
    ----------
    name : str
        Distribution name (``scipy``, ``typing-extensions``).
    dest : Path
        Folder the wheel is written into.

    Returns
    -------
    Path
        The wheel, named ``{name}-{version}-{tag}.whl``.

    Raises
    ------
    NotRepackable
        When ``name`` is not installed, or not from a wheel.
    """
    try:
        dist = md.distribution(name)
    except md.PackageNotFoundError as exc:
        raise NotRepackable(f"{name} is not installed in this Python") from exc
    files = [f for f in dist.files or () if not f.as_posix().startswith("..") and f.suffix != ".pyc"]
    if not files:
        raise NotRepackable(f"{name}: its installed files are not recorded (no RECORD)")
    project = dist.metadata["Name"].replace("-", "_").replace(".", "_")
    wheel = Path(dest) / f"{project}-{dist.version}-{_tag(dist)}.whl"
    record_name = next(f.as_posix() for f in files if f.name == "RECORD" and f.parent.name.endswith(".dist-info"))
    lines = []
    with zipfile.ZipFile(wheel, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as out:
        for f in files:
            posix = f.as_posix()
            if posix == record_name or posix.endswith((".dist-info/INSTALLER", ".dist-info/REQUESTED")):
                continue
            data = Path(dist.locate_file(f)).read_bytes()
            out.writestr(posix, data)
            lines.append(record_line(posix, data))
        out.writestr(record_name, "\n".join([*lines, f"{record_name},,"]) + "\n")
    return wheel
