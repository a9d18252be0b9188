"""Every user-facing option of heatcore, declared once.

An :class:`Option` states an option's name (the keyword of the Python API,
the Blender property, the command line's ``dest``), its type, its range or
choices, its default, its unit, one help text, and where it goes:

- ``"mesh"``: a keyword of the domain (:class:`~heatcore.TriangleMesh`,
  ``DomainFile.domain``);
- ``"solver"``: a keyword of :class:`~heatcore.HeatSolver`;
- ``"read"``: how a file is read (:func:`heatcore.io.domain.read_domain`);
- ``"output"``: how the distance is coloured or made into weights.

The front ends are generated from this table or checked by it: the
``heatcore`` command's and the MeshLab command's argparse options
(:func:`add_argument`), the Blender properties, the MeshLab filter's
parameters and :func:`heatcore.geodesic_distance` (:func:`check`).
``tests/test_options.py`` holds every front end to it. Every bad value gets
one message format, ``<unknown|invalid> <label> <value>: <name> must be
<requirement>`` (followed by ``: <high_why>`` for a number above a ``high``
that declares why), in an :class:`~heatcore.errors.InvalidOptionError`.

Examples
--------
>>> check("m", 2)
2.0
>>> check("refine", "auto"), check("refine", 3), check("weld", None)
('auto', 3, None)
>>> check("m", -1.0)
Traceback (most recent call last):
...
heatcore.errors.InvalidOptionError: invalid time factor -1.0: m must be a positive number <= 1e+06
>>> check("m", 1e15)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
heatcore.errors.InvalidOptionError: invalid time factor 1000000000000000.0: m must be ... <= 1e+06: above 1e+06 the heat step ...
>>> OPTIONS["weld"].unit
'mesh units (a length)'
"""

import argparse
from dataclasses import dataclass

import numpy as np

from .errors import InvalidOptionError, InvalidSourceError

#: Names of heatcore's colormaps (:data:`heatcore.viz.colormap.COLORMAPS`, sorted; a test keeps them equal).
COLORMAP_NAMES = ("cividis", "inferno", "magma", "plasma", "viridis")

_NUMBER = (int, float, np.integer, np.floating)
_BOOL = (bool, np.bool_)


