"""Reading heatcore's imports statically: the module graph of ``heatcore/`` and ``blender_addon/``.

Every ``import`` statement is read with :mod:`ast` (nothing is imported or
executed): absolute and relative imports, imports inside functions (they still
close cycles at run time) and ``importlib.import_module`` calls, relative ones
too (``import_module(".gpu", __package__)``), whose name the source spells: a
constant, ``pkg.__name__ + ".sub"``, or an f-string over a name bound from a
module-level literal table (``module, cls = BACKENDS[key]``: one arrow per
entry). A call whose name cannot be read is listed (:attr:`Graph.dynamic`),
not guessed. An import ``from pkg import name`` is an arrow to the module
``pkg.name`` when that module exists, else to ``pkg``. Importing a submodule
also runs its parents' ``__init__``; those implicit arrows are not counted.

Uses of another module's private names are listed (:attr:`Graph.private`):
``from m import _name``, ``m._name`` where ``m`` names an imported module,
and ``import_module("m")._name``.

The checks on this graph (layers, cycles) are :mod:`import_graph`'s.

Examples
--------
>>> graph = build_graph({"heatcore/__init__.py": "import importlib\\nimportlib.import_module('.heat', __name__)",
...                      "heatcore/heat.py": "from . import _pins", "heatcore/_pins.py": ""})
>>> sorted(graph.edges), graph.private, graph.dynamic
([('heatcore', 'heatcore.heat'), ('heatcore.heat', 'heatcore._pins')], [], [])
"""

from __future__ import annotations

import ast
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
ROOTS = ("heatcore", "blender_addon")


@dataclass
class Graph:
    """Modules (name -> path), arrows (importer, imported) -> line numbers, external imports, the
    ``import_module`` calls whose name the source does not spell (``dynamic``), and the uses of another
    module's private names (``private``)."""

    modules: dict = field(default_factory=dict)
    edges: dict = field(default_factory=dict)
    externals: dict = field(default_factory=dict)  # module -> {top-level external name: [lines]}
    lines: dict = field(default_factory=dict)  # module -> line count
    dynamic: list = field(default_factory=list)  # (module, line, call as written): name not read statically
    private: list = field(default_factory=list)  # (importer, module, name, line): another module's _name


@dataclass
class _Source:
    """One module being read: its syntax tree and the names its imports bind."""

    name: str
    tree: ast.Module
    package: str  # the value of ``__package__`` in the module
    bindings: dict = field(default_factory=dict)  # local name -> internal module bound to it
    tables: dict = field(default_factory=dict)  # module-level name -> its dict, tuple or list literal
    imported: dict = field(default_factory=dict)  # local name -> (internal module, name) of ``from m import name``
    everyone: dict = field(default_factory=dict)  # module name -> _Source of every module read
    calls: dict = field(default_factory=dict)  # import_module call -> internal modules it imports
    parents: dict = field(default_factory=dict)  # node -> the node that holds it

    def table(self, name, depth=0):
        """The module-level literal ``name`` of this module, or of the module it was imported from."""
        if name in self.tables:
            return self.tables[name]
        module, original = self.imported.get(name, (None, None))
        if module in self.everyone and depth < 10:
            return self.everyone[module].table(original, depth + 1)
        return None

    def scope(self, node):
        """The function whose body holds ``node``, else the module."""
        while node in self.parents:
            node = self.parents[node]
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                return node
        return self.tree


