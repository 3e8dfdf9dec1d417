"""The package's shape: one configuration boundary, one model chain, layers without cycles, and a
rerun hash that follows the actual imports (rail.provenance)."""

import ast
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from rail import contact, provenance
from rail.setup.config import load_yaml
from rail.setup.runtime import one_blas_thread, reporting_only

ROOT = Path(__file__).resolve().parents[1]
RAIL = ROOT / "rail"
SCRIPTS = sorted((ROOT / "workflow/scripts").glob("*.py"))
LAYERS = {"physics": 0, "setup": 1, "studies": 2, "plotting": 3, "app": 4}
# packages of the physics layer (rail/contact/: the contact models; rail/creepage/: dynamic creepage; rail/growth_spectrum/;
# rail/noise/: CNOSSOS-EU rolling noise)
PHYSICS_PACKAGES = {"contact", "creepage", "growth_spectrum", "noise"}


def _layer(path: Path) -> str:
    rel = path.relative_to(RAIL)
    return rel.parts[0] if len(rel.parts) > 1 and rel.parts[0] not in PHYSICS_PACKAGES else "physics"


def _rail_files():
    return sorted(p for p in RAIL.rglob("*.py") if "__pycache__" not in p.parts)


def _physics_reads(source: str) -> list[str]:
    """Reads of the config dict (config[...], cfg[...], config.get) other than its figure settings."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) and node.value.id in ("config", "cfg"):
            key = node.slice.value if isinstance(node.slice, ast.Constant) else None
            if key != "figures":
                out.append(f"{node.lineno}: {ast.unparse(node)}")
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get"
                and isinstance(node.func.value, ast.Name) and node.func.value.id in ("config", "cfg")):
            out.append(f"{node.lineno}: {ast.unparse(node)}")
    return out


def test_no_script_reads_the_configuration_for_a_physics_value():
    # scripts read physics only through rail.setup.build.scenario; from the config dict they may
    # read the figure settings (what a figure shows), nothing else
    offenders = [f"{f.name}:{r}" for f in SCRIPTS for r in _physics_reads(f.read_text())]
    assert not offenders, "scripts read physics from the config dict:\n" + "\n".join(offenders)


def test_the_ast_check_finds_a_physics_read():
    # the check above can fail: the old wear_case script's reads are caught, a figure setting is not
    bad = 'def main(config):\n    rho = float(config["material"]["density"])\n    n = config.get("numerics")\n    s = config["figures"]["wear"]\n'
    assert sorted(_physics_reads(bad)) == ["2: config['material']", "3: config.get('numerics')"]


def _calls(path: Path, names: set[str]) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else None
            if name in names:
                found.add(name)
    return found


def test_the_model_chain_is_written_once():
    # solve_forces -> bay_wear -> run_growth are called together only in rail/chain.py; scripts,
    # studies and benchmarks call the chain
    chain_calls = {"solve_forces", "bay_wear", "run_growth"}
    users = {}
    for f in _rail_files() + SCRIPTS + sorted((ROOT / "tests/benchmarks").glob("*.py")):
        if f.name in ("interaction.py", "wear.py", "growth.py") and f.parent == RAIL:
            continue  # where they are defined
        hit = {c for c in _calls(f, chain_calls)}
        hit_low = {c for c in hit if c != "solve_forces"} | ({"solve_forces"} if _lowlevel_solve(f) else set())
        if hit_low:
            users[str(f.relative_to(ROOT))] = sorted(hit_low)
    assert users == {"rail/chain.py": ["bay_wear", "run_growth", "solve_forces"]}


def _lowlevel_solve(path: Path) -> bool:
    """Whether the file calls interaction.solve_forces (not chain.solve_forces)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "solve_forces":
            if isinstance(node.func.value, ast.Name) and node.func.value.id in ("interaction", "I"):
                return True
    return False


def _imports(path: Path) -> set[Path]:
    """rail files a file imports directly (any import statement, also inside functions)."""
    out = set()
    for name in provenance._imported_names(path, RAIL):
        f = provenance._module_file(name, RAIL)
        if f is not None and f != path:
            out.add(f)
    return out