@dataclass(frozen=True)
class Option:
    """The declaration of one user-facing option.

    Parameters
    ----------
    name : str
        Keyword in the API, Blender property name, argparse ``dest``.
    label : str
        A few words naming it in messages ("time factor").
    type : {float, int, bool, str}
        Type of the value (``str``: one of ``choices``).
    default
        Default value everywhere, unless ``front_end_defaults`` says otherwise.
    unit : str
        Unit of the value ("unitless", "mesh units (a length)", ...).
    help : str
        The one help text: argparse help, Blender description, docstrings.
    target : {"mesh", "solver", "read", "output"}
        Where the value goes (see the module docstring).
    choices : tuple of str
        Allowed values of a ``str`` option, in display order.
    choice_help : tuple of str
        One line per choice (Blender's enum items).
    low, high : float, optional
        Bounds of a number; ``low_open``: ``low`` itself is excluded.
    specials : tuple of str
        Words a number option accepts too (``"auto"``).
    none_means : str, optional
        Whether ``None`` is accepted, and what it means ("no welding").
    flag, metavar, off_flag, off_help : str, optional
        Command-line flag (None: not on the command line); for a boolean
        whose default is True, or an option that may be None, the flag that
        turns it off (``--no-robust``, ``--no-weld``) and that flag's help.
    ui_label : str, optional
        Friendlier label in graphical front ends (default: ``label`` titled).
    ui_min, soft_max : float, optional
        Smallest value a slider offers where ``low`` is open, and the upper
        end of the slider range.
    front_end_defaults : tuple of (front_end, value, text)
        Front ends whose default differs from ``default``, with the text their
        help shows; one with no None (Blender) declares the value standing for it,
        except for a switch (``switch_help``), whose off stands for None.
    switch_help : str, optional
        For an option that may be None: graphical front ends (Blender) offer it
        as an on/off switch named ``ui_label`` with this help, off for None and
        on for ``default`` (``weld``: *Merge Coincident Vertices*, weld=0.0).
    high_why : str, optional
        Why values above ``high`` are refused: the error for one says it
        (``m``: past :data:`M_MAX` the heat flow has no digits left).
    picture_help : str, optional
        What the option does to a PNG picture, in the help of the commands
        that draw one only (``heatcore logmap`` draws none).

    Examples
    --------
    >>> opt = OPTIONS["refine"]
    >>> opt.requirement(), opt.target, opt.default
    ("'auto' or an integer 0..8", 'mesh', 'auto')
    """

    name: str
    label: str
    type: type
    default: object
    unit: str
    help: str
    target: str
    choices: tuple = ()
    choice_help: tuple = ()
    low: float = None
    high: float = None
    low_open: bool = False
    specials: tuple = ()
    none_means: str = None
    flag: str = None
    metavar: str = None
    off_flag: str = None
    off_help: str = None
    ui_label: str = None
    ui_min: float = None
    soft_max: float = None
    front_end_defaults: tuple = ()
    switch_help: str = None
    high_why: str = None
    picture_help: str = ""

    def requirement(self, with_none=True):
        """What a value must be, in words.

        Examples
        --------
        >>> OPTIONS["weld"].requirement(), OPTIONS["weld"].requirement(with_none=False)
        ('a number >= 0 or None (no welding)', 'a number >= 0')
        """
        if self.choices:
            text = "one of " + ", ".join(self.choices)
        elif self.type is bool:
            text = "True or False"
        else:
            what = "an integer" if self.type is int else "a number"
            if self.type is float and self.low == 0 and self.low_open:
                text = "a positive number" + ("" if self.high is None else f" <= {self.high:g}")
            elif self.type is int and self.low is not None and self.high is not None:
                text = f"{what} {self.low}..{self.high}"
            elif self.high is None:
                text = f"{what} {'>' if self.low_open else '>='} {self.low}"
            else:
                text = f"{what} in {'(' if self.low_open else '['}{self.low}, {self.high}]"
        text = "".join(f"{word!r} or " for word in self.specials) + text
        return text + (f" or None ({self.none_means})" if with_none and self.none_means else "")

    def error(self, value, extra=()):
        """The :class:`~heatcore.errors.InvalidOptionError` for a bad ``value`` (one format for all)."""
        adjective = "unknown" if self.choices else "invalid"
        requirement = "one of " + ", ".join(self.choices + tuple(extra)) if extra else self.requirement()
        why = self._why(value)
        return InvalidOptionError(f"{adjective} {self.label} {value!r}: {self.name} must be {requirement}{why}")

    def check(self, value, extra=()):
        """The value, normalized (float, int, bool, str or None); :meth:`error` when it is not allowed.

        ``extra``: further choices a front end accepts (MeshLab's colour ramps).

        Examples
        --------
        >>> OPTIONS["isolines"].check(np.int64(4)), OPTIONS["robust"].check(np.True_)
        (4, True)
        """
        if value is None and self.none_means:
            return None
        if isinstance(value, str) and value in self.specials:
            return value
        if self.choices:
            if isinstance(value, str) and (value in self.choices or value in extra):
                return str(value)
        elif self.type is bool:
            if isinstance(value, _BOOL) or (isinstance(value, (int, np.integer)) and value in (0, 1)):
                return bool(value)
        elif self.type is int:
            if isinstance(value, (int, np.integer)) and not isinstance(value, _BOOL) and self._in_range(value):
                return int(value)
        elif isinstance(value, _NUMBER) and not isinstance(value, _BOOL) and np.isfinite(value) and self._in_range(value):
            return float(value)
        raise self.error(value, extra)

    def _why(self, value):
        """``": <high_why>"`` for a number above ``high`` (where declared), else ``""``."""
        number = isinstance(value, _NUMBER) and not isinstance(value, _BOOL)
        return f": {self.high_why}" if self.high_why and number and value > self.high else ""

    def _in_range(self, value):
        low_ok = self.low is None or (value > self.low if self.low_open else value >= self.low)
        return low_ok and (self.high is None or value <= self.high)

    def default_for(self, front_end):
        """The default in ``front_end`` (a key of :data:`heatcore.settings.FRONT_END_OPTIONS`).

        Examples
        --------
        >>> OPTIONS["isolines"].default_for("blender"), OPTIONS["isolines"].default_for("meshlab")
        (10, 0)
        """
        return next((value for end, value, _ in self.front_end_defaults if end == front_end), self.default)

    def parse(self, text):
        """Command-line text to a checked value; :class:`argparse.ArgumentTypeError` when it is bad.

        Examples
        --------
        >>> OPTIONS["m"].parse("0.5")
        0.5
        >>> OPTIONS["weld"].parse("-1")
        Traceback (most recent call last):
        ...
        argparse.ArgumentTypeError: must be a number >= 0, got '-1'
        """
        if text in self.specials:
            return text
        kind, what = (int, "an integer") if self.type is int else (float, "a number")
        try:
            value = kind(text)
        except ValueError:
            if self.specials:
                raise argparse.ArgumentTypeError(f"must be {self.requirement(False)}, got {text!r}") from None
            raise argparse.ArgumentTypeError(f"not {what}: {text!r}") from None
        try:
            return self.check(value)
        except InvalidOptionError:
            why = self._why(value)
            raise argparse.ArgumentTypeError(f"must be {self.requirement(False)}, got {text!r}{why}") from None

    def help_text(self, front_end="cli", picture=True):
        """Help with the front end's default appended (argparse: ``%`` escaped by the caller).

        ``picture``: whether the command draws a PNG (``picture_help`` and the default it shows).
        """
        shown = next((text for end, _, text in self.front_end_defaults if end == front_end), None)
        if not picture and self.picture_help:
            shown = self.default
        elif shown is None:
            shown = {True: "on", False: "off"}.get(self.default, self.default) if self.type is bool else self.default
        limit = f"; at most {self.high:g}" if self.high_why else ""  # a range that is not the type's own
        return f"{self.help}{self.picture_help if picture else ''}{limit} (default: {shown})"


