"""Small dense solves compiled with numba, shared by the contact march and the wavenumber tables."""

from __future__ import annotations

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
    n, m = A.shape[0], B.shape[1]
    for k in range(n):
        piv, big = k, abs(A[k, k])
        for r in range(k + 1, n):
            v = abs(A[r, k])
            if v > big:
                piv, big = r, v
        if piv != k:
            for c in range(n):
                A[k, c], A[piv, c] = A[piv, c], A[k, c]
            for c in range(m):
                B[k, c], B[piv, c] = B[piv, c], B[k, c]
        inv = 1.0 / A[k, k]
        for r in range(k + 1, n):
            f = A[r, k] * inv
            if f != 0.0:
                A[r, k] = f
                for c in range(k + 1, n):
                    A[r, c] -= f * A[k, c]
                for c in range(m):
                    B[r, c] -= f * B[k, c]
    for k in range(n - 1, -1, -1):
        inv = 1.0 / A[k, k]
        for c in range(m):
            acc = B[k, c]
            for j in range(k + 1, n):
                acc -= A[k, j] * B[j, c]
            B[k, c] = acc * inv


@njit(cache=True, error_model="numpy")
def lu_in_place(A, n, piv):
    """Factor the leading n x n block of A in place (P A = L U, partial pivoting as solve_in_place):
    A[:n, :n] is overwritten by L (unit diagonal, below) and U; piv[k] is the row exchanged with row k
    at step k. For solving the same matrix again with lu_solve_in_place.

    Parameters
    ----------
    A : (>= n, >= n) float ndarray
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
def lu_solve_in_place(A, n, piv, b):
    """Solve (leading n x n block of the original A) x = b[:n] with the factors of lu_in_place,
    overwriting b[:n] with x. A zero pivot leaves inf or nan in x.

    Parameters
    ----------
    A : (>= n, >= n) float ndarray
        The LU factors of lu_in_place [any unit].
    n : int
        The order [-].
    piv : (>= n,) int64 ndarray
        The row exchanges of lu_in_place [-].
    b : (>= n,) float ndarray
        The right-hand side [any unit]; overwritten by the solution.

    Returns
    -------
    None
        x [unit of b / unit of A] is left in b.
    """
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for r in range(1, n):
        acc = b[r]
        for c in range(r):
            acc -= A[r, c] * b[c]
        b[r] = acc
    for k in range(n - 1, -1, -1):
        acc = b[k]
        for j in range(k + 1, n):
            acc -= A[k, j] * b[j]
        b[k] = acc * (1.0 / A[k, k])  # as solve_in_place, so that a fresh factor solves to the same bits