def module_name(path):
    """Dotted module name of a source path: ``heatcore/io/__init__.py`` -> ``heatcore.io``.

    Examples
    --------
    >>> module_name("heatcore/domains/triangle.py"), module_name("heatcore/io/__init__.py")
    ('heatcore.domains.triangle', 'heatcore.io')
    """
    parts = list(Path(path).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def read_sources(rev=None, repo=REPO):
    """``{path: source}`` of every ``.py`` under ``heatcore/`` and ``blender_addon/``.

    With ``rev`` (a commit, tag or branch) the files are read through ``git show``,
    without touching the working tree.
    """
    if rev is None:
        return {
            p.relative_to(repo).as_posix(): p.read_text(encoding="utf-8")
            for root in ROOTS
            for p in sorted((repo / root).rglob("*.py"))
            if "_vendor" not in p.parts and "__pycache__" not in p.parts
        }
    names = subprocess.run(
        ["git", "-C", str(repo), "ls-tree", "-r", "--name-only", rev, "--", *ROOTS],
        check=True, capture_output=True, text=True,
    ).stdout.split()
    return {
        name: subprocess.run(
            ["git", "-C", str(repo), "show", f"{rev}:{name}"], check=True, capture_output=True, text=True
        ).stdout
        for name in names
        if name.endswith(".py") and "/_vendor/" not in name
    }


def absolute_name(name, package):
    """The absolute module name of ``name`` (``".gpu"``, ``"..errors"``) imported from ``package``.

    Examples
    --------
    >>> absolute_name(".gpu", "heatcore.linalg"), absolute_name("..errors", "heatcore.linalg")
    ('heatcore.linalg.gpu', 'heatcore.errors')
    >>> absolute_name("numpy", "heatcore"), absolute_name(".", "heatcore.io")
    ('numpy', 'heatcore.io')
    """
    rest = name.lstrip(".")
    level = len(name) - len(rest)
    if not level:
        return name
    base = package.split(".")
    base = base[: len(base) - (level - 1)]
    return ".".join(base + ([rest] if rest else []))


def _internal(name, modules):
    """The longest prefix of ``name`` that is one of ``modules`` (None when external)."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        candidate = ".".join(parts[:i])
        if candidate in modules:
            return candidate
    return None


def _is_private(name):
    return name.startswith("_") and not name.startswith("__")


def _note(externals, name, line):
    lines = externals.setdefault(name, [])
    if line not in lines:
        lines.append(line)


def _add_edge(graph, src, dst, line):
    if dst != src:
        lines = graph.edges.setdefault((src, dst), [])
        if line not in lines:
            lines.append(line)


# --- the values a string expression can take, as far as the source spells them --------------------------

WHOLE = "whole"  # a name bound to the whole value, not to one item of an unpacked tuple


def string_values(node, source, scope):
    """Every value the string expression ``node`` can take, read from the source; None when unknown.

    Read: string constants, ``__name__`` and ``__package__``, ``module.__name__`` of an imported
    module, ``+`` and f-strings of these, and a local name bound only from a constant or from a
    module-level literal table (``module, cls = BACKENDS[key]``: every first item of the table).

    Examples
    --------
    >>> text = 'T = {"a": ("x", 1), "b": ("y", 2)}\\ndef f(key):\\n    m, n = T[key]\\n    return f".{m}"'
    >>> source = _parse("heatcore/k.py", text)
    >>> joined = source.tree.body[1].body[1].value
    >>> string_values(joined, source, source.scope(joined))
    ['.x', '.y']
    >>> string_values(ast.parse("key + '.x'").body[0].value, source, source.tree.body[1])  # a parameter
    
    """
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.Name) and node.id in ("__name__", "__package__"):
        return [source.name if node.id == "__name__" else source.package]
    if isinstance(node, ast.Attribute) and node.attr == "__name__":
        target = _module_of(node.value, source, None)
        return None if target is None else [target]
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        return _concatenations([node.left, node.right], source, scope)
    if isinstance(node, ast.JoinedStr):
        parts = []
        for value in node.values:
            if isinstance(value, ast.FormattedValue):
                if value.conversion != -1 or value.format_spec is not None:
                    return None
                value = value.value
            parts.append(value)
        return _concatenations(parts, source, scope)
    if isinstance(node, ast.Name):
        values = _name_values(node.id, source, scope)
        if values is None and scope is not source.tree:  # a module-level name read in a function
            values = _name_values(node.id, source, source.tree)
        return values
    return None


def _concatenations(parts, source, scope):
    out = [""]
    for part in parts:
        values = string_values(part, source, scope)
        if values is None:
            return None
        out = [a + b for a in out for b in values]
    return out


def _position(target, name):
    """Where ``name`` sits in an assignment target: WHOLE, its index in a tuple, or None (not there)."""
    if isinstance(target, ast.Name):
        return WHOLE if target.id == name else None
    if isinstance(target, (ast.Tuple, ast.List)):
        for i, item in enumerate(target.elts):
            if isinstance(item, ast.Name) and item.id == name:
                return i
    return None


def _name_values(name, source, scope):
    """The values of ``name`` when every binding of it in ``scope`` is an assignment read by
    :func:`_assigned_values` (a parameter, loop or ``with`` target is not); None otherwise."""
    stores = [n for n in ast.walk(scope) if isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store)]
    if not stores or any(isinstance(n, ast.arg) and n.arg == name for n in ast.walk(scope)):
        return None
    values, read = [], 0
    for node in ast.walk(scope):
        if isinstance(node, ast.Assign):
            for target in node.targets:
                position = _position(target, name)
                if position is None:
                    continue
                got = _assigned_values(node.value, position, source)
                if got is None:
                    return None
                values += got
                read += 1
    return values if read == len(stores) else None


def _assigned_values(value, position, source):
    """String values of ``value`` (or of its item ``position``): a literal, or any entry of a table."""
    table = None
    if isinstance(value, ast.Subscript) and isinstance(value.value, ast.Name):
        table = source.table(value.value.id)
    if table is not None:
        items = table.values if isinstance(table, ast.Dict) else table.elts
    else:
        items = [value]
    out = []
    for item in items:
        if position is not WHOLE:
            if not isinstance(item, (ast.Tuple, ast.List)) or position >= len(item.elts):
                return None
            item = item.elts[position]
        if not (isinstance(item, ast.Constant) and isinstance(item.value, str)):
            return None
        out.append(item.value)
    return out


# --- reading one module ----------------------------------------------------------------------------------

def _parse(path, text):
    name = module_name(path)
    tree = ast.parse(text, filename=path)
    source = _Source(name, tree, name if Path(path).name == "__init__.py" else name.rpartition(".")[0])
    for node in ast.walk(tree):
        for child in ast.iter_child_nodes(node):
            source.parents[child] = node
    assigned = [n.targets[0].id for n in tree.body if isinstance(n, ast.Assign) and isinstance(n.targets[0], ast.Name)]
    for node in tree.body:
        if (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)
                and isinstance(node.value, (ast.Dict, ast.Tuple, ast.List)) and assigned.count(node.targets[0].id) == 1):
            source.tables[node.targets[0].id] = node.value
    return source


def _read_imports(graph, source):
    """Arrows of the ``import`` statements; returns the ``from m import name`` of names that are not
    modules, as ``(local name, m, name)`` (a re-exported module is bound once all modules are read)."""
    externals, reexports = graph.externals.setdefault(source.name, {}), []
    for node in ast.walk(source.tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                top = alias.name.split(".")[0]
                target = _internal(alias.name, graph.modules) if top in ROOTS else None
                if target is None:
                    _note(externals, top, node.lineno)
                    continue
                _add_edge(graph, source.name, target, node.lineno)
                source.bindings[alias.asname or top] = target if alias.asname else top
        elif isinstance(node, ast.ImportFrom):
            base = absolute_name("." * node.level + (node.module or ""), source.package)
            if base not in graph.modules:
                if base.split(".")[0] not in ROOTS:
                    _note(externals, base.split(".")[0], node.lineno)
                continue  # a module not in the tree (blender_addon._vendor: the bundled copy)
            for alias in node.names:
                full = f"{base}.{alias.name}"
                _add_edge(graph, source.name, full if full in graph.modules else base, node.lineno)
                if full in graph.modules:
                    source.bindings[alias.asname or alias.name] = full
                else:
                    source.imported[alias.asname or alias.name] = (base, alias.name)
                    reexports.append((alias.asname or alias.name, base, alias.name))
                    if _is_private(alias.name) and base != source.name:
                        graph.private.append((source.name, base, alias.name, node.lineno))
    return reexports


def _follow_reexports(sources, reexports):
    """Bind ``from m import name`` where ``name`` is a module that ``m`` imported (``from ._heatcore import
    heatcore``), until nothing changes."""
    changed = True
    while changed:
        changed = False
        for source, (local, module, name) in reexports:
            target = sources[module].bindings.get(name)
            if target is not None and local not in source.bindings:
                source.bindings[local] = target
                changed = True


def _calls_import_module(node):
    func = node.func
    return (isinstance(func, ast.Attribute) and func.attr == "import_module") or (
        isinstance(func, ast.Name) and func.id == "import_module"
    )


def _imported_names(call, source):
    """The absolute names ``import_module(name, package)`` can import; None when the source does not say."""
    keywords = {k.arg: k.value for k in call.keywords}
    name = call.args[0] if call.args else keywords.get("name")
    package = call.args[1] if len(call.args) > 1 else keywords.get("package")
    scope = source.scope(call)
    names = None if name is None else string_values(name, source, scope)
    if names is None or not any(n.startswith(".") for n in names):
        return names
    packages = None if package is None else string_values(package, source, scope)
    return None if packages is None else [absolute_name(n, p) for n in names for p in packages]


def _read_dynamic_imports(graph, source):
    """Arrows of the ``importlib.import_module`` calls; a name the source does not spell is listed."""
    externals = graph.externals.setdefault(source.name, {})
    for node in ast.walk(source.tree):
        if not (isinstance(node, ast.Call) and _calls_import_module(node)):
            continue
        names = _imported_names(node, source)
        if names is None:
            graph.dynamic.append((source.name, node.lineno, ast.unparse(node)))
            continue
        source.calls[node] = []
        for name in names:
            target = _internal(name, graph.modules)
            if target is None:
                _note(externals, name.split(".")[0], node.lineno)
            else:
                _add_edge(graph, source.name, target, node.lineno)
                source.calls[node].append(target)
    for node in ast.walk(source.tree):  # options = importlib.import_module(...): ``options`` names a module
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            target = _module_of(node.value, source, graph.modules)
            if target is not None:
                source.bindings.setdefault(node.targets[0].id, target)


def _module_of(node, source, modules):
    """The internal module an expression names (``np``-like name of an import, ``pkg.sub``, an
    ``import_module`` call that imports one module), else None. ``modules`` None: names only."""
    if isinstance(node, ast.Name):
        return source.bindings.get(node.id)
    if isinstance(node, ast.Call):
        targets = source.calls.get(node, [])
        return targets[0] if len(targets) == 1 else None
    if isinstance(node, ast.Attribute) and modules is not None:
        base = _module_of(node.value, source, modules)
        if base is not None and f"{base}.{node.attr}" in modules:
            return f"{base}.{node.attr}"
    return None


def _read_private_uses(graph, source):
    """``module._name`` where ``module`` is another internal module (imported, or an import_module call)."""
    for node in ast.walk(source.tree):
        if isinstance(node, ast.Attribute) and _is_private(node.attr):
            module = _module_of(node.value, source, graph.modules)
            if module is not None and module != source.name and f"{module}.{node.attr}" not in graph.modules:
                graph.private.append((source.name, module, node.attr, node.lineno))


def build_graph(sources):
    """The import graph of ``{path: source}`` (see :func:`read_sources`).

    Examples
    --------
    >>> g = build_graph({"heatcore/__init__.py": "", "heatcore/a.py": "from . import b\\nimport numpy",
    ...                  "heatcore/b.py": "from .a import x"})
    >>> sorted(g.edges), g.externals["heatcore.a"]
    ([('heatcore.a', 'heatcore.b'), ('heatcore.b', 'heatcore.a')], {'numpy': [2]})

    ``importlib.import_module`` calls count, relative ones too; a name built from a literal table
    counts once per entry; one the source does not spell is listed in ``dynamic``:

    >>> g = build_graph({"heatcore/__init__.py": "", "heatcore/gpu.py": "", "heatcore/cpu.py": "",
    ...     "heatcore/f.py": "import importlib\\nB = {'g': ('gpu', 1), 'c': ('cpu', 2)}\\n"
    ...                      "importlib.import_module('.gpu', __package__)\\n"
    ...                      "def load(key, name):\\n    module, _ = B[key]\\n"
    ...                      "    importlib.import_module(f'.{module}', __package__)\\n"
    ...                      "    importlib.import_module(name)\\n"})
    >>> sorted(b for a, b in g.edges), g.edges[("heatcore.f", "heatcore.gpu")]
    (['heatcore.cpu', 'heatcore.gpu'], [3, 6])
    >>> g.dynamic
    [('heatcore.f', 7, 'importlib.import_module(name)')]

    A private name of another module, imported or read through the module, is listed in ``private``:

    >>> g = build_graph({"heatcore/__init__.py": "", "heatcore/a.py": "def _f(): pass",
    ...     "heatcore/b.py": "from .a import _f\\nimport heatcore.a\\nimport importlib\\nheatcore.a._f\\n"
    ...                      "importlib.import_module('heatcore.a')._f"})
    >>> g.private
    [('heatcore.b', 'heatcore.a', '_f', 1), ('heatcore.b', 'heatcore.a', '_f', 4), ('heatcore.b', 'heatcore.a', '_f', 5)]
    """
    graph, parsed, reexports = Graph(), {}, []
    for path, text in sorted(sources.items()):
        source = _parse(path, text)
        parsed[source.name] = source
        graph.modules[source.name] = path
        graph.lines[source.name] = len(text.splitlines())
    for source in parsed.values():
        source.everyone = parsed
        reexports += [(source, r) for r in _read_imports(graph, source)]
    _follow_reexports(parsed, reexports)
    for source in parsed.values():
        _read_dynamic_imports(graph, source)
        _read_private_uses(graph, source)
    for lines in graph.edges.values():
        lines.sort()
    graph.dynamic.sort()
    graph.private = sorted(set(graph.private))
    return graph