def test_layers_import_only_downwards_and_without_cycles():
    # physics (rail/*.py) <- setup <- studies <- plotting; plotting draws datasets and imports no
    # physics; the graph of rail's own imports has no cycle
    graph = {f: _imports(f) for f in _rail_files()}
    wrong = []
    for f, deps in graph.items():
        for d in deps:
            if d.name == "__init__.py" and d.parent == RAIL:
                continue
            if LAYERS[_layer(d)] > LAYERS[_layer(f)]:
                wrong.append(f"{f.relative_to(RAIL)} imports {d.relative_to(RAIL)}")
            if _layer(f) == "plotting" and _layer(d) != "plotting":
                wrong.append(f"{f.relative_to(RAIL)} imports {d.relative_to(RAIL)} (plotting takes datasets)")
    assert not wrong, "\n".join(wrong)
    state = {}

    def visit(f, stack):
        state[f] = 1
        for d in graph.get(f, ()):
            if state.get(d) == 1:
                raise AssertionError("import cycle: " + " -> ".join(str(p.relative_to(RAIL)) for p in stack + [f, d]))
            if d not in state:
                visit(d, stack + [f])
        state[f] = 2

    for f in graph:
        if f not in state:
            visit(f, [])


# Private names may cross modules only inside the compiled contact kernels: rail/contact's basis,
# steps, creep, march and tangent share numba functions (and rail.contact re-exports three), and
# rail.kernels compiles them ahead of a run. Everywhere else a name used by another module is public,
# with its docstring, in one home.
PRIVATE_IMPORT_ALLOWED = {"contact": {"contact"}, "kernels.py": {"contact"}}


def _home(path: Path, root: Path = RAIL) -> str:
    """The allow-list's name of a rail file: its package under rail/ or, at the top, its file name."""
    rel = path.relative_to(root)
    return rel.parts[0] if len(rel.parts) > 1 else rel.name


def _private_imports(path: Path, root: Path = RAIL) -> list[str]:
    """Private names (``_name``, not dunder) a rail file or workflow script takes from a rail module
    other than its own: by ``from <rail module> import _name`` or by ``<rail module>._name`` after
    importing the module."""
    inside = path.is_relative_to(root)
    here = provenance._dotted_of(path, root) if inside else ""
    pkg = here.split(".") if path.name == "__init__.py" else here.split(".")[:-1]
    out, modules = [], {}
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level and inside:
                base = pkg[: len(pkg) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            elif (node.module or "").split(".")[0] == "rail":
                mod = node.module
            else:
                continue
            for a in node.names:
                sub = provenance._module_file(f"{mod}.{a.name}", root)
                if sub is not None:  # a module imported by name: its attributes are checked below
                    modules[a.asname or a.name] = sub
                elif a.name.startswith("_") and not a.name.startswith("__"):
                    src = provenance._module_file(mod, root)
                    if src is not None and src != path:
                        out.append((node.lineno, a.name, src))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "rail" and a.asname:
                    modules[a.asname] = provenance._module_file(a.name, root)
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in modules
                and node.attr.startswith("_") and not node.attr.startswith("__") and modules[node.value.id] is not None):
            out.append((node.lineno, node.attr, modules[node.value.id]))
    where = path.relative_to(root) if inside else path.name
    return [f"{where}:{line} takes {name} from {src.relative_to(root)}" for line, name, src in out
            if not inside or _home(src, root) not in PRIVATE_IMPORT_ALLOWED.get(_home(path, root), set())]


def test_no_module_takes_a_private_name_from_another_rail_module():
    # the workflow's scripts are held to the same rule (they are adapters over rail's public API)
    offenders = [o for f in _rail_files() + SCRIPTS for o in _private_imports(f)]
    assert not offenders, "private names crossing modules (make them public in one home):\n" + "\n".join(offenders)


