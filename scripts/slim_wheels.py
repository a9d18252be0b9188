"""Wheels without the files Blender never loads: test suites, build tools, unused solvers.

A wheel carries more than its package imports at run time: scipy its test
suites (4.4 MB of the Linux zip), cholespy the METIS command-line programs,
static library and headers it was built with, cvxopt the GLPK, GSL, FFTW,
DSDP and UMFPACK interfaces with their libraries (heatcore calls only
``cvxopt.cholmod`` and ``cvxopt.amd``, and ``import cvxopt`` loads none of
them: cvxopt imports them inside the functions that use them). :func:`prune`
rewrites a wheel without the members :data:`PRUNE` names, under the same name
and with its ``RECORD`` rewritten, so that every zip stays under 60 MB.
tests/blender_install_check.py imports and runs what stays, inside Blender.

Examples
--------
>>> pruned(["scipy/sparse/tests/test_base.py", "scipy/sparse/_base.py"], "scipy")
['scipy/sparse/tests/test_base.py']
"""

import fnmatch
import sys
import zipfile
from pathlib import Path

if str(Path(__file__).resolve().parent) not in sys.path:  # loaded by path (tests): find its neighbours
    sys.path.insert(0, str(Path(__file__).resolve().parent))

from installed_wheels import record_line

_CVXOPT_UNUSED = ["glpk", "gsl", "fftw", "dsdp", "umfpack"]

#: Distribution -> ``fnmatch`` patterns (``*`` spans folders) of the wheel members left out.
PRUNE = {
    "scipy": ["scipy/*/tests/*"],
    "cholespy": ["bin/*", "lib/*", "include/*"],
    "cvxopt": [f"cvxopt/{m}.*" for m in _CVXOPT_UNUSED]
    + [f"cvxopt.libs/lib{lib}-*" for lib in ["glpk", "gmp", "gsl", "fftw3", "dsdp", "umfpack"]],
}


def distribution(wheel_name):
    """``scipy-1.15.3-cp311-...whl`` -> ``scipy`` (lower case, ``-`` for ``_``)."""
    return Path(wheel_name).name.split("-")[0].lower().replace("_", "-")


def pruned(names, dist):
    """The member ``names`` of a wheel of ``dist`` that :data:`PRUNE` leaves out."""
    patterns = PRUNE.get(dist, [])
    return [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in patterns)]


def prune(wheel):
    """Rewrite ``wheel`` in place without the members :data:`PRUNE` names for its distribution.

    Returns
    -------
    before : tuple of int
        The wheel's ``(file bytes, unpacked bytes)`` before pruning (equal to after when nothing went).
    """
    wheel = Path(wheel)
    with zipfile.ZipFile(wheel) as z:
        infos = z.infolist()
    before = (wheel.stat().st_size, sum(i.file_size for i in infos))
    drop = set(pruned([i.filename for i in infos], distribution(wheel.name)))
    if not drop:
        return before
    record = next(i.filename for i in infos if i.filename.endswith(".dist-info/RECORD"))
    tmp = wheel.with_suffix(".tmp")
    lines = []
    with zipfile.ZipFile(wheel) as src, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as out:
        for info in infos:
            if info.filename in drop or info.filename == record or info.is_dir():
                continue
            data = src.read(info)
            out.writestr(info, data, compress_type=zipfile.ZIP_DEFLATED, compresslevel=6)
            lines.append(record_line(info.filename, data))
        out.writestr(record, "\n".join([*lines, f"{record},,"]) + "\n")
    tmp.replace(wheel)
    return before