#: Largest time factor ``m`` a user may give (``t = m h^2``). Measured (tests/test_time_factor_range.py
#: states the figures): the smoothed distance stops changing by m = 1e5-1e6 (t far beyond the mesh's
#: diameter squared: the heat is uniform but for a tail of ~1/t, whose gradient is the direction field),
#: and from m = 1e9 that tail sinks into rounding: an icosahedron's largest distance falls to 0.61 of the
#: truth at 1e9, spot's to 0.12 at 1e12 and to zeros or a failed factorization above. m is unitless, so the
#: limit is the same at any coordinate scale. The underflow guard's own raise of m
#: (:func:`heatcore.steps.time_step.underflow_safe_m`, about (hops / 400)^2) is not held to it.
M_MAX = 1e6

#: What one ``accuracy="high"`` query costs, in smooth queries of the same solver (its factorizations
#: paid once): the range over six shared meshes of 2.9k-50k vertices (spot, homer, cheburashka,
#: rocker-arm, stanford-bunny, nefertiti) and two runs, with numba (the ``fast`` extra's compiled fast
#: marching) and without it (the vectorized eikonal pass). Measured with ``scripts/bench_high_cost.py``
#: on 2026-11-28 (a busy 2-core virtual machine: each figure is a median of 15 queries). Every
#: statement of the cost (the option's help, ``geodesic_distance``'s docstring, README, docs/*.md,
#: pyproject.toml) says :data:`HIGH_ACCURACY_COST_TEXT`; ``tests/test_high_cost.py`` holds them to it.
HIGH_ACCURACY_COST = {"numba": (1.1, 2.9), "vectorized": (6.4, 15.9)}

#: The one sentence on :data:`HIGH_ACCURACY_COST`.
HIGH_ACCURACY_COST_TEXT = (f"a query costs {'-'.join(f'{x:g}' for x in HIGH_ACCURACY_COST['numba'])} smooth ones "
                           f"with the 'fast' extra (numba), {'-'.join(f'{x:g}' for x in HIGH_ACCURACY_COST['vectorized'])} "
                           "without it")

