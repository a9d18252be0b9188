"""Hypothesis strategies for random triangle meshes and source specifications.

Meshes are drawn as small *recipes* (part kind, sizes, seed, scale) and built
deterministically with numpy, so that a failing example prints a short,
reproducible description instead of arrays. A mesh is made of one or more
disjoint parts (grids, tubes, perturbed icospheres, tetrahedra, lifted
Delaunay triangulations of random points), placed side by side along x so
that no two parts share a position, plus optional unreferenced vertices.

Used by ``tests/test_properties.py``.
"""

import dataclasses
import functools
from dataclasses import dataclass, field

import numpy as np
from hypothesis import strategies as st

#: Upper bound on the vertex count of a drawn mesh (before soups or copies).
MAX_VERTICES = 300

INT_DTYPES = (np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64, np.intp)


# --------------------------------------------------------------------------- parts


@dataclass(frozen=True)
class PartRecipe:
    kind: str  # "grid", "tube", "sphere", "tetra", "delaunay"
    a: int
    b: int
    seed: int
    rough: float  # 0: regular; up to 1: jittered / lifted / perturbed
    scale: float = 1.0

    def n_vertices(self):
        return part_size(self.kind, self.a, self.b)


def part_size(kind, a, b):
    if kind in ("grid", "tube"):
        return a * b
    if kind == "sphere":
        return (12, 42, 162)[a]
    if kind == "tetra":
        return 4
    if kind == "delaunay":
        return a + 4
    raise AssertionError(kind)


@functools.cache
def _icosphere(level):
    t = (1.0 + 5**0.5) / 2.0
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]  # fmt: skip
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
         [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]  # fmt: skip
    V = np.asarray(V, float)
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    F = np.asarray(F, np.int64)
    for _ in range(level):
        mid = {}
        verts = list(V)
        new_faces = []
        for face in F:
            m = []
            for i, j in ((face[0], face[1]), (face[1], face[2]), (face[2], face[0])):
                key = (min(i, j), max(i, j))
                if key not in mid:
                    p = verts[i] + verts[j]
                    verts.append(p / np.linalg.norm(p))
                    mid[key] = len(verts) - 1
                m.append(mid[key])
            a, b, c = face
            ab, bc, ca = m
            new_faces += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        V, F = np.asarray(verts), np.asarray(new_faces, np.int64)
    return V, F


def _grid_faces(nx, ny, rng, random_diagonals):
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="xy")
    a = (j * nx + i).ravel()
    b, c, d = a + 1, a + nx, a + nx + 1
    flip = rng.random(a.size) < 0.5 if random_diagonals else ((i + j) % 2 == 0).ravel()
    return np.concatenate(
        [
            np.where(flip[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1)),
            np.where(flip[:, None], np.stack([a, d, c], 1), np.stack([b, d, c], 1)),
        ]
    ).astype(np.int64)


