"""Moving harmonic loads on the periodically supported rail: the wavenumber method (report ref. [18]).

A load F exp(i Omega t) moves at speed V along the rail (position V t, a support at x = 0 at
t = 0).  The rail displacement at the load, and at points moving with it at offsets d, is

    w(V t + d, t) = F exp(i Omega t) sum_n a_n(Omega, d) exp(i n Omega_0 t),  Omega_0 = 2 pi V / L,

with (docs/track.md, derived by a space-time Fourier transform and Poisson summation)::

    a_n(Omega, d) = delta_n0 / (2 pi) int g_0(beta) e^{-i beta d} d beta
                    - 1 / (2 pi L) int w(beta) g_0(beta) g_n(beta) e^{-i (beta - n beta0) d} d beta,
    g_j(beta) = H(beta - j beta0, omega),  omega = Omega + beta V,
    w(beta)   = L K_s(omega) / (L + K_s(omega) S(beta, omega)).

For Omega = k Omega_0 the shift beta -> beta + k beta0 maps every harmonic onto one table of
h_j(beta) = H(beta - j beta0, beta V): the whole receptance matrix for the periodic problem,

    A_d[p, k] = a_{p-k}(k Omega_0, d) = delta_pk / (2 pi) int h_k e_k^d - 1/(2 pi L) int w h_k h_p e_p^d,

(e_j^d = exp(-i (beta - j beta0) d)) comes from a single weighted Gram product.  The diagonal is
integrated in the combined form h (L + K_s (S - h)) / (L + K_s S), in which the divergences of
the free-rail term and the support term at the static point (beta -> 0, omega -> 0) cancel.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._lazyjit import njit
from ._linalg import solve_in_place
from .quadrature import adaptive_panels, filon_weights
from .cell import TrackCell, cell_sum_matrix, point_stiffness
from .track import Track, damping_problem, free_receptance, rail_stiffnesses

__all__ = ["MovingReceptance", "receptance_table", "bloch_tables", "cell_receptance_table", "moving_coefficients", "critical_speed"]


@dataclass(frozen=True)
class MovingReceptance:
    """Receptance matrices of the moving-load problem at one speed.

    Attributes
    ----------
    speed : V, m/s
    harmonics : K; rows p and columns k run over -K..K (fraction 0) or -K..K-1 (fraction > 0, so
                that the frequencies (k + nu) Omega_0 of the classes nu and 1 - nu mirror each other)
    offsets : d, m (0 = at the load)
    A : complex (offset, p, k), m/N: response at (p + nu) Omega_0 at offset d per unit force
                at (k + nu) Omega_0, A_d[p, k] = a_{p-k}((k + nu) Omega_0, d)
    error : upper bound of the absolute quadrature error of A (same shape), m/N: the error of
                the rule with half the nodes; the result's own error is far smaller (docs/track.md)
    nodes : number of wavenumber quadrature nodes
    fraction : Bloch fraction nu in [0, 1) of the base frequency nu Omega_0 (0: bay-periodic loads)
    bays : N, the track's cell in bays (rail.cell): the harmonics are then of the cell
                frequency Omega_P = Omega_0 / N and ``harmonics`` counts them (N K)
    supports : positions of the cell's point attachments in the period [m] (None: the uniform track)
    """

    speed: float
    harmonics: int
    offsets: np.ndarray
    A: np.ndarray
    error: np.ndarray
    nodes: int
    fraction: float = 0.0
    bays: int = 1
    supports: tuple | None = None

    @property
    def indices(self) -> np.ndarray:
        """The harmonic indices k of the rows and columns."""
        K = self.harmonics
        return np.arange(-K, K + (1 if self.fraction == 0 else 0))

    def a(self, n: int, k: int, offset_index: int = 0) -> complex:
        """a_n(k Omega_0, d): needs abs(k) <= K and abs(k + n) <= K."""
        K = self.harmonics
        hi = K if self.fraction == 0 else K - 1
        if not (-K <= k <= hi and -K <= k + n <= hi):
            raise ValueError(f"a_n((k + nu) Omega_0) with n = {n}, k = {k} needs k and k + n in [{-K}, {hi}].")
        return complex(self.A[offset_index, k + n + K, k + K])


@njit(cache=True, error_model="numpy")
def _free_column(b, EI, kGA, inertia, rhoA_w2):
    """H(b, omega) of rail.track.free_receptance in real arithmetic: (real, imaginary) [m^2/N], with
    EI, kGA [N m^2, N] complex, inertia = rho I omega^2 [N] and rhoA_w2 = rho A omega^2 [N/m^2]."""
    b2 = b * b
    br, bi = EI.real * b2 - inertia, EI.imag * b2  # EI beta^2 - rho I omega^2
    nr, ni = br + kGA.real, bi + kGA.imag  # the numerator, + kappa G A
    tr, ti = kGA.real * b2, kGA.imag * b2
    dr = tr * br - ti * bi - rhoA_w2 * nr
    di = tr * bi + ti * br - rhoA_w2 * ni
    inv = 1.0 / (dr * dr + di * di)
    return (nr * dr + ni * di) * inv, (ni * dr - nr * di) * inv


@njit(cache=True, error_model="numpy")
def _uniform_entry(b, EI, kGA, inertia, rhoA_w2, cr, ci, invP):
    """One entry of the uniform track's tables: h = H(b, omega) (``_free_column``), the reaction
    y = c h (c = cr + i ci [N/m]) and the diagonal integrand h - h y / P (invP = 1 / P [1/m]), each as
    (real, imaginary): (gr, gi, yr, yi, dr, di)."""
    gr, gi = _free_column(b, EI, kGA, inertia, rhoA_w2)
    yr, yi = cr * gr - ci * gi, cr * gi + ci * gr
    return gr, gi, yr, yi, gr - (gr * yr - gi * yi) * invP, gi - (gr * yi + gi * yr) * invP


@njit(cache=True, error_model="numpy")
def _uniform_columns(beta, js, bP, EI, kGA, inertia, rhoA_w2, coef, P):
    """The uniform track's node tables in one pass (``_node_tables`` with one support at x = 0).

    h_j = H(beta - j beta_P, omega) (rail.track.free_receptance's formula), the reactions Y_j = c h_j
    with c = K_s / (1 + K_s S / P) per node, and the diagonal integrands h_j - h_j Y_j / P, in real
    arithmetic without numpy's ten temporaries of nodes x columns. The numbers are numpy's to rounding
    (a few 1e-16 of each h_j; tests/test_track.py), not bit for bit: numpy's complex product and
    quotient round differently (its product uses fused multiply-adds where the CPU has them).

    Parameters
    ----------
    beta : (n,) float
        The nodes [rad/m].
    js : (J,) int
        The columns j [-].
    bP : float
        beta_P [rad/m].
    EI, kGA : (n,) complex
        The rail's bending and shear stiffness at omega = Omega + beta V [N m^2, N].
    inertia, rhoA_w2 : (n,) float
        rho I omega^2 [N] and rho A omega^2 [N/m^2].
    coef : (n,) complex
        c [N/m]; 0 where the caller replaces the node (the static point).
    P : float
        The period [m].

    Returns
    -------
    G : (n, J) complex [m^2/N];  Y : (n, J) complex [m/N];  diag : (n, J) complex [m^2/N]
    """
    n, J = beta.shape[0], js.shape[0]
    G = np.empty((n, J), dtype=np.complex128)
    Y = np.empty((n, J), dtype=np.complex128)
    diag = np.empty((n, J), dtype=np.complex128)
    invP = 1.0 / P
    for i in range(n):
        cr, ci = coef[i].real, coef[i].imag
        for j in range(J):
            gr, gi, yr, yi, dr, di = _uniform_entry(beta[i] - js[j] * bP, EI[i], kGA[i], inertia[i], rhoA_w2[i], cr, ci, invP)
            G[i, j] = complex(gr, gi)
            Y[i, j] = complex(yr, yi)
            diag[i, j] = complex(dr, di)
    return G, Y, diag


@njit(cache=True, error_model="numpy")
def _uniform_proxy(beta, js, bP, EI, kGA, inertia, rhoA_w2, coef, P, jac, c0):
    """What the adaptive rule follows on the uniform track, times the map's Jacobian ``jac`` (n,):
    every column's diagonal integrand and the reactions to the central column ``c0``, shape (n, J + 1),
    as ``_uniform_columns`` computes them (the same numbers) without forming G and Y."""
    n, J = beta.shape[0], js.shape[0]
    out = np.empty((n, J + 1), dtype=np.complex128)
    invP = 1.0 / P
    for i in range(n):
        cr, ci = coef[i].real, coef[i].imag
        w = jac[i]
        for j in range(J):
            gr, gi, yr, yi, dr, di = _uniform_entry(beta[i] - js[j] * bP, EI[i], kGA[i], inertia[i], rhoA_w2[i], cr, ci, invP)
            out[i, j] = complex(dr * w, di * w)
            if j == c0:
                out[i, J] = complex(yr * w, yi * w)
    return out


@njit(cache=True, error_model="numpy")
def _cell_columns(beta, js, bP, EI, kGA, inertia, rhoA_w2, eb, ej, Kq, S, P):
    """A track cell's node tables in one pass per node (``_node_tables`` with several attachments).

    Per node: h_j = H(beta - j beta_P, omega) (``_free_column``), the phases
    e_qj = exp(i (beta - j beta_P) s_q) = eb[q] ej[q, j], the row factors U = h e, the attachments'
    reactions Y = (I + diag(K) S / P)^-1 diag(K) (h / e) (one small LU per node, every column
    solved with it) and the diagonal integrands h_j - sum_q U_qj Y_qj / P.

    Parameters
    ----------
    beta : (n,) float [rad/m];  js : (J,) int;  bP : beta_P [rad/m]
    EI, kGA : (n,) complex [N m^2, N];  inertia, rhoA_w2 : (n,) float [N, N/m^2]
    eb : (n, Q) complex, exp(i beta s_q);  ej : (Q, J) complex, exp(-i j beta_P s_q)
    Kq : (n, Q) complex, the attachments' stiffnesses [N/m];  S : (n, Q, Q) complex, the lattice sums [m^2/N]
    P : the cell's length [m]

    Returns
    -------
    G : (n, J);  diag : (n, J);  U, Y : (n, Q, J), complex
    """
    n, J, Q = beta.shape[0], js.shape[0], eb.shape[1]
    G = np.empty((n, J), dtype=np.complex128)
    diag = np.empty((n, J), dtype=np.complex128)
    U = np.empty((n, Q, J), dtype=np.complex128)
    Y = np.empty((n, Q, J), dtype=np.complex128)
    A = np.empty((Q, Q), dtype=np.complex128)
    B = np.empty((Q, J), dtype=np.complex128)
    invP = 1.0 / P
    for i in range(n):
        for j in range(J):
            gr, gi = _free_column(beta[i] - js[j] * bP, EI[i], kGA[i], inertia[i], rhoA_w2[i])
            G[i, j] = complex(gr, gi)
        for q in range(Q):
            for r in range(Q):
                A[q, r] = (1.0 if q == r else 0.0) + Kq[i, q] * S[i, q, r] * invP
            for j in range(J):
                e = eb[i, q] * ej[q, j]
                g = G[i, j]
                U[i, q, j] = g * e
                B[q, j] = Kq[i, q] * (g * e.conjugate())  # h / e: abs(e) = 1
        solve_in_place(A, B)
        for j in range(J):
            acc = 0j
            for q in range(Q):
                Y[i, q, j] = B[q, j]
                acc += U[i, q, j] * B[q, j]
            diag[i, j] = G[i, j] - acc * invP
    return G, diag, U, Y


def _free_scalars(beta, omega, js, cell: TrackCell):
    """The free rail's per-node arguments of the compiled columns (``_uniform_columns``,
    ``_uniform_proxy``, ``_cell_columns``): beta, js, beta_P, EI, kGA, rho I omega^2, rho A omega^2."""
    EI, kGA = rail_stiffnesses(cell.track, omega)
    r = cell.track.rail
    return (np.ascontiguousarray(beta, dtype=float), np.ascontiguousarray(js, dtype=np.int64), float(cell.beta_p),
            np.ascontiguousarray(EI, dtype=complex), np.ascontiguousarray(kGA, dtype=complex),
            r.density * r.second_moment_of_area * omega**2, r.density * r.area * omega**2)


def _support_coef(beta, omega, Kq, far, cell: TrackCell):
    """The uniform track's c = K_s / (1 + K_s S / P) per node [N/m]; 0 at the nodes not ``far``, which
    the static point's formula replaces."""
    coef = np.zeros(len(beta), dtype=complex)
    if far.any():
        S = cell_sum_matrix(beta[far], omega[far], cell)
        coef[far] = (Kq[far] / (1 + Kq[far] * S[:, :, 0] / cell.period))[:, 0]
    return coef


