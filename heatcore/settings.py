"""One frozen, validated settings object: what every front end hands the core.

Options are declared once, in :mod:`heatcore.options`. A front end (the
Python API, the ``heatcore`` command, batch runs, the MeshLab filter and
command, the Blender add-on, the vector heat method) turns what its user set
into one :class:`Settings` with :meth:`Settings.of`: each value given is
checked once, the front end's own defaults fill the rest
(:meth:`~heatcore.options.Option.default_for`), and an option the front end
does not offer (:data:`FRONT_END_OPTIONS`) is refused. The object is split
once into the parts each stage takes:

- ``settings.mesh`` (:class:`MeshSettings`): the domain's build (``robust``, ``refine``, ``weld``);
- ``settings.solver`` (:class:`SolverSettings`): :class:`~heatcore.HeatSolver`
  (``m``, ``boundary``, ``accuracy``, ``backend``) and the ``intent`` the
  front end knows: a solver kept for many queries (``"reuse"``) or asked one
  (``"one query"``), which decides the backend that "auto" stands for;
- ``settings.output`` (:class:`OutputSettings`): colors, isolines and weights;
- ``settings.domain``: how a file is read (the ``domain`` option).

Nothing downstream checks or defaults a value again: the domains and the
solver take these parts as they are (their keyword arguments build the same
parts, for callers of the Python API).

Examples
--------
>>> s = Settings.of("cli", m=2, refine=0)
>>> s.solver.m, s.solver.accuracy, s.mesh.refine, s.output.isolines
(2.0, 'auto', 0, None)
>>> s.mesh.given
frozenset({'refine'})
>>> Settings.of("meshlab", domain="tet")
Traceback (most recent call last):
...
heatcore.errors.InvalidOptionError: the MeshLab front end does not offer the option domain; it offers m, boundary, accuracy, backend, robust, refine, weld, colormap, isolines
>>> Settings.of("vector heat").solver.accuracy  # the front end's own default
'high'
"""

from dataclasses import dataclass

from .errors import InvalidOptionError
from .options import OPTIONS, names

_SOLVER, _MESH, _OUTPUT = names("solver"), names("mesh"), names("output")

#: The options each front end offers its users (and takes in :meth:`Settings.of`).
FRONT_END_OPTIONS = {
    "api": (*_SOLVER, *_MESH),
    "cli": (*_SOLVER, *_MESH, "domain", "colormap", "isolines"),
    "batch": (*_SOLVER, *_MESH, "domain"),
    "meshlab": (*_SOLVER, *_MESH, "colormap", "isolines"),
    "blender": (*_SOLVER, *_MESH, *_OUTPUT),
    "vector heat": (*_SOLVER, *_MESH),
    "signed heat": tuple(name for name in (*_SOLVER, *_MESH) if name != "accuracy"),  # its own distance is sharper
    "blender uv map": (*_SOLVER, *_MESH),
}

#: How each front end is named in messages.
FRONT_END_NAMES = {"api": "Python API", "cli": "command-line", "batch": "batch", "meshlab": "MeshLab",
                   "blender": "Blender", "vector heat": "vector heat", "signed heat": "signed heat",
                   "blender uv map": "Blender UV map"}

#: What a solver is built for: many queries (``"reuse"``: "auto" picks the backends that solve fastest
#: once factored), one (``"one query"``: the backend that factors fastest, see :mod:`heatcore.linalg`), or
#: clicks (``"interactive"``: kept for the next clicks, but its first answer is waited for, so it
#: factors as for one query; a solve costs a millisecond more at 41k vertices, a factorization 0.4 s less).
#: A ``"one query"`` solver does not order a large Laplacian by nested dissection, which waits for METIS
#: (:data:`heatcore.steps.factors.NESTED_DISSECTION_FOR`).
INTENTS = ("reuse", "one query", "interactive")