def test_the_private_name_check_finds_an_import_and_an_attribute(tmp_path):
    # the check can fail: a studies module taking a private helper by import or by attribute is caught,
    # the contact kernels sharing theirs are not
    pkg = tmp_path / "rail"
    (pkg / "studies").mkdir(parents=True)
    (pkg / "contact").mkdir()
    for f in ("__init__.py", "studies/__init__.py", "contact/__init__.py", "contact/steps.py"):
        (pkg / f).write_text("")
    (pkg / "track.py").write_text("def _damped():\n    pass\n")
    (pkg / "studies/a.py").write_text("from ..track import _damped\nfrom .. import track\nx = track._damped\n")
    (pkg / "contact/march.py").write_text("from .steps import _advance\n")
    assert _private_imports(pkg / "studies/a.py", pkg) == [
        "studies/a.py:1 takes _damped from track.py", "studies/a.py:3 takes _damped from track.py"]
    assert _private_imports(pkg / "contact/march.py", pkg) == []


# The order inside the physics layer (rail/*.py and rail/contact/): a module imports only modules of
# the groups above its own. The report's chain read from the bottom up; each group with its reason.
PHYSICS_ORDER = [
    ({"provenance", "csvinput", "bands"},
     "tools: the rerun hash, the CSV reader; the one-third-octave bands (IEC 61260-1), "
     "in frequency for the decay rate and in wavelength for the roughness"),
    ({"_lazyjit"}, "the lazy numba decorator, whose cache is marked by the code's hash (rail.provenance's imports)"),
    ({"_linalg"}, "small compiled dense solves (numba, through the lazy decorator)"),
    ({"quadrature", "halfspace"}, "quadrature rules; the elastic half-space and contact-spring damping (report 4.1)"),
    ({"track"}, "the Timoshenko rail on periodic discrete supports (4.2)"),
    ({"cell"}, "supports that vary over a cell of bays, built from track's parts"),
    ({"moving", "decay", "creepage.rail_flexibility"}, "moving-load receptances of a track cell; its EN 15461 decay rate; the rail "
     "head's longitudinal receptances under moving loads (the same Bloch method, on the track alone)"),
    ({"creepage.rail_flexibility_cell"}, "the rail head's longitudinal receptances on a track cell (rail_flexibility's transfers "
     "on the cell's supports)"),
    ({"roughness", "interaction"}, "roughness over N bays; wheel/rail forces on it (4.3), through the moving receptances"),
    ({"creepage", "creepage.modes"}, "longitudinal modes in the slip, which the contact's march carries (the package's "
     "docstring imports nothing)"),
    ({"contact"}, "normal and tangential contact (4.4), along the force histories"),
    ({"creepage.wheelset", "creepage.coupling", "creepage.choices"}, "the wheelset's modes; u_bar coupled with the contact's "
     "march; the sources of dynamic creepage as model choices"),
    ({"wear", "growth"}, "frictional-work wear (4.5); growth over passages (4.6)"),
    ({"scenario"}, "one scenario: every input of the chain as one frozen object"),
    ({"chain"}, "the model chain, written once"),
    ({"growth_spectrum"}, "growth rate over wavelength, each line a run of the chain"),
    ({"fleet"}, "a fleet of vehicle classes, each a scenario"),
    ({"traffic", "uncertainty"}, "growth under a mix of traffic; a seeded ensemble of uncertain inputs"),
    ({"kernels"}, "compiles the contact kernels ahead of a run"),
    ({"noise"}, "rolling noise by CNOSSOS-EU from the roughness (Directive 2002/49/EC Annex II 2.3), on the bands alone"),
]


SPLIT_PACKAGES = {"creepage"}  # packages whose modules sit at their own places in PHYSICS_ORDER (creepage.<module>)


def _physics_name(path: Path) -> str:
    rel = path.relative_to(RAIL)
    if len(rel.parts) > 1 and rel.parts[0] in SPLIT_PACKAGES:
        return f"{rel.parts[0]}.{rel.stem}" if rel.stem != "__init__" else rel.parts[0]
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _physics_order_problems(graph: dict, order: list) -> list[str]:
    rank = {name: i for i, (names, _) in enumerate(order) for name in names}
    problems = []
    for f, deps in graph.items():
        if _layer(f) != "physics" or f == RAIL / "__init__.py":
            continue
        me = _physics_name(f)
        if me not in rank:
            problems.append(f"{f.relative_to(RAIL)} is in no group of PHYSICS_ORDER")
            continue
        for d in deps:
            them = _physics_name(d)
            if _layer(d) != "physics" or d == RAIL / "__init__.py" or them == me:
                continue
            if rank.get(them, len(order)) >= rank[me]:
                problems.append(f"{f.relative_to(RAIL)} imports {d.relative_to(RAIL)}, not above it in PHYSICS_ORDER")
    return problems


