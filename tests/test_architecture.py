"""The layers of docs/architecture.md, checked on the source (ast): no module imports another
module's underscore name, nothing outside jaxdamp/cli imports argparse, the library never imports
upward (core -> baselines/paper -> plotting -> cli -> jaxdamp_optimize), and the import graph has no
cycle. Also: importing jaxdamp changes no JAX configuration and imports no matplotlib, and nothing
imports the optimiser by its folder's name (`optimize/` installs as `jaxdamp_optimize`)."""

import ast
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# Package name -> its folder: the optimiser's folder optimize/ installs as jaxdamp_optimize
# (pyproject.toml's package-dir), so its modules are named jaxdamp_optimize.* here.
FOLDERS = {"jaxdamp": "jaxdamp", "jaxdamp_optimize": "optimize"}
PACKAGES = tuple(FOLDERS)
# Layer of each part; an import may only point to the same or a lower layer.
LAYERS = {"core": 0, "baselines": 1, "paper": 1, "modal_file": 1, "plotting": 2, "cli": 3, "jaxdamp_optimize": 4}


def modules():
    for pkg, folder in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT / folder).with_suffix("")
            parts = [pkg, *rel.parts]
            if parts[-1] == "__init__":
                parts = parts[:-1]
            yield ".".join(parts), path


def layer(module: str) -> int:
    parts = module.split(".")
    if parts[0] == "jaxdamp_optimize":
        return LAYERS["jaxdamp_optimize"]
    if len(parts) > 1 and parts[1] in LAYERS:
        return LAYERS[parts[1]]
    return LAYERS["core"]


def imports(module: str, path: Path):
    """(imported module, imported names) for every import statement, relative ones resolved."""
    tree = ast.parse(path.read_text())
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, []
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                pkg = package.split(".")
                pkg = pkg[: len(pkg) - node.level + 1]
                base = ".".join(pkg + ([base] if base else []))
            yield base, [a.name for a in node.names]


def own(target: str) -> bool:
    return target.split(".")[0] in PACKAGES


def test_no_module_imports_another_modules_underscore_name():
    """Private functions, classes and constants stay in their module. A package's private helper
    modules (`jaxdamp._validate`, `jaxdamp.cli.common`) may be imported inside that package."""
    known = {m for m, _ in modules()}
    bad = []
    for module, path in modules():
        for target, names in imports(module, path):
            if not own(target) or target == module:
                continue
            parent = target.rpartition(".")[0]
            inside = module == parent or module.startswith(parent + ".")
            if target.rpartition(".")[2].startswith("_") and not inside:
                bad.append(f"{module}: import of the private module {target}")
            bad += [f"{module}: from {target} import {n}" for n in names
                    if n.startswith("_") and not n.startswith("__")
                    and f"{target}.{n}" not in known]
    assert not bad, "\n".join(bad)


NAMEDTUPLE_API = {"_fields", "_replace", "_asdict", "_make", "_field_defaults"}  # public, "_" or not


def test_tests_use_no_private_name_of_the_project():
    """Tests check what users can call: no `from jaxdamp.x import _y`, and no `m._y` on a name
    bound to one of the project's modules (`from jaxdamp import batch as B; B._COMPILED`)."""
    bad = []
    for path in sorted((ROOT / "tests").glob("*.py")):
        tree = ast.parse(path.read_text())
        modules_bound = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and own(node.module or ""):
                bad += [f"{path.name}: from {node.module} import {a.name}" for a in node.names
                        if a.name.startswith("_") and not a.name.startswith("__")]
                modules_bound |= {a.asname or a.name for a in node.names}
            elif isinstance(node, ast.Import):
                modules_bound |= {(a.asname or a.name).split(".")[0] for a in node.names
                                  if own(a.name)}
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                    and not node.attr.startswith("__") and node.attr not in NAMEDTUPLE_API
                    and isinstance(node.value, ast.Name)
                    and node.value.id in modules_bound):
                bad.append(f"{path.name}:{node.lineno}: {node.value.id}.{node.attr}")
    assert not bad, "\n".join(bad)


