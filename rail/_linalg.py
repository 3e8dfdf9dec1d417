"""Small dense solves compiled with numba, shared by the contact march and the wavenumber tables."""

from __future__ import annotations

from ._lazyjit import njit

__all__ = ["solve_in_place"]


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
