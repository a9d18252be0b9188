"""Every front end agrees with heatcore/options.py: names, ranges or choices, defaults, help texts.

The command line (``heatcore distance/demo/batch``), the MeshLab command and
filter, the Blender properties and :func:`heatcore.geodesic_distance` are
compared with the declarations, value by value.
"""

import argparse
import importlib.util
import inspect
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import heatcore as hc
from heatcore import options
from heatcore.apps import cli, meshlab
from heatcore.apps.outputs import PNG_ISOLINES
from heatcore.errors import InvalidOptionError
from heatcore.options import OPTIONS
from heatcore.settings import FRONT_END_OPTIONS

REPO = Path(__file__).resolve().parents[1]
TRIANGLE = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]))


def _flat(text):
    return " ".join(text.split()).lower()


def bad_values(opt):
    """Values just outside the declared range or choices, and of the wrong type."""
    if opt.choices:
        return ["not-a-choice", None, 1]
    if opt.type is bool:
        return ["yes", 2, None]
    values = ["x", [1]]
    if opt.low is not None:
        values.append(opt.low if opt.low_open else opt.low - (1 if opt.type is int else 1e-9))
    if opt.high is not None:
        values.append(opt.high + 1)
    if opt.type is int:
        values += [1.5, True]
    if not opt.none_means:
        values.append(None)
    return values


def good_values(opt):
    """The default, the ends of the range, the specials and every choice."""
    if opt.choices:
        return list(opt.choices)
    if opt.type is bool:
        return [True, False]
    values = [*opt.specials, *([None] if opt.none_means else [])]
    if opt.low is not None:
        values.append(opt.low * 1.5 + 1e-9 if opt.low_open else opt.low)
    if opt.high is not None:
        values.append(opt.high)
    return values


# ---------------------------------------------------------------- the table itself


@pytest.mark.parametrize("name", list(OPTIONS))
def test_declaration_is_complete_and_its_default_is_valid(name):
    opt = OPTIONS[name]
    assert opt.name == name and opt.label and opt.unit and opt.help
    assert opt.target in ("mesh", "solver", "read", "output")
    assert opt.type in (float, int, bool, str) and (opt.type is str) == bool(opt.choices)
    assert len(opt.choice_help) in (0, len(opt.choices))
    assert opt.check(opt.default) == opt.default
    for value in good_values(opt):
        assert opt.check(value) == value
    for value in bad_values(opt):
        with pytest.raises(InvalidOptionError) as caught:
            opt.check(value)
        why = f": {opt.high_why}" if opt.high_why and isinstance(value, float) and value > opt.high else ""
        assert str(caught.value) == f"{'unknown' if opt.choices else 'invalid'} {opt.label} {value!r}: " \
                                    f"{name} must be {opt.requirement()}{why}"


def test_declared_choices_match_the_code_that_implements_them():
    from heatcore.io.domain import DOMAIN_KINDS
    from heatcore.viz.colormap import COLORMAPS

    assert OPTIONS["colormap"].choices == tuple(sorted(COLORMAPS))
    assert OPTIONS["domain"].choices == DOMAIN_KINDS
    assert OPTIONS["refine"].requirement() == "'auto' or an integer 0..8"
    assert f"{PNG_ISOLINES} in the PNG" in OPTIONS["isolines"].help_text("cli")
    assert options.names("mesh") == ("robust", "refine", "weld")
    assert options.names("output") == ("colormap", "isolines", "weight_radius", "weight_falloff", "weight_invert")
    assert set(options.names("solver")) == {"m", "boundary", "accuracy", "backend"}


def test_check_normalizes_and_names_unknown_options():
    assert options.check("m", np.float32(2)) == 2.0 and type(options.check("m", 2)) is float
    assert options.check("refine", np.int64(3)) == 3 and type(options.check("refine", np.int64(3))) is int
    assert options.check("colormap", "none", extra=("none",)) == "none"
    with pytest.raises(InvalidOptionError, match="unknown option 'time_factor'"):
        options.check("time_factor", 1.0)
    with pytest.raises(hc.InvalidSourceError, match="source vertex -1 is out of range"):
        options.check_source_vertices([0, -1], 5)


# ---------------------------------------------------------------- command lines