def test_few_imports_inside_functions_each_with_its_reason():
    """A core module's imports (jaxdamp/*.py and the core's subpackages response/ and fit/) sit at
    its top, where a reader finds them; at most 9 inside functions (an import measured to cost
    `import jaxdamp` time, such as optimistix for the loop fit), each under a comment."""
    inside = []
    core = [*(ROOT / "jaxdamp").glob("*.py"), *(ROOT / "jaxdamp" / "response").glob("*.py"),
            *(ROOT / "jaxdamp" / "fit").glob("*.py")]
    for path in sorted(core):
        lines = path.read_text().splitlines()
        for fn in ast.walk(ast.parse(path.read_text())):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                inside += [(path.name, node.lineno, lines[node.lineno - 2].strip())
                           for node in ast.walk(fn) if isinstance(node, (ast.Import, ast.ImportFrom))]
    assert len(inside) <= 9, inside
    assert all(above.startswith("#") for _, _, above in inside), inside


def test_modules_stay_small_or_say_why():
    """No module over 500 lines unless docs/architecture.md's "Module size" table names it and
    says why; none over 600; the table's line counts are today's."""
    import re

    doc = (ROOT / "docs" / "architecture.md").read_text()
    listed = {m: int(n) for m, n in re.findall(r"^\| `((?:jaxdamp|optimize)/[\w/]+\.py)` \| (\d+) \|",
                                               doc, re.M)}
    bad = []
    for folder in FOLDERS.values():
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel, n = path.relative_to(ROOT).as_posix(), len(path.read_text().splitlines())
            if n > 600 or (n > 500 and rel not in listed) or listed.get(rel, n) != n:
                bad.append(f"{rel}: {n} lines (listed: {listed.get(rel)})")
    assert not bad, "\n".join(bad)


def test_every_import_of_the_project_resolves():
    """Every import of a project module names something that exists, at module level or inside a
    function: a lazy import runs only in the tests that reach it, so a moved name can hide there
    (plotting/amplitude.py's, after amplitude_curves moved to curves.py)."""
    import importlib
    import importlib.util

    bad = []
    for module, path in modules():
        for target, names in imports(module, path):
            if not own(target):
                continue
            try:
                found = importlib.import_module(target)
            except ImportError as exc:
                bad.append(f"{module}: {target}: {exc}")
                continue
            submodule = lambda n: (hasattr(found, "__path__")  # noqa: E731  (a package's module)
                                   and importlib.util.find_spec(f"{target}.{n}") is not None)
            bad += [f"{module}: from {target} import {n}" for n in names
                    if not hasattr(found, n) and not submodule(n)]
    assert not bad, "\n".join(bad)


def test_argparse_only_in_cli():
    bad = [module for module, path in modules()
           if not module.startswith(("jaxdamp.cli", "jaxdamp_optimize.cli"))
           and any(t == "argparse" for t, _ in imports(module, path))]
    assert not bad, bad


def test_no_import_points_up_a_layer():
    bad = []
    for module, path in modules():
        if module == "jaxdamp":  # the facade re-exports the core only (checked below)
            continue
        for target, names in imports(module, path):
            if not own(target):
                continue
            targets = [target] + [f"{target}.{n}" for n in names]
            for t in targets:
                known = any(t == m for m, _ in modules())
                if known and layer(t) > layer(module):
                    bad.append(f"{module} -> {t}")
    assert not bad, "\n".join(bad)


def test_facade_reexports_the_core_only():
    path = ROOT / "jaxdamp" / "__init__.py"
    for target, _ in imports("jaxdamp", path):
        if own(target):
            assert layer(target) == LAYERS["core"], target


