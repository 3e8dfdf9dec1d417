"""Adaptive composite Gauss-Legendre quadrature for vector integrands with narrow peaks.

Wavenumber integrals of the track model have peaks as narrow as the damping allows (free and
Floquet waves).  The interval is cut into panels; each panel is integrated with n Gauss points
on the whole and on each half, and the difference is its error estimate.  Panels are halved,
largest error first, until the summed error of every component is below its tolerance.  The
final nodes and weights are returned, so an expensive product (a Gram matrix) can be formed
once on them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["QuadratureResult", "adaptive_panels", "filon_weights"]


@dataclass(frozen=True)
class QuadratureResult:
    """nodes, weights : final rule; integral : per component; error : estimated absolute error
    per component; panels : number of panels; converged : tolerance reached within max_panels;
    edges : (panels, 2) sorted final panel edges [a, b] (each panel holds 2 order nodes, order in
    each half [a, (a + b) / 2] and [(a + b) / 2, b])."""

    nodes: np.ndarray
    weights: np.ndarray
    integral: np.ndarray
    error: np.ndarray
    panels: int
    converged: bool
    edges: np.ndarray | None = None


def _gauss(n):
    x, w = np.polynomial.legendre.leggauss(n)
    return x, w


def adaptive_panels(f, edges, rtol=1e-6, atol=0.0, order=16, max_panels=20000, scale=None) -> QuadratureResult:
    """Integrate the vector function ``f`` over the union of panels given by ``edges``.

    Adaptive composite Gauss-Legendre rule (module docstring): each panel is integrated with ``order``
    points on the whole and on each half, the difference being its error estimate; panels carrying
    more than their share of the error budget are halved until the summed error of every component is
    below its tolerance ``rtol * scale + atol``, or until ``max_panels`` would be exceeded.

    Parameters
    ----------
    f : callable
        ``f(x)`` for a 1-D array x returns an array of shape (len(x), m) (or (len(x),)).
    edges : array_like
        Sorted breakpoints [unit of x]; discontinuities of f must be among them.
    rtol : float, optional
        Relative tolerance per component [-], against ``scale``; default 1e-6.
    atol : float, optional
        Absolute tolerance floor per component [unit of the integral]; default 0.
    order : int, optional
        Gauss points per half panel [-]; default 16.
    max_panels : int, optional
        Largest number of panels [-]; default 20000.
    scale : array_like, optional
        Magnitude per component against which ``rtol`` is applied [unit of the integral];
        default: the integral of abs(f_c) over ``edges``.

    Returns
    -------
    QuadratureResult
        The final rule (nodes [unit of x], sorted, and weights [unit of x], 2 ``order`` per panel), the
        integral and its estimated absolute error per component [unit of the integral], the number of
        panels, and whether the tolerance was reached within ``max_panels``.
    """
    xg, wg = _gauss(order)
    edges = np.asarray(edges, dtype=float)
    a, b = edges[:-1], edges[1:]

    def halves(a, b):
        m = 0.5 * (a + b)
        h = 0.25 * (b - a)
        # nodes of the left and right halves, shape (panels, 2 order)
        xl = 0.5 * (a + m)[:, None] + h[:, None] * xg[None, :]
        xr = 0.5 * (m + b)[:, None] + h[:, None] * xg[None, :]
        xs = np.concatenate([xl, xr], axis=1)
        ws = np.concatenate([np.outer(h, wg), np.outer(h, wg)], axis=1)
        return xs, ws

    def evaluate(a, b):
        xs, ws = halves(a, b)
        xf = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * xg[None, :]
        wf = np.outer(0.5 * (b - a), wg)
        P = len(a)
        vals_h = np.asarray(f(xs.ravel()))
        vals_f = np.asarray(f(xf.ravel()))
        if vals_h.ndim == 1:
            vals_h, vals_f = vals_h[:, None], vals_f[:, None]
        m = vals_h.shape[1]
        vh = vals_h.reshape(P, 2 * order, m)
        vf = vals_f.reshape(P, order, m)
        I_h = np.einsum("pn,pnm->pm", ws, vh)
        I_f = np.einsum("pn,pnm->pm", wf, vf)
        A_h = np.einsum("pn,pnm->pm", ws, np.abs(vh))
        return xs, ws, I_h, np.abs(I_h - I_f), A_h

    done_x, done_w, done_I, done_E, done_ab = [], [], [], [], []
    xs, ws, I_p, E_p, A_p = evaluate(a, b)
    if scale is None:
        scale = A_p.sum(axis=0)
    scale = np.maximum(np.asarray(scale, dtype=float), 1e-300)
    tol = rtol * scale + atol
    n_panels = len(a)
    converged = True
    while True:
        total_err = E_p.sum(axis=0) + (np.sum(done_E, axis=0) if done_E else 0.0)
        norm = (E_p / tol).max(axis=1)  # worst component per active panel
        if np.all(total_err <= tol):
            split = np.zeros(len(a), dtype=bool)
        else:
            # halve every panel carrying more than its share of the worst component's budget
            split = norm > 1.0 / max(n_panels, 1)
            if not split.any():
                split = norm >= norm.max()
        if n_panels + split.sum() > max_panels:
            converged = not split.any()
            split[:] = False
        keep = ~split
        done_x.append(xs[keep].ravel())
        done_w.append(ws[keep].ravel())
        done_I.append(I_p[keep].sum(axis=0))
        done_E.append(E_p[keep].sum(axis=0))
        done_ab.append(np.stack([a[keep], b[keep]], axis=1))
        if not split.any():
            break
        am, bm = a[split], b[split]
        mid = 0.5 * (am + bm)
        a = np.concatenate([am, mid])
        b = np.concatenate([mid, bm])
        n_panels += split.sum()
        xs, ws, I_p, E_p, A_p = evaluate(a, b)
    nodes = np.concatenate(done_x)
    weights = np.concatenate(done_w)
    order_idx = np.argsort(nodes)
    ab = np.concatenate(done_ab)
    return QuadratureResult(
        nodes=nodes[order_idx],
        weights=weights[order_idx],
        integral=np.sum(done_I, axis=0),
        error=np.sum(done_E, axis=0),
        panels=int(n_panels),
        converged=bool(converged),
        edges=ab[np.argsort(ab[:, 0])],
    )


def filon_weights(nodes, seg_a, seg_b, d: float) -> np.ndarray:
    """Complex weights of a Filon-type rule for int f(x) exp(-i d x) dx over the union of segments.

    On each segment [a_s, b_s] the smooth factor f is replaced by its polynomial interpolant through
    the segment's m nodes (degree m - 1, in the Legendre basis of the segment), and the product with
    the oscillating factor is integrated exactly with the moments

        int_{-1}^{1} P_l(x) exp(-i z x) dx = 2 (-i)^l j_l(z)   (j_l: spherical Bessel function),

    so the number of nodes follows the features of f, not the oscillation of exp(-i d x): the rule
    is exact for f a polynomial of degree m - 1 on each segment, for any d (Iserles & Norsett 2005;
    the classical Filon rule is m = 3 on a uniform grid). For d = 0 it is the interpolatory rule on
    the nodes (on Gauss nodes, the Gauss rule).

    Parameters
    ----------
    nodes : (S, m) array_like
        The nodes of each segment [unit of x], inside it.
    seg_a, seg_b : (S,) array_like
        Segment ends a_s < b_s [unit of x].
    d : float
        Frequency of the oscillating factor [1 / unit of x], any sign.

    Returns
    -------
    (S, m) ndarray of complex
        Weights w_sn [unit of x]: sum over s, n of w_sn f(x_sn) approximates the integral.
    """
    from scipy.special import spherical_jn

    x = np.asarray(nodes, dtype=float)
    a = np.asarray(seg_a, dtype=float)
    b = np.asarray(seg_b, dtype=float)
    m = x.shape[1]
    c, h = 0.5 * (a + b), 0.5 * (b - a)
    xi = (x - c[:, None]) / h[:, None]
    V = np.polynomial.legendre.legvander(xi, m - 1)  # (S, m nodes, m degrees)
    l = np.arange(m)
    z = h * abs(d)
    mom = 2.0 * spherical_jn(l[None, :], z[:, None]) * ((-1j * np.sign(d)) ** l)[None, :]
    mom = mom * (h * np.exp(-1j * c * d))[:, None]
    # sum_n w_sn P_l(xi_sn) = mom_sl for every degree l
    return np.linalg.solve(np.swapaxes(V, 1, 2), mom[:, :, None])[:, :, 0]
