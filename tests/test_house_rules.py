"""House rules that run (issue 57, item 7): the lint (ruff, with pyproject.toml's rules), the workflow's
format (snakefmt for the Snakefile, the project's own rule for workflow/rules/*.smk), and the facts a
reader trusts first: every repository path quoted in the README, docs/*.md, the comments of
requirements.txt and pyproject.toml and the module docstrings exists, and rail/__init__.py lists the
layers tests/test_architecture.py enforces."""

import ast
import re
import subprocess
import sys
import tomllib
from pathlib import Path

from test_architecture import LAYERS

ROOT = Path(__file__).resolve().parents[1]
LINE_LENGTH = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["ruff"]["line-length"]

# A quoted path: one of the repository's top folders, then a path (globs, {wildcard} and <placeholder> allowed)
PATH = re.compile(r"(?<![\w./~$-])((?:tests|rail|config|docs|workflow)/[\w./*{}<>+-]*[\w*}>/])")
# Files the documentation names as examples of a user's own (written by the user, not kept here)
EXAMPLES = {"config/scenarios/draft.yaml", "config/scenarios/my_site.yaml", "config/scenarios/my_pad.yaml",
            "config/measured/<track>_decay_rate.csv"}


def _run(*args):
    return subprocess.run([sys.executable, "-m", *args], cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_ruff_finds_nothing():
    out = _run("ruff", "check", "--no-cache", "--output-format", "concise", ".")
    assert out.returncode == 0, out.stdout + out.stderr


def test_the_snakefile_is_as_snakefmt_writes_it():
    out = _run("snakefmt", "--check", "--diff", "Snakefile")
    assert out.returncode == 0, out.stdout + out.stderr


def format_problems(files) -> list[str]:
    """The workflow's own format where snakefmt does not run (pyproject.toml [tool.snakefmt]): lines
    within ruff's line length, spaces not tabs, no trailing blanks, one final newline."""
    problems = []
    for f in files:
        text = f.read_text()
        for n, line in enumerate(text.split("\n"), 1):
            if len(line) > LINE_LENGTH:
                problems.append(f"{f.name}:{n}: {len(line)} characters (at most {LINE_LENGTH})")
            if "\t" in line:
                problems.append(f"{f.name}:{n}: a tab")
            if line != line.rstrip():
                problems.append(f"{f.name}:{n}: trailing blanks")
        if not text.endswith("\n") or text.endswith("\n\n"):
            problems.append(f"{f.name}: does not end with one newline")
    return problems


def test_the_workflow_rule_files_keep_the_house_format():
    files = sorted((ROOT / "workflow/rules").glob("*.smk"))
    assert len(files) > 10
    problems = format_problems(files)
    assert not problems, "\n".join(problems)


def test_the_format_rule_finds_a_long_line_a_tab_and_trailing_blanks(tmp_path):
    f = tmp_path / "x.smk"
    long = "    output: '" + "y" * LINE_LENGTH + "'"
    f.write_text("rule a:\n\tinput: 'x'  \n" + long + "\n")
    assert format_problems([f]) == ["x.smk:2: a tab", "x.smk:2: trailing blanks",
                                    f"x.smk:3: {len(long)} characters (at most {LINE_LENGTH})"]


def _generated() -> list[str]:
    """Folders the build writes (listed in .gitignore): docs/_build/, docs/reference/api/."""
    return [line.strip().lstrip("/") for line in (ROOT / ".gitignore").read_text().splitlines() if line.strip().endswith("/")]


def _exists(path: str) -> bool:
    if path in EXAMPLES or any(path.startswith(g) for g in _generated()):
        return True
    # {wildcard} and <placeholder> stand for any name, NN for two digits (figNN: fig02 ... fig27)
    pattern = re.sub(r"\{[^}]*\}|<[^>]*>", "*", path.rstrip("/")).replace("NN", "[0-9][0-9]")
    if any(c in pattern for c in "*?["):
        return any(ROOT.glob(pattern))
    return (ROOT / pattern).exists()


def stale_paths(texts) -> list[str]:
    """'where: path' for every quoted repository path of texts ({where: text}) that does not exist."""
    return [f"{where}: {m.group(1).rstrip('.')}" for where, text in texts.items() for m in PATH.finditer(text)
            if not _exists(m.group(1).rstrip("."))]


def quoted_texts() -> dict:
    """The README, docs/*.md, the comments of requirements.txt and pyproject.toml, and the module
    docstrings of rail/, workflow/scripts/, tests/ and docs/."""
    texts = {"README.md": (ROOT / "README.md").read_text()}
    texts.update({str(f.relative_to(ROOT)): f.read_text() for f in sorted((ROOT / "docs").glob("*.md"))})
    for name in ("requirements.txt", "pyproject.toml"):
        texts[name] = "\n".join(line.split("#", 1)[1] for line in (ROOT / name).read_text().splitlines() if "#" in line)
    modules = [*(ROOT / "rail").rglob("*.py"), *(ROOT / "workflow/scripts").glob("*.py"), *(ROOT / "tests").rglob("*.py"),
               *(ROOT / "docs").glob("*.py")]
    for f in sorted(modules):
        doc = ast.get_docstring(ast.parse(f.read_text()))
        if doc:
            texts[str(f.relative_to(ROOT))] = doc
    return texts


def test_every_path_quoted_in_the_docs_and_docstrings_exists():
    texts = quoted_texts()
    assert {"README.md", "requirements.txt", "pyproject.toml", "rail/__init__.py", "docs/usage.md"} <= set(texts)
    stale = stale_paths(texts)
    assert not stale, "paths quoted that do not exist:\n" + "\n".join(stale)


def test_the_path_check_reports_every_stale_path_at_once():
    texts = {"a.md": "see tests/test_nosuch.py and rail/setup/config.py, then `rail/nosuch.py`.",
             "b.txt": "workflow/rules/*.smk, config/scenarios/{name}.yaml, docs/_build/html, workflow/report/figNN.rst, config/nosuch/*.yaml"}
    assert stale_paths(texts) == ["a.md: tests/test_nosuch.py", "a.md: rail/nosuch.py", "b.txt: config/nosuch/*.yaml"]


NUMBERS = {"two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7}


def test_the_package_docstring_lists_the_layers_the_architecture_test_enforces():
    doc = ast.get_docstring(ast.parse((ROOT / "rail/__init__.py").read_text()))
    count = re.search(r"\b(\w+) layers, each importing only", doc)
    assert count and NUMBERS.get(count.group(1).lower()) == len(LAYERS), count and count.group(0)
    bullets = [line for line in doc.splitlines() if line.startswith("* ")]
    named = ["physics" if b.startswith("* physics") else re.match(r"\* ``rail\.(\w+)``", b).group(1) for b in bullets]
    assert named == sorted(LAYERS, key=LAYERS.get)