def build_part(r):
    """(V, F) of one connected part, centred near the origin, scaled by ``r.scale``."""
    rng = np.random.default_rng(r.seed)
    if r.kind == "grid":
        nx, ny = r.a, r.b
        x, y = np.meshgrid(np.arange(nx, dtype=float), np.arange(ny, dtype=float), indexing="xy")
        x, y = x.ravel(), y.ravel()
        inner = (x > 0) & (x < nx - 1) & (y > 0) & (y < ny - 1)
        x = x + inner * rng.uniform(-0.3, 0.3, x.size) * r.rough
        y = y + inner * rng.uniform(-0.3, 0.3, y.size) * r.rough
        z = r.rough * np.sin(rng.uniform(0.2, 1.0) * x + rng.uniform(0, 6)) * np.cos(rng.uniform(0.2, 1.0) * y)
        V = np.column_stack([x, y, z])
        F = _grid_faces(nx, ny, rng, random_diagonals=r.rough > 0.5)
    elif r.kind == "tube":
        around, along = r.a, r.b
        theta = 2 * np.pi * np.arange(around) / around
        radius = around / (2 * np.pi)
        th, zz = np.meshgrid(theta, np.arange(along, dtype=float), indexing="xy")
        th, zz = th.ravel(), zz.ravel()
        rad = radius * (1 + 0.2 * r.rough * rng.uniform(-1, 1, th.size))
        V = np.column_stack([rad * np.cos(th), rad * np.sin(th), zz])
        i, j = np.meshgrid(np.arange(around), np.arange(along - 1), indexing="xy")
        a = (j * around + i).ravel()
        b = (j * around + (i + 1) % around).ravel()
        c, d = a + around, b + around
        F = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)]).astype(np.int64)
    elif r.kind == "sphere":
        V, F = _icosphere(r.a)
        V = V * (1 + 0.3 * r.rough * rng.uniform(-1, 1, (V.shape[0], 1)))
        F = F.copy()
    elif r.kind == "tetra":
        V = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
        V = V + 0.3 * r.rough * rng.uniform(-1, 1, V.shape)
        F = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]], np.int64)
    elif r.kind == "delaunay":
        from scipy.spatial import Delaunay

        side = max(1.0, np.sqrt(r.a))
        pts = np.r_[[[0, 0], [side, 0], [0, side], [side, side]], rng.uniform(0.05, 0.95, (r.a, 2)) * side]
        F = Delaunay(pts).simplices.astype(np.int64)
        z = r.rough * np.sin(pts[:, 0] * rng.uniform(0.2, 1.0)) * np.cos(pts[:, 1] * rng.uniform(0.2, 1.0))
        V = np.column_stack([pts, z])
    else:  # pragma: no cover
        raise AssertionError(r.kind)
    V = V - V.mean(axis=0)
    return V * r.scale, F


SCALE_REGIMES = ("tiny", "moderate", "huge", "any")


def scale_values(regime="any"):
    """Finite positive scale factors: powers ``10**k`` (``k`` in -100..100) and arbitrary floats.

    ``regime`` narrows them: "tiny" (1e-100..1e-10), "moderate" (1e-10..1e10), "huge" (1e10..1e100).
    """
    lo, hi = {"tiny": (-100, -10), "moderate": (-10, 10), "huge": (10, 100), "any": (-100, 100)}[regime]
    powers = st.integers(lo, hi).map(lambda k: float(10.0**k))
    floats = st.floats(min_value=10.0**lo, max_value=10.0**hi, allow_nan=False, allow_infinity=False)
    if regime == "moderate":
        return st.one_of(st.sampled_from([1.0, 0.1, 3.0, 1e-8, 1e8]), powers, floats)
    return st.one_of(powers, floats)


