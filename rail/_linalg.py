"""Small dense solves compiled with numba, shared by the contact march and the wavenumber tables.

solve_in_place: Gaussian elimination written out, real or complex (the tables, the tangent's solves).
getrf_rows, getrs_rows: LAPACK's dgetrf (scipy's, through numba's helper library) on a row-major
block, for the contact step's stick solve: at its size (about 40 unknowns) 9 us against 16 us.
"""

from __future__ import annotations

from ._lazyjit import njit

__all__ = ["solve_in_place", "getrf_rows", "getrs_rows"]

_dgetrf = None  # LAPACK's dgetrf through numba's helper library: bound by _before_compile (rail._lazyjit)


def _before_compile(namespace):
    """Bind _dgetrf when the module's compiled functions are made (importing numba here, not with the module)."""
    from numba import types
    from numba.np.linalg import _LAPACK

    namespace["_dgetrf"] = _LAPACK().numba_xxgetrf(types.float64)


@njit(cache=True, error_model="numpy")
def solve_in_place(A, B):
    """Solve A X = B for X by Gaussian elimination with partial pivoting (the entry of largest
    modulus in the column), overwriting A with its factors and B (n, m) with X; real or complex.

    For small systems solved many times: the tangent march's stick-block derivative (tens of nodes,
    several right-hand sides, rail.contact.tangent) and a track cell's attachments at each wavenumber
    node (rail.moving, complex). A plain loop in place costs less than numba's np.linalg.solve with its
    copies and compiles faster. (The march's own stick solve factors by getrf_rows, below.) A zero pivot
    leaves inf or nan in X (the callers check finiteness).

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


@njit(cache=True)
def getrf_rows(A, n, piv):
    """LU factors of the leading n x n block of a row-major float array by LAPACK's dgetrf, in place.

    LAPACK reads the block in column order, that is A^T: it factors P A^T = L U (partial pivoting), so
    that A = U^T L^T P, and leaves U^T in the lower triangle of A's rows (with the diagonal) and L^T
    (unit diagonal) in the strict upper triangle. getrs_rows solves with them.

    Parameters
    ----------
    A : (>= n, m) float64 ndarray, C order, m >= n
        The matrix [any unit]; its leading block is overwritten by the factors.
    n : int
        The order [-].
    piv : (>= n,) int32 ndarray
        Overwritten by LAPACK's row exchanges (1-based) [-].

    Returns
    -------
    int
        LAPACK's info: 0, or i > 0 if U(i, i) is exactly zero (getrs_rows then gives inf or nan) [-].
    """
    return _dgetrf(100, n, n, A.ctypes, A.shape[1], piv.ctypes)  # 100: ord('d'), double precision


@njit(cache=True, error_model="numpy")
def getrs_rows(A, n, piv, B):
    """Solve (the leading n x n block of the original A) X = B[:n] with getrf_rows' factors, in place:
    U^T Y = B (forward), L^T W = Y (backward, unit diagonal), X = P^T W (the exchanges undone in reverse).

    Parameters
    ----------
    A : (>= n, m) float64 ndarray
        The factors of getrf_rows [any unit].
    n : int
        The order [-].
    piv : (>= n,) int32 ndarray
        The row exchanges of getrf_rows [-].
    B : (>= n, k) float64 ndarray
        The right-hand sides [any unit]; overwritten by the solution.

    Returns
    -------
    None
        X [unit of B / unit of A] is left in B.
    """
    k = B.shape[1]
    for c in range(k):
        for i in range(n):
            acc = B[i, c]
            for j in range(i):
                acc -= A[i, j] * B[j, c]
            B[i, c] = acc / A[i, i]
        for i in range(n - 1, -1, -1):
            acc = B[i, c]
            for j in range(i + 1, n):
                acc -= A[i, j] * B[j, c]
            B[i, c] = acc
        for i in range(n - 1, -1, -1):
            p = piv[i] - 1
            if p != i:
                B[i, c], B[p, c] = B[p, c], B[i, c]
