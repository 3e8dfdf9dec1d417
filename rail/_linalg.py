"""Small dense solves compiled with numba, shared by the contact march and the wavenumber tables."""

from __future__ import annotations

import numpy as np

from ._lazyjit import njit

__all__ = ["solve_in_place", "lu_in_place", "lu_solve_in_place"]


@njit(cache=True, error_model="numpy")
def solve_in_place(A, B):
    """Solve A X = B for X by Gaussian elimination with partial pivoting (the entry of largest
    modulus in the column), overwriting A with its factors and B (n, m) with X; real or complex.

    For small systems solved many times: the contact step's stick solve (tens of nodes,
    rail.contact.steps) and a track cell's attachments at each wavenumber node (rail.moving). A plain
    loop in place costs less than LAPACK's call with its copies and compiles faster than numba's
    np.linalg.solve. A zero pivot leaves inf or nan in X (the callers check finiteness).

    Parameters
    ----------
    A : (n, n) float or complex ndarray
        The matrix [any unit]; overwritten by its LU factors.
    B : (n, m) ndarray of A's dtype
        The right-hand sides [any unit]; overwritten by the solution.

    Returns
    -------
    None
        X [unit of B / unit of A] is left in B.
    """
    n = A.shape[0]
    piv = np.empty(n, dtype=np.int64)
    lu_in_place(A, n, piv)
    lu_solve_in_place(A, n, piv, B)


@njit(cache=True, error_model="numpy")
def lu_in_place(A, n, piv):
    """Factor the leading n x n block of A in place (P A = L U, partial pivoting as solve_in_place):
    A[:n, :n] is overwritten by L (unit diagonal, below) and U; piv[k] is the row exchanged with row k
    at step k. For solving the same matrix again with lu_solve_in_place.

    Parameters
    ----------
    A : (>= n, >= n) float or complex ndarray
        The matrix [any unit]; its leading block is overwritten by its LU factors.
    n : int
        The order of the block [-].
    piv : (>= n,) int64 ndarray
        Overwritten by the row exchanges [-].

    Returns
    -------
    None
        The factors are left in A and piv.
    """
    for k in range(n):
        p, big = k, abs(A[k, k])
        for r in range(k + 1, n):
            v = abs(A[r, k])
            if v > big:
                p, big = r, v
        piv[k] = p
        if p != k:
            for c in range(n):
                A[k, c], A[p, c] = A[p, c], A[k, c]
        inv = 1.0 / A[k, k]
        for r in range(k + 1, n):
            f = A[r, k] * inv
            A[r, k] = f
            if f != 0.0:
                for c in range(k + 1, n):
                    A[r, c] -= f * A[k, c]


@njit(cache=True, error_model="numpy")
def lu_solve_in_place(A, n, piv, B):
    """Solve (leading n x n block of the original A) X = B[:n] with the factors of lu_in_place,
    overwriting B[:n] with X (the row exchanges first, then L and U: the same operations in the same
    order as eliminating B along with A). A zero pivot leaves inf or nan in X.

    Parameters
    ----------
    A : (>= n, >= n) float or complex ndarray
        The LU factors of lu_in_place [any unit].
    n : int
        The order [-].
    piv : (>= n,) int64 ndarray
        The row exchanges of lu_in_place [-].
    B : (>= n, m) ndarray of A's dtype
        The right-hand sides [any unit]; overwritten by the solution.

    Returns
    -------
    None
        X [unit of B / unit of A] is left in B.
    """
    m = B.shape[1]
    for k in range(n):
        p = piv[k]
        if p != k:
            for c in range(m):
                B[k, c], B[p, c] = B[p, c], B[k, c]
    for r in range(1, n):
        for c in range(m):
            acc = B[r, c]
            for j in range(r):
                acc -= A[r, j] * B[j, c]
            B[r, c] = acc
    for k in range(n - 1, -1, -1):
        inv = 1.0 / A[k, k]
        for c in range(m):
            acc = B[k, c]
            for j in range(k + 1, n):
                acc -= A[k, j] * B[j, c]
            B[k, c] = acc * inv
