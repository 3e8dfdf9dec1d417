"""The square-root-weighted traction basis of the tangential march and its log-kernel influence
coefficients (report eqs 29-33; docs/contact.md, "Discretisation").

q(zeta) = W(zeta) sum_n g_n phi_n(zeta), W = sqrt(1 - zeta^2 / a^2), g_n = q_n / W(xi_n): the basis
function of node n is psi_n = W phi_n / W(xi_n), with phi_n the hats except that the two outermost
are constant 1 from the outermost loaded node to the edge. All integrals here are in units of the
grid spacing (Delta = 1) unless stated. ``_closure_matrix`` adds the closure's rigid term and gives
the influence matrix the march uses (rows: the nodes and the leading neighbour; the rows at the
patch edges).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._lazyjit import njit

__all__ = ["chebyshev_hat_moments"]


@njit(cache=True)
def _g0(t: float) -> float:
    """Antiderivative of ln|t|: t ln|t| - t (0 at t = 0)."""
    return t * math.log(abs(t)) - t if t != 0 else 0.0


@njit(cache=True)
def _g1(t: float) -> float:
    """Antiderivative of t ln|t|: t^2 ln|t| / 2 - t^2 / 4 (0 at t = 0)."""
    return t * t * (0.5 * math.log(abs(t)) - 0.25) if t != 0 else 0.0



@njit(cache=True)
def _log_hat_scalar(j):
    """int over the unit hat centred at j of ln|t| dt (t in units of the spacing)."""
    left = (_g1(j) - _g1(j - 1.0)) + (1.0 - j) * (_g0(j) - _g0(j - 1.0))
    right = (j + 1.0) * (_g0(j + 1.0) - _g0(j)) - (_g1(j + 1.0) - _g1(j))
    return left + right


# --- Square-root-weighted traction basis ---------------------------------------------------------------
# q(zeta) = W(zeta) sum_n g_n phi_n(zeta), W = sqrt(1 - zeta^2 / a^2), g_n = q_n / W(xi_n): the basis function
# of node n is psi_n = W phi_n / W(xi_n), with phi_n the hats except that the two outermost are constant 1 from
# the outermost loaded node to the edge. All integrals below are in units of the grid spacing (Delta = 1).

@functools.lru_cache(maxsize=1)
def _gauss_legendre_400():
    """The 400-point Gauss-Legendre rule on [-1, 1] (nodes, weights), computed once: its eigenvalue
    problem costs 0.03 s on one BLAS thread and up to 1.7 s CPU on two (measured on the 2-core host),
    and every process importing this module (the Snakemake process among them) needs it twice."""
    return np.polynomial.legendre.leggauss(400)


def _gauss_log_rule(nq: int):
    """Gauss rule for int_0^1 f(t) (-ln t) dt (nodes, weights), exact for polynomials of degree < 2 nq.
    Discretised Stieltjes procedure on t = u^8 (smooth integrand), then the Jacobi matrix."""
    x, wx = _gauss_legendre_400()
    u = 0.5 * (x + 1)
    t = u**8
    wt = 0.5 * wx * 64 * u**7 * (-np.log(u))
    alpha = np.zeros(nq)
    beta = np.zeros(nq)
    p_prev, p = np.zeros_like(t), np.ones_like(t)
    nrm = np.sum(wt)
    b0 = nrm
    for k in range(nq):
        alpha[k] = np.sum(wt * t * p * p) / nrm
        if k + 1 < nq:
            pn = (t - alpha[k]) * p - (beta[k] * p_prev if k > 0 else 0.0)
            nn = np.sum(wt * pn * pn)
            beta[k + 1] = nn / nrm
            p_prev, p, nrm = p, pn, nn
    J = np.diag(alpha) + np.diag(np.sqrt(beta[1:]), 1) + np.diag(np.sqrt(beta[1:]), -1)
    ev, V = np.linalg.eigh(J)
    return np.ascontiguousarray(ev), np.ascontiguousarray(b0 * V[0] ** 2)


def _gauss_legendre01(nq: int):
    x, w = np.polynomial.legendre.leggauss(nq)
    return np.ascontiguousarray(0.5 * (x + 1)), np.ascontiguousarray(0.5 * w)


_GL_X, _GL_W = _gauss_legendre01(10)  # singular points at least half an interval length away: errors < 1e-11
_GL8_X, _GL8_W = _gauss_legendre01(8)
_GL6_X, _GL6_W = _gauss_legendre01(6)
_GL4_X, _GL4_W = _gauss_legendre01(4)
_GL3_X, _GL3_W = _gauss_legendre01(3)
_GM_X, _GM_W = _gauss_legendre01(20)  # moments of the edge basis (exact to degree 39; the higher moments enter with factors < 0.56^k)
_GLOG_X, _GLOG_W = _gauss_log_rule(12)  # exact for degree < 24 (the Chebyshev moments of the hats)
_GLOG8_X, _GLOG8_W = _gauss_log_rule(8)
_EDGE_CELLS = 2  # D: basis functions within D cells of an edge are integrated with the square root explicitly
_N_MOM = 40  # terms of the far-field expansion of the edge columns (rows beyond 0.9 L of its centre)
_KMAX = 20  # Chebyshev terms of W / W_n on the support of an interior hat
_CHEB_TOL = 1e-10
_INV_K = np.r_[0.0, 1.0 / np.arange(1, _N_MOM)]


def _chebyshev_tables(kmax: int):
    """Chebyshev interpolation at K points (K = 1..kmax): nodes t_q and the matrix giving the coefficients."""
    nodes = np.zeros((kmax + 1, kmax))
    mat = np.zeros((kmax + 1, kmax, kmax))
    for K in range(1, kmax + 1):
        th = np.pi * (np.arange(K) + 0.5) / K
        nodes[K, :K] = np.cos(th)
        m = (2.0 / K) * np.cos(np.outer(np.arange(K), th))
        m[0] /= 2
        mat[K, :K, :K] = m
    return nodes, mat


_CHEB_NODES, _CHEB_MAT = _chebyshev_tables(_KMAX)
_N_POW = 48  # far-field terms of the row at +a for an interior column (ratio <= 1/2)


def _hat_chebyshev_powers(kmax: int, npow: int):
    """H[j, i] = int_{-1}^{1} hat(t) T_j(t) t^i dt (exact: 40-point Gauss-Legendre on each half)."""
    x, w = np.polynomial.legendre.leggauss(40)
    H = np.zeros((kmax, npow))
    for t, wt in ((0.5 * (x - 1), 0.5 * w), (0.5 * (x + 1), 0.5 * w)):
        T = np.cos(np.outer(np.arange(kmax), np.arccos(t))) * (1 - np.abs(t))[None, :]
        H += (T * wt[None, :]) @ (t[:, None] ** np.arange(npow)[None, :])
    return np.ascontiguousarray(H)


_HAT_CHEB_POW = _hat_chebyshev_powers(_KMAX, _N_POW)
_MOMENT_CACHE: dict = {}


def chebyshev_hat_moments(n_off: int):
    """Chebyshev moments of the hat functions against the log kernel of eq 29 (cached).

    Smooth cases by 40-point Gauss-Legendre on each half of the hat, the three rows where the log is
    singular at an end of a half by the Gauss rule with the log weight.

    Parameters
    ----------
    n_off : int
        Largest node offset [-].

    Returns
    -------
    M : ndarray, shape (_KMAX, 2 n_off + 1)
        M[j, x + n_off] = int_{-1}^{1} hat(t) T_j(t) ln abs(x - t) dt for integer x in [-n_off, n_off]
        [in units of the grid spacing].
    mu : ndarray, shape (_KMAX,)
        mu[j] = int hat T_j [in units of the grid spacing].
    """
    if n_off in _MOMENT_CACHE:
        return _MOMENT_CACHE[n_off]
    x, w = np.polynomial.legendre.leggauss(40)
    tl, tr = 0.5 * (x - 1), 0.5 * (x + 1)  # left half [-1, 0], right half [0, 1]
    wl = 0.5 * w
    J = _KMAX

    def hat_cheb(t):  # hat(t) T_j(t), j < J, at the points t (rows: j)
        t = np.asarray(t, dtype=float)
        return np.cos(np.outer(np.arange(J), np.arccos(np.clip(t, -1, 1)))) * (1 - np.abs(t))[None, :]

    Tl, Tr = hat_cheb(tl), hat_cheb(tr)
    xs = np.arange(-n_off, n_off + 1)
    Mom = np.empty((J, xs.size))
    for i, xv in enumerate(xs):
        if abs(xv) >= 2:
            Mom[:, i] = (Tl * np.log(np.abs(xv - tl))) @ wl + (Tr * np.log(np.abs(xv - tr))) @ wl
    # the log singular at an end of a half: int_0^1 f(u) ln u du = -sum w_L f(x_L), exact (degree < 24)
    u, wu = _GLOG_X, _GLOG_W
    Mom[:, n_off] = -(hat_cheb(-u) @ wu) - (hat_cheb(u) @ wu)  # x = 0
    Mom[:, n_off + 1] = (Tl * np.log(1 - tl)) @ wl - (hat_cheb(1 - u) @ wu)  # x = 1
    Mom[:, n_off - 1] = -(hat_cheb(u - 1) @ wu) + (Tr * np.log(1 + tr)) @ wl  # x = -1
    mu = Tl @ wl + Tr @ wl
    out = (np.ascontiguousarray(Mom), np.ascontiguousarray(mu))
    _MOMENT_CACHE[n_off] = out
    return out


@njit(cache=True)
def _fw(v, at):
    """2 v^2 S(v^2): the integrand factor of the square-root basis in v = sqrt(a - zeta) (units of the
    spacing), W = sqrt(s) S(s), S(s) = sqrt(2 at - s) / at, s = v^2; d zeta = 2 v dv."""
    s = v * v
    return 2.0 * s * math.sqrt(max(2.0 * at - s, 0.0)) / at


@njit(cache=True)
def _gl_seg(x1, x2, p, cplx, at, out):
    """out += int_{x1}^{x2} 2v^2 S (1, v^2) ln|v - p| dv (cplx: ln(v^2 + p^2)), 12-point Gauss-Legendre."""
    h = x2 - x1
    for q in range(_GL_X.size):
        v = x1 + h * _GL_X[q]
        f = _fw(v, at) * h * _GL_W[q]
        L = math.log(v * v + p * p) if cplx else math.log(abs(v - p))
        out[0] += f * L
        out[1] += f * L * v * v


@njit(cache=True)
def _glog_end(x0, h, at, out):
    """out += int F(v) ln|v - x0| over [x0, x0 + h] (h > 0) or [x0 + h, x0] (h < 0): log weight at x0."""
    ah = abs(h)
    lh = math.log(ah)
    for q in range(_GL_X.size):
        v = x0 + h * _GL_X[q]
        f = _fw(v, at) * ah * _GL_W[q] * lh
        out[0] += f
        out[1] += f * v * v
        v = x0 + h * _GLOG8_X[q]
        f = -_fw(v, at) * ah * _GLOG8_W[q]
        out[0] += f
        out[1] += f * v * v


@njit(cache=True)
def _graded(v1, v2, p, cplx, left, dist, at, out):
    """Gauss-Legendre on [v1, v2] graded (halving) toward the end nearest a singular point at distance dist."""
    h = v2 - v1
    if dist >= 0.5 * h:
        _gl_seg(v1, v2, p, cplx, at, out)
        return
    ell = h
    while ell > 2.0 * dist:
        hi = ell
        ell *= 0.5
        if left:
            _gl_seg(v1 + ell, v1 + hi, p, cplx, at, out)
        else:
            _gl_seg(v2 - hi, v2 - ell, p, cplx, at, out)
    if left:
        _gl_seg(v1, v1 + ell, p, cplx, at, out)
    else:
        _gl_seg(v2 - ell, v2, p, cplx, at, out)


@njit(cache=True)
def _log_term(v1, v2, p, at, out):
    """out += int_{v1}^{v2} 2v^2 S (1, v^2) ln|v - p| dv for real p (singular at p)."""
    if p == v1:
        _glog_end(v1, v2 - v1, at, out)
    elif p == v2:
        _glog_end(v2, v1 - v2, at, out)
    elif v1 < p < v2:
        _glog_end(p, v1 - p, at, out)
        _glog_end(p, v2 - p, at, out)
    elif p < v1:
        _graded(v1, v2, p, False, True, v1 - p, at, out)
    else:
        _graded(v1, v2, p, False, False, p - v2, at, out)


@njit(cache=True)
def _piece_log(v1, v2, d, at, out):
    """out[0], out[1] = int_{v1}^{v2} 2v^2 S(v^2) (1, v^2) ln|v^2 - d| dv, 0 <= v1 < v2: the log-kernel
    integral over s = v^2 in [v1^2, v2^2] of sqrt(s) S(s) (1, s) against a row at s = d (s = a - zeta)."""
    out[0] = 0.0
    out[1] = 0.0
    h = v2 - v1
    if d > 0:
        c = math.sqrt(d)
        if min(abs(c - v1), abs(c - v2)) >= h and (v1 > c or v2 < c):  # both roots far: one rule for both
            if v1 + c >= h:
                for q in range(_GL_X.size):
                    v = v1 + h * _GL_X[q]
                    f = _fw(v, at) * h * _GL_W[q] * math.log(abs(v * v - d))
                    out[0] += f
                    out[1] += f * v * v
                return
        _log_term(v1, v2, c, at, out)
        _log_term(v1, v2, -c, at, out)
    elif d == 0:
        _log_term(v1, v2, 0.0, at, out)
        out[0] *= 2.0
        out[1] *= 2.0
    else:
        b = math.sqrt(-d)
        _graded(v1, v2, b, True, True, math.sqrt(v1 * v1 + b * b), at, out)


@njit(cache=True)
def _log_term_pre(v1, v2, p, at, pv, pf, ps, lf, ls, rf, rs, out):
    """_log_term with the integrand factor precomputed at the Gauss-Legendre points pv (weights included:
    pf, pf * ps) and at the log-weighted points from the left (lf, ls) and right (rf, rs) ends."""
    h = v2 - v1
    if p == v1 or p == v2:
        lh = math.log(h)
        for q in range(pv.size):
            out[0] += lh * pf[q]
            out[1] += lh * pf[q] * ps[q]
        if p == v1:
            for q in range(lf.size):
                out[0] -= lf[q]
                out[1] -= lf[q] * ls[q]
        else:
            for q in range(rf.size):
                out[0] -= rf[q]
                out[1] -= rf[q] * rs[q]
    elif (p < v1 and v1 - p >= 0.5 * h) or (p > v2 and p - v2 >= 0.5 * h):
        for q in range(pv.size):
            f = pf[q] * math.log(abs(pv[q] - p))
            out[0] += f
            out[1] += f * ps[q]
    else:
        _log_term(v1, v2, p, at, out)


@njit(cache=True)
def _piece_log_pre(v1, v2, d, at, pv, pf, ps, lf, ls, rf, rs, out):
    """_piece_log with precomputed integrand factors (see _log_term_pre)."""
    out[0] = 0.0
    out[1] = 0.0
    h = v2 - v1
    if d > 0:
        c = math.sqrt(d)
        if (v1 - c >= 0.5 * h or c - v2 >= 0.5 * h) and v1 + c >= 0.5 * h:  # both roots far: one rule for both
            for q in range(pv.size):
                f = pf[q] * math.log(abs(ps[q] - d))
                out[0] += f
                out[1] += f * ps[q]
            return
        _log_term_pre(v1, v2, c, at, pv, pf, ps, lf, ls, rf, rs, out)
        _log_term_pre(v1, v2, -c, at, pv, pf, ps, lf, ls, rf, rs, out)
    elif d == 0:
        _log_term_pre(v1, v2, 0.0, at, pv, pf, ps, lf, ls, rf, rs, out)
        out[0] *= 2.0
        out[1] *= 2.0
    else:
        b2 = -d
        if v1 * v1 + b2 >= 0.25 * h * h:
            for q in range(pv.size):
                f = pf[q] * math.log(ps[q] + b2)
                out[0] += f
                out[1] += f * ps[q]
        else:
            _graded(v1, v2, math.sqrt(b2), True, True, math.sqrt(v1 * v1 + b2), at, out)


@njit(cache=True)
def _edge_columns(at, e, D, js, res, mom, wts, w1, w3):
    """The D basis functions nearest the leading edge (column i: node lead - i, i < D) against rows at
    s = a - x = e + js[r] (units of the spacing): res[i, r] = int psi_i(s) ln|s - d_r| ds. Also their
    far-field moments mom[i, k] = int psi_i (s - s_c)^k ds about s_c = (e + D) / 2, and wts[i] = int psi_i.
    The trailing edge is the mirror image. Pieces: s in [0, e], where g = q / W is extrapolated linearly
    from the last two nodes (psi_lead = W (1 + t) / W_lead, psi_lead-1 = -W t / W_lead-1, t = (zeta - xi_lead)
    / Delta; a partition of unity, exact for g linear), then whole cells (hats).
    w1, w3: work arrays (_basis_workspace)."""
    npc = D + 1
    sb = w1[0]
    vb = w1[1]
    wc = w1[2]
    out = w1[3]
    ser = w1[4]
    sb[0] = 0.0
    vb[0] = 0.0
    for i in range(1, npc + 1):
        sb[i] = e + (i - 1)
        vb[i] = math.sqrt(sb[i])
    for i in range(D):
        sc = sb[i + 1]
        wc[i] = math.sqrt(sc) * math.sqrt(2.0 * at - sc) / at
    L = sb[npc]
    s_c = 0.5 * L
    # moments (Gauss-Legendre in v: polynomial times the smooth S)
    mom[:, :] = 0.0
    for p in range(npc):
        h = vb[p + 1] - vb[p]
        for q in range(_GM_X.size):
            v = vb[p] + h * _GM_X[q]
            s = v * v
            f = _fw(v, at) * h * _GM_W[q]
            y = s - s_c
            if p == 0 and D == 1:  # (a patch of less than two cells: g constant beyond the last node)
                g0 = f / wc[0]
                m0 = mom[0]
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    yk *= y
                continue
            if p == 0:  # beyond the last node g is extrapolated linearly: phi_lead = 1 + t, phi_lead-1 = -t
                g0 = f * (sb[2] - s) / wc[0]
                g1 = f * (s - sb[1]) / wc[1]
                m0 = mom[0]
                m1 = mom[1]
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    m1[k] += g1 * yk
                    yk *= y
                continue
            g0 = f * (sb[p + 1] - s) / wc[p - 1]
            m0 = mom[p - 1]
            if p < D:
                g1 = f * (s - sb[p]) / wc[p]
                m1 = mom[p]
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    m1[k] += g1 * yk
                    yk *= y
            else:
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    yk *= y
    for i in range(D):
        wts[i] = mom[i, 0]
    nm = mom.shape[1]
    ng, nl = _GL_X.size, _GLOG8_X.size
    pv, pf, ps, lf, ls, rf, rs = w3[0], w3[1], w3[2], w3[3], w3[4], w3[5], w3[6]
    for p in range(npc):
        h = vb[p + 1] - vb[p]
        for q in range(ng):
            v = vb[p] + h * _GL_X[q]
            pv[p, q] = v
            ps[p, q] = v * v
            pf[p, q] = _fw(v, at) * h * _GL_W[q]
        for q in range(nl):
            v = vb[p] + h * _GLOG8_X[q]
            ls[p, q] = v * v
            lf[p, q] = _fw(v, at) * h * _GLOG8_W[q]
            v = vb[p + 1] - h * _GLOG8_X[q]
            rs[p, q] = v * v
            rf[p, q] = _fw(v, at) * h * _GLOG8_W[q]
    for r in range(js.size):
        d = e + js[r]
        dc = s_c - d
        if abs(dc) >= 0.9 * L:  # far field: ln|s - d| = ln|dc| + ln(1 + (s - s_c) / dc)
            ser[0] = math.log(abs(dc))
            my = -1.0 / dc
            # terms while (s_c / |dc|)^k / k > 1e-14 (|s - s_c| <= s_c)
            nk = min(nm, int(math.ceil(-32.2 / math.log(s_c / abs(dc)))) + 1)
            yk = -1.0
            for k in range(1, nk):
                yk *= my
                ser[k] = yk * _INV_K[k]  # (-1)^(k+1) / (k dc^k)
            for i in range(D):
                acc = 0.0
                for k in range(nk):
                    acc += mom[i, k] * ser[k]
                res[i, r] = acc
            continue
        for i in range(D):
            res[i, r] = 0.0
        for p in range(npc):
            _piece_log_pre(vb[p], vb[p + 1], d, at, pv[p, :ng], pf[p, :ng], ps[p, :ng], lf[p, :nl], ls[p, :nl],
                           rf[p, :nl], rs[p, :nl], out)
            if p == 0 and D == 1:
                res[0, r] += out[0] / wc[0]
            elif p == 0:
                res[0, r] += (sb[2] * out[0] - out[1]) / wc[0]
                res[1, r] += (out[1] - sb[1] * out[0]) / wc[1]
            else:
                res[p - 1, r] += (sb[p + 1] * out[0] - out[1]) / wc[p - 1]
                if p < D:
                    res[p, r] += (out[1] - sb[p] * out[0]) / wc[p]


def _basis_workspace(nn: int):
    """Work arrays of _basis_matrix for a grid of nn nodes (allocated once per solve)."""
    nr = nn + 1
    return (np.empty((nn, _KMAX)), np.empty(nr + 1), np.empty((_EDGE_CELLS, nr + 1)), np.empty((_EDGE_CELLS, _N_MOM)),
            np.empty(_EDGE_CELLS), np.empty((5, max(_N_MOM, _EDGE_CELLS + 2))),
            np.empty((7, _EDGE_CELLS + 1, max(_GL_X.size, _GLOG8_X.size))))


@njit(cache=True)
def _basis_matrix(ai, delta, M, Mom, mu, A, r_a, w, ws):
    """The influence of the square-root-weighted basis at half-length ai, in units of the spacing
    (in place): A[n, r] = int psi_n(zeta) ln|x_r - zeta| d zeta (column n, row r: the nodes and the leading
    neighbour), r_a[n] = the same at the row x = +a, w[n] = int psi_n. Columns of unloaded nodes: plain
    hats. ws: work arrays (_basis_workspace). Returns (lead, trail)."""
    cf, js, res, mom, wts, wk1, wk3 = ws
    nn = A.shape[0]
    nr = A.shape[1]
    off = (Mom.shape[1] - 1) // 2
    at = ai / delta
    lead = int(math.floor(at - 1e-12)) + M
    trail = 2 * M - lead
    e = at - (lead - M)
    D = min(_EDGE_CELLS, lead - M)
    if D < 1:
        raise ValueError("the patch must span more than two grid cells")
    # unloaded nodes: plain hats
    for n in range(nn):
        if n > lead or n < trail:
            for r in range(nr):
                A[n, r] = Mom[0, r - n + off]
            w[n] = mu[0]
            r_a[n] = _log_hat_scalar(n - M - at)
    # interior columns: Chebyshev series of W / W_n on the hat's support, Toeplitz moments
    for n in range(trail + D, lead - D + 1):
        xn = float(n - M)
        wn = math.sqrt(1.0 - (xn / at) ** 2)
        dist = at - abs(xn)
        rho = dist + math.sqrt(dist * dist - 1.0)
        K = int(math.ceil(-math.log(_CHEB_TOL) / math.log(rho)))
        K = min(max(K, 3), _KMAX)
        cfn = cf[n]
        for j in range(_KMAX):
            cfn[j] = 0.0
        for qq in range(K):
            z = (xn + _CHEB_NODES[K, qq]) / at
            f = math.sqrt(1.0 - z * z) / wn
            for j in range(K):
                cfn[j] += _CHEB_MAT[K, j, qq] * f
        ww = 0.0
        arow = A[n]
        base = off - n
        c = cfn[0]
        mrow = Mom[0, base:base + nr]
        for r in range(nr):
            arow[r] = c * mrow[r]
        for j in range(K):
            ww += cfn[j] * mu[j]
        for j in range(1, K):
            c = cfn[j]
            mrow = Mom[j, base:base + nr]
            for r in range(nr):
                arow[r] += c * mrow[r]
        w[n] = ww
        r_a[n] = 0.0
    # row at +a for the interior columns, x = a - xi_n >= 2 cells from the hat's centre: the far field
    # ln|x - t| = ln x - sum_i (t / x)^i / i of the same truncated Chebyshev series as the columns
    # (exact moments), so that the row of a particle entering just past a node,
    # (E_n - theta r_a) / (1 - theta), cancels to rounding
    for n in range(trail + D, lead - D + 1):
        x = at - float(n - M)
        cfn = cf[n]
        ni = min(_N_POW, int(math.ceil(32.3 / math.log(x))) + 1)  # (1/x)^i / i < 1e-14
        lx = math.log(x)
        acc = 0.0
        for j in range(_KMAX):
            acc += cfn[j] * _HAT_CHEB_POW[j, 0]
        acc *= lx
        ix = 1.0 / x
        pw = 1.0
        for i in range(1, ni):
            pw *= ix
            nu = 0.0
            for j in range(_KMAX):
                nu += cfn[j] * _HAT_CHEB_POW[j, i]
            acc -= nu * pw / i
        r_a[n] = acc
    # edge columns: lead - i (rows at s = a - x = e + (lead - r)) and trail + i (s = a + x = e + (r - trail))
    for side in range(2):
        for r in range(nr):
            js[r] = float(lead - r) if side == 0 else float(r - trail)
        js[nr] = -e if side == 0 else 2.0 * at - e  # the row at +a
        _edge_columns(at, e, D, js, res[:D], mom[:D], wts[:D], wk1, wk3)
        for i in range(D):
            n = lead - i if side == 0 else trail + i
            for r in range(nr):
                A[n, r] = res[i, r]
            r_a[n] = res[i, nr]
            w[n] = wts[i]
    return lead, trail


@njit(cache=True)
def _influence_arrays(nn):
    """The arrays _closure_matrix fills for a grid of nn nodes: (C, r_edge, r_trail, w, AT, r_a, wu)."""
    return (np.empty((nn + 1, nn)), np.empty(nn), np.empty(nn), np.empty(nn), np.empty((nn, nn + 1)), np.empty(nn),
            np.empty(nn))


@njit(cache=True)
def _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT,
                    r_a, wu, ws):
    """Influence matrix C of the square-root-weighted basis (rows: nodes plus the leading neighbour), its
    rows r_edge at xi = +a and r_trail at xi = -a and the column weights w = int psi_n, at half-length ai
    (in place; AT, r_a, wu, ws: work arrays of _basis_matrix). The rigid term is that of the closure (0: default,
    1: report)."""
    nn = xi.size
    lead, trail = _basis_matrix(ai, delta, M, Mom, mu, AT, r_a, wu, ws)
    logd = math.log(delta)
    for c in range(nn):
        w[c] = delta * wu[c]
    rigid = np.empty(nn)
    if closure == 0:
        lc = k * math.log(0.5 * ai * math.exp(2 * closure_scale / math.pi))
        for c in range(nn):
            rigid[c] = lc * w[c]
    else:
        for c in range(nn):
            rigid[c] = k * delta * AT[c, M] + k * logd * w[c]  # minus the row at xi = 0
        rigid[M] += closure_scale * report_coef * ai
    for c in range(nn):
        col = -k * logd * w[c] + rigid[c]
        for r in range(nn + 1):
            C[r, c] = -k * delta * AT[c, r] + col
    for n in range(nn):
        r_edge[n] = -k * delta * r_a[n] - k * logd * w[n] + rigid[n]
    for n in range(nn):  # the grid, the basis and the rigid term are symmetric about xi = 0
        r_trail[n] = r_edge[nn - 1 - n]
    return lead, trail

