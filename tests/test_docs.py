"""The documentation: the README's front page and the Sphinx site built from docs/ and the
docstrings (docs/conf.py).

The site is built as from a clean checkout (docs/ copied without its build output and generated
API stubs) with warnings as errors, and its inventory (objects.inv) must hold every public
function and class of rail.app and of every other module of rail/, found by introspection."""

import importlib
import inspect
import pkgutil
import re
import shutil
import subprocess
import sys
import zlib
from pathlib import Path

import pytest

import rail
import rail.contact

# Runs snakemake or sphinx in a subprocess with a time limit: .ci/run runs these tests one at a time.
pytestmark = pytest.mark.workflow

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"

# the README's two commands, character for character (.ci/run runs the second)
FIGURES_COMMAND = "python3 -m venv .venv && . .venv/bin/activate && pip install -r requirements.txt && snakemake -j2"
TESTS_COMMAND = "python3 -m venv .venv && . .venv/bin/activate && pip install -r requirements.txt && python -m pytest"


# --- the public names the API reference must hold -------------------------------------------------

def rail_modules() -> list[str]:
    """Every public module of the rail package (the physics layer rail.*, setup, studies, plotting,
    app); a private module (a name part starting with "_", e.g. rail._lazyjit) is not API, and
    autosummary leaves it out as Python's convention says."""
    return sorted(m.name for m in pkgutil.walk_packages(rail.__path__, "rail.")
                  if not any(part.startswith("_") for part in m.name.split(".")))


def public_names(module_name: str) -> set[str]:
    """Functions and classes a module defines (not imported) whose names do not start with _."""
    module = importlib.import_module(module_name)
    return {f"{module_name}.{name}" for name, obj in vars(module).items()
            if not name.startswith("_") and (inspect.isfunction(obj) or inspect.isclass(obj))
            and getattr(obj, "__module__", None) == module_name}


def read_inventory(path: Path) -> dict[str, str]:
    """Object name -> role (py:function, py:class, ...) of a Sphinx objects.inv (format version 2:
    four header lines, then zlib-compressed lines "name domain:role priority uri dispname")."""
    data = path.read_bytes()
    header = data.split(b"\n", 4)
    assert header[0] == b"# Sphinx inventory version 2", header[0]
    out = {}
    for line in zlib.decompress(header[4]).decode().splitlines():
        m = re.match(r"(.+?)\s+(\S+:\S+)\s+(-?\d+)\s+(\S*)\s+(.*)", line)
        if m:
            out[m.group(1)] = m.group(2)
    return out


def missing_from_inventory(inventory: dict[str, str], modules: list[str]) -> dict[str, list[str]]:
    """Per module, its public functions and classes that the inventory lacks (or lists with a
    role other than py:function / py:class)."""
    missing = {}
    for module in modules:
        names = sorted(n for n in public_names(module) if inventory.get(n) not in ("py:function", "py:class"))
        if names:
            missing[module] = names
    return missing


def test_the_modules_checked_include_the_app_and_every_physics_module():
    modules = rail_modules()
    physics = {f"rail.{m.name}" for m in pkgutil.iter_modules(rail.__path__) if not m.ispkg and not m.name.startswith("_")}
    assert {"rail.app", "rail.app.api", "rail.app.cli"} <= set(modules) and "rail._lazyjit" not in modules
    physics |= {f"rail.contact.{m.name}" for m in pkgutil.iter_modules(rail.contact.__path__) if not m.name.startswith("_")}
    assert physics <= set(modules) and {"rail.halfspace", "rail.track", "rail.contact.march", "rail.wear", "rail.growth"} <= physics
    assert "rail.contact" in modules
    assert public_names("rail.app.api") >= {"rail.app.api.load", "rail.app.api.growth", "rail.app.api.Study"}
    # a name a module imports is documented where it is defined: rail.chain imports Scenario and Track
    assert "rail.chain.Scenario" not in public_names("rail.chain") and "rail.scenario.Scenario" in public_names("rail.scenario")
    assert "rail.chain.Track" not in public_names("rail.chain") and "rail.chain.grow" in public_names("rail.chain")


def test_the_inventory_check_fails_for_a_module_left_out():
    # an inventory holding every public name passes; with one module's entries removed the check
    # names exactly that module and its functions and classes
    modules = ["rail.halfspace", "rail.app.api"]
    full = {n: ("py:class" if inspect.isclass(eval_name(n)) else "py:function")
            for m in modules for n in public_names(m)}
    assert missing_from_inventory(full, modules) == {}
    without = {n: r for n, r in full.items() if not n.startswith("rail.halfspace.")}
    missing = missing_from_inventory(without, modules)
    assert list(missing) == ["rail.halfspace"]
    assert "rail.halfspace.rayleigh_residue" in missing["rail.halfspace"]
    assert "rail.halfspace.ElasticMaterial" in missing["rail.halfspace"]