def test_physics_modules_import_only_modules_above_them_in_the_report_order():
    graph = {f: _imports(f) for f in _rail_files()}
    problems = _physics_order_problems(graph, PHYSICS_ORDER)
    assert not problems, "\n".join(problems)


def test_the_physics_order_check_finds_an_import_upwards():
    # the check can fail: the track made to import the wear model, or a module left out of the order
    graph = {f: _imports(f) for f in _rail_files()}
    graph[RAIL / "track.py"] = graph[RAIL / "track.py"] | {RAIL / "wear.py"}
    assert _physics_order_problems(graph, PHYSICS_ORDER) == ["track.py imports wear.py, not above it in PHYSICS_ORDER"]
    without_decay = [(names - {"decay"}, why) for names, why in PHYSICS_ORDER]
    assert _physics_order_problems({RAIL / "decay.py": set()}, without_decay) == ["decay.py is in no group of PHYSICS_ORDER"]


def test_contact_nodes_are_bounded_in_one_place():
    schema = load_yaml(ROOT / "config/schema/config.schema.yaml")
    nodes = schema["properties"]["numerics"]["properties"]["contact"]["properties"]["nodes"]
    assert nodes["minimum"] == contact.MIN_NODES
    with pytest.raises(ValueError, match=rf"numerics\.contact\.nodes = 10 is not allowed: it must be an integer >= {contact.MIN_NODES}"):
        contact.ContactNumerics(10, "default", 1.0, "report", "wheel")


def test_every_rule_with_a_script_hashes_that_scripts_imports():
    missing = []
    for smk in sorted((ROOT / "workflow/rules").glob("*.smk")):
        for block in re.split(r"(?m)^(?=rule )", smk.read_text()):
            m = re.search(r'script:\s*\n\s*"\.\./scripts/(\w+\.py)"', block)
            if m and f'code=code("{m.group(1)}")' not in block:
                missing.append(f"{smk.name}: {block.splitlines()[0]}")
    assert not missing, "rules without code=code(<their script>):\n" + "\n".join(missing)


def _unmeasured_rules(text: str) -> list[str]:
    """Rules of a .smk text that run a script or shell without a benchmark file (peak memory,
    max_rss) or without mem_mb; and benchmark files whose wildcards differ from the log's (two jobs
    would write one file). A `use rule ... with:` that changes the log must change the benchmark."""
    problems = []
    for block in re.split(r"(?m)^(?=rule |use rule )", text):
        head = block.splitlines()[0].rstrip(":") if block.strip() else ""
        runs = re.search(r"(?m)^    (script|shell|run|notebook|wrapper):", block)
        log = re.search(r'(?m)^    log:\n\s+"([^"]+)"', block)
        bench = re.search(r'(?m)^    benchmark:\n\s+"([^"]+)"', block)
        if head.startswith("rule ") and runs:
            if not bench:
                problems.append(f"{head}: no benchmark")
            if not re.search(r"(?m)^    resources:\n(\s{8}.*\n)*?\s{8}mem_mb=", block):
                problems.append(f"{head}: no resources mem_mb")
        if head.startswith("use rule ") and log and not bench:
            problems.append(f"{head}: changes the log, not the benchmark")
        if bench and log and set(re.findall(r"{(\w+)", bench.group(1))) != set(re.findall(r"{(\w+)", log.group(1))):
            problems.append(f"{head}: benchmark {bench.group(1)} and log {log.group(1)} differ in wildcards")
        if bench and not re.fullmatch(r"benchmarks/.+\.tsv", bench.group(1)):
            problems.append(f"{head}: benchmark {bench.group(1)} not benchmarks/...tsv")
    return problems