def _near_static(beta, static_j, bP):
    """The nodes within half a cell wavenumber of the static point beta = static_j beta_P (none if
    static_j is None), where ``_node_tables`` takes the divergent lattice term out of S."""
    if static_j is None:
        return np.zeros(len(beta), dtype=bool)
    return np.abs(beta - static_j * bP) < bP / 2


def _rotational_tables(beta, Omega, V, js, cell: TrackCell, static_j):
    """``_node_tables`` of the uniform track whose pads have a rotational stiffness (Pad.rotational_stiffness).

    Each support acts on the rail with a force and a moment: two channels q at x = 0, the force (q = 0, on w)
    and the moment (q = 1, on psi). With the free rail's 2 x 2 receptance H = [[H_ww, H_wM], [H_psiF, H_psiM]]
    (rail.track.free_beam_receptances) and its lattice sum S (rail.track.beam_lattice_sums), the reactions
    to column k are Y_k = P (C + S)^-1 v_k, C = diag(P / K_s, P / k_theta), v_k = (H_ww, H_psiF)(beta - k beta0),
    and the rows U_p = (H_ww, H_wM)(beta - p beta0): the scalar formula of docs/track.md with 2 x 2 blocks.

    Near the static point (beta' = beta - static_j beta0 -> 0 with omega -> 0) the m = 0 term H_0 of S diverges;
    with B = C + S - H_0 and D_0 = H_0^-1 (the free rail's dynamic stiffness, a polynomial) the static column's
    reactions are P (I + D_0 B)^-1 e_0, its row P [(I + B D_0)^-1 v_k]_0 and its diagonal [(I + B D_0)^-1 B]_00,
    each finite (H_0 - H_0 (B + H_0)^-1 H_0 = (I + B D_0)^-1 B). S - H_0 is formed without H_0
    (rail.track.beam_lattice_sums_excluding): as the closed form minus H_0 it lost the digits of S to the
    cancellation, an error the integral near the static point magnified as the adaptive rule refined there.
    Returns as ``_node_tables`` (U and Y with two channels).
    """
    from .track import beam_lattice_sums, beam_lattice_sums_excluding, free_beam_receptances, support_rotational_stiffness, support_stiffness

    t = cell.track
    P, bP = cell.period, cell.beta_p
    omega = Omega + beta * V
    b = beta[:, None] - js[None, :] * bP
    Hww, HwM, HpF, HpM = free_beam_receptances(b, omega[:, None], t)
    Sww, SwM, SpF, SpM = beam_lattice_sums(beta, omega, t)
    n, J = len(beta), len(js)
    Cm = np.zeros((n, 2, 2), dtype=complex)
    Cm[:, 0, 0] = P / support_stiffness(t, omega)
    Cm[:, 1, 1] = P / support_rotational_stiffness(t, omega)
    S = np.stack([np.stack([Sww, SwM], -1), np.stack([SpF, SpM], -1)], -2)  # (n, 2, 2) [response, load]
    U = np.stack([Hww, HwM], 1)  # (n, 2, J): w at the load per unit support force, moment
    Vv = np.stack([Hww, HpF], 1)  # (n, 2, J): w, psi at the support per unit load
    Y = P * np.linalg.solve(Cm + S, Vv)
    diag = Hww - np.einsum("nqj,nqj->nj", U, Y) / P
    near = _near_static(beta, static_j, bP)
    row = None
    if near.any():
        col = int(np.where(js == static_j)[0][0])
        Xww, XwM, XpF, XpM = beam_lattice_sums_excluding(b[near, col], omega[near], t)  # S - H_0, formed without H_0
        B = Cm[near] + np.stack([np.stack([Xww, XwM], -1), np.stack([XpF, XpM], -1)], -2)
        bn, on = b[near, col], omega[near]
        EI, kGA = rail_stiffnesses(t, on)
        r = t.rail
        D0 = np.empty((len(bn), 2, 2), dtype=complex)
        D0[:, 0, 0] = kGA * bn**2 - r.density * r.area * on**2
        D0[:, 0, 1] = -1j * bn * kGA
        D0[:, 1, 0] = 1j * bn * kGA
        D0[:, 1, 1] = EI * bn**2 + kGA - r.density * r.second_moment_of_area * on**2
        eye = np.eye(2)[None]
        left = np.linalg.inv(eye + B @ D0)  # (I + B D_0)^-1 = H_0 (B + H_0)^-1
        right = np.linalg.inv(eye + D0 @ B)  # (I + D_0 B)^-1 = (B + H_0)^-1 H_0
        Yn = Y[near]
        Yn[:, :, col] = P * right[:, :, 0]
        Y[near] = Yn
        row = np.zeros((n, J), dtype=complex)
        row[near] = P * np.einsum("nq,nqj->nj", left[:, 0, :], Vv[near])
        row[near, col] = 0.0
        Un = U[near].copy()
        Un[:, :, col] = 0.0
        dn = Hww[near] - np.einsum("nqj,nqj->nj", Un, Yn) / P
        dn[:, col] = (left @ B)[:, 0, 0]
        diag[near] = dn
    return Hww, diag, U, Y, row, near