def subparser(name):
    parser = cli.build_parser()
    return parser._subparsers._group_actions[0].choices[name]


def actions_by_dest(parser):
    found = {}
    for action in parser._actions:
        found.setdefault(action.dest, []).append(action)
    return found


def assert_parser_matches(parser, names, front_end, extra_choices=()):
    actions = actions_by_dest(parser)
    for name in names:
        opt = OPTIONS[name]
        found = actions.get(name)
        assert found, f"{parser.prog}: no option {name}"
        flags = sorted(f for a in found for f in a.option_strings)
        assert flags == sorted(f for f in (opt.flag, opt.off_flag) if f), (parser.prog, name, flags)
        for action in found:
            assert action.default == opt.default_for(front_end), (parser.prog, name, action.default)
            if opt.flag and opt.off_flag in action.option_strings:  # --no-weld: its own declared help
                assert action.help == opt.off_help
            else:
                assert opt.help in action.help.replace("%%", "%"), (parser.prog, name, action.help)
        main = next((a for a in found if opt.flag in a.option_strings), None)
        if main is None:  # --no-robust only
            assert found[0].const is False and opt.type is bool and opt.default is True
            continue
        if opt.choices:
            assert tuple(main.choices) == opt.choices + tuple(extra_choices), (parser.prog, name)
            continue
        for value in good_values(opt):
            if value is not None:
                assert main.type(str(value)) == value
        for value in bad_values(opt):
            if isinstance(value, (int, float, str)) and not isinstance(value, bool):
                with pytest.raises(argparse.ArgumentTypeError):
                    main.type(str(value))
        if opt.none_means:
            off = next(a for a in found if opt.off_flag in a.option_strings)
            assert off.const is None


#: Each subcommand's front end (its row of FRONT_END_OPTIONS) and the options of that row it has no use for.
COMMANDS = {"distance": ("cli", ()), "demo": ("cli", ("domain",)), "batch": ("batch", ()),
            "path": ("cli", ("domain", "colormap", "isolines")), "logmap": ("vector heat", ())}


@pytest.mark.parametrize("command", list(COMMANDS))
def test_cli_options_are_the_front_ends_table(command):
    parser = subparser(command)
    front_end, unused = COMMANDS[command]
    names = [n for n in FRONT_END_OPTIONS[front_end] if n not in unused]
    if command == "logmap":  # the log map writes colours of the radius, as heatcore distance does
        names += ["colormap", "isolines"]
    assert_parser_matches(parser, [n for n in names if n not in ("colormap", "isolines")], front_end)
    assert_parser_matches(parser, [n for n in names if n in ("colormap", "isolines")], "cli")
    # every parsed option that shares a name with a declaration is that declaration
    declared = set(actions_by_dest(parser)) & set(OPTIONS)
    assert declared == set(names)


def test_cli_makes_one_settings_object_of_the_options_set():
    from heatcore.apps.arguments import settings_of

    args = subparser("distance").parse_args(["x.ply", "--m", "3", "--refine", "2", "--no-weld", "--no-robust"])
    settings = settings_of(args, intent="one query")
    assert settings.mesh.keywords() == {"robust": False, "refine": 2, "weld": None}
    assert settings.solver.keywords() == {"m": 3.0, "boundary": "robin", "accuracy": "auto", "backend": "auto"}
    assert settings.mesh.given == {"robust", "refine", "weld"} and settings.solver.intent == "one query"
    assert settings_of(subparser("distance").parse_args(["x.ply"])).mesh.given == frozenset()
    logmap = settings_of(subparser("logmap").parse_args(["x.ply", "-s", "0"]), "vector heat")
    assert logmap.solver.accuracy == "high"


MESHLAB_OPTIONS = FRONT_END_OPTIONS["meshlab"]


def test_meshlab_command_options_are_the_declared_ones():
    parser = meshlab.build_parser()
    assert_parser_matches(parser, [n for n in MESHLAB_OPTIONS if n != "colormap"], "meshlab")
    assert_parser_matches(parser, ["colormap"], "meshlab", extra_choices=meshlab.EXTRA_COLORMAPS)
    assert set(actions_by_dest(parser)) & set(OPTIONS) == set(MESHLAB_OPTIONS)