#: ``accuracy="auto"`` is "high" for one query (:func:`heatcore.geodesic_distance`) on a triangle mesh of at least this
#: many vertices (after refinement), where numba is installed; "smooth" otherwise. Measured with
#: ``hc.geodesic_distance(V, F, [0])`` on cube spheres of 48k-194k vertices and nefertiti subdivided 0-2 times
#: (50k-800k), a busy 2-core virtual machine, 2026-11-29: the march (its operators never built, nothing factored)
#: takes 0.31-0.64 of the heat method's time at every size from 2.9k vertices, but a fresh process first loads the
#: compiled march (0.28 s): counting that, the march is faster from about 72k vertices (101k: 0.61 s against 0.78 s).
AUTO_HIGH_VERTICES = 100_000

_OPTIONS = (
    Option(
        "m", "time factor", float, 1.0, "unitless (t = m h^2, h in mesh units)",
        "heat time factor: t = m * h^2, h the mean edge length; larger m gives a smoother distance",
        "solver", low=0, low_open=True, high=M_MAX, flag="--m", metavar="M", ui_label="Time Factor", ui_min=1e-3,
        soft_max=1000.0, high_why=f"above {M_MAX:g} the heat step t = m h^2 is so long that the heat is uniform to "
        "within rounding and the distance loses its digits (it collapses from about 1e9 on; the smoothed distance "
        "stops changing by 1e5, so larger m gains nothing)",
    ),
    Option(
        "boundary", "boundary condition", str, "robin", "none (a choice)",
        "boundary condition of the heat step on meshes with boundary: robin (mean of neumann and "
        "dirichlet, the paper's advice), neumann or dirichlet",
        "solver", choices=("robin", "neumann", "dirichlet"),
        choice_help=("Mean of the Neumann and Dirichlet heat solutions (recommended)",
                     "Zero-flux boundary: distance bends less near holes", "Zero heat on the boundary"),
        flag="--boundary", ui_label="Boundary",
    ),
    Option(
        "accuracy", "accuracy", str, "smooth", "none (a choice)",
        f"smooth: the heat method (its error is 1-2%); high: an eikonal pass (about 0.1-0.3% error; "
        f"{HIGH_ACCURACY_COST_TEXT}); auto: high for one query on a triangle mesh of {AUTO_HIGH_VERTICES:,} vertices "
        "or more where the 'fast' extra (numba) is installed (its fast marching, with no heat solved, is then "
        "faster), smooth otherwise",
        "solver", choices=("smooth", "high", "auto"),
        choice_help=("The heat method: smooth distance, about 1-2% error",
                     f"An eikonal pass: about 0.1-0.3% error, {HIGH_ACCURACY_COST['numba'][0]:g}-"
                     f"{HIGH_ACCURACY_COST['vectorized'][1]:g} times slower (see the docs)",
                     "High for one query on a large triangle mesh where it is faster, else smooth"),
        flag="--accuracy", front_end_defaults=(("api", "auto", "auto"),
                                               ("cli", "auto", "auto: high for a distance on a large mesh with numba"),
                                               ("meshlab", "auto", "auto: high on a large mesh with numba"),
                                               ("vector heat", "high", "high: the log map's radius"),
                                               ("blender uv map", "high", "high: the UV map's radii")),
    ),
    Option(
        "backend", "linear-algebra backend", str, "auto", "none (a choice)",
        "sparse factorization backend: auto picks by size (see heatcore.linalg)",
        "solver", choices=("auto", "supernodal", "qdldl", "cholmod", "superlu", "gpu"),
        choice_help=("The fastest installed library for the mesh size (recommended)",
                     "CHOLMOD's supernodal Cholesky through cvxopt: fastest factorization of large meshes",
                     "QDLDL's simplicial LDL^T: fast factorization of small and medium meshes",
                     "CHOLMOD through cholespy: the fastest solves", "SciPy's SuperLU: always present, slowest",
                     "cuDSS on an NVIDIA GPU (the gpu extra): millions of vertices"),
        flag="--backend", ui_label="Backend",
    ),
    Option(
        "robust", "robust setting", bool, True, "none (on or off)",
        "intrinsic Delaunay operators (accurate on badly shaped triangles); off: plain cotan operators "
        "on the input triangles (faster to build, much less accurate on poor meshes)",
        "mesh", off_flag="--no-robust", ui_label="Robust",
    ),
    Option(
        "refine", "refinement", int, "auto", "subdivision levels (each splits every triangle in 4)",
        "midpoint subdivision levels before solving: 'auto' (refine parts under 11,000 vertices) or "
        "0..8; results are read back at the input vertices",
        "mesh", low=0, high=8, specials=("auto",), flag="--refine", metavar="LEVELS", ui_label="Refine",
    ),
    Option(
        "weld", "weld tolerance", float, 0.0, "mesh units (a length)",
        "merge vertices closer than this tolerance (mesh units) into one before solving, as STL files "
        "and OBJ seams need; 0 merges vertices at exactly the same position; distances are still "
        "given for every input vertex",
        "mesh", low=0, none_means="no welding", flag="--weld-tolerance", metavar="TOL",
        off_flag="--no-weld", off_help="no welding: solve on the vertices as they are (coincident vertices stay apart)",
        ui_label="Merge Coincident Vertices",
        front_end_defaults=(("blender", None, "off: the mesh as connected in Blender"),
                            ("blender uv map", None, "off: the mesh as connected in Blender")),
        switch_help="merge vertices at exactly the same position into one before solving, for meshes imported as "
                    "triangle soup (STL); off: the mesh is measured as it is connected in Blender, so islands that "
                    "touch at a vertex (Suzanne's eyes) stay apart: a source on one reaches no other",
    ),
    Option(
        "domain", "domain kind", str, "auto", "none (a choice)",
        "how to read a file: auto (tets from volume formats, points from files without faces, "
        "triangles otherwise), or force one; 'polygon' keeps quads and n-gons as faces (each measured "
        "on heatcore's Delaunay triangulation of it) instead of the reader's fan triangles",
        "read", choices=("auto", "triangle", "polygon", "tet", "points"), flag="--domain",
    ),
    Option(
        "colormap", "colormap", str, "viridis", "none (a choice)",
        "perceptual colormap of the vertex colors",
        "output", choices=COLORMAP_NAMES, choice_help=tuple(f"Perceptual colormap {c}" for c in COLORMAP_NAMES),
        flag="--colormap", picture_help=" (and of the PNG picture)",
    ),
    Option(
        "isolines", "isoline count", int, 0, "count (evenly spaced in distance)",
        "number of evenly spaced isolines (0: none): dark stripes in the vertex colors",
        "output", low=0, flag="--isolines", metavar="N", ui_label="Isolines", soft_max=50,
        picture_help=" (and lines in the PNG picture)",
        front_end_defaults=(("cli", None, "none in the PLY, 12 in the PNG"), ("blender", 10, "10")),
    ),
    Option("weight_radius", "weight radius", float, None, "mesh units (a length; scene units in Blender's World space)",
        "geodesic distance at which the weight reaches 0 (it is 1 at the sources); unset: the largest distance",
        "output", low=0, low_open=True, none_means="the largest distance", ui_label="Radius",
        front_end_defaults=(("blender", 0.0, "0: the largest distance"),)),
    Option("weight_falloff", "weight falloff", str, "LINEAR", "none (a choice)",
        "curve of the weight from 1 at the sources to 0 at the radius (Blender's falloff types)", "output",
        choices=("LINEAR", "SMOOTH", "SHARP", "ROOT"), ui_label="Falloff", choice_help=(
            "Even fall with distance (a cone)", "Smoothstep: flat at the sources and at the radius",
            "Squared: drops fast near the sources (a spike)", "Square root: stays high, drops at the radius")),
    Option("weight_invert", "weight inversion", bool, False, "none (on or off)", "invert the falloff: weight 0 at the "
        "sources rising to 1 at the radius (vertices no source reaches stay 0)", "output", ui_label="Invert Falloff"),
)

