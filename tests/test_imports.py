"""Import structure of the project, read from the source with :mod:`ast` (nothing is imported).

The graph has one node per project module (the packages in ``PACKAGES`` and ``pipeline.py``)
and an edge for every ``import`` statement naming another project module, wherever it stands
in the module: at the top, under ``if``/``try`` or inside a function. An import hidden in a
function still ties the two modules together; it only moves the cost to the first call.

Rules checked:

(a) the graph has no cycle;
(b) layering: the physics packages never import ``stages``, ``pipeline``, ``curve_squeal`` (the
    Python API), ``cli`` or ``exports``; ``stages`` imports none of the last four; ``squealcore``
    imports no physics package, and ``profiles`` (the wheel and rail
    profiles, below ``mesh`` and ``contact_geometry``, which both build on them) imports only
    ``squealcore``;
(c) a project import inside a function carries a comment ``# lazy: <reason>`` on its line
    (the reason being a measured import-time cost);
(d) the tests import no benchmark: no ``import benchmarks...`` or ``from benchmarks... import``
    in ``tests/*.py`` (what a test needs lives in the package; the benchmarks import the
    installed package, never the other way round);
(e) no module but the registering ones (``interaction/wheel_models.py``, each contact model's
    ``contact/<model>/__init__.py``)
    names a wheel or contact model in a comparison or a membership test (nor a wheel model as a
    dict key): the rest of the code asks the registries;
(f) no module is over 1000 lines (one job per module).
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from pathlib import Path


ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("mesh", "fe", "waveguide", "interaction", "contact", "stability", "contact_geometry", "radiation", "profiles",
            "curving", "squealcore", "stages", "studies", "curve_squeal", "cli", "exports")
TOP_MODULES = ("pipeline",)
PHYSICS = ("mesh", "fe", "waveguide", "interaction", "contact", "stability", "contact_geometry", "radiation", "profiles",
           "curving")
ORCHESTRATION = ("stages", "pipeline", "curve_squeal", "cli", "exports")  # curve_squeal: the Python API, over stages
#: Packages above the stage engine: the commands and the exports; ``stages`` never imports them.
ABOVE_STAGES = ("cli", "exports", "curve_squeal", "pipeline")
LAZY_COMMENT = re.compile(r"#\s*lazy:\s*\S")


@dataclass(frozen=True)
class ImportSite:
    """One project import statement.

    Attributes
    ----------
    importer : str
        Dotted name of the importing module.
    target : str
        Dotted name of the imported project module.
    line : int
        First line of the statement (1-based).
    in_function : bool
        The statement stands inside a function or method body.
    lazy_comment : bool
        One of the statement's lines carries ``# lazy: <reason>``.
    """

    importer: str
    target: str
    line: int
    in_function: bool
    lazy_comment: bool


def module_files(root=ROOT):
    """Map dotted module name -> source path of every project module."""
    files = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            files[".".join(parts)] = path
    for name in TOP_MODULES:
        files[name] = root / f"{name}.py"
    return files


def _resolve(name, modules):
    """Longest project module that ``name`` (a dotted import target) names, or None."""
    parts = name.split(".")
    for stop in range(len(parts), 0, -1):
        candidate = ".".join(parts[:stop])
        if candidate in modules:
            return candidate
    return None


def _base_of_relative(importer, is_package, level, module):
    """Absolute dotted name of ``from <level dots><module> import ...`` in ``importer``."""
    package = importer.split(".") if is_package else importer.split(".")[:-1]
    if level > 1:
        package = package[:-(level - 1)]
    return ".".join(package + ([module] if module else []))


def _statement_targets(node, importer, is_package, modules):
    """Project modules named by one ``Import``/``ImportFrom`` node."""
    targets = []
    if isinstance(node, ast.Import):
        targets = [_resolve(alias.name, modules) for alias in node.names]
    else:
        base = node.module or ""
        if node.level:
            base = _base_of_relative(importer, is_package, node.level, node.module)
        for alias in node.names:
            # ``from fe import hex20`` imports the module fe.hex20; ``from fe.hex20 import f``
            # imports fe.hex20.
            targets.append(_resolve(f"{base}.{alias.name}", modules) or _resolve(base, modules))
    return sorted({t for t in targets if t is not None and t != importer})


def _function_imports(tree):
    """ids of the import nodes that stand inside a function or method body."""
    inside = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            inside.update(id(sub) for sub in ast.walk(node) if isinstance(sub, (ast.Import, ast.ImportFrom)))
    return inside


def import_sites(root=ROOT):
    """Every project import statement of every project module, as :class:`ImportSite`."""
    modules = module_files(root)
    sites = []
    for importer, path in modules.items():
        source = path.read_text(encoding="utf-8")
        lines = source.splitlines()
        tree = ast.parse(source, filename=str(path))
        in_function = _function_imports(tree)
        is_package = path.name == "__init__.py"
        for node in ast.walk(tree):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            text = lines[node.lineno - 1:node.end_lineno]
            lazy = any(LAZY_COMMENT.search(line) for line in text)
            for target in _statement_targets(node, importer, is_package, modules):
                sites.append(ImportSite(importer, target, node.lineno, id(node) in in_function, lazy))
    return sites


def import_graph(sites):
    """Adjacency ``{module: set of imported project modules}``."""
    graph = {}
    for site in sites:
        graph.setdefault(site.importer, set()).add(site.target)
        graph.setdefault(site.target, set())
    return graph


def strongly_connected(graph):
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []
    counter = 0
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, successors = work[-1]
            advanced = False
            for succ in successors:
                if succ not in index:
                    index[succ] = low[succ] = counter
                    counter += 1
                    stack.append(succ)
                    on_stack.add(succ)
                    work.append((succ, iter(sorted(graph[succ]))))
                    advanced = True
                    break
                if succ in on_stack:
                    low[node] = min(low[node], index[succ])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    components.append(sorted(component))
    return components


def one_cycle(graph, component):
    """A closed path ``[m0, m1, ..., m0]`` through modules of one strongly connected component."""
    members = set(component)
    start = component[0]
    # breadth-first search back to ``start`` inside the component: the shortest cycle through it
    parent = {start: None}
    queue = [start]
    while queue:
        node = queue.pop(0)
        for succ in sorted(graph[node] & members):
            if succ == start:
                path = [node]
                while parent[path[-1]] is not None:
                    path.append(parent[path[-1]])
                return path[::-1] + [start]
            if succ not in parent:
                parent[succ] = node
                queue.append(succ)
    raise AssertionError(f"{component} is not strongly connected")  # unreachable for a real SCC


def _describe_cycles(sites):
    graph = import_graph(sites)
    lines = []
    for component in strongly_connected(graph):
        cycle = one_cycle(graph, component)
        steps = []
        for a, b in zip(cycle, cycle[1:]):
            where = sorted({s.line for s in sites if s.importer == a and s.target == b})
            steps.append(f"{a} -> {b} (line {', '.join(map(str, where))})")
        lines.append(f"cycle among {', '.join(component)}: " + "; ".join(steps))
    return lines


def _package(module):
    return module.split(".")[0]


# --------------------------------------------------------------------------- the checker itself


def _write_project(root, files):
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    for package in PACKAGES:
        (root / package).mkdir(exist_ok=True)
        (root / package / "__init__.py").touch()
    for name in TOP_MODULES:
        (root / f"{name}.py").touch()


def benchmark_imports(root=ROOT):
    """``(file, line)`` of every ``import benchmarks...`` / ``from benchmarks... import`` in ``tests/*.py``."""
    found = []
    for path in sorted((root / "tests").glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            if any(name == "benchmarks" or name.startswith("benchmarks.") for name in names):
                found.append((path.relative_to(root).as_posix(), node.lineno))
    return found


def test_checker_finds_planted_cycle_layering_and_hidden_import(tmp_path):
    """The rules catch what they should on a small planted project (so their passing means something)."""
    _write_project(tmp_path, {
        "fe/a.py": "from fe import b\n",
        "fe/b.py": "def f():\n    from fe.c import g\n",
        "fe/c.py": "from . import a\nimport numpy\n",
        "fe/d.py": "def f():\n    from fe import (  # lazy: 0.8 s of numba compilation\n        a,\n    )\n",
        "interaction/x.py": "from stages.y import z\n",
        "squealcore/s.py": "import waveguide.w\n",
        "waveguide/w.py": "",
        "stages/y.py": "",
    })
    sites = import_sites(tmp_path)
    cycles = _describe_cycles(sites)
    assert len(cycles) == 1 and "fe.a, fe.b, fe.c" in cycles[0]
    assert "fe.a -> fe.b (line 1); fe.b -> fe.c (line 2); fe.c -> fe.a (line 1)" in cycles[0]
    hidden = {(s.importer, s.target, s.lazy_comment) for s in sites if s.in_function}
    assert hidden == {("fe.b", "fe.c", False), ("fe.d", "fe.a", True)}
    edges = {(s.importer, s.target) for s in sites}
    assert ("interaction.x", "stages.y") in edges and ("squealcore.s", "waveguide.w") in edges
    assert not any(s.target == "numpy" for s in sites)


def test_checker_finds_planted_benchmark_imports(tmp_path):
    """(d) catches both import forms, also inside a function, and nothing else."""
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_a.py").write_text("import benchmarks.simulate\nimport benchmarks_other\n")
    (tmp_path / "tests" / "test_b.py").write_text(
        "from stages import summary\n\n\ndef test_x():\n    from benchmarks.simulate import main\n")
    (tmp_path / "tests" / "test_c.py").write_text("from benchmarks import simulate\nfrom . import benchmarks\n")
    assert benchmark_imports(tmp_path) == [("tests/test_a.py", 1), ("tests/test_b.py", 5), ("tests/test_c.py", 1)]


def test_checker_reads_the_real_project():
    """Sanity: the real tree is found and has the edges everyone knows about."""
    modules = module_files()
    assert {"pipeline", "fe.rotation", "fe.centrifugal", "stages.wheel", "squealcore.errors"} <= set(modules)
    edges = {(s.importer, s.target) for s in import_sites()}
    assert ("fe.rotation", "fe.centrifugal") in edges
    assert ("pipeline", "squealcore.errors") in edges


# --------------------------------------------------------------------------- the rules


def test_no_import_cycle():
    """(a) No module reaches itself through imports (also those inside functions)."""
    cycles = _describe_cycles(import_sites())
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def test_layering():
    """(b) Physics never imports the orchestration; squealcore imports no physics package; profiles
    imports only squealcore; the stage engine and bodies (``stages``) never import the commands
    (``cli``), the exports, the Python API or ``pipeline``."""
    bad = []
    for site in import_sites():
        importer, target = _package(site.importer), _package(site.target)
        if importer in PHYSICS and target in ORCHESTRATION:
            bad.append(site)
        if importer == "squealcore" and target in PHYSICS:
            bad.append(site)
        if importer == "profiles" and target not in ("profiles", "squealcore"):
            bad.append(site)
        if importer == "stages" and target in ABOVE_STAGES:
            bad.append(site)
    assert not bad, "layering violations:\n" + "\n".join(
        f"{s.importer} (line {s.line}) imports {s.target}" for s in bad)


def test_no_hidden_project_import():
    """(c) Project imports stand at module top, unless marked ``# lazy: <measured reason>``."""
    hidden = [s for s in import_sites() if s.in_function and not s.lazy_comment]
    assert not hidden, "project imports inside functions without '# lazy: <reason>':\n" + "\n".join(
        f"{s.importer} (line {s.line}) imports {s.target}" for s in hidden)


def test_tests_import_no_benchmark():
    """(d) No test imports ``benchmarks`` (a benchmark may change or go; the tests check the package)."""
    found = benchmark_imports()
    assert not found, "tests importing a benchmark:\n" + "\n".join(f"{f} (line {n})" for f, n in found)


def test_no_benchmark_script_shadows_a_package():
    """A benchmark run as ``python benchmarks/<name>.py`` has ``benchmarks/`` first on ``sys.path``: a script
    named like a top-level package (``benchmarks/radiation.py``) would be imported instead of the package."""
    clashes = sorted(p.name for p in (ROOT / "benchmarks").glob("*.py") if p.stem in PACKAGES + TOP_MODULES)
    assert not clashes, f"benchmark scripts named like a package of the project: {clashes}"


#: The registries and the constructor their entries are made with: only the modules that make
#: entries (the wheel registry; each contact model's folder, ``contact/<model>/__init__.py``)
#: may name a model.
REGISTRIES = {"interaction.wheel_models": "WheelModel", "contact": "ContactModelSpec"}


def registering_modules(root=ROOT):
    """``{module: names}`` of the modules that register models: the first arguments of their
    ``<constructor>("name", ...)`` calls, for the constructors of :data:`REGISTRIES`, read from
    the source of the registry's package (nothing is imported)."""
    found = {}
    for module, path in module_files(root).items():
        constructors = {c for r, c in REGISTRIES.items() if module == r or module.startswith(r + ".")}
        if not constructors:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        names = {call.args[0].value for call in ast.walk(tree)
                 if isinstance(call, ast.Call) and getattr(call.func, "id", "") in constructors
                 and call.args and isinstance(call.args[0], ast.Constant)}
        if names:
            found[module] = names
    return found


def registered_names(registry, constructor, root=ROOT):
    """Names of the models registered with ``constructor`` in the package or module ``registry``."""
    return set().union(*(names for module, names in registering_modules(root).items()
                         if (module == registry or module.startswith(registry + "."))
                         and REGISTRIES.get(registry) == constructor))


def model_name_branches(root=ROOT):
    """``(module, line)`` of every comparison or membership test naming a registered wheel or contact
    model by a string literal outside its registry, and of every dict keyed by a wheel model's name.

    Those are the places that would have to change when a model is added; the rest of the code
    asks the registries (``wheel_models()``, ``rotating_names()``, ``REFERENCE``; ``contact_spec``).
    (Dict keys are checked for the wheel models only: ``"point"`` is also an operating point.)
    """
    modules = module_files(root)
    wheel = registered_names("interaction.wheel_models", "WheelModel", root)
    contact = registered_names("contact", "ContactModelSpec", root)
    registering = registering_modules(root)
    assert wheel and contact, "no model found in a registry's source"

    def literal_names(node, names):
        items = node.elts if isinstance(node, (ast.Tuple, ast.List, ast.Set)) else [node]
        return {i.value for i in items if isinstance(i, ast.Constant) and isinstance(i.value, str)} & names

    found = []
    for module, path in modules.items():
        if module in registering:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Compare) and any(literal_names(n, wheel | contact)
                                                     for n in [node.left, *node.comparators]):
                found.append((module, node.lineno))
            elif isinstance(node, ast.Dict) and any(k is not None and literal_names(k, wheel) for k in node.keys):
                found.append((module, node.lineno))
    return found


def test_no_module_branches_on_a_model_name():
    """(e) Wheel and contact models are named where they register only (interaction/wheel_models.py,
    contact/<model>/__init__.py): no other module compares with, tests membership in or keys
    a dict by a model's name."""
    found = model_name_branches()
    assert not found, "model names outside the registries:\n" + "\n".join(f"{m} (line {n})" for m, n in found)


def test_the_name_check_finds_a_planted_branch(tmp_path):
    # the check can fail: a module that branches on a model's name is found
    import shutil
    for package in PACKAGES:
        (tmp_path / package).mkdir()
    for folder in ("contact/point", "contact/halfspace"):
        (tmp_path / folder).mkdir()
    for registry in ("interaction/wheel_models.py", "contact/registry.py", "contact/point/__init__.py",
                     "contact/halfspace/__init__.py"):
        (tmp_path / registry).write_text((ROOT / registry).read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "stages" / "planted.py").write_text('def f(m):\n    return m == "eulerian"\n', encoding="utf-8")
    (tmp_path / "radiation" / "styles.py").write_text('STYLE = {"moving_load": 1}\n', encoding="utf-8")
    (tmp_path / "stages" / "contact.py").write_text('def g(m):\n    return m in ("point", "x")\n', encoding="utf-8")
    shutil.copy(ROOT / "pipeline.py", tmp_path / "pipeline.py")
    assert sorted(model_name_branches(tmp_path)) == [("radiation.styles", 1), ("stages.contact", 2),
                                                      ("stages.planted", 2)]


#: Largest module of the product, in lines: beyond it a module does more than one job (issue 34).
MAX_MODULE_LINES = 1000


def test_no_module_over_the_size_limit():
    """(f) No module of the product is longer than :data:`MAX_MODULE_LINES` lines."""
    long = {name: n for name, path in module_files().items()
            if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES}
    assert not long, f"modules over {MAX_MODULE_LINES} lines: {long}"