def test_import_graph_has_no_cycle():
    names = {m for m, _ in modules()}
    graph = {}
    for module, path in modules():
        deps = set()
        for target, imported in imports(module, path):
            for t in [target] + [f"{target}.{n}" for n in imported]:
                if t in names and t != module:
                    deps.add(t)
        # A package's __init__ is imported with any of its submodules: not a dependency edge back.
        graph[module] = {d for d in deps if not module.startswith(d + ".")}
    state = {}

    def visit(node, stack):
        state[node] = 1
        for nxt in graph[node]:
            if state.get(nxt) == 1:
                raise AssertionError("cycle: " + " -> ".join(stack + [node, nxt]))
            if not state.get(nxt):
                visit(nxt, stack + [node])
        state[node] = 2

    for node in graph:
        if not state.get(node):
            visit(node, [])


def test_import_jaxdamp_is_side_effect_free():
    code = """
import json, sys
import jax
before = {k: getattr(jax.config, k) for k in ("jax_enable_x64", "jax_numpy_rank_promotion",
                                               "jax_compilation_cache_dir")}
import jaxdamp, jaxdamp.baselines, jaxdamp.paper
after = {k: getattr(jax.config, k) for k in before}
print(json.dumps({"same": before == after, "mpl": "matplotlib" in sys.modules,
                  "backend_started": jax._src.xla_bridge._backends != {}}))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    res = json.loads(out.stdout)
    assert res == {"same": True, "mpl": False, "backend_started": False}, res


def test_float32_is_refused_with_instructions():
    code = """
import jaxdamp as jd
try:
    jd.base_cycle(jd.family_shape("60sym"), 0.5)
except jd.Float64Required as exc:
    print("refused:", exc)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.startswith("refused:") and "enable_x64" in out.stdout


# The public surfaces other layers on top may use: the package's top level and its public
# subpackages. optimize/ and benchmarks/ use only these (docs/architecture.md).
PUBLIC = {"jaxdamp", "jaxdamp.blocks", "jaxdamp.baselines", "jaxdamp.paper", "jaxdamp.plotting",
          "jaxdamp.cli", "jaxdamp.modal_file"}
# Benchmarks that measure an internal choice import the module that makes it: the solve forms
# (linalg, tract, cycle, and choice, whose `candidate_rates` bench_core.py swaps for the variants
# it times), the compiler options (runtime), the two-stage batching (batch) and the Jacobian
# programs (gradients). Nothing in optimize/ may.
MEASURED_INTERNALS = {"jaxdamp.linalg", "jaxdamp.runtime", "jaxdamp.tract", "jaxdamp.cycle",
                      "jaxdamp.choice", "jaxdamp.batch", "jaxdamp.gradients", "jaxdamp.amplitude",
                      "jaxdamp.curves", "jaxdamp.sequence", "jaxdamp.band"}


def _public(target: str) -> bool:
    """jaxdamp's top level, or a module of one of its public subpackages."""
    return target in PUBLIC or target.rpartition(".")[0] in PUBLIC - {"jaxdamp"}


def _scripts(folder):
    for path in sorted((ROOT / folder).glob("*.py")):
        yield f"{folder}.{path.stem}", path


def test_optimize_and_benchmarks_use_the_public_api_only():
    bad = []
    for module, path in [*((m, p) for m, p in modules() if m.startswith("jaxdamp_optimize")),
                         *_scripts("benchmarks")]:
        for target, _ in imports(module, path):
            internal = module.startswith("benchmarks") and target in MEASURED_INTERNALS
            if target.split(".")[0] == "jaxdamp" and not (_public(target) or internal):
                bad.append(f"{module}: imports {target}")
            if target.startswith("jax._src"):
                bad.append(f"{module}: imports JAX's private {target}")
    assert not bad, "\n".join(bad)


def test_every_module_says_what_it_exports():
    """Every library module has __all__, and every name in it exists; jaxdamp's __all__ holds
    everything a user or optimize/ imports from it, so help(jaxdamp) lists the whole API."""
    import importlib.util

    bad = []
    for module, path in modules():
        if path.name == "__main__.py":
            continue
        mod = importlib.import_module(module)
        names = getattr(mod, "__all__", None)
        if names is None:
            bad.append(f"{module}: no __all__")
            continue
        bad += [f"{module}.__all__ names a missing {n}" for n in names if not hasattr(mod, n)]
    import jaxdamp

    used = {n for module, path in [*modules(), *_scripts("benchmarks")]
            if not module.startswith("jaxdamp")
            for target, names in imports(module, path) if target == "jaxdamp" for n in names
            if importlib.util.find_spec(f"jaxdamp.{n}") is None}  # a submodule is not an API name
    bad += [f"jaxdamp.__all__ lacks {n}, which optimize/ or benchmarks/ import" for n in
            sorted(used - set(jaxdamp.__all__))]
    assert not bad, "\n".join(bad)


