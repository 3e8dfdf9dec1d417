"""numba's ``njit``, imported when a compiled function is first used rather than when its module is.

Importing numba costs about 0.7 s CPU (more on a loaded machine). Every workflow job and the
Snakemake process itself import rail.contact for its dataclasses and constants, but only the jobs
that roll the contact call its compiled loops. ``njit(cache=True)`` here records the Python function;
the first call (or attribute access, e.g. ``.signatures``) of any recorded function of a module
imports numba, makes every recorded function of that module a numba dispatcher with the same
options, and rebinds the module's globals to them, so that compiled functions calling each other see
dispatchers when numba types them. Names imported from another module (``from .contact import
_march``) are rebound the same way in the importing module when its own functions are first used.

numba's cache (``cache=True``) is kept where numba keeps it (``__pycache__`` beside the file), but its
freshness is judged by the code, not by the file's time: numba marks a compiled function with the
modification time and size of its own file only, so a change in a module it calls (the march calling
the steps of rail.contact.steps, a constant such as THETA_EDGE that the compiled code holds) left the
old machine code in use. Here every rail function's mark is a hash of its file and every rail file that
file imports, directly or not (rail.provenance.file_hash, as the workflow's rerun hash): a change in
any of them recompiles it, an untouched file keeps its cache, and the same sources in a fresh clone
hash the same (``_SourceStamp``; tests/test_lazyjit.py). With ``NUMBA_CACHE_DIR`` set, the cache is
filed by the folder inside the package rather than by its absolute path, so that a fresh clone of the
same code loads the kernels another checkout compiled (``NUMBA_CACHE_DIR=~/.cache/railgrowth-numba
snakemake -j2`` skips the march's 25-30 s compile after the first clone).
"""

from __future__ import annotations

import functools
import sys
from pathlib import Path

_PENDING: dict[str, list["LazyJit"]] = {}


class LazyJit:
    """A function to be compiled by ``numba.njit(**options)`` when first used.

    Attributes
    ----------
    py_func : the Python function
    options : keyword arguments of numba.njit
    """

    def __init__(self, func, options):
        self.py_func = func
        self.options = options
        self.__name__ = func.__name__
        self.__qualname__ = func.__qualname__
        self.__module__ = func.__module__
        self.__doc__ = func.__doc__
        self._dispatcher = None
        _PENDING.setdefault(func.__module__, []).append(self)

    def dispatcher(self):
        """The numba dispatcher of this function (every recorded function of its module made one)."""
        if self._dispatcher is None:
            compile_module(self.__module__)
        return self._dispatcher

    def __call__(self, *args, **kwargs):
        return self.dispatcher()(*args, **kwargs)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(self.dispatcher(), name)


def compile_module(module: str) -> None:
    """Make every recorded function of ``module`` a numba dispatcher and rebind the module's globals
    (its own functions and the recorded functions it imported from other modules). A module may define
    ``_before_compile(namespace)``, called first, to bind globals its compiled code needs and that
    would import numba with the module (rail._linalg: LAPACK's getrf through numba's helper library).

    Parameters
    ----------
    module : str
        The module's name, e.g. 'rail.contact' [-].

    Returns
    -------
    None
        The module's namespace is changed in place [-].
    """
    from numba import njit as numba_njit

    _install_stamp()
    namespace = sys.modules[module].__dict__
    if callable(namespace.get("_before_compile")):  # globals the compiled code needs that import numba (rail._linalg)
        namespace["_before_compile"](namespace)
    for lazy in _PENDING.pop(module, []):
        lazy._dispatcher = numba_njit(**lazy.options)(lazy.py_func)
    for name, value in list(namespace.items()):
        if isinstance(value, LazyJit):
            if value._dispatcher is None:
                compile_module(value.__module__)
            namespace[name] = value._dispatcher
    # modules that imported this module's functions before they were compiled
    for other in list(sys.modules.values()):
        d = getattr(other, "__dict__", None)
        if not d or not str(getattr(other, "__name__", "")).startswith("rail."):
            continue
        for name, value in list(d.items()):
            if isinstance(value, LazyJit) and value._dispatcher is not None:
                d[name] = value._dispatcher


def njit(*args, **options):
    """Drop-in for ``numba.njit`` used as ``@njit`` or ``@njit(cache=True)`` (keyword options only).

    Parameters
    ----------
    *args : the function, when used as ``@njit`` [-]
    **options : keyword options of numba.njit [-]

    Returns
    -------
    LazyJit or callable
        The recorded function, or a decorator that records one [-].
    """
    if args and callable(args[0]) and len(args) == 1 and not options:
        return LazyJit(args[0], {})
    if args:
        raise TypeError("rail._lazyjit.njit takes keyword options only (signatures are not supported)")

    def wrap(func):
        return LazyJit(func, options)

    return wrap


_RAIL = Path(__file__).resolve().parent
_STAMP_INSTALLED = []


@functools.lru_cache(maxsize=None)
def source_stamp(py_file: str) -> str:
    """The freshness mark of the compiled functions of a rail file: sha256 of the file and of every rail
    file it imports, directly or not, by their path inside the package and their text.

    Parameters
    ----------
    py_file : str
        A source file of the rail package (or of a copy of it: its package is the outermost folder
        above it that holds an ``__init__.py``) [-].

    Returns
    -------
    str
        64 hex digits [-].
    """
    from .provenance import file_hash

    f = Path(py_file).resolve()
    root = f.parent
    while (root.parent / "__init__.py").is_file():
        root = root.parent
    return file_hash(f, root)


def _is_rail_file(py_file) -> bool:
    """Whether py_file is a module of this rail package."""
    try:
        Path(py_file).resolve().relative_to(_RAIL)
    except (TypeError, ValueError):
        return False
    return True


def _install_stamp() -> None:
    """Put numba's cache locators for rail's files, marked by source_stamp, ahead of numba's own (once)."""
    if _STAMP_INSTALLED:
        return
    from numba.core import caching

    class _SourceStamp:
        """A numba cache locator whose freshness mark is source_stamp (for rail's files only)."""

        @classmethod
        def from_function(cls, py_func, py_file):
            if not _is_rail_file(py_file):
                return None
            return super().from_function(py_func, py_file)

        def get_source_stamp(self):
            return source_stamp(self._py_file)

        @classmethod
        def get_suitable_cache_subpath(cls, py_file):
            # by the folder inside the package, not its absolute path: with NUMBA_CACHE_DIR (or the user-wide
            # cache of a read-only install) two checkouts of the same code share their compiled kernels
            return "_".join(("railgrowth",) + Path(py_file).resolve().parent.relative_to(_RAIL.parent).parts)

    bases = (caching.UserProvidedCacheLocator, caching.InTreeCacheLocator, caching.UserWideCacheLocator)
    ours = [type("Stamped" + b.__name__, (_SourceStamp, b), {}) for b in bases]
    caching.CacheImpl._locator_classes[0:0] = ours
    _STAMP_INSTALLED.append(True)