def test_every_rule_with_a_script_records_its_peak_memory_and_declares_mem_mb():
    # issue 33: each job's peak memory (max_rss) in its benchmark file, and a measured mem_mb for
    # the SLURM profile (README, "Memory per job")
    problems = [f"{smk.name}: {p}" for smk in sorted((ROOT / "workflow/rules").glob("*.smk")) for p in _unmeasured_rules(smk.read_text())]
    assert not problems, "\n".join(problems)


def test_the_memory_check_finds_a_rule_without_benchmark_or_mem_mb():
    good = ('rule a:\n    output:\n        "results/{x}.nc",\n    log:\n        "logs/a/{x}.log",\n'
            '    benchmark:\n        "benchmarks/a/{x}.tsv"\n    resources:\n        mem_mb=300,\n        runtime=5,\n'
            '    script:\n        "../scripts/a.py"\n')
    assert _unmeasured_rules(good) == []
    assert _unmeasured_rules(good.replace('    benchmark:\n        "benchmarks/a/{x}.tsv"\n', "")) == ["rule a: no benchmark"]
    assert _unmeasured_rules(good.replace("        mem_mb=300,\n", "")) == ["rule a: no resources mem_mb"]
    assert _unmeasured_rules(good.replace("benchmarks/a/{x}.tsv", "benchmarks/a.tsv")) == [
        "rule a: benchmark benchmarks/a.tsv and log logs/a/{x}.log differ in wildcards"]
    assert _unmeasured_rules('use rule a as b with:\n    log:\n        "logs/b/{y}.log",\n') == [
        "use rule a as b with: changes the log, not the benchmark"]
    # a named target without a script needs neither
    assert _unmeasured_rules('rule all:\n    input:\n        "results/x.nc",\n') == []