def _node_tables(beta, Omega, V, js, cell: TrackCell, static_j, compiled: bool = True):
    """Everything the wavenumber integrands need at the nodes ``beta`` (docs/track.md, "A cell of N bays").

    h_j = H(beta - j beta_P, omega), omega = Omega + beta V, for the columns ``js``; the reactions of
    the cell's attachments to a unit load of every column, Y[:, q, k] = (I + diag(K) S / P)^-1 diag(K) v_k
    with v_k[l] = h_k exp(-i (beta - k beta_P) s_l); the row factors U[:, q, p] = h_p exp(i (beta - p beta_P) s_q),
    so that the support part of A[p, k] integrates -(1 / 2 pi P) sum_q U[q, p] Y[q, k]; and each
    column's whole diagonal integrand h_k - sum_q U[q, k] Y[q, k] / P.

    ``static_j``: the column whose h diverges at the static point (beta = static_j beta_P, omega = 0),
    or None.  Within half a cell wavenumber of it the divergent lattice term is taken out of S and
    put back by the Sherman-Morrison formula, so that no quantity there is formed from the
    difference of two large ones: with B = I + diag(K) S' / P (S' without it), a = exp(-i beta' s),
    b = exp(i beta' s), z = B^-1 diag(K) a and c = b^T z, the static column's diagonal is
    h / (1 + h c / P), its reactions h z / (1 + h c / P), and its row b^T B^-1 diag(K) v_k h / (1 + h c / P).
    For one support this is the combined form h (L + K_s (S - h)) / (L + K_s S) of the uniform track.

    The uniform track (one support at x = 0) takes its columns from a compiled loop
    (``_uniform_columns``: numpy's numbers to rounding, without numpy's temporaries), and so does a
    cell at the nodes away from its static point (``_cell_columns``: a small LU per node);
    ``compiled=False`` forms them with numpy (for tests).

    Returns
    -------
    G : (n, J) h_j;  diag : (n, J) diagonal integrands;  U, Y : (n, Q, J);
    row : (n, J) or None, the static column's row (replacing U[:, :, static] . Y at the near nodes);
    near : (n,) bool
    """
    P, bP = cell.period, cell.beta_p
    s = cell.positions
    if cell.track.pad.rotational_stiffness > 0:  # the pads' moment springs: the uniform track only
        if not (len(s) == 1 and s[0] == 0.0):
            raise ValueError("track.pad.rotational_stiffness > 0 is not carried on a track cell (track.cell): "
                             "the moving-load tables hold it on the uniform track only.")
        return _rotational_tables(beta, Omega, V, js, cell, static_j)
    omega = Omega + beta * V
    Kq = point_stiffness(cell, omega)  # (n, Q)
    uniform = len(s) == 1 and s[0] == 0.0
    n, Q, J = len(beta), len(s), len(js)
    near = _near_static(beta, static_j, bP)
    far = ~near
    eye = np.eye(Q)
    if uniform and compiled:
        G, Y2, diag = _uniform_columns(*_free_scalars(beta, omega, js, cell), _support_coef(beta, omega, Kq, far, cell), float(P))
        U = Vv = G[:, None, :]
        Y = Y2[:, None, :]
    elif compiled and not near.any():  # a cell, every node away from the static point
        eb = np.exp(1j * beta[:, None] * s[None, :])
        ej = np.exp(-1j * bP * np.outer(s, js))
        G, diag, U, Y = _cell_columns(*_free_scalars(beta, omega, js, cell), eb, ej, np.ascontiguousarray(Kq, dtype=complex),
                                      np.ascontiguousarray(cell_sum_matrix(beta, omega, cell), dtype=complex), float(P))
        return G, diag, U, Y, None, near
    else:
        G = free_receptance(beta[:, None] - js[None, :] * bP, omega[:, None], cell.track)
        if uniform:  # no phases
            U = Vv = G[:, None, :]
        else:  # exp(i (beta - j beta_P) s_q) as the product of two small tables
            eplus = np.exp(1j * beta[:, None] * s[None, :])[:, :, None] * np.exp(-1j * bP * np.outer(s, js))[None]
            U = G[:, None, :] * eplus
            Vv = G[:, None, :] / eplus
        Y = np.empty_like(U)
        if far.any():
            S = cell_sum_matrix(beta[far], omega[far], cell)
            if Q == 1:
                Y[far] = (Kq[far] / (1 + Kq[far] * S[:, :, 0] / P))[:, :, None] * Vv[far]
            else:
                Mx = eye[None] + Kq[far][:, :, None] * S / P
                Y[far] = np.linalg.solve(Mx, Kq[far][:, :, None] * Vv[far])
        diag = np.empty((n, J), dtype=complex)
        diag[far] = G[far] - (U[far][:, 0] * Y[far][:, 0] if Q == 1 else np.einsum("nqj,nqj->nj", U[far], Y[far])) / P
    row = None
    if near.any():
        col = int(np.where(js == static_j)[0][0])
        bn, on = beta[near] - static_j * bP, omega[near]
        Sx = cell_sum_matrix(bn, on, cell, exclude_zero=True)
        Kn = Kq[near]
        B = eye[None] + Kn[:, :, None] * Sx / P
        a = np.exp(-1j * bn[:, None] * s[None, :])
        rhs = np.concatenate([(Kn * a)[:, :, None], Kn[:, :, None] * Vv[near]], axis=2)
        Z = np.linalg.solve(B, rhs)
        z, Zk = Z[:, :, 0], Z[:, :, 1:]
        b = 1.0 / a
        c = np.sum(b * z, axis=1)
        t = np.einsum("nq,nqj->nj", b, Zk)
        h = G[near, col]
        gam = h / (P + h * c)  # (h / P) / (1 + h c / P), finite as h -> inf
        Yn = Zk - z[:, :, None] * (gam[:, None] * t)[:, None, :]
        Yn[:, :, col] = P * gam[:, None] * z
        Y[near] = Yn
        row = np.zeros((n, J), dtype=complex)
        row[near] = P * gam[:, None] * t
        row[near, col] = 0.0
        Un = U[near].copy()
        Un[:, :, col] = 0.0
        diag[near] = G[near] - np.einsum("nqj,nqj->nj", Un, Yn) / P
        diag[near, col] = P * gam
    return G, diag, U, Y, row, near