#: Every option by name.
OPTIONS = {opt.name: opt for opt in _OPTIONS}


def check(name, value, extra=()):
    """Validate and normalize the value of option ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`OPTIONS`.
    value
        The value given.
    extra : tuple of str, optional
        Further choices the calling front end accepts (MeshLab's colour ramps).

    Returns
    -------
    The value as float, int, bool, str or None.

    Raises
    ------
    InvalidOptionError
        Unknown option, or a value outside its type, range or choices.

    Examples
    --------
    >>> check("boundary", "neumann"), check("isolines", 0), check("robust", False)
    ('neumann', 0, False)
    >>> check("boundary", "periodic")
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidOptionError: unknown boundary condition 'periodic': boundary must be one of robin, neumann, dirichlet
    """
    if name not in OPTIONS:
        raise InvalidOptionError(f"unknown option {name!r}; options are {', '.join(OPTIONS)}")
    return OPTIONS[name].check(value, extra)


def names(target):
    """Names of the options that go to ``target``, in declaration order.

    Examples
    --------
    >>> names("mesh")
    ('robust', 'refine', 'weld')
    """
    return tuple(opt.name for opt in _OPTIONS if opt.target == target)


def defaults(target):
    """``{name: default}`` of the options that go to ``target``.

    Examples
    --------
    >>> defaults("solver")
    {'m': 1.0, 'boundary': 'robin', 'accuracy': 'smooth', 'backend': 'auto'}
    """
    return {opt.name: opt.default for opt in _OPTIONS if opt.target == target}