class OptionGroup:
    """The checked values of the options that go to one target; frozen.

    Read a value as an attribute (``settings.m``). ``given`` names the
    options set explicitly (the others hold their front end's default).

    Parameters
    ----------
    front_end : str, default "api"
        Whose defaults fill the options not given (a key of :data:`FRONT_END_OPTIONS`).
    **values
        Option values; each is checked (:meth:`heatcore.options.Option.check`).

    Raises
    ------
    InvalidOptionError
        An option this target does not take, or a bad value.

    Examples
    --------
    >>> mesh = MeshSettings(refine=2)
    >>> mesh.refine, mesh.robust, mesh.keywords()
    (2, True, {'robust': True, 'refine': 2, 'weld': 0.0})
    >>> mesh.replace(weld=None).weld is None
    True
    >>> mesh.m
    Traceback (most recent call last):
    ...
    AttributeError: MeshSettings has no option 'm'
    """

    #: The :class:`~heatcore.options.Option` target whose options the group holds.
    target = None

    def __init__(self, front_end="api", **values):
        allowed = names(self.target)
        unknown = sorted(set(values).difference(allowed))
        if unknown:
            raise InvalidOptionError(
                f"unknown {self.target} option{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}; "
                f"the {self.target} options are {', '.join(allowed)}"
            )
        checked = {
            name: OPTIONS[name].check(values[name]) if name in values else OPTIONS[name].default_for(front_end)
            for name in allowed
        }
        object.__setattr__(self, "_values", checked)
        object.__setattr__(self, "given", frozenset(values))
        object.__setattr__(self, "front_end", front_end)

    def __getattr__(self, name):
        values = self.__dict__.get("_values", {})
        if name in values:
            return values[name]
        raise AttributeError(f"{type(self).__name__} has no option {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is frozen: use replace({name}=...)")

    @classmethod
    def of(cls, settings=None, **options):
        """``settings`` (a group of this class, or a whole :class:`Settings`) with ``options`` applied and checked.

        How the domains and the solver take their options: a front end hands
        over its checked part of :class:`Settings`, a caller of the Python API
        gives keywords (``settings`` None), which are checked here, once.

        Examples
        --------
        >>> SolverSettings.of(m=2).m, SolverSettings.of(Settings.of("cli", m=3), boundary="neumann").m
        (2.0, 3.0)
        >>> MeshSettings.of(Settings.of("blender")).weld is None
        True
        >>> SolverSettings.of({"m": 2})
        Traceback (most recent call last):
        ...
        heatcore.errors.InvalidOptionError: settings must be SolverSettings or Settings, not dict
        """
        if settings is None:
            return cls(**options)
        if isinstance(settings, Settings):
            settings = getattr(settings, cls.target)
        if type(settings) is not cls:
            raise InvalidOptionError(f"settings must be {cls.__name__} or Settings, not {type(settings).__name__}")
        return settings.replace(**options) if options else settings

    def keywords(self):
        """``{name: value}`` of every option of the group."""
        return dict(self._values)

    def replace(self, **changes):
        """A copy with ``changes`` checked and applied (they count as given)."""
        given = {name: self._values[name] for name in self.given}
        return type(self)(self.front_end, **{**given, **changes}, **self._extra())

    def _extra(self):
        """Further constructor keywords of a subclass (its fields that are not options)."""
        return {}

    def __eq__(self, other):
        return type(other) is type(self) and self._key() == other._key()

    def __hash__(self):
        return hash(self._key())

    def _key(self):
        return tuple(self._values.items()) + tuple(self._extra().items())

    def __repr__(self):
        shown = ", ".join(f"{k}={v!r}" for k, v in (*self._values.items(), *self._extra().items()))
        return f"{type(self).__name__}({shown})"


