"""The house rules of docs/design.md ("Layout"), checked on the working tree.

- no import cycle among the modules of ``heatcore/`` and ``blender_addon/``
  (function-level imports included: they close cycles at run time, and
  ``importlib.import_module`` calls, relative ones too);
- every ``import_module`` call names its module in the source (one loader of
  third-party libraries excepted, :data:`DYNAMIC_IMPORTS`);
- no module uses another module's private name (``from m import _name``,
  ``m._name``, ``import_module("m")._name``);
- no import arrow up the layers or between sibling groups, and the fences
  (domains import no linalg backend), per ``scripts/import_graph.py``;
- every module belongs to a layer;
- ``ctypes`` imported only under ``heatcore/linalg/``;
- no module over 350 code lines (docstrings, comments and blank lines not counted) in
  ``heatcore/`` and ``blender_addon/``;
- every public function and class defined in ``heatcore/`` has a numpy-style
  docstring with an ``Examples`` section holding at least one ``>>>`` line.
  Public: defined at module level (not a method) in a module whose dotted
  path has no part starting with ``_`` (``__init__`` excepted), and either
  named in the module's ``__all__`` or not starting with ``_``. Methods are
  not checked (the class's Examples shows them in use); ``__main__`` holds no
  API.

The examples themselves run as doctests (``--doctest-modules``).
"""

import ast
import doctest
import importlib.util
import io
import re
import sys
import tokenize
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
MAX_CODE_LINES = 350


def _load_import_graph():
    spec = importlib.util.spec_from_file_location("heatcore_import_graph", REPO / "scripts" / "import_graph.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


import_graph = _load_import_graph()


@pytest.fixture(scope="module")
def sources():
    return import_graph.read_sources()


@pytest.fixture(scope="module")
def graph(sources):
    return import_graph.build_graph(sources)


def test_no_import_cycle(graph):
    cycles = import_graph.find_cycles(graph)
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c + [c[0]]) for c in cycles)


#: ``import_module`` calls whose module the source does not spell, and why each may stay so.
DYNAMIC_IMPORTS = {
    ("heatcore.linalg.libraries", "importlib.import_module(name)"):
        "optional() imports the third-party library its caller names (cvxopt, qdldl, cholespy, nvmath, ...)",
    ("heatcore.linalg.libraries", "importlib.import_module(submodule)"):
        "the submodules that library needs first (SUBMODULES); none is a heatcore module",
}


def test_importlib_imports_are_arrows(graph):
    # each of these is made only through importlib.import_module (relative, or heatcore.__name__ + ".sub")
    for arrow in [("heatcore.linalg.factor", "heatcore.linalg.gpu"), ("heatcore.linalg.factor", "heatcore.linalg.qdldl"),
                  ("blender_addon.stages", "heatcore.options"), ("blender_addon.stages", "heatcore.progress"),
                  ("blender_addon._heatcore", "heatcore.viz.colormap"), ("blender_addon.path_api", "heatcore.paths")]:
        assert arrow in graph.edges, f"{arrow[0]} -> {arrow[1]} (through importlib) is not in the graph"


def test_every_import_module_call_is_read(graph):
    unread = [f"{graph.modules[m]}:{line} {call}" for m, line, call in graph.dynamic if (m, call) not in DYNAMIC_IMPORTS]
    assert not unread, "import_module calls whose module the checker cannot read:\n" + "\n".join(unread)


def test_no_module_uses_another_modules_private_name(graph):
    assert not graph.private, "private names used outside their module:\n" + "\n".join(
        f"  {graph.modules[m]}:{line} uses {other}.{name}" for m, other, name, line in graph.private
    )


def test_the_checker_examples_run():
    for module in (import_graph, sys.modules["import_reader"]):
        result = doctest.testmod(module)
        assert result.attempted and not result.failed, module.__name__


def test_no_upward_arrow(graph):
    upward = import_graph.upward_arrows(graph)
    assert not upward, "imports against the layers:\n" + "\n".join(
        f"  {graph.modules[a]}:{lines[0]} imports {b}: {why}" for a, b, lines, why in upward
    )


def test_every_module_has_a_layer(graph):
    assert not import_graph.unlayered(graph), (
        "modules in no layer (add them to LAYERS in scripts/import_graph.py): "
        + ", ".join(import_graph.unlayered(graph))
    )


