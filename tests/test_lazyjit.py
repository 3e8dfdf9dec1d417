"""numba's cache of rail's compiled functions follows the code they call (rail._lazyjit.source_stamp).

numba marks a cached function with its own file's time and size only: a change in a module it calls
leaves the old machine code in use. The first test shows that with numba's own njit; the second that
rail's functions recompile when a module they call changes, and keep their cache when nothing changed.
Each run is a fresh process, as a workflow job is.
"""

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

RAIL = Path(__file__).resolve().parents[1] / "rail"


def _run(cwd: Path, code: str, cache_dir: Path | None = None) -> str:
    env = dict(os.environ, PYTHONPATH=str(cwd))
    env.pop("NUMBA_CACHE_DIR", None)
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = str(cache_dir)
    out = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout.split()


def _write(path: Path, text: str, stamp: int) -> None:
    path.write_text(textwrap.dedent(text))
    os.utime(path, (stamp, stamp))  # a new modification time, as an edit gives (numba's mark)


def test_numbas_own_cache_keeps_a_stale_callee(tmp_path):
    # the error the stamp removes: with numba.njit, f's cache outlives a change of the g it calls
    pkg = tmp_path / "probe"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    _write(pkg / "b.py", "from numba import njit\n@njit(cache=True)\ndef g():\n    return 1\n", 1_000_000)
    _write(pkg / "a.py", "from numba import njit\nfrom .b import g\n@njit(cache=True)\ndef f():\n    return g()\n", 1_000_000)
    code = "from probe.a import f; print(f())"
    assert _run(tmp_path, code) == ["1"]
    _write(pkg / "b.py", "from numba import njit\n@njit(cache=True)\ndef g():\n    return 2\n", 2_000_000)
    assert _run(tmp_path, code) == ["1"]  # stale: g now returns 2


def test_rails_cache_follows_the_modules_a_function_calls(tmp_path):
    pkg = tmp_path / "rail"
    shutil.copytree(RAIL, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    b = "from ._lazyjit import njit\n@njit(cache=True)\ndef g():\n    return {}\n"
    _write(pkg / "_probe_b.py", b.format(1), 1_000_000)
    _write(pkg / "_probe_a.py", "from ._lazyjit import njit\nfrom ._probe_b import g\n@njit(cache=True)\n"
           "def f():\n    return g()\n", 1_000_000)
    code = "from rail._probe_a import f; v = f(); print(v, f.stats.cache_hits.get(f.signatures[0], 0))"
    assert _run(tmp_path, code) == ["1", "0"]  # compiled
    assert _run(tmp_path, code) == ["1", "1"]  # nothing changed: from the cache
    _write(pkg / "_probe_b.py", b.format(2), 2_000_000)
    assert _run(tmp_path, code) == ["2", "0"]  # the callee changed: recompiled
    assert _run(tmp_path, code) == ["2", "1"]
    # a change of time alone (a fresh clone, a checkout) keeps the cache: the mark is the code
    _write(pkg / "_probe_b.py", b.format(2), 3_000_000)
    _write(pkg / "_probe_a.py", (pkg / "_probe_a.py").read_text(), 3_000_000)
    assert _run(tmp_path, code) == ["2", "1"]


def test_two_checkouts_of_the_same_code_share_a_numba_cache_dir(tmp_path):
    # NUMBA_CACHE_DIR: the second checkout (another path, other file times) loads what the first compiled;
    # a third with a changed callee compiles its own
    b = "from ._lazyjit import njit\n@njit(cache=True)\ndef g():\n    return {}\n"
    for name, value, stamp in (("one", 1, 1_000_000), ("two", 1, 2_000_000), ("three", 3, 3_000_000)):
        pkg = tmp_path / name / "rail"
        shutil.copytree(RAIL, pkg, ignore=shutil.ignore_patterns("__pycache__"))
        _write(pkg / "_probe_b.py", b.format(value), stamp)
        _write(pkg / "_probe_a.py", "from ._lazyjit import njit\nfrom ._probe_b import g\n@njit(cache=True)\n"
               "def f():\n    return g()\n", stamp)
    code = "from rail._probe_a import f; v = f(); print(v, f.stats.cache_hits.get(f.signatures[0], 0))"
    cache = tmp_path / "cache"
    assert _run(tmp_path / "one", code, cache) == ["1", "0"]
    assert _run(tmp_path / "two", code, cache) == ["1", "1"]
    assert _run(tmp_path / "three", code, cache) == ["3", "0"]
    assert not list((tmp_path / "two" / "rail").rglob("*.nbi"))  # nothing beside the sources