def _edges_theta(Bmap, points, cut=None, panels=96):
    """Initial panel edges in theta (beta = Bmap tan theta), with the given beta breakpoints."""
    th = list(np.linspace(-np.pi / 2, np.pi / 2, panels + 1))
    for b in points:
        th.append(np.arctan(b / Bmap))
    if cut is not None:
        th += [np.arctan(-cut / Bmap), np.arctan(cut / Bmap), np.arctan(-2 * cut / Bmap), np.arctan(2 * cut / Bmap)]
    return np.unique(np.array(th))


def _taper(beta, cut):
    """Window for the transfer (d != 0) integrals: 1 for |beta| <= cut, cos^2 down to 0 at 2 cut.

    An abrupt truncation of an oscillating integrand leaves an error f(cut) / d; the C^1 window
    removes that boundary term, leaving O(f / (d^3 cut^2)).
    """
    u = np.clip((np.abs(beta) - cut) / cut, 0.0, 1.0)
    return np.cos(0.5 * np.pi * u) ** 2


def _filon_segments(q, to_beta, order, limit):
    """Half-panels of the adaptive rule q (in theta) that lie inside |beta| < limit, in beta:
    (node index (S, order), segment starts, segment ends)."""
    a, b = q.edges[:, 0], q.edges[:, 1]
    m = 0.5 * (a + b)
    ends = np.concatenate([np.stack([a, m], 1), np.stack([m, b], 1)])
    ends = ends[np.argsort(ends[:, 0])]  # the half-panels in order, each [start, end] kept together
    idx = np.arange(len(q.nodes)).reshape(len(ends), order)
    ba, bb = to_beta(ends[:, 0])[0], to_beta(ends[:, 1])[0]
    inside = np.abs(0.5 * (ba + bb)) < limit
    return idx[inside], ba[inside], bb[inside]


