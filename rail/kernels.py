"""Compile the numba kernels of the contact marches once (rule compile_kernels).

The first call of a compiled march in a fresh checkout compiles it (about 30 s CPU for
rail.contact.march's march, 25 s more for rail.contact.tangent's); numba keeps the result in its cache next
to the sources. Run once before parallel jobs, so that they load the cache instead of each compiling.
"""

from __future__ import annotations

import numpy as np

from . import contact
from .contact import march, tangent

__all__ = ["compile_kernels"]


def compile_kernels(tangent_too: bool = False) -> list[str]:
    """Compile the contact marches once (or load them from numba's cache): a tiny rolling contact
    through solve_tangential and (tangent=True) through rail.contact.tangent.work_tangent, with the
    argument types of every production call (float64 arrays, the closure as an integer flag).

    The first call of the compiled march in a fresh checkout takes about 30 s CPU; the workflow runs
    this once (rule compile_kernels) before the jobs that roll the contact, so that parallel jobs
    load the cache instead of each compiling it.

    Parameters
    ----------
    tangent_too : bool
        Also the derivative march of the growth-rate spectrum (about 25 s CPU more).

    Returns
    -------
    list of str
        The compiled functions and their signatures [-] (the tiny case is in SI units: a 100 kN
        load [N], a 2.5 mm half-length [m], 40 m/s [m/s]).
    """
    m = contact.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)
    M, steps, delta, speed = 4, 12, 1e-3, 40.0
    P, a = np.full(steps, 1e5), np.full(steps, 2.5e-3)
    shape = np.ones((steps, 2 * M + 1))
    contact.solve_tangential(P, a, m, speed, delta, M, closure="default", shape=shape)
    d = np.ones((steps, 1))
    if tangent_too:
        tangent.work_tangent(P, a, m, speed, delta, M, d * 1e3, d * 1e-5, dshape=np.zeros((steps, 2 * M + 1, 1)), shape=shape)
    out = []
    for mod in (march,) + ((tangent,) if tangent_too else ()):
        for name, obj in sorted(vars(mod).items()):
            if hasattr(obj, "signatures") and obj.signatures and obj.py_func.__module__ == mod.__name__:
                out += [f"{mod.__name__}.{name}{tuple(str(t) for t in sig)}" for sig in obj.signatures]
    return out