def _imports_of_source(text: str):
    """The top-level names imported by a piece of Python source (empty when it does not parse,
    e.g. a notebook cell with shell magics)."""
    try:
        tree = ast.parse(text)
    except SyntaxError:
        return set()
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            names.add(node.module.split(".")[0])
    return names


def test_nothing_imports_the_optimiser_by_its_folder_name():
    """The wheel installs the optimiser as `jaxdamp_optimize` and no top-level `optimize`: from the
    repository root a plain `import optimize` would still work, so tests, scripts, benchmarks, the
    notebooks' code cells and the docs' Python blocks are checked here."""
    import re

    sources = []
    for folder in ("tests", "scripts", "benchmarks", "optimize", "jaxdamp"):
        sources += [(str(p.relative_to(ROOT)), p.read_text()) for p in sorted((ROOT / folder).rglob("*.py"))]
    for nb in sorted((ROOT / "notebooks").glob("*.ipynb")):
        for k, cell in enumerate(json.loads(nb.read_text())["cells"]):
            if cell["cell_type"] == "code":
                src = cell["source"]
                sources.append((f"{nb.name} cell {k}", "".join(src) if isinstance(src, list) else src))
    fence = re.compile(r"^```python[^\n]*\n(.*?)^```", re.S | re.M)
    for md in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        sources += [(str(md.relative_to(ROOT)), m.group(1)) for m in fence.finditer(md.read_text())]
    assert len(sources) > 100
    bad = [where for where, text in sources if "optimize" in _imports_of_source(text)]
    assert bad == []
    # the positive case: the optimiser's users do import it under its package name
    assert any("jaxdamp_optimize" in _imports_of_source(text) for _, text in sources)


def test_every_module_is_in_the_docs_and_has_its_tests():
    """docs/architecture.md's promises, held: its core table lists every core module, and every
    module has tests/test_<module>.py (test_<package>_<module>.py, test_optimize_<module>.py) or a
    row of the coverage table naming test files that exist."""
    import re

    doc = (ROOT / "docs" / "architecture.md").read_text()
    core_section = doc.split("## The core", 1)[1].split("\n## ", 1)[0]
    core_table = set(re.findall(r"^\| `(\w+\.py)` \|", core_section, re.M))
    coverage = dict(re.findall(r"^\| `((?:jaxdamp|optimize)/[\w/]+\.py)` \| (.+?) \|$", doc, re.M))
    tests = {p.name for p in (ROOT / "tests").glob("test_*.py")}
    bad = [f"the core table lacks jaxdamp/{p.name}" for p in sorted((ROOT / "jaxdamp").glob("*.py"))
           if p.name != "__init__.py" and p.name not in core_table]
    for folder in FOLDERS.values():
        for path in sorted((ROOT / folder).rglob("*.py")):
            if path.name in ("__init__.py", "__main__.py"):
                continue
            rel = path.relative_to(ROOT)
            parts = rel.with_suffix("").parts
            names = {f"test_{parts[-1]}.py", f"test_{'_'.join(parts[1:])}.py",
                     f"test_{'_'.join(parts)}.py"}
            if names & tests:
                continue
            named = re.findall(r"`(tests/\w+\.py)`", coverage.get(rel.as_posix(), ""))
            if not named:
                bad.append(f"{rel}: no {' / '.join(sorted(names))} and no coverage row")
            bad += [f"{rel}: its coverage row names {f}, which does not exist" for f in named
                    if not (ROOT / f).exists()]
    assert not bad, "\n".join(bad)