def _integrate(cell: TrackCell, V, Omega, js, offsets, static_j, rtol, cut, order=16, max_panels=40000, block=None, filon=True,
               progress=None, compiled=True):
    """Adaptive wavenumber quadrature of the receptance matrices (shared by the table and the
    single-frequency coefficients).  Returns (A, error, nodes).

    The harmonics ``js`` are of the cell wavenumber beta_P = 2 pi / P (for the uniform track, the
    cell of one support: beta0).  The rule adapts to the smooth factors of the integrands only
    (every column's diagonal integrand and the reactions to the central column); the oscillating
    factor exp(-i beta d) of an offset d != 0 is integrated exactly against the piecewise
    polynomial interpolant of those factors on the same nodes (Filon weights,
    rail.quadrature.filon_weights), so the cost does not grow with |d| (docs/track.md,
    "Quadrature"). ``filon=False`` multiplies the Gauss weights by exp(-i beta d) instead (for tests:
    on the nodes of the d = 0 rule that aliases the oscillation of a far offset).  The node tables
    are evaluated in blocks of ``block`` nodes (default: about 2**21 / (attachments x columns)), so
    memory does not grow with the node count. ``progress``, if given, is called with one line of text
    per refinement pass of the rule and per block of the Gram products ("<i> of <n> node blocks, ...").
    ``compiled=False`` forms the node tables with numpy (``_node_tables``; for tests)."""
    b0, P = cell.beta_p, cell.period
    offsets = np.asarray(offsets, dtype=float)
    J = len(js)
    Q = len(cell.positions)
    if block is None:
        block = int(min(4096, max(64, 2**21 // (Q * J))))
    Bmap = (np.max(np.abs(js)) + 4) * b0
    beta_s = -Omega / V  # where omega = 0: hysteretic damping changes sign
    has_offsets = np.any(offsets != 0)
    c0 = int(np.argmin(np.abs(js)))
    uniform = Q == 1 and cell.positions[0] == 0.0 and cell.track.pad.rotational_stiffness == 0  # rail.moving._uniform_columns

    def to_beta(th):
        return Bmap * np.tan(th), Bmap / np.cos(th) ** 2

    passes = [0]

    def proxy(th):
        if progress is not None:
            passes[0] += 1
            progress(f"wavenumber rule: refinement pass {passes[0]}, {len(th)} new nodes")
        # diagonal integrands (free-wave peaks of every column) and the reactions to the central
        # column (Floquet-wave peaks) carry every feature of the off-diagonal integrands
        out = []
        for lo in range(0, len(th), block):
            beta, jac = to_beta(th[lo : lo + block])
            if compiled and uniform and not _near_static(beta, static_j, b0).any():
                omega = Omega + beta * V
                far = np.ones(len(beta), dtype=bool)
                coef = _support_coef(beta, omega, point_stiffness(cell, omega), far, cell)
                out.append(_uniform_proxy(*_free_scalars(beta, omega, js, cell), coef, float(P),
                                          np.ascontiguousarray(jac, dtype=float), c0))
                continue
            G, diag, U, Y, row, near = _node_tables(beta, Omega, V, js, cell, static_j, compiled)
            out.append(np.concatenate([diag, Y[:, 0, c0][:, None]], axis=1) * jac[:, None])
        return np.concatenate(out)

    edges = _edges_theta(Bmap, [beta_s], cut if has_offsets else None)
    q = adaptive_panels(proxy, edges, rtol=rtol, order=order, max_panels=max_panels)
    th, wt = q.nodes, q.weights
    beta, jac = to_beta(th)
    # weights per offset: Gauss (d = 0) or Filon times the taper (d != 0, zero beyond 2 cut)
    W = np.zeros((len(offsets), len(th)), dtype=complex)
    W[offsets == 0] = wt * jac
    if has_offsets:
        seg, sa, sb = _filon_segments(q, to_beta, order, 2 * cut)
        taper = _taper(beta[seg], cut)
        for i, d in enumerate(offsets):
            if d != 0 and filon:
                W[i, seg] = filon_weights(beta[seg], sa, sb, d) * taper
            elif d != 0:
                W[i, seg] = (wt * jac)[seg] * np.exp(-1j * beta[seg] * d) * taper
    # the Gram products in blocks of nodes: memory bounded by the block, not by the node count
    M = np.zeros((len(offsets), J, J), dtype=complex)
    D = np.zeros((len(offsets), J), dtype=complex)
    n_blocks = -(-len(th) // block)
    for lo in range(0, len(th), block):
        if progress is not None:
            progress(f"{lo // block} of {n_blocks} node blocks (Gram products over {len(th)} nodes, {J} columns, "
                     f"{len(offsets)} offsets)")
        sl = slice(lo, lo + block)
        G, diag, U, Y, row, near = _node_tables(beta[sl], Omega, V, js, cell, static_j, compiled)
        D += W[:, sl] @ diag
        if row is not None and near.any():
            U[near, :, int(np.where(js == static_j)[0][0])] = 0.0
        n, Qn = U.shape[0], U.shape[1]  # Qn: the attachments, or 2 channels with the pads' moment springs
        Yf = Y.reshape(n * Qn, J)
        for i in range(len(offsets)):
            M[i] += (U * W[i, sl][:, None, None]).reshape(n * Qn, J).T @ Yf  # M[p, k] = int sum_q u_p^q Y_k^q e^d_p
            if row is not None and near.any():
                M[i, int(np.where(js == static_j)[0][0])] += W[i, sl] @ row
    if progress is not None:
        progress(f"{n_blocks} of {n_blocks} node blocks (Gram products over {len(th)} nodes, {J} columns, {len(offsets)} offsets)")
    A = -M / (2 * np.pi * P)  # A[p, k]
    A[:, np.arange(J), np.arange(J)] = D / (2 * np.pi)
    A *= np.exp(1j * js[None, :] * b0 * offsets[:, None])[:, :, None]  # row factor exp(i p beta_P d)
    # Error bound: the proxies' |coarse - fine| per panel (the error of the rule with half the
    # nodes), relative to each proxy, applied to every entry of a column on the scale of that
    # column: the larger of the entry and the column's diagonal at d = 0 (the proxy integral).
    # An entry far below its column's scale (a far offset, a distant harmonic) has an absolute
    # error set by the column, not by itself. The fine rule actually used is far more accurate
    # (measured in tests/test_track.py against rtol = 1e-7 and in docs/track.md).
    rel = np.max(q.error / np.maximum(np.abs(q.integral), 1e-300))
    column = np.abs(q.integral[:J]) / (2 * np.pi)
    err = np.maximum(np.abs(A), column[None, None, :]) * rel
    err = err + (0 if q.converged else np.inf)
    return A, err, len(th)


def receptance_table(
    track: Track, speed: float, harmonics: int, offsets=(0.0,), rtol: float = 1e-4, transfer_cut: float | None = None,
    fraction: float = 0.0, progress=None,
) -> MovingReceptance:
    """Receptance matrices A_d[p, k] = a_{p-k}((k + nu) Omega_0, d) at one speed.

    With the Bloch fraction nu = 0 (default) abs(p), abs(k) <= K: loads periodic over one bay. With
    0 < nu < 1, p, k = -K..K-1: the class of loads at frequencies (k + nu) Omega_0, which a roughness
    periodic over N bays excites for nu = r / N (docs/track.md, "Roughness periodic over N bays").
    The base frequency nu Omega_0 enters the same single Gram product (g_j(beta) = H(beta - j beta0,
    nu Omega_0 + beta V)); for 0 < nu < 1 no column has a static point.

    The moving-load coefficients a_n of the module docstring for every harmonic k Omega_0 of the
    sleeper-passing frequency, from a single adaptive wavenumber quadrature (docs/track.md, "One
    table for every harmonic").

    Parameters
    ----------
    track : Track
        The track; its rail damping must be large enough (``rail.track.damping_problem``).
    speed : float
        Speed V [m/s], > 0.
    harmonics : int
        Number of harmonics K [-], >= 0.
    offsets : sequence of float, optional
        Offsets d [m] of points moving with the load (other wheels: d = position of the receiving
        wheel minus that of the loading one); default (0.0,), at the load.
    rtol : float, optional
        Relative tolerance of the adaptive wavenumber quadrature [-]; default 1e-4.
    transfer_cut : float, optional
        Start of the cos^2 window of the d != 0 integrands [rad/m]; default (K + 12) beta0.
    fraction : float, optional
        Bloch fraction nu [-] in [0, 1); default 0.
    progress : callable, optional
        Called with one line of text per refinement pass of the quadrature and per block of nodes of
        the Gram products ("<i> of <n> node blocks ..."); default None, silent.

    Returns
    -------
    MovingReceptance
        The matrices A [m/N], shape (offset, 2K + 1, 2K + 1), with their error bound [m/N] and the
        number of quadrature nodes.

    Raises
    ------
    ValueError
        If speed <= 0 (use rail.track.stationary_receptance for V = 0), if harmonics is not an
        integer >= 0, or if the rail damping is too small (``rail.track.damping_problem``).
    """
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it must be a finite number > 0 (use rail.track.stationary_receptance for V = 0).")
    if not (np.isfinite(rtol) and 0 < rtol < 1):
        raise ValueError(f"rtol = {rtol!r} is not allowed: the quadrature tolerance must lie in (0, 1).")
    if int(harmonics) != harmonics or harmonics < 0:
        raise ValueError(f"harmonics = {harmonics!r} is not allowed: it must be an integer >= 0.")
    if (problem := damping_problem(track)) is not None:
        raise ValueError(problem)
    if not (np.isfinite(fraction) and 0.0 <= fraction < 1.0):
        raise ValueError(f"fraction = {fraction!r} is not allowed: the Bloch fraction must lie in [0, 1).")
    K = int(harmonics)
    js = np.arange(-K, K + (1 if fraction == 0 else 0))
    offsets = np.atleast_1d(np.asarray(offsets, dtype=float))
    cut = (K + 12) * track.beta0 if transfer_cut is None else float(transfer_cut)
    Omega = fraction * track.beta0 * speed
    A, err, n = _integrate(TrackCell.uniform(track), speed, Omega, js, offsets, 0 if fraction == 0 else None, rtol, cut,
                           progress=progress)
    return MovingReceptance(float(speed), K, offsets, A, err, n, float(fraction))


def bloch_tables(track: Track, speed: float, harmonics: int, bays: int, offsets=(0.0,), rtol: float = 1e-4, progress=None):
    """The receptance tables a roughness periodic over N bays needs: fractions nu = r / N for
    r = 0..floor(N/2) (the classes r > N/2 are the complex conjugates of N - r for a real load).

    Parameters
    ----------
    track : Track
    speed : float
        Speed V [m/s], > 0.
    harmonics : int
        K [-]: the force frequencies (k + nu) Omega_0 reach abs(K Omega_0).
    bays : int
        N, the roughness period in bays [-], >= 1.
    offsets : sequence of float
        Offsets d [m] between the wheels.
    rtol : float
        Relative tolerance of the wavenumber quadrature [-].
    progress : callable, optional
        Called with one line of text after each table ("<i> of <n> tables, ..."); default None, silent.

    Returns
    -------
    tuple of MovingReceptance
        One table per r = 0..floor(N/2) [m/N].
    """
    if int(bays) != bays or bays < 1:
        raise ValueError(f"roughness.bays = {bays!r} is not allowed: it must be an integer >= 1.")
    n = int(bays) // 2 + 1
    out = []
    for r in range(n):
        out.append(receptance_table(track, speed, harmonics, offsets, rtol, fraction=r / bays))
        if progress is not None:
            progress(f"{r + 1} of {n} tables (Bloch fraction {r}/{int(bays)}, {out[-1].nodes} nodes)")
    return tuple(out)


def cell_receptance_table(cell: TrackCell, speed: float, harmonics: int, offsets=(0.0,), rtol: float = 1e-4,
                          transfer_cut: float | None = None, progress=None) -> MovingReceptance:
    """Receptance matrices of a track periodic over a cell of N bays (docs/track.md, "A cell of N bays").

    The loads and responses are periodic over the cell: frequencies q Omega_P, Omega_P = 2 pi V / P,
    abs(q) <= N K, so the force harmonics reach K Omega_0 as on the uniform track (Omega_0 = 2 pi V / L,
    L = P / N).  A_d[p, q] = a_{p-q}(q Omega_P, d) with the cell's reactions in the support term
    (one N x N solve per wavenumber node).  For a cell of one support this is
    ``receptance_table``; for N identical supports at equal spacing its entries with p = q (mod N)
    are those of the Bloch tables of rail.moving.bloch_tables and the others vanish.

    Parameters
    ----------
    cell : TrackCell
    speed : float
        V [m/s], > 0.
    harmonics : int
        K per bay [-], >= 0: the table has 2 N K + 1 harmonics of Omega_P.
    offsets : sequence of float
        Offsets d [m] of the receiving wheels from the loading one.
    rtol : float
        Relative tolerance of the adaptive wavenumber quadrature [-].
    transfer_cut : float, optional
        Start of the cos^2 window of the d != 0 integrands [rad/m]; default (K + 12) beta0.
    progress : callable, optional
        As for receptance_table; default None, silent.

    Returns
    -------
    MovingReceptance
        harmonics = N K (of Omega_P), bays = N; A [m/N] of shape (offset, 2 N K + 1, 2 N K + 1).
    """
    if not isinstance(cell, TrackCell):
        raise TypeError(f"cell must be a rail.cell.TrackCell, not {type(cell).__name__}.")
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it must be a finite number > 0.")
    if not (np.isfinite(rtol) and 0 < rtol < 1):
        raise ValueError(f"rtol = {rtol!r} is not allowed: the quadrature tolerance must lie in (0, 1).")
    if int(harmonics) != harmonics or harmonics < 0:
        raise ValueError(f"harmonics = {harmonics!r} is not allowed: it must be an integer >= 0.")
    if (problem := damping_problem(cell.track)) is not None:
        raise ValueError(problem)
    N = cell.bays
    J = N * int(harmonics)
    js = np.arange(-J, J + 1)
    offsets = np.atleast_1d(np.asarray(offsets, dtype=float))
    cut = (int(harmonics) + 12) * 2 * np.pi / cell.mean_spacing if transfer_cut is None else float(transfer_cut)
    A, err, n = _integrate(cell, speed, 0.0, js, offsets, 0, rtol, cut, progress=progress)
    return MovingReceptance(float(speed), J, offsets, A, err, n, 0.0, N, tuple(float(x) for x in cell.positions))


def moving_coefficients(track: Track, speed: float, Omega: float, n_max: int, offset: float = 0.0, rtol: float = 1e-6):
    """Moving-load coefficients a_n(Omega, d) for abs(n) <= n_max at any excitation frequency Omega, one speed.

    a_n is defined in the module docstring (docs/track.md, "Moving harmonic load").  For
    Omega = k Omega_0 this equals column k of ``receptance_table``.

    Parameters
    ----------
    track : Track
        The track; its rail damping must be large enough (``rail.track.damping_problem``).
    speed : float
        Speed V [m/s], > 0.
    Omega : float
        Excitation frequency of the load [rad/s].
    n_max : int
        Largest harmonic order abs(n) [-].
    offset : float, optional
        Offset d of the response point moving with the load [m]; default 0 (at the load).
    rtol : float, optional
        Relative tolerance of the adaptive wavenumber quadrature [-]; default 1e-6.

    Returns
    -------
    n : ndarray of int
        Harmonic orders -n_max..n_max [-].
    a_n : complex ndarray
        a_n(Omega, d) [m/N], one per order.
    error : ndarray
        Upper bound of the absolute quadrature error of a_n [m/N].

    Raises
    ------
    ValueError
        If speed <= 0, or if the rail damping is too small (``rail.track.damping_problem``).
    """
    if not speed > 0:
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it must be > 0.")
    if (problem := damping_problem(track)) is not None:
        raise ValueError(problem)
    ns = np.arange(-n_max, n_max + 1)
    js = ns.copy()
    Omega0 = track.beta0 * speed
    kk = Omega / Omega0
    static_j = None
    if abs(kk - round(kk)) < 1e-12:
        # omega = 0 at beta = -Omega/V = -k beta0: column j = -k diverges there
        j = -int(round(kk))
        static_j = j if abs(j) <= n_max else None
    cut = (n_max + 12) * track.beta0 + abs(Omega) / speed
    A, err, _ = _integrate(TrackCell.uniform(track), speed, Omega, js, [offset], static_j, rtol, cut)
    col = n_max  # j = 0 is the load's own column
    return ns, A[0, :, col], err[0, :, col]


def critical_speed(track: Track, v_min: float = 20.0, v_max: float = 1000.0, step: float = 10.0, rtol: float = 1e-5) -> float:
    """Critical speed of the track: where the mean rail deflection under a moving constant load is largest.

    The mean deflection is abs(a_0(0)) of the moving-load receptance (docs/track.md, "Critical speed").
    The supports are discrete and damped, so the resonance is a broad maximum rather than a
    singularity; the scan is on a grid of ``step`` m/s refined by a parabola through the
    largest value (a maximum at either end of the grid is returned unrefined).  (A smeared-support
    free-wave estimate is not used: its sleeper-mass branch is flat, and its smallest phase velocity
    tends to zero.)

    Parameters
    ----------
    track : Track
        The track; its rail damping must be large enough (``rail.track.damping_problem``).
    v_min : float, optional
        Lowest speed of the scan [m/s], > 0; default 20.
    v_max : float, optional
        Highest speed of the scan [m/s]; default 1000.
    step : float, optional
        Speed step of the scan [m/s]; default 10.
    rtol : float, optional
        Relative tolerance of ``moving_coefficients`` [-]; default 1e-5.

    Returns
    -------
    float
        Critical speed [m/s].

    Raises
    ------
    ValueError
        If v_min <= 0, or if the rail damping is too small (from ``moving_coefficients``).
    """
    V = np.arange(v_min, v_max + step / 2, step)
    amp = np.array([abs(moving_coefficients(track, v, 0.0, 0, rtol=rtol)[1][0]) for v in V])
    i = int(np.argmax(amp))
    if i in (0, len(V) - 1):
        return float(V[i])
    y0, y1, y2 = amp[i - 1 : i + 2]
    return float(V[i] + 0.5 * step * (y0 - y2) / (y0 - 2 * y1 + y2))