def test_meshlab_command_builds_one_settings_for_one_query():
    args = meshlab.build_parser().parse_args(["x.ply", "--m", "3", "--backend", "superlu", "--no-weld"])
    settings = meshlab.settings_of(args)
    assert settings.front_end == "meshlab" and settings.solver.intent == "one query"
    assert (settings.solver.m, settings.solver.backend, settings.mesh.weld) == (3.0, "superlu", None)


def test_meshlab_filter_parameters_are_the_declared_ones():
    params = inspect.signature(meshlab.geodesic_distance_from_selection).parameters
    names = [n for n in params if n in OPTIONS]
    assert set(names) == set(MESHLAB_OPTIONS)
    for name in names:
        assert params[name].default == OPTIONS[name].default_for("meshlab"), name


@pytest.mark.parametrize("name", MESHLAB_OPTIONS)
def test_meshlab_filter_checks_through_options(name):
    pymeshlab = pytest.importorskip("pymeshlab")
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(TRIANGLE[0], TRIANGLE[1].astype(np.int32)))
    for value in bad_values(OPTIONS[name]):
        with pytest.raises(InvalidOptionError) as caught:
            meshlab.geodesic_distance_from_selection(ms, **{name: value})
        extra = meshlab.EXTRA_COLORMAPS if name == "colormap" else ()
        assert str(caught.value) == str(OPTIONS[name].error(value, extra))
    with pytest.raises(Exception, match="heat_distance"):  # nothing was written
        ms.current_mesh().vertex_custom_scalar_attribute_array("heat_distance")


# ---------------------------------------------------------------- the Python API


API_OPTIONS = hc.settings.FRONT_END_OPTIONS["api"]


def test_geodesic_distance_keywords_are_the_declared_ones():
    params = inspect.signature(hc.geodesic_distance).parameters
    assert sorted(n for n in params if n in OPTIONS) == sorted(API_OPTIONS)
    doc = _flat(hc.geodesic_distance.__doc__)
    for name in API_OPTIONS:
        opt = OPTIONS[name]
        assert params[name].default == opt.default_for("api"), name
        assert _flat(opt.help) in doc, f"geodesic_distance's docstring lacks the help text of {name}"


@pytest.mark.parametrize("name", API_OPTIONS)
def test_geodesic_distance_checks_through_options(name):
    opt = OPTIONS[name]
    for value in bad_values(opt):
        with pytest.raises(InvalidOptionError) as caught:
            hc.geodesic_distance(*TRIANGLE, [0], **{name: value})
        assert str(caught.value) == str(opt.error(value))
    for value in good_values(opt)[:2]:
        kw = {"refine": 0, name: value} if name != "refine" else {name: value if value != 8 else 1}
        assert np.isfinite(hc.geodesic_distance(*TRIANGLE, [0], **kw)).all()


def test_geodesic_distance_source_keywords_old_and_new():
    d_region = hc.geodesic_distance(*TRIANGLE, region=[0], refine=0)
    bary = ([0], [[0.2, 0.3, 0.5]])
    d_points = hc.geodesic_distance(*TRIANGLE, points=bary, refine=0)
    with pytest.warns(DeprecationWarning, match="faces"):
        old_region = hc.geodesic_distance(*TRIANGLE, faces=[0], refine=0)
    with pytest.warns(DeprecationWarning, match="face_points"):
        old_points = hc.geodesic_distance(*TRIANGLE, face_points=bary, refine=0)
    np.testing.assert_array_equal(old_region, d_region)
    np.testing.assert_array_equal(old_points, d_points)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        hc.geodesic_distance(*TRIANGLE, [0], refine=0)  # the new names warn nothing
    with pytest.raises(hc.InvalidSourceError, match="twice"), pytest.warns(DeprecationWarning):
        hc.geodesic_distance(*TRIANGLE, region=[0], faces=[0], refine=0)


# ---------------------------------------------------------------- Blender


@pytest.fixture(scope="module")
def blender_properties():
    pytest.importorskip("bpy")
    if "blender_addon" not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            "blender_addon", REPO / "blender_addon" / "__init__.py",
            submodule_search_locations=[str(REPO / "blender_addon")],
        )
        module = importlib.util.module_from_spec(spec)
        sys.modules["blender_addon"] = module
        spec.loader.exec_module(module)
    return sys.modules["blender_addon"].properties


