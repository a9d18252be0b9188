"""Bit-for-bit fingerprint of heatcore's distances, to prove a refactor changes no result.

Computes a fixed set of cases (every domain, both accuracies where the domain
has them) on the shared test meshes and either stores every result array or
compares the results against stored ones, bit for bit.

Cases
-----
Each solver case runs ``solver.distance([s0])``, ``solver.distance([s1])`` and
``solver.distances([s0, s1, [s2, s3]])``, with four fixed source vertices
picked from the vertices the elements use (the first, and those at 1/2, 1/4
and 3/4 of the sorted list).

* ``TriangleMesh`` on spot, homer, fandisk, suzanne (triangulated by
  :func:`heatcore.io.read_domain`), stanford-bunny and rocker-arm, with the
  default options at ``accuracy="smooth"`` and ``"high"``; on the bunny (it has
  boundary) also ``refine=0``, ``m=3`` and ``boundary="neumann"``, one each;
  on spot also each backend named explicitly (all but "gpu"), smooth.
* ``PolygonMesh`` on suzanne and beast, polygons kept, ``refine="auto"`` and
  ``refine=0`` (beast with ``split_crossing=True``: it has bowtie quads).
* ``TetMesh`` on the Delaunay tetrahedralization of a jittered 8x8x8 grid
  (fixed seed; its tets are a case too, so a change of qhull shows as such).
* ``PointCloud`` on spot's vertices.
* On spot, both accuracies: ``heatcore.geodesic_distance(V, F, [s0])``, the
  points of ``solver.geodesic_path(s0, s1)`` and ``VectorHeatSolver(...).log_map(s0)``
  (and the log map with the solver's own default accuracy).

The cases run in this fixed order; each file, domain and solver is built once
and shared by the cases that use it, so what a domain keeps for its next
solver (orderings, factors, frames) is exercised as in a session of queries.

Usage
-----
Store the results of the code before the change, then compare the code after it::

    python scripts/distance_fingerprint.py --save before.npz
    python scripts/distance_fingerprint.py --compare before.npz

To store the results of an older commit, check it out in a git worktree and put
that worktree first on ``PYTHONPATH`` (``heatcore from ...``, the first line
printed, says which code ran).

``--meshes DIR`` names the folder of the shared meshes (default
``../shared/meshes`` from the repository root). ``--compare`` prints, per case,
the largest absolute difference, the largest difference relative to the
case's largest finite value, and whether the arrays are bit-identical (same
shape, dtype and bytes). A case that raises is reported as ``failed: <error>``
and the run goes on. The exit status is 1 when any case is not bit-identical,
failed or is missing from either side (the worst case is printed last), else 0.

Bit-identical results need the same numpy, scipy and solver libraries on both
sides: the stored file records their versions and ``--compare`` warns when they
differ.
"""

import argparse
import json
import platform
import sys
import time
import warnings
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay

import heatcore as hc

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_MESHES = ROOT.parent / "shared" / "meshes"
TRIANGLE_MESHES = ("spot", "homer", "fandisk", "suzanne", "stanford-bunny", "rocker-arm")
POLYGON_MESHES = ("suzanne", "beast")
#: beast has 24 bowtie quads: split into their fan triangles, as tests/test_polygon.py reads it.
POLYGON_OPTIONS = {"beast": {"split_crossing": True}}
BOUNDARY_MESH = "stanford-bunny"
#: Options besides the defaults, each alone, on the mesh with boundary.
BOUNDARY_MESH_VARIANTS = (("refine=0", {"refine": 0}, {}), ("m=3", {}, {"m": 3.0}),
                          ("neumann", {}, {"boundary": "neumann"}))
#: Backends named explicitly (spot, smooth), besides "auto" everywhere; "gpu" needs a device.
BACKENDS = ("supernodal", "qdldl", "cholmod", "superlu")
#: Libraries whose versions decide the bits; recorded in the stored file.
LIBRARIES = ("numpy", "scipy", "qdldl", "cholespy", "cvxopt", "pymetis", "numba", "trimesh", "meshio", "potpourri3d")
META_KEY = "__meta__"
TET_SEED = 20240533