def add_argument(parser, name, *, front_end="cli", extra=(), note="", picture=True):
    """Add option ``name``'s flags to an argparse parser or group.

    The help is the option's help plus the front end's default; ``extra``
    choices and a ``note`` may widen it (MeshLab's colour ramps); ``picture``
    False leaves out what it does to a PNG (a command that draws none). An option
    that may be None gets its two flags in a mutually exclusive group.

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_argument(p, "weld"); add_argument(p, "robust")
    >>> p.parse_args(["--no-weld", "--no-robust"])
    Namespace(weld=None, robust=False)
    >>> p.parse_args(["--weld-tolerance", "0.5"]).weld
    0.5
    """
    opt = OPTIONS[name]
    help = (opt.help_text(front_end, picture) if not note else f"{opt.help}; {note} (default: {opt.default_for(front_end)})")
    help = help.replace("%", "%%")
    default = opt.default_for(front_end)
    if opt.off_flag and opt.none_means:  # --weld-tolerance TOL | --no-weld
        parser = parser.add_mutually_exclusive_group()
    if opt.flag:
        kwargs = {"dest": name, "default": default, "help": help}
        if opt.choices:
            kwargs["choices"] = opt.choices + tuple(extra)
        else:
            kwargs.update(type=opt.parse, metavar=opt.metavar)
        parser.add_argument(opt.flag, **kwargs)
    if opt.off_flag:
        off = {"action": "store_const", "const": None, "default": default} if opt.none_means else {"action": "store_false"}
        off_help = opt.off_help if opt.flag else f"turn {name} off; {name}: {help}"
        parser.add_argument(opt.off_flag, dest=name, help=off_help, **off)


def check_source_vertices(sources, n_vertices):
    """Source vertex indices as an int64 array, or one error when one is not a vertex.

    The one source-range check of the front ends (CLI, MeshLab, Blender, batch).

    Raises
    ------
    InvalidSourceError
        An index below 0 or at least ``n_vertices``.

    Examples
    --------
    >>> check_source_vertices([0, 5], 10).tolist()
    [0, 5]
    >>> check_source_vertices([3, 10], 10)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidSourceError: source vertex 10 is out of range: the mesh has 10 vertices (0..9)
    """
    sources = np.asarray(sources, dtype=np.int64).ravel()
    bad = sources[(sources < 0) | (sources >= n_vertices)]
    if bad.size:
        raise InvalidSourceError(
            f"source vertex {bad[0]} is out of range: the mesh has {n_vertices} vertices (0..{n_vertices - 1})"
        )
    return sources