def test_ctypes_only_in_linalg(graph):
    outside = import_graph.fenced_externals(graph)
    assert not outside, "ctypes (or another fenced module) imported outside its fence: " + ", ".join(
        f"{graph.modules[m]}:{lines[0]} imports {e}" for m, e, lines in outside
    )


def code_lines(text):
    """Lines holding code: not blank, not only a comment, not part of a docstring."""
    docstrings = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                docstrings.update(range(first.lineno, first.end_lineno + 1))
    skip = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT, tokenize.ENDMARKER}
    lines = set()
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type not in skip:
            lines.update(range(token.start[0], token.end[0] + 1))
    return len(lines - docstrings)


def test_no_module_over_350_code_lines(sources):
    long = {path: n for path, text in sources.items() if (n := code_lines(text)) > MAX_CODE_LINES}
    assert not long, f"modules over {MAX_CODE_LINES} code lines: " + ", ".join(f"{p} ({n})" for p, n in sorted(long.items()))


def test_code_lines_can_fail():
    assert code_lines("x = 1\n" * (MAX_CODE_LINES + 1)) > MAX_CODE_LINES
    assert code_lines('"""' + "doc\n" * 1000 + '"""\n# c\n\nx = 1  # one\ny = (2,\n     3)\n') == 3


EXAMPLES = re.compile(r"^\s*Examples\n\s*-{8,}\s*$", re.MULTILINE)


def docstring_problem(doc):
    """Why ``doc`` is not a numpy-style docstring with a runnable Examples section (None when it is)."""
    if not doc or not doc.strip():
        return "no docstring"
    match = EXAMPLES.search(doc)
    if match is None:
        return "no 'Examples' section (a line 'Examples' underlined with dashes)"
    if ">>>" not in doc[match.end():]:
        return "an 'Examples' section without a '>>>' line"
    return None


def _module_all(tree):
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            try:
                return set(ast.literal_eval(node.value))
            except ValueError:
                return None
    return None


def _top_level_definitions(body):
    """Functions and classes at module level, including those under ``if``/``try`` at module level."""
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            yield node
        elif isinstance(node, (ast.If, ast.Try)):
            yield from _top_level_definitions(node.body)
            yield from _top_level_definitions(node.orelse)
            for handler in getattr(node, "handlers", []):
                yield from _top_level_definitions(handler.body)
            yield from _top_level_definitions(getattr(node, "finalbody", []))


def public_definitions(sources):
    """``(path, line, name, node)`` of every public function and class defined in ``heatcore/``."""
    out = []
    for path, text in sorted(sources.items()):
        module = import_graph.module_name(path)
        parts = module.split(".")
        if parts[0] != "heatcore" or any(p.startswith("_") for p in parts[1:]):
            continue  # blender_addon, __main__, private modules
        tree = ast.parse(text, filename=path)
        exported = _module_all(tree) or set()
        for node in _top_level_definitions(tree.body):
            if node.name in exported or not node.name.startswith("_"):
                out.append((path, node.lineno, node.name, node))
    return out


def test_public_api_has_numpy_docstrings_with_examples(sources):
    missing = []
    for path, line, name, node in public_definitions(sources):
        problem = docstring_problem(ast.get_docstring(node))
        if problem:
            missing.append(f"{path}:{line} {name}: {problem}")
    assert not missing, f"{len(missing)} public functions/classes lack a docstring with Examples:\n" + "\n".join(
        missing
    )


# --- the checks can fail: each is run once on a planted violation -----------------------------------------


def _planted(extra):
    sources = {
        "heatcore/__init__.py": "from . import heat\n",
        "heatcore/errors.py": "",
        "heatcore/heat.py": "from .errors import x\n",
        "heatcore/domains/__init__.py": "",
        "heatcore/domains/triangle.py": "",
        "heatcore/linalg/__init__.py": "",
        "heatcore/linalg/cholmod.py": "import ctypes\n",
        "heatcore/apps/__init__.py": "",
        "heatcore/apps/cli.py": "from .. import heat\n",
    }
    sources.update(extra)
    return import_graph.build_graph(sources)