def test_the_gpu_backend_is_offered_in_blender_only_where_it_can_run(blender_properties):
    """Issue 37, GPU row: a Blender user cannot act on "pip install 'heatcore[gpu]'": the choice is hidden instead."""
    from heatcore.linalg import available_backends

    items = [item[0] for item in blender_properties.GeodesicOptions.__annotations__["backend"].keywords["items"]]
    assert ("gpu" in items) == ("gpu" in available_backends())
    assert all(blender_properties.usable_choice("backend", c) for c in items)
    assert blender_properties.usable_choice("colormap", "magma")


def test_blender_properties_are_the_declared_ones(blender_properties):
    import bpy

    annotations = blender_properties.GeodesicOptions.__annotations__
    tooltips = sys.modules[blender_properties.__name__.rpartition(".")[0] + ".tooltips"]
    help_, choice_help = tooltips.option_help, tooltips.choice_help  # blender_addon/tooltips.py
    declared = [n for n in annotations if n in OPTIONS]
    assert declared == list(blender_properties.HEATCORE_OPTIONS)
    assert "time_factor" not in annotations
    for name in declared:
        opt, prop = OPTIONS[name], annotations[name]
        kw = prop.keywords
        if opt.switch_help:  # an on/off switch (weld): off is None, on the core's default
            assert prop.function is bpy.props.BoolProperty and kw["description"] == help_(name, opt.switch_help), name
            assert kw["default"] is (opt.default_for("blender") is not None) and opt.none_means, name
            assert blender_properties.option_value(name, False) is None, name
            assert blender_properties.option_value(name, True) == opt.check(opt.default) == opt.default, name
            continue
        assert kw["description"] == help_(name, opt.help), name  # the declared help, as a Blender user reads it
        assert kw["default"] == opt.default_for("blender"), name
        if opt.choices:  # the declared choices, but a backend that cannot run here (the GPU's)
            offered = [(c, text) for c, text in zip(opt.choices, opt.choice_help)
                       if blender_properties.usable_choice(name, c)]
            assert prop.function is bpy.props.EnumProperty
            assert [item[0] for item in kw["items"]] == [c for c, _ in offered]
            assert [item[2] for item in kw["items"]] == [choice_help(name, c, text) for c, text in offered]
        elif opt.specials:  # words or the numbers of the range (refine: "auto" or 0..8), each back to its value
            assert prop.function is bpy.props.EnumProperty, name
            values = [*opt.specials, *range(opt.low, opt.high + 1)]
            assert [item[0] for item in kw["items"]] == [str(v) for v in values], name
            assert [blender_properties.option_value(name, item[0]) for item in kw["items"]] == values, name
            assert all(opt.check(v) == v for v in values), name
        elif opt.type is bool:
            assert prop.function is bpy.props.BoolProperty
        else:
            assert prop.function is (bpy.props.IntProperty if opt.type is int else bpy.props.FloatProperty)
            low = kw.get("min")
            if opt.default is None:  # Blender has no None: the declared Blender default stands for it
                assert low == kw["default"] == opt.default_for("blender") and not opt._in_range(low), name
                assert blender_properties.option_value(name, low) is None, name
                assert blender_properties.option_value(name, 2.5) == 2.5 == opt.check(2.5), name
            else:
                assert (low > opt.low and low == opt.ui_min) if opt.low_open else low == opt.low, name
            assert kw.get("max") == opt.high and kw.get("soft_max") == opt.soft_max, name
    assert declared == list(FRONT_END_OPTIONS["blender"])  # every option the Blender front end offers
    assert set(blender_properties.SOLVER_OPTIONS) <= set(declared)
    assert all(OPTIONS[n].target in ("mesh", "solver") for n in blender_properties.SOLVER_OPTIONS)


@pytest.mark.parametrize(("where", "options"), [("solver_options", {"m": -1}), ("mesh_options", {"refine": 9})])
def test_batch_checks_its_options_before_any_work(tmp_path, where, options):
    from heatcore.apps.batch import run_batch
    from heatcore.io import demo_mesh_path

    out = tmp_path / "out"
    with pytest.raises(hc.InvalidOptionError, match=next(iter(options))):
        run_batch([demo_mesh_path()], out, "0", workers=0, progress=False, **{where: options})
    assert not out.exists()