class Cases:
    """The domains, solvers and sources of the cases, each built once, on first use.

    A failure is remembered as well as a result: every case that needs a
    domain that cannot be built reports that domain's error.
    """

    def __init__(self, meshes):
        self.meshes = Path(meshes)
        self._done = {}

    def once(self, key, build):
        if key not in self._done:
            try:
                self._done[key] = (True, build())
            except Exception as exc:  # noqa: BLE001 - any failure of the code under test is a result
                self._done[key] = (False, exc)
        ok, value = self._done[key]
        if not ok:
            raise value
        return value

    def file(self, mesh, kind="auto"):
        """:func:`heatcore.io.read_domain` of a shared mesh (``kind`` positional: its keyword's name may change)."""
        return self.once(("file", mesh, kind), lambda: hc.io.read_domain(self.meshes / f"{mesh}.obj", kind))

    def tet_grid(self):
        return self.once(("tet grid",), tet_grid)

    def domain(self, kind, mesh, options):
        """The domain of ``kind`` ("triangle", "polygon", "tet", "points") on ``mesh`` with ``options`` (a dict)."""

        def build():
            if kind == "triangle":
                f = self.file(mesh)
                return hc.TriangleMesh(f.vertices, f.cells, **options)
            if kind == "polygon":
                f = self.file(mesh, "polygon")
                return hc.PolygonMesh(f.vertices, f.cells, **options)
            if kind == "tet":
                return hc.TetMesh(*self.tet_grid(), **options)
            return hc.PointCloud(self.file(mesh).vertices, **options)

        return self.once(("domain", kind, mesh, _key(options)), build)

    def sources(self, kind, mesh):
        """Four fixed source vertices s0..s3 of a domain: used vertices at 0, 1/2, 1/4 and 3/4 of their sorted list."""

        def build():
            if kind == "tet":
                used = self.tet_grid()[1]
            elif kind == "points":
                used = np.arange(len(self.file(mesh).vertices))
            else:  # the triangles (of the polygons, for a polygon mesh) use every vertex the elements use
                used = self.file(mesh, "polygon" if kind == "polygon" else "auto").surface
            used = np.unique(np.asarray(used).ravel())
            return [int(used[i * len(used) // 4]) for i in (0, 2, 1, 3)]

        return self.once(("sources", kind, mesh), build)

    def solver(self, kind, mesh, mesh_options, solver_options):
        return self.once(("solver", kind, mesh, _key(mesh_options), _key(solver_options)),
                         lambda: hc.HeatSolver(self.domain(kind, mesh, mesh_options), **solver_options))

    def solver_cases(self, kind, mesh, variant, mesh_options=None, solver_options=None):
        """``distance([s0])``, ``distance([s1])`` and ``distances([s0, s1, [s2, s3]])`` of one solver."""
        mesh_options, solver_options = mesh_options or {}, solver_options or {}
        prefix = f"{kind}/{mesh}/{variant}/{solver_options.get('accuracy', 'smooth')}"

        def solver():
            return self.solver(kind, mesh, mesh_options, solver_options)

        def source(i):
            return self.sources(kind, mesh)[i]

        return [
            (f"{prefix}/distance[s0]", lambda: solver().distance([source(0)])),
            (f"{prefix}/distance[s1]", lambda: solver().distance([source(1)])),
            (f"{prefix}/distances[s0,s1,[s2,s3]]",
             lambda: solver().distances([source(0), source(1), [source(2), source(3)]])),
        ]

    def spot_cases(self, accuracy):
        """geodesic_distance, a geodesic path's points and a log map on spot."""
        spot, options = "spot", {"accuracy": accuracy}

        def source(i):
            return self.sources("triangle", spot)[i]

        def geodesic_distance():
            f = self.file(spot)
            return hc.geodesic_distance(f.vertices, f.cells, [source(0)], **options)

        def path_points():
            return self.solver("triangle", spot, {}, options).geodesic_path(source(0), source(1)).points

        return [
            (f"api/{spot}/{accuracy}/geodesic_distance[s0]", geodesic_distance),
            (f"triangle/{spot}/default/{accuracy}/geodesic_path(s0,s1).points", path_points),
            (f"vector/{spot}/{accuracy}/log_map(s0)", lambda: self.spot_log_map(options)),
        ]

    def spot_log_map(self, options):
        """``VectorHeatSolver(spot, **options).log_map(s0)``."""
        domain, s0 = self.domain("triangle", "spot", {}), self.sources("triangle", "spot")[0]
        return hc.VectorHeatSolver(domain, **options).log_map(s0)

    def all_cases(self):
        """Every case as ``(name, thunk)``; a thunk returns an array."""
        cases = []
        for mesh in TRIANGLE_MESHES:
            for accuracy in ("smooth", "high"):
                cases += self.solver_cases("triangle", mesh, "default", solver_options={"accuracy": accuracy})
            if mesh == BOUNDARY_MESH:
                for variant, mesh_options, solver_options in BOUNDARY_MESH_VARIANTS:
                    cases += self.solver_cases("triangle", mesh, variant, mesh_options, solver_options)
        for backend in BACKENDS:
            cases += self.solver_cases("triangle", "spot", f"backend={backend}", solver_options={"backend": backend})
        for mesh in POLYGON_MESHES:
            for refine in ("auto", 0):
                options = {**POLYGON_OPTIONS.get(mesh, {}), "refine": refine}
                cases += self.solver_cases("polygon", mesh, f"refine={refine}", options)
        cases.append(("tet/grid8/tets", lambda: self.tet_grid()[1]))
        cases += self.solver_cases("tet", "grid8", "default")
        cases += self.solver_cases("points", "spot", "default")
        for accuracy in ("smooth", "high"):
            cases += self.spot_cases(accuracy)
        cases.append(("vector/spot/its default accuracy/log_map(s0)", lambda: self.spot_log_map({})))
        return cases


def _key(options):
    return tuple(sorted(options.items()))


def tet_grid(seed=TET_SEED, n=8):
    """A jittered n x n x n grid of points in the unit cube and its Delaunay tets."""
    rng = np.random.default_rng(seed)
    axis = np.linspace(0.0, 1.0, n)
    P = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    P = P + rng.uniform(-0.2, 0.2, P.shape) * (axis[1] - axis[0])
    return P, np.asarray(Delaunay(P).simplices, dtype=np.int64)


def run_cases(meshes, verbose):
    """Run every case: ``{name: array}`` and ``{name: error text}``, in case order."""
    results, failures = {}, {}
    for name, thunk in Cases(meshes).all_cases():
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                results[name] = np.asarray(thunk())
        except Exception as exc:  # noqa: BLE001 - reported per case, the run goes on
            failures[name] = short_error(exc)
        if verbose:
            state = "ok" if name in results else f"failed: {failures[name]}"
            print(f"{time.perf_counter() - start:7.2f} s  {name}  {state}", flush=True)
    return results, failures


def short_error(exc, limit=160):
    """``Type: message``, first line only, cut at ``limit`` characters."""
    text = f"{type(exc).__name__}: {exc}".splitlines()[0]
    return text if len(text) <= limit else text[: limit - 3] + "..."


def library_versions():
    found = {"python": platform.python_version()}
    for name in LIBRARIES:
        try:
            found[name] = version(name)
        except PackageNotFoundError:
            found[name] = None
    return found


def differences(before, after):
    """Largest absolute difference, largest one relative to ``before``'s largest finite magnitude, bit-identical."""
    if before.shape != after.shape:
        return np.inf, np.inf, False
    identical = before.dtype == after.dtype and before.tobytes() == after.tobytes()
    if before.size == 0:
        return 0.0, 0.0, identical
    a, b = before.astype(float), after.astype(float)
    finite = np.isfinite(a) & np.isfinite(b)
    same_nonfinite = (np.isnan(a) & np.isnan(b)) | (a == b)  # inf == inf, nan with nan
    if not (finite | same_nonfinite).all():
        return np.inf, np.inf, identical
    abs_diff = float(np.abs(a[finite] - b[finite]).max(initial=0.0))
    scale = float(np.abs(a[finite]).max(initial=0.0))
    return abs_diff, (abs_diff / scale if scale > 0 else (0.0 if abs_diff == 0 else np.inf)), identical


def compare(stored, results, failures):
    """Print the table; return True when every case is bit-identical."""
    names = list(results) + [n for n in failures if n not in results]
    names += [n for n in stored if n not in names]
    width = max(len(n) for n in names)
    print(f"{'case':<{width}}  {'max abs diff':>12}  {'max rel diff':>12}  bit-identical")
    worst, worst_score = None, -1.0
    for name in names:
        if name in failures:
            row, score = f"failed: {failures[name]}", np.inf
        elif name not in stored:
            row, score = "not in the stored file", np.inf
        elif name not in results:
            row, score = "stored, but not computed now", np.inf
        else:
            abs_diff, rel_diff, identical = differences(stored[name], results[name])
            row = f"{abs_diff:12.3e}  {rel_diff:12.3e}  {'yes' if identical else 'no'}"
            score = -1.0 if identical else max(rel_diff, 1e-300)
        print(f"{name:<{width}}  {row}")
        if score > worst_score:
            worst, worst_score, worst_row = name, score, row
    if worst_score < 0:
        print(f"\nall {len(names)} cases bit-identical")
        return True
    bad = sum(1 for n in names if n in failures or n not in stored or n not in results
              or not differences(stored[n], results[n])[2])
    print(f"\n{bad} of {len(names)} cases not bit-identical; worst: {worst}  {worst_row.strip()}")
    return False


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--save", metavar="OUT.npz", type=Path, help="compute and store every case")
    mode.add_argument("--compare", metavar="BEFORE.npz", type=Path, help="compute again and compare bit for bit")
    parser.add_argument("--meshes", type=Path, default=DEFAULT_MESHES, help="folder of the shared test meshes")
    parser.add_argument("-q", "--quiet", action="store_true", help="no line per case while computing")
    args = parser.parse_args(argv)

    print(f"heatcore from {Path(hc.__file__).parent}", flush=True)
    start = time.perf_counter()
    results, failures = run_cases(args.meshes, not args.quiet)
    print(f"{len(results)} cases computed, {len(failures)} failed, {time.perf_counter() - start:.1f} s\n")

    if args.save:
        meta = {"versions": library_versions(), "failed": failures}
        np.savez_compressed(args.save, **results, **{META_KEY: np.array(json.dumps(meta))})
        print(f"stored {len(results)} cases in {args.save}")
        for name, error in failures.items():
            print(f"failed, not stored: {name}: {error}")
        return 1 if failures else 0

    with np.load(args.compare) as data:
        stored = {name: data[name] for name in data.files if name != META_KEY}
        meta = json.loads(str(data[META_KEY])) if META_KEY in data.files else {}
    then, now = meta.get("versions", {}), library_versions()
    for name in sorted(set(then) | set(now)):
        if then.get(name) != now.get(name):
            print(f"warning: {name} {then.get(name)} when stored, {now.get(name)} now")
    return 0 if compare(stored, results, failures) else 1


if __name__ == "__main__":
    sys.exit(main())