def test_the_checks_catch_planted_violations():
    clean = _planted({})
    assert not import_graph.find_cycles(clean)
    assert not import_graph.upward_arrows(clean)
    assert not import_graph.fenced_externals(clean)
    assert not import_graph.unlayered(clean)

    cyclic = _planted({"heatcore/errors.py": "def f():\n    from .heat import solve\n"})
    assert import_graph.find_cycles(cyclic) == [["heatcore.errors", "heatcore.heat"]]

    upward = _planted({"heatcore/domains/triangle.py": "from ..apps import cli\nfrom ..linalg import cholmod\n"})
    assert [(a, b) for a, b, _, _ in import_graph.upward_arrows(upward)] == [
        ("heatcore.domains.triangle", "heatcore.apps.cli"),  # up the layers
        ("heatcore.domains.triangle", "heatcore.linalg.cholmod"),  # a linalg backend: fenced
    ]

    sideways = _planted({"heatcore/io/__init__.py": "", "heatcore/viz/render.py": "import heatcore.io\n"})
    assert [(a, b) for a, b, _, _ in import_graph.upward_arrows(sideways)] == [("heatcore.viz.render", "heatcore.io")]

    ctypes_outside = _planted({"heatcore/apps/cli.py": "def f():\n    import ctypes.util\n"})
    assert import_graph.fenced_externals(ctypes_outside) == [("heatcore.apps.cli", "ctypes", [2])]

    assert import_graph.unlayered(_planted({"heatcore/misc.py": ""})) == ["heatcore.misc"]


def test_importlib_and_private_checks_catch_planted_violations():
    # the factor <-> gpu cycle of c07dd69: gpu imports factor, factor imports gpu through importlib
    cyclic = _planted({
        "heatcore/linalg/factor.py": "import importlib\nBACKENDS = {'gpu': ('gpu', 'GPUFactor')}\n"
                                     "def gpu_count():\n    return importlib.import_module('.gpu', __package__).count()\n"
                                     "def factor(backend):\n    module, cls = BACKENDS[backend]\n"
                                     "    return getattr(importlib.import_module(f'.{module}', __package__), cls)\n",
        "heatcore/linalg/gpu.py": "from .factor import Factor\n",
    })
    assert import_graph.find_cycles(cyclic) == [["heatcore.linalg.factor", "heatcore.linalg.gpu"]]
    assert cyclic.edges[("heatcore.linalg.factor", "heatcore.linalg.gpu")] == [4, 7]

    blender = _planted({"blender_addon/__init__.py": "", "blender_addon/_heatcore.py": "import heatcore\n",
                        "blender_addon/stages.py": "import importlib\nfrom ._heatcore import heatcore\n"
                                                   "errors = importlib.import_module(heatcore.__name__ + '.errors')\n"
                                                   "def f(name):\n    return importlib.import_module(f'.{name}', __package__)\n"})
    assert ("blender_addon.stages", "heatcore.errors") in blender.edges
    assert blender.dynamic == [("blender_addon.stages", 5, "importlib.import_module(f'.{name}', __package__)")]

    # the private imports of a342800 (apps/cli.py, linalg/hermitian.py) and the other ways to reach one
    private = _planted({
        "heatcore/apps/reporting.py": "class _stage: pass\n",
        "heatcore/apps/cli.py": "from .reporting import _stage, build_progress\nfrom . import reporting\n"
                                "reporting._stage\nimport importlib\nimportlib.import_module('heatcore.heat')._solve\n"
                                "reporting.__name__\n",
        "heatcore/linalg/hermitian.py": "def f():\n    from .cholmod import _indices\n",
    })
    assert private.private == [("heatcore.apps.cli", "heatcore.apps.reporting", "_stage", 1),
                               ("heatcore.apps.cli", "heatcore.apps.reporting", "_stage", 3),
                               ("heatcore.apps.cli", "heatcore.heat", "_solve", 5),
                               ("heatcore.linalg.hermitian", "heatcore.linalg.cholmod", "_indices", 2)]
    assert not _planted({}).private and not _planted({}).dynamic


def test_docstring_check_catches_planted_violations():
    text = '''
__all__ = ["_exported"]

def documented():
    """Summary.

    Examples
    --------
    >>> documented()
    """

def no_examples():
    """Summary only."""

def empty_examples():
    """Summary.

    Examples
    --------
    None here.
    """

def _private():
    pass

def _exported():
    pass

class Undocumented:
    def method(self):
        pass
'''
    found = {name: docstring_problem(ast.get_docstring(node))
             for _, _, name, node in public_definitions({"heatcore/planted.py": text})}
    assert found == {
        "documented": None,
        "no_examples": "no 'Examples' section (a line 'Examples' underlined with dashes)",
        "empty_examples": "an 'Examples' section without a '>>>' line",
        "_exported": "no docstring",
        "Undocumented": "no docstring",
    }
    assert public_definitions({"heatcore/_private.py": text, "blender_addon/api.py": text}) == []