class MeshSettings(OptionGroup):
    """The options of a domain's build: ``robust``, ``refine``, ``weld`` (see :mod:`heatcore.options`).

    Examples
    --------
    >>> MeshSettings("blender").weld is None  # Blender measures the mesh as it is connected
    True
    """

    target = "mesh"

    def refuse_untaken(self, taken, domain_name):
        """Raise where an option was given that a domain (which takes only ``taken``) would ignore.

        Examples
        --------
        >>> MeshSettings(refine=0).refuse_untaken(("refine",), "point cloud")
        >>> MeshSettings(weld=0.5).refuse_untaken(("refine",), "point cloud")
        Traceback (most recent call last):
        ...
        heatcore.errors.InvalidOptionError: a point cloud does not take the option weld (it takes refine)
        """
        refused = sorted(self.given.difference(taken))
        if refused:
            takes = ", ".join(taken) or "no mesh option"
            raise InvalidOptionError(f"a {domain_name} does not take the option{'s' if len(refused) > 1 else ''} "
                                     f"{', '.join(refused)} (it takes {takes})")


class OutputSettings(OptionGroup):
    """The options of the outputs: ``colormap``, ``isolines`` and the weights.

    Examples
    --------
    >>> OutputSettings("blender").isolines, OutputSettings(colormap="magma").colormap
    (10, 'magma')
    """

    target = "output"


class SolverSettings(OptionGroup):
    """The options of :class:`~heatcore.HeatSolver`, and what it is built for.

    Parameters
    ----------
    front_end : str, default "api"
    intent : {"reuse", "one query", "interactive"}, default "reuse"
        See :data:`INTENTS`.
    **values
        ``m``, ``boundary``, ``accuracy``, ``backend``.

    Examples
    --------
    >>> s = SolverSettings(m=3, intent="one query")
    >>> s.m, s.backend, s.intent
    (3.0, 'auto', 'one query')
    >>> s.replace(accuracy="high").intent
    'one query'
    """

    target = "solver"

    def __init__(self, front_end="api", *, intent="reuse", **values):
        if intent not in INTENTS:
            raise InvalidOptionError(f"unknown intent {intent!r}: intent must be one of {', '.join(INTENTS)}")
        super().__init__(front_end, **values)
        object.__setattr__(self, "intent", intent)

    def _extra(self):
        return {"intent": self.intent}


@dataclass(frozen=True)
class Settings:
    """Everything a front end's user set, checked once and split by where it goes.

    Attributes
    ----------
    front_end : str
    mesh : MeshSettings
    solver : SolverSettings
    output : OutputSettings
    domain : str
        How a file is read (the ``domain`` option).

    Examples
    --------
    >>> s = Settings.of("batch", accuracy="high", weld=None, domain="polygon")
    >>> s.solver.accuracy, s.mesh.weld, s.domain
    ('high', None, 'polygon')
    """

    front_end: str
    mesh: MeshSettings
    solver: SolverSettings
    output: OutputSettings
    domain: str

    @classmethod
    def of(cls, front_end="api", *, intent="reuse", **values):
        """The settings of one run of ``front_end``, from the option values its user set.

        Parameters
        ----------
        front_end : str
            A key of :data:`FRONT_END_OPTIONS`.
        intent : {"reuse", "one query", "interactive"}
            What the solver is built for (:data:`INTENTS`).
        **values
            Option values by name; an option left out takes the front end's default.

        Raises
        ------
        InvalidOptionError
            An option the front end does not offer, or a bad value.
        """
        offered = FRONT_END_OPTIONS[front_end]
        refused = [name for name in values if name not in offered]
        if refused:
            raise InvalidOptionError(
                f"the {FRONT_END_NAMES[front_end]} front end does not offer the option{'s' if len(refused) > 1 else ''} "
                f"{', '.join(refused)}; it offers {', '.join(offered)}"
            )
        part = {target: {k: v for k, v in values.items() if OPTIONS[k].target == target} for target in
                ("mesh", "solver", "output", "read")}
        domain = OPTIONS["domain"].check(part["read"]["domain"]) if "domain" in part["read"] else "auto"
        return cls(
            front_end,
            MeshSettings(front_end, **part["mesh"]),
            SolverSettings(front_end, intent=intent, **part["solver"]),
            OutputSettings(front_end, **part["output"]),
            domain,
        )