@st.composite
def part_recipes(draw, budget=MAX_VERTICES, scaled=False):
    """One part recipe holding at most ``budget`` (>= 4) vertices; ``scaled``: False or a scale regime."""
    budget = max(4, budget)
    kinds = ["tetra", "grid"] + (["delaunay"] if budget >= 5 else []) + (["tube"] if budget >= 6 else [])
    kinds += ["sphere"] if budget >= 12 else []
    kind = draw(st.sampled_from(kinds))
    if kind == "grid":
        nx = draw(st.integers(2, min(17, budget // 2)))
        a, b = nx, draw(st.integers(2, min(17, budget // nx)))
    elif kind == "tube":
        around = draw(st.integers(3, min(16, budget // 2)))
        a, b = around, draw(st.integers(2, min(12, budget // around)))
    elif kind == "sphere":
        a, b = draw(st.integers(0, 2 if budget >= 162 else (1 if budget >= 42 else 0))), 0
    elif kind == "delaunay":
        a, b = draw(st.integers(1, min(120, budget - 4))), 0
    else:
        a, b = 0, 0
    seed = draw(st.integers(0, 2**16))
    rough = draw(st.sampled_from([0.0, 0.3, 1.0]))
    scale = draw(scale_values("any" if scaled is True else scaled)) if scaled else 1.0
    return PartRecipe(kind, a, b, seed, rough, scale)


# --------------------------------------------------------------------------- meshes


@dataclass
class Mesh:
    """A drawn mesh: arrays plus the part of each vertex (``-1``: unreferenced)."""

    V: np.ndarray
    F: np.ndarray
    part: np.ndarray
    n_parts: int
    recipe: tuple = ()
    n_unreferenced: int = 0
    notes: list = field(default_factory=list)

    @property
    def n(self):
        return self.V.shape[0]

    def face_part(self):
        return self.part[self.F[:, 0]]

    def part_vertices(self, p):
        return np.flatnonzero(self.part == p)

    def edges(self):
        e = np.sort(np.concatenate([self.F[:, [0, 1]], self.F[:, [1, 2]], self.F[:, [2, 0]]]), axis=1)
        return np.unique(e, axis=0)

    def __repr__(self):
        parts = ", ".join(
            f"{r.kind}(a={r.a}, b={r.b}, seed={r.seed}, rough={r.rough}, scale={r.scale!r})" for r in self.recipe
        )
        extra = f", unreferenced={self.n_unreferenced}" if self.n_unreferenced else ""
        notes = f", {'; '.join(self.notes)}" if self.notes else ""
        return f"Mesh(n={self.n}, faces={self.F.shape[0]}, parts=[{parts}]{extra}{notes})"

    def _repr_pretty_(self, p, cycle):  # hypothesis prints dataclasses field by field otherwise
        p.text(repr(self))


def assemble(recipes, n_unreferenced=0, unreferenced_seed=0):
    """Place the parts side by side along x (smallest first) and append unreferenced vertices.

    Each part is translated by about its own extent, so a part of scale 1e-100
    next to one of scale 1e100 keeps its geometry (the small ones sit near the
    origin). No two parts share a vertex position.
    """
    built = [build_part(r) for r in recipes]
    extents = [float(np.ptp(V, axis=0).max()) for V, _ in built]
    order = np.argsort(extents, kind="stable")
    Vs, Fs = [None] * len(built), [None] * len(built)
    cursor = None
    for k in order:
        V, F = built[k]
        ext = extents[k]
        if cursor is not None:
            V = V + np.array([cursor + 0.5 * ext - V[:, 0].min(), 0.0, 0.0])
            assert V[:, 0].min() > cursor
        cursor = float(V[:, 0].max())
        Vs[k], Fs[k] = V, F
    offset = 0
    allV, allF = [], []
    for k, (V, F) in enumerate(zip(Vs, Fs)):
        allV.append(V)
        allF.append(F + offset)
        offset += V.shape[0]
    part = np.concatenate([np.full(V.shape[0], k) for k, V in enumerate(Vs)])
    V = np.concatenate(allV)
    F = np.concatenate(allF)
    if n_unreferenced:
        rng = np.random.default_rng(unreferenced_seed)
        ext = max(extents) if extents else 1.0
        U = rng.uniform(-1, 1, (n_unreferenced, 3)) * max(ext, 1.0)
        U[:, 0] = cursor + ext * (1.0 + np.arange(n_unreferenced))
        rows = rng.permutation(V.shape[0] + n_unreferenced)  # unreferenced vertices anywhere in the order
        fullV = np.empty((V.shape[0] + n_unreferenced, 3))
        is_unref = np.zeros(fullV.shape[0], bool)
        is_unref[rows[:n_unreferenced]] = True
        fullV[is_unref] = U
        fullV[~is_unref] = V
        new_index = np.flatnonzero(~is_unref)
        F = new_index[F]
        fullpart = np.full(fullV.shape[0], -1)
        fullpart[~is_unref] = part
        V, part = fullV, fullpart
    return Mesh(V, F, part, len(recipes), tuple(recipes), n_unreferenced)


@st.composite
def meshes(draw, min_parts=1, max_parts=3, max_vertices=MAX_VERTICES, scaled_parts=False, unreferenced=True):
    """A mesh of ``min_parts..max_parts`` disjoint parts, at most ``max_vertices`` referenced vertices.

    ``scaled_parts``: False (every part at scale 1), True or a regime of :func:`scale_values`
    (each part at its own random scale).
    """
    n_parts = draw(st.integers(min_parts, max_parts))
    recipes, budget = [], max_vertices
    for k in range(n_parts):
        share = max(4, budget - 4 * (n_parts - k - 1))
        if recipes and recipes[-1].n_vertices() <= share and draw(st.integers(0, 3)) == 0:
            # a twin of the previous part (same shape), at its own scale when parts are scaled
            scale = draw(scale_values("any" if scaled_parts is True else scaled_parts)) if scaled_parts else 1.0
            r = dataclasses.replace(recipes[-1], scale=scale)
        else:
            r = draw(part_recipes(budget=share, scaled=scaled_parts))
        recipes.append(r)
        budget -= r.n_vertices()
    n_unref = draw(st.integers(0, 3)) if unreferenced else 0
    seed = draw(st.integers(0, 2**16)) if n_unref else 0
    return assemble(recipes, n_unref, seed)


# --------------------------------------------------------------------------- sources


@dataclass
class Sources:
    """A valid source specification in canonical form, and how to pass it.

    ``vertices`` is a list of ints (or None), ``form`` says how it is passed:
    "int" (a Python int; one vertex), "list", "tuple", "numpy:<dtype>" or
    "numpy-scalar:<dtype>". ``edges`` are vertex pairs, ``faces`` face indices,
    ``face_points`` a (faces, barycentric rows) pair.
    """

    vertices: list | None = None
    form: str = "list"
    edges: list | None = None
    faces: list | None = None
    face_points: tuple | None = None
    edge_form: str = "list"

    def vertex_arg(self):
        v = self.vertices
        if v is None:
            return None
        if self.form == "int":
            return int(v[0])
        if self.form == "tuple":
            return tuple(v)
        if self.form.startswith("numpy-scalar:"):
            return np.dtype(self.form.split(":")[1]).type(v[0])
        if self.form.startswith("numpy:"):
            return np.asarray(v, dtype=self.form.split(":")[1])
        return list(v)

    def kwargs(self):
        kw = {}
        if self.edges is not None:
            kw["edges"] = np.asarray(self.edges, dtype=np.int64) if self.edge_form == "numpy" else [list(e) for e in self.edges]
        if self.faces is not None:
            kw["region"] = list(self.faces)
        if self.face_points is not None:
            fi, bary = self.face_points
            kw["points"] = (list(fi), np.asarray(bary, float))
        return kw

    def query(self, solver):
        return solver.distance(self.vertex_arg(), **self.kwargs())

    def call(self, V, F, **options):
        import heatcore as hc

        return hc.geodesic_distance(V, F, self.vertex_arg(), **self.kwargs(), **options)

    def map_vertices(self, new_index):
        """The same sources after renumbering vertex ``i`` to ``new_index[i]`` (faces unchanged)."""
        new_index = np.asarray(new_index)
        return Sources(
            None if self.vertices is None else [int(new_index[v]) for v in self.vertices],
            self.form,
            None if self.edges is None else [tuple(int(new_index[x]) for x in e) for e in self.edges],
            self.faces,
            self.face_points,
            self.edge_form,
        )

    def remap(self, vertex_index, face_index):
        """The same sources with vertex ``i`` renumbered ``vertex_index[i]`` and face ``f`` ``face_index[f]``."""
        v, f = np.asarray(vertex_index), np.asarray(face_index)
        vertices = None if self.vertices is None else [int(v[x]) for x in self.vertices]
        form = self.form
        if vertices and ":" in form and np.iinfo(np.dtype(form.split(":")[1])).max < max(vertices):
            form = form.split(":")[0] + ":int64"  # the new indices do not fit the old dtype
        return Sources(
            vertices,
            form,
            None if self.edges is None else [tuple(int(v[x]) for x in e) for e in self.edges],
            None if self.faces is None else [int(f[x]) for x in self.faces],
            None if self.face_points is None else ([int(f[x]) for x in self.face_points[0]], self.face_points[1]),
            self.edge_form,
        )

    def union(self, other):
        """Both source sets together (forms of ``self`` kept)."""

        def cat(a, b):
            return None if a is None and b is None else list(a or []) + list(b or [])

        fp = None
        if self.face_points is not None or other.face_points is not None:
            a, b = self.face_points or ([], []), other.face_points or ([], [])
            fp = (list(a[0]) + list(b[0]), [list(r) for r in a[1]] + [list(r) for r in b[1]])
        form = self.form if self.vertices is not None else other.form
        if form == "int" or form.startswith("numpy-scalar") or (form.startswith("numpy:") and form != "numpy:int64"):
            form = "list"
        return Sources(cat(self.vertices, other.vertices), form, cat(self.edges, other.edges),
                       cat(self.faces, other.faces), fp, self.edge_form)  # fmt: skip

    def source_vertices(self, F):
        """Input vertices touched by the sources (for locating their parts)."""
        out = list(self.vertices or [])
        out += [x for e in (self.edges or []) for x in e]
        out += [int(x) for f in (self.faces or []) for x in F[f]]
        if self.face_points is not None:
            out += [int(x) for f in self.face_points[0] for x in F[f]]
        return out

    def __repr__(self):
        bits = []
        if self.vertices is not None:
            bits.append(f"vertices={self.vertices} as {self.form}")
        if self.edges is not None:
            bits.append(f"edges={self.edges} as {self.edge_form}")
        if self.faces is not None:
            bits.append(f"faces={self.faces}")
        if self.face_points is not None:
            bits.append(f"face_points=({self.face_points[0]}, {np.asarray(self.face_points[1]).tolist()})")
        return "Sources(" + ", ".join(bits) + ")"

    def _repr_pretty_(self, p, cycle):  # hypothesis prints dataclasses field by field otherwise
        p.text(repr(self))


def _vertex_form(draw, n):
    fits = [d for d in INT_DTYPES if np.iinfo(d).max >= n]
    return draw(
        st.sampled_from(["list", "tuple"])
        | st.sampled_from([f"numpy:{np.dtype(d).name}" for d in fits])
    )


def barycentric():
    """Barycentric coordinates (3,), corners and edge points included."""
    corner = st.integers(0, 2).map(lambda c: np.eye(3)[c])
    on_edge = st.tuples(st.integers(0, 2), st.floats(0.0, 1.0)).map(
        lambda t: np.roll(np.array([t[1], 1.0 - t[1], 0.0]), t[0])
    )
    inside = st.tuples(st.floats(0.01, 1.0), st.floats(0.01, 1.0), st.floats(0.01, 1.0)).map(
        lambda w: np.asarray(w) / sum(w)
    )
    return st.one_of(corner, on_edge, inside)


@st.composite
def sources(draw, mesh, parts=None, kinds=("vertex", "vertex", "edge", "face", "face_point")):
    """Valid sources lying on the parts ``parts`` (default: a random non-empty subset of the parts).

    Returns ``(Sources, source_parts)``, every part in ``source_parts`` holding at least one source.
    """
    if parts is None:
        parts = draw(st.sets(st.integers(0, mesh.n_parts - 1), min_size=1, max_size=mesh.n_parts))
    parts = sorted(parts)
    fpart = mesh.face_part()
    edges = mesh.edges()
    epart = mesh.part[edges[:, 0]]
    src = Sources()
    for p in parts:
        kind = draw(st.sampled_from(kinds))
        if kind == "vertex":
            verts = mesh.part_vertices(p)
            k = draw(st.integers(1, min(3, verts.size)))
            chosen = [int(verts[draw(st.integers(0, verts.size - 1))]) for _ in range(k)]
            src.vertices = (src.vertices or []) + chosen
        elif kind == "edge":
            ids = np.flatnonzero(epart == p)
            e = edges[ids[draw(st.integers(0, ids.size - 1))]]
            e = e if draw(st.booleans()) else e[::-1]
            src.edges = (src.edges or []) + [(int(e[0]), int(e[1]))]
        elif kind == "face":
            ids = np.flatnonzero(fpart == p)
            src.faces = (src.faces or []) + [int(ids[draw(st.integers(0, ids.size - 1))])]
        else:
            ids = np.flatnonzero(fpart == p)
            f = int(ids[draw(st.integers(0, ids.size - 1))])
            b = draw(barycentric())
            fi, bary = src.face_points or ([], [])
            src.face_points = (fi + [f], bary + [b.tolist()])
    if src.vertices is not None:
        if len(src.vertices) == 1 and draw(st.booleans()):
            src.form = draw(st.sampled_from(["int", "numpy-scalar:int64", "numpy-scalar:int32", "numpy-scalar:uint16"]))
        else:
            src.form = _vertex_form(draw, mesh.n)
    if src.edges is not None:
        src.edge_form = draw(st.sampled_from(["list", "numpy"]))
    return src, parts


def vertex_sources(mesh, parts):
    """Sources strategy restricted to vertex indices (and faces/face points, which need no remapping)."""
    return sources(mesh, parts=parts, kinds=("vertex", "face", "face_point"))


# --------------------------------------------------------------------------- derived meshes


def soup(mesh):
    """Every face with its own 3 vertex copies: ``(V', F')`` and the original vertex of each copy."""
    origin = mesh.F.ravel()
    return mesh.V[origin].copy(), np.arange(origin.size, dtype=np.int64).reshape(-1, 3), origin


def soup_sources(src, mesh, choose):
    """``src`` on the soup of ``mesh``: a vertex goes to one of its copies (``choose(candidates)``)."""
    flat = mesh.F.ravel()
    vertices = None
    if src.vertices is not None:
        vertices = []
        for v in src.vertices:
            vertices.append(int(choose(np.flatnonzero(flat == v))))
    edges = None
    if src.edges is not None:
        edges = []
        for u, v in src.edges:
            faces = np.flatnonzero((mesh.F == u).any(axis=1) & (mesh.F == v).any(axis=1))
            f = int(choose(faces))
            cu, cv = int(np.flatnonzero(mesh.F[f] == u)[0]), int(np.flatnonzero(mesh.F[f] == v)[0])
            edges.append((3 * f + cu, 3 * f + cv))
    form = src.form if src.form in ("list", "tuple") else "list"
    return Sources(vertices, form, edges, src.faces, src.face_points, src.edge_form)


def restrict(mesh, parts):
    """The sub-mesh made of ``parts`` (same coordinates): ``(sub, keep_vertices, keep_faces)``.

    Sub-mesh vertex ``i`` is ``mesh`` vertex ``keep_vertices[i]``, sub face ``j`` is face ``keep_faces[j]``.
    """
    parts = np.asarray(sorted(parts))
    keep_v = np.flatnonzero(np.isin(mesh.part, parts))
    keep_f = np.flatnonzero(np.isin(mesh.face_part(), parts))
    new = np.full(mesh.n, -1, dtype=np.int64)
    new[keep_v] = np.arange(keep_v.size)
    part = np.searchsorted(parts, mesh.part[keep_v])
    recipe = tuple(mesh.recipe[p] for p in parts) if mesh.recipe else ()
    sub = Mesh(mesh.V[keep_v].copy(), new[mesh.F[keep_f]], part, parts.size, recipe)
    return sub, keep_v, keep_f