def test_rerun_hash_follows_the_imports_in_a_changed_copy(tmp_path):
    # a copy of the package: changing a plotting module changes the hash of the scripts that draw
    # with it and not that of the growth script; changing a physics module two imports deep
    # (quadrature, imported by track and moving) changes the growth script's hash
    pkg = tmp_path / "rail"
    shutil.copytree(RAIL, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    scripts = tmp_path / "scripts"
    shutil.copytree(ROOT / "workflow/scripts", scripts)
    names = ("growth.py", "growth_figure.py", "track_receptance.py", "halfspace_figure.py")

    def hashes():
        return {s: provenance.code_hash(scripts / s, pkg) for s in names}

    before = hashes()
    assert before["growth.py"] != before["growth_figure.py"]  # plotting is not among the growth script's imports
    with (pkg / "plotting/report.py").open("a") as fh:
        fh.write("\n# changed\n")
    after = hashes()
    assert after["growth.py"] == before["growth.py"] and after["track_receptance.py"] == before["track_receptance.py"]
    assert after["growth_figure.py"] != before["growth_figure.py"] and after["halfspace_figure.py"] != before["halfspace_figure.py"]
    with (pkg / "quadrature.py").open("a") as fh:
        fh.write("\n# changed\n")
    assert hashes()["growth.py"] != after["growth.py"]
    # a new import is followed: the growth script made to import the plotting module
    s = (scripts / "growth.py").read_text().replace("from rail import chain", "from rail import chain\nfrom rail.plotting import track")
    (scripts / "growth.py").write_text(s)
    assert pkg / "plotting/track.py" in provenance.rail_imports(scripts / "growth.py", pkg)


def test_rerun_hash_follows_the_schemas_defaults(tmp_path):
    # the defaults of optional keys live in the schema (rail.setup.config.setting): changing one
    # changes the hash of the scripts that build a scenario; changing a description does not
    pkg = tmp_path / "rail"
    shutil.copytree(RAIL, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    (tmp_path / "config/schema").mkdir(parents=True)
    schema = tmp_path / "config/schema/config.schema.yaml"
    text = (ROOT / "config/schema/config.schema.yaml").read_text()
    schema.write_text(text)
    script = ROOT / "workflow/scripts/growth.py"
    before = provenance.code_hash(script, pkg)
    schema.write_text(text.replace("Omit it for identical supports", "Leave it out for identical supports"))
    assert provenance.code_hash(script, pkg) == before
    assert "unit: m/s, default: 0, description" in text
    schema.write_text(text.replace("unit: m/s, default: 0, description", "unit: m/s, default: 0.1, description"))
    assert provenance.code_hash(script, pkg) != before


# A documented parameter or return of one of these types is a number or an array of numbers: a quantity whose unit
# the docstring must state (the lighter rule of the layers above the physics)
NUMERIC_TYPE = re.compile(r"\b(float|complex|number|ndarray|array|array_like|array-like)s?\b")


def _numeric_entries(doc: str) -> list[str]:
    """Names of the Parameters and Returns entries of a numpydoc docstring whose type is numeric (NUMERIC_TYPE)."""
    from numpydoc.docscrape import NumpyDocString

    try:
        parsed = NumpyDocString(doc)
    except Exception:  # not parseable: the Sphinx build (tests/test_docs.py, -W) says why
        return []
    return [p.name or p.type for section in ("Parameters", "Returns") for p in parsed[section] if NUMERIC_TYPE.search(p.type)]


def _docstring_problems(files, units: str = "always") -> list[str]:
    """Public functions of the files whose docstring lacks numpydoc Parameters or Returns, or a unit in brackets:
    in every function (``units="always"``, the physics layer), or (``units="quantities"``) in a function one of
    whose documented parameters or returns is a number or an array (NUMERIC_TYPE)."""
    unitless = {"single_wheel", "damping_problem", "data_rows"}  # take and give only objects or text
    problems = []
    for f in files:
        name = f.relative_to(RAIL) if f.is_relative_to(RAIL) else f.name
        for node in ast.parse(f.read_text()).body:
            if not isinstance(node, ast.FunctionDef) or node.name.startswith("_"):
                continue
            d = ast.get_docstring(node) or ""
            args = [a.arg for a in node.args.args + node.args.kwonlyargs]
            if args and "Parameters\n----------" not in d:
                problems.append(f"{name}: {node.name} has no Parameters section")
            if "Returns\n-------" not in d:
                problems.append(f"{name}: {node.name} has no Returns section")
            needs_unit = node.name not in unitless if units == "always" else bool(_numeric_entries(d))
            if needs_unit and not re.search(r"\[[^\]]*\]", d):
                problems.append(f"{name}: {node.name} states no unit in brackets")
    return problems


def _physics_files():
    """Every module of the physics layer: rail/*.py and the physics packages (PHYSICS_PACKAGES, any depth)."""
    return [f for f in _rail_files() if _layer(f) == "physics" and f.name != "provenance.py"]  # provenance: the rerun hash, no physics


def test_public_physics_functions_have_numpydoc_docstrings_with_units():
    # every public function of the physics layer states its parameters and returns (numpydoc),
    # with units in brackets: the modules of rail/ and of its physics packages (issue 57: the rule
    # globbed rail/*.py, and 19 functions of rail/contact and rail/growth_spectrum escaped it)
    files = _physics_files()
    assert {f.parent.name for f in files} >= {"rail", *PHYSICS_PACKAGES}
    problems = _docstring_problems(files)
    assert not problems, "\n".join(problems)


def test_public_functions_of_every_other_package_have_numpydoc_docstrings_with_units_of_their_quantities():
    # issue 54: "the docstring rule covers every package in rail/, not only the top level". The packages above the
    # physics (rail/setup, rail/studies, rail/plotting, rail/app) take and give configurations, datasets, figures,
    # paths and text as much as numbers: each public function states its parameters and returns (numpydoc), and
    # a function with a parameter or a return that is a number or an array (float, complex, ndarray, ...) states
    # its unit in brackets ([m], [Hz], [-]). A function of text, paths, mappings and objects alone needs none,
    # where the physics rule would ask for a bracket that says nothing.
    files = [f for f in _rail_files() if _layer(f) != "physics"]
    assert {f.parent.name for f in files} == {"setup", "studies", "plotting", "app"}
    problems = _docstring_problems(files, units="quantities")
    assert not problems, "\n".join(problems)


def test_the_docstring_rule_finds_a_function_of_a_physics_package_without_one(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "m.py").write_text('def rate(x):\n    """A rate."""\n    return x\n\n\ndef _helper(x):\n    return x\n')
    assert _docstring_problems([pkg / "m.py"]) == ["m.py: rate has no Parameters section", "m.py: rate has no Returns section",
                                                   "m.py: rate states no unit in brackets"]


def test_the_lighter_rule_asks_a_unit_only_of_a_function_of_numbers(tmp_path):
    returns = "\n    Returns\n    -------\n    str\n    \"\"\"\n"
    (tmp_path / "m.py").write_text(
        'def label(name):\n    """A label.\n\n    Parameters\n    ----------\n    name : str\n' + returns
        + '\n\ndef speed(v):\n    """A speed.\n\n    Parameters\n    ----------\n    v : float\n        Speed.\n' + returns
        + '\n\ndef table(v):\n    """A table.\n\n    Returns\n    -------\n    ndarray\n    """\n')
    assert _docstring_problems([tmp_path / "m.py"], units="quantities") == [
        "m.py: speed states no unit in brackets", "m.py: table has no Parameters section", "m.py: table states no unit in brackets"]


def test_workflow_scripts_read_intermediate_netcdf_files_only_through_open_intermediate():
    # issue 32: a truncated intermediate file is moved aside (and rebuilt by the next run) only when it
    # is read through rail.setup.io.open_intermediate
    offenders = [f"{p.name}:{n}" for p in SCRIPTS for n, line in enumerate(p.read_text().splitlines(), 1)
                 if re.search(r"\b(open_dataset|load_dataset|open_mfdataset|open_dataarray|netCDF4\.Dataset)\(", line)]
    assert not offenders, "scripts open netCDF files directly:\n" + "\n".join(offenders)


def test_jobs_run_one_blas_thread_unless_the_caller_says_otherwise():
    # issue 33: with the BLAS libraries' default of a thread per core, two jobs on two cores ran four
    # busy-waiting threads (a 400-point Gauss rule cost 1.7 s CPU instead of 0.03 s). The Snakefile
    # sets the variables (rail.setup.runtime.one_blas_thread) before its first include imports numpy,
    # and importing that module imports no numpy; jobs inherit them.
    text = (ROOT / "Snakefile").read_text()
    first_include = text.index("\ninclude:")
    assert re.search(r"(?m)^one_blas_thread\(os\.environ\)$", text[:first_include])
    env = {"OMP_NUM_THREADS": "4"}
    assert one_blas_thread(env) == {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "4", "MKL_NUM_THREADS": "1"} == env
    probe = "import sys, rail.setup.runtime; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT, check=True,
                         env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert out.stdout.strip() == "False"


def test_report_alone_is_told_from_a_run_that_reports_after():
    # `snakemake --report report.html` reports what is built (default target report_all); with
    # --report-after-run the run builds the figure set first
    assert reporting_only(["snakemake", "--report", "report.html"])
    assert reporting_only(["snakemake", "--report=report.html"])
    assert not reporting_only(["snakemake", "--report", "report.html", "--report-after-run"])
    assert not reporting_only(["snakemake", "-j2", "--report-stylesheet", "s.css"])
    assert not reporting_only(["snakemake", "-j2"])


# Each model choice's family (issue 54: one home): its names, the configuration's values (the schema's
# enum, or rail.contact.FRICTION_LAWS for the friction law, which no key names), and its home, the only
# files that may compare them. Elsewhere a module asks the choice's object (rail.scenario.ModelChoices:
# ``path.modelled_shift``, ``wheelset.modelled``, ``flexibility.bending``, ``law.falling``) or looks a stored
# value up (rail.contact.wear_path, rail.creepage.choices.wheelset_model), never compares the name.
# The dynamic-creepage family's homes are listed file by file until it is gathered into one package.
MODEL_FAMILIES = {
    "contact.normal": ("contact/",),
    "contact.wear_path": ("contact/",),
    "wheelset.model": ("creepage/",),
    "rail_flexibility.model": ("creepage/",),
    "friction law": ("contact/",),
}
# a comparison is of a family's name only where its other side speaks of that choice (not, say,
# contact.closure == 'report', a roughness kind or contact.loss_factor_model == 'constant')
_CHOICE_WORDS = {"contact.normal": re.compile(r"normal"), "contact.wear_path": re.compile(r"path|wear"),
                 "wheelset.model": re.compile(r"wheelset|model|\bws\b"), "rail_flexibility.model": re.compile(r"flex|model|\brf\b|head"),
                 "friction law": re.compile(r"friction|law")}


def _model_names(schema: dict) -> dict:
    """family -> the set of its names, from the schema's enums (and the friction laws from rail.contact)."""
    props = schema["properties"]
    names = {key: set(props[key.split(".")[0]]["properties"][key.split(".")[1]]["enum"]) for key in MODEL_FAMILIES if "." in key}
    names["friction law"] = set(contact.FRICTION_LAWS)
    return names


def _strings(node) -> list:
    """The string constants of a node: itself, or the items of a tuple, list or set of them."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [v for e in node.elts for v in _strings(e)]
    return []


def _model_name_comparisons(root: Path, names: dict, homes: dict = MODEL_FAMILIES) -> list[str]:
    """Every comparison (==, !=, in, not in, startswith) of a model choice's name outside its family's home,
    in rail/ and workflow/scripts/ under ``root``, as 'path:line: family: code'."""
    files = sorted(p for p in (root / "rail").rglob("*.py") if "__pycache__" not in p.parts)
    files += sorted((root / "workflow/scripts").glob("*.py"))
    out = []
    for f in files:
        rel = f.relative_to(root).as_posix()
        inside = rel[len("rail/"):] if rel.startswith("rail/") else None
        for n in ast.walk(ast.parse(f.read_text())):
            if isinstance(n, ast.Compare) and all(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in n.ops):
                sides = [n.left, *n.comparators]
            elif isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "startswith":
                sides = [n.func.value, *n.args]
            else:
                continue
            consts = {v for s in sides for v in _strings(s)}
            other = " ".join(ast.unparse(s) for s in sides if not _strings(s))
            for family, home in homes.items():
                if (consts & names[family] and _CHOICE_WORDS[family].search(other)
                        and not (inside is not None and inside.startswith(home))):
                    out.append(f"{rel}:{n.lineno}: {family}: {ast.unparse(n)}")
    return out


def test_no_module_outside_a_models_package_compares_its_name():
    # issue 54: the wear path, the normal contact, the creepage sources and the friction law are objects
    # that know their behaviour; their names are compared in their own package only
    names = _model_names(load_yaml(ROOT / "config/schema/config.schema.yaml"))
    offenders = _model_name_comparisons(ROOT, names)
    assert not offenders, "model names compared outside their package:\n" + "\n".join(offenders)


def test_the_model_name_check_finds_a_comparison_of_each_kind(tmp_path):
    # the check can fail: a wear path compared by ==, a rail flexibility by `in`, a stored value by startswith
    # and a wheelset model by != in a script; a closure 'report' and the same names inside their home pass
    names = _model_names(load_yaml(ROOT / "config/schema/config.schema.yaml"))
    (tmp_path / "rail/studies").mkdir(parents=True)
    (tmp_path / "rail/contact").mkdir()
    (tmp_path / "workflow/scripts").mkdir(parents=True)
    (tmp_path / "rail/studies/a.py").write_text(
        'ok = scn.contact_numerics.path == "patch"\nrod = flex in ("rod", "rod_and_bending")\n'
        'old = str(attrs["wear_path"]).startswith("wheel")\nclosure = c.closure == "report"\n')
    (tmp_path / "rail/contact/passage.py").write_text('own = numerics.path == "patch"\n')
    (tmp_path / "workflow/scripts/s.py").write_text('motored = cfg["wheelset"]["model"] != "fixed_creepage"\n')
    found = _model_name_comparisons(tmp_path, names)
    assert [line.split(": ")[0] + ": " + line.split(": ")[1] for line in found] == [
        "rail/studies/a.py:1: contact.wear_path", "rail/studies/a.py:2: rail_flexibility.model", "rail/studies/a.py:3: contact.wear_path",
        "workflow/scripts/s.py:1: wheelset.model"]