def eval_name(dotted: str):
    module, _, name = dotted.rpartition(".")
    return getattr(importlib.import_module(module), name)


# --- the site ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def built_site(tmp_path_factory):
    """docs/ built as from a clean checkout: a copy without docs/_build and the generated API stubs,
    beside links to the sources it documents and shows (rail/, the figure baselines, the report
    captions, the configuration), with warnings as errors."""
    tmp = tmp_path_factory.mktemp("site")
    shutil.copytree(ROOT / "docs", tmp / "docs",
                    ignore=lambda d, names: [n for n in names if n in ("_build", "__pycache__")
                                             or (Path(d).name == "reference" and n == "api")])
    for name in ("rail", "tests", "workflow", "config"):
        (tmp / name).symlink_to(ROOT / name, target_is_directory=True)
    out = tmp / "html"
    run = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-d", str(tmp / "doctrees"),
         str(tmp / "docs"), str(out)],
        capture_output=True, text=True, timeout=900, cwd=tmp)
    return run, out


@pytest.mark.slow
def test_the_documentation_site_builds_without_warnings(built_site):
    run, out = built_site
    assert run.returncode == 0, f"sphinx -W failed:\n{run.stderr[-6000:]}"
    assert "WARNING" not in run.stderr and "ERROR" not in run.stderr, run.stderr[-6000:]
    # every docs/*.md page is a page of the site (the index's glob takes pages added later)
    for page in sorted((ROOT / "docs").glob("*.md")):
        assert (out / f"{page.stem}.html").is_file(), f"{page.name} is not in the site"
    # the gallery shows every figure baseline, the API reference has a page per module
    gallery = (out / "reference" / "gallery.html").read_text()
    baselines = sorted((ROOT / "tests/baselines/figures").glob("fig*.png"))
    study = sorted((ROOT / "docs/images/study").glob("*.png"))  # the study figures' section (issue 45)
    assert len(baselines) >= 25 and len(study) >= 5 and gallery.count("<img") == len(baselines) + len(study)
    for png in baselines:  # Sphinx renames a copied image whose name is taken; the alt text stays
        assert f'alt="Fig. {int(png.stem[3:])}"' in gallery, f"{png.name} is not in the gallery"
    for module in rail_modules():
        assert (out / "reference" / "api" / f"{module}.html").is_file(), f"no API page for {module}"
    # the formulas of the derivations are typeset by MathJax
    track = (out / "track.html").read_text()
    assert 'class="math' in track and "mathjax" in track.lower()


@pytest.mark.slow
def test_every_public_function_and_class_is_in_the_api_reference(built_site):
    run, out = built_site
    assert run.returncode == 0, run.stderr[-3000:]
    inventory = read_inventory(out / "objects.inv")
    modules = rail_modules()
    assert not missing_from_inventory(inventory, modules)
    assert all(inventory.get(m) == "py:module" for m in modules)


# --- the README -------------------------------------------------------------------------------------

def test_the_readme_gives_the_two_commands():
    text = README.read_text()
    blocks = re.findall(r"```bash\n(.*?)\n```", text, flags=re.S)
    assert blocks == [FIGURES_COMMAND, TESTS_COMMAND]
    ci = (ROOT / ".ci/run").read_text()
    # CI runs the README's test command, step by step in its order (the lint between the install and the tests)
    steps = [line for line in ci.splitlines() if not line.startswith("#")]
    at = [next(i for i, line in enumerate(steps) if part in line.split(" && ")) for part in TESTS_COMMAND.split(" && ")]
    assert at == sorted(at)
    assert "python -m sphinx -W" in ci


def github_slug(heading: str) -> str:
    """The anchor GitHub (and MyST's heading anchors) give a heading."""
    text = re.sub(r"[`*]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def test_the_readme_links_resolve():
    text = README.read_text()
    links = re.findall(r"\]\(([^)\s]+)\)", text)
    assert links
    for link in links:
        if re.match(r"[a-z]+://", link):
            continue
        path, _, anchor = link.partition("#")
        target = ROOT / path
        assert target.exists(), f"README links to {path}, which does not exist"
        if anchor:
            headings = re.findall(r"^#+ (.+)$", target.read_text(), flags=re.M)
            assert anchor in {github_slug(h) for h in headings}, f"README links to {link}: no such heading"
