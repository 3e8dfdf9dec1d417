"""Which source a result depends on: the rail modules a script or module imports, followed through
every import (relative, absolute and inside functions), and a hash of their text.

The workflow puts ``code_hash(script)`` in every rule's params, so that changing a module reruns
exactly the jobs whose scripts import it, directly or through other modules; the growth checkpoints
carry the hash of rail.chain's imports, so that a checkpoint written by other physics code is never
resumed. Derived from the imports themselves, the list cannot go stale. A script that imports
rail.setup.config hashes the schema's defaults of optional keys too (read there: rail.setup.config.setting).
This module imports nothing from rail.
"""

from __future__ import annotations

import ast
import functools
import hashlib
from pathlib import Path

import yaml

__all__ = ["rail_imports", "code_hash", "module_hash", "file_hash"]

PACKAGE = "rail"
ROOT = Path(__file__).resolve().parent  # the rail package folder


@functools.lru_cache(maxsize=None)
def _module_file(dotted: str, root: Path) -> Path | None:
    """The file of module ``rail.a.b`` (rail/a/b.py or rail/a/b/__init__.py), or None.

    Remembered per process: the workflow's start-up follows the imports of about 40 scripts, which
    ask for the same modules about 20,000 times (a module file added while a process runs is not
    seen by it)."""
    parts = dotted.split(".")[1:]
    base = root.joinpath(*parts)
    for cand in (base.with_suffix(".py"), base / "__init__.py"):
        if parts and cand.is_file():
            return cand
    if not parts and (root / "__init__.py").is_file():
        return root / "__init__.py"
    return None


def _dotted_of(path: Path, root: Path) -> str:
    rel = path.relative_to(root).with_suffix("")
    parts = [p for p in rel.parts if p != "__init__"]
    return ".".join([PACKAGE, *parts])


def _imported_names(path: Path, root: Path) -> set[str]:
    """Dotted names of the rail modules a file imports (each may be a module or a package).

    Parsed once per file version (path, modification time and size): the workflow hashes the
    imports of about 30 scripts at start-up, which share most of their modules."""
    st = path.stat()
    return set(_parse_imports(str(path), str(root), st.st_mtime_ns, st.st_size))


def _statements(node):
    """Every statement under node, at any depth (imports are statements: the expressions, most of a
    module's nodes, are not walked)."""
    for child in ast.iter_child_nodes(node):
        if isinstance(child, (ast.stmt, ast.excepthandler, ast.match_case)):
            yield child
            yield from _statements(child)


@functools.lru_cache(maxsize=None)
def _parse_imports(path_text: str, root_text: str, _mtime_ns: int, _size: int) -> frozenset[str]:
    path, root = Path(path_text), Path(root_text)
    tree = ast.parse(path.read_text(), filename=str(path))
    is_pkg = path.name == "__init__.py"
    here = _dotted_of(path, root) if path.is_relative_to(root) else None
    out = set()
    for node in _statements(tree):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name == PACKAGE or a.name.startswith(PACKAGE + ".")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                if here is None:
                    continue
                pkg = here.split(".") if is_pkg else here.split(".")[:-1]
                base = pkg[: len(pkg) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if not (mod == PACKAGE or mod.startswith(PACKAGE + ".")):
                continue
            out.add(mod)
            out |= {f"{mod}.{a.name}" for a in node.names}  # 'from rail import chain': chain may be a module
    return frozenset(out)


def rail_imports(path, root: Path = ROOT) -> list[Path]:
    """Every rail source file that importing ``path`` executes.

    Parameters
    ----------
    path : str or Path
        A Python file (a script or a module of the package).
    root : Path
        The rail package folder.

    Returns
    -------
    list of Path
        The modules it imports, their packages' __init__ files, and so on transitively (sorted;
        ``path`` itself only if it imports itself).
    """
    root = Path(root).resolve()
    seen: set[Path] = set()
    todo = [Path(path).resolve()]
    first = True
    while todo:
        f = todo.pop()
        if not first and f in seen:
            continue
        if not first:
            seen.add(f)
        first = False
        for name in _imported_names(f, root):
            parts = name.split(".")
            for i in range(1, len(parts) + 1):  # the packages on the way are executed too
                mf = _module_file(".".join(parts[:i]), root)
                if mf is not None and mf not in seen:
                    todo.append(mf)
    return sorted(seen)


def code_hash(path, root: Path = ROOT) -> str:
    """Hash of the rail sources a file imports.

    Parameters
    ----------
    path : str or Path
    root : Path
        The rail package folder.

    Returns
    -------
    str
        sha256 (12 hex digits) of rail_imports(path), by their path inside the package and their text.
    """
    root = Path(root).resolve()
    h = hashlib.sha256()
    imports = rail_imports(path, root)
    for f in imports:
        h.update(str(f.relative_to(root)).encode())
        h.update(f.read_bytes())
    if root / "setup" / "config.py" in imports:  # it reads the schema's defaults of optional keys (rail.setup.config.setting)
        h.update(_schema_defaults(root.parent / "config" / "schema" / "config.schema.yaml"))
    return h.hexdigest()[:12]


def _schema_defaults(path: Path) -> bytes:
    """The ``default:`` of every key of the schema at ``path``, as sorted text (empty without a schema)."""
    if not path.is_file():
        return b""
    return _defaults_of_text(path.read_text())


@functools.lru_cache(maxsize=4)
def _defaults_of_text(text: str) -> bytes:
    """_schema_defaults of a schema's text, kept by the text itself: the workflow hashes the code of 44
    scripts at start-up, and parsing the 2,000-value schema each time was most of Snakemake's 7 s there."""
    out = []

    def walk(node, key):
        if isinstance(node, dict):
            if "default" in node and key:
                out.append(f"{key}={node['default']!r}")
            for name, child in node.get("properties", {}).items():
                walk(child, f"{key}.{name}" if key else name)

    schema = yaml.safe_load(text)
    walk(schema, "")
    for name, child in ((schema or {}).get("$defs") or {}).items():  # a shared definition's defaults (fleet_wheelset.model)
        walk(child, f"$defs.{name}")
    return "\n".join(sorted(out)).encode()


def module_hash(dotted: str, root: Path = ROOT) -> str:
    """Hash of a rail module and everything it imports.

    Parameters
    ----------
    dotted : str
        Module name, e.g. 'rail.chain'.
    root : Path

    Returns
    -------
    str
        12 hex digits.
    """
    root = Path(root).resolve()
    f = _module_file(dotted, root)
    if f is None:
        raise ValueError(f"no module {dotted} under {root}")
    return file_hash(f, root)[:12]


def file_hash(path, root: Path = ROOT) -> str:
    """Hash of a rail source file and every rail file it imports, directly or not (module_hash of a file;
    the mark of numba's cache of its compiled functions, rail._lazyjit).

    Parameters
    ----------
    path : str or Path
        A source file under root.
    root : Path
        The rail package folder.

    Returns
    -------
    str
        sha256 (64 hex digits) of the files, by their path inside the package and their text.
    """
    root = Path(root).resolve()
    f = Path(path).resolve()
    h = hashlib.sha256()
    for g in sorted(set(rail_imports(f, root)) | {f}):
        h.update(str(g.relative_to(root)).encode())
        h.update(g.read_bytes())
    return h.hexdigest()
