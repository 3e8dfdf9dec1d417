"""Moving harmonic loads on the periodically supported rail: the wavenumber method (report ref. [18]).

A load F exp(i Omega t) moves at speed V along the rail (position V t, a support at x = 0 at
t = 0).  The rail displacement at the load, and at points moving with it at offsets d, is

    w(V t + d, t) = F exp(i Omega t) sum_n a_n(Omega, d) exp(i n Omega_0 t),  Omega_0 = 2 pi V / L,

with (docs/track.md, derived by a space-time Fourier transform and Poisson summation)

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
from scipy import special

from .quadrature import adaptive_panels, filon_weights
from .track import Track, damping_problem, free_receptance, periodic_sum, rail_stiffnesses, support_stiffness

__all__ = ["MovingReceptance", "receptance_table", "bloch_tables", "moving_coefficients", "critical_speed"]


@dataclass(frozen=True)
class MovingReceptance:
    """Receptance matrices of the moving-load problem at one speed.

    speed     : V, m/s
    harmonics : K; rows p and columns k run over -K..K (fraction 0) or -K..K-1 (fraction > 0, so
                that the frequencies (k + nu) Omega_0 of the classes nu and 1 - nu mirror each other)
    offsets   : d, m (0 = at the load)
    A         : complex (offset, p, k), m/N: response at (p + nu) Omega_0 at offset d per unit force
                at (k + nu) Omega_0, A_d[p, k] = a_{p-k}((k + nu) Omega_0, d)
    error     : upper bound of the absolute quadrature error of A (same shape), m/N: the error of
                the rule with half the nodes; the result's own error is far smaller (docs/track.md)
    nodes     : number of wavenumber quadrature nodes
    fraction  : Bloch fraction nu in [0, 1) of the base frequency nu Omega_0 (0: bay-periodic loads)
    """

    speed: float
    harmonics: int
    offsets: np.ndarray
    A: np.ndarray
    error: np.ndarray
    nodes: int
    fraction: float = 0.0

    @property
    def indices(self) -> np.ndarray:
        """The harmonic indices k of the rows and columns."""
        K = self.harmonics
        return np.arange(-K, K + (1 if self.fraction == 0 else 0))

    def a(self, n: int, k: int, offset_index: int = 0) -> complex:
        """a_n(k Omega_0, d): needs |k| <= K and |k + n| <= K."""
        K = self.harmonics
        hi = K if self.fraction == 0 else K - 1
        if not (-K <= k <= hi and -K <= k + n <= hi):
            raise ValueError(f"a_n((k + nu) Omega_0) with n = {n}, k = {k} needs k and k + n in [{-K}, {hi}].")
        return complex(self.A[offset_index, k + n + K, k + K])


def _static_tail(beta, omega, track, M):
    """sum over |m| > M of the quasi-static H_0(beta + m beta0) = 1/(EI b^4) + 1/(kGA b^2), via polygamma."""
    EI, kGA = rail_stiffnesses(track, omega)
    b0 = track.beta0
    a = beta / b0
    s2 = (special.polygamma(1, M + 1 + a) + special.polygamma(1, M + 1 - a)) / b0**2
    s4 = (special.polygamma(3, M + 1 + a) + special.polygamma(3, M + 1 - a)) / (6 * b0**4)
    return s4 / EI + s2 / kGA


def _sum_excluding(beta, omega, m_star, track, M=40):
    """sum over m != m_star of H(beta + m beta0, omega), by explicit summation and a static tail.

    Used near the static point, where the closed-form periodic sum would lose every digit
    to the cancellation with the m_star term, which diverges like 1/(EI beta^4).
    """
    b0 = track.beta0
    out = _static_tail(beta + m_star * b0, omega, track, M)
    for m in range(-M, M + 1):
        if m != 0:
            out = out + free_receptance(beta + (m_star + m) * b0, omega, track)
    return out


def _node_tables(beta, Omega, V, js, track, static_j):
    """Columns g_j = H(beta - j beta0, Omega + beta V), support weight parts, and the combined
    diagonal factor at the wavenumber nodes ``beta``.  ``static_j``: index j whose column
    diverges at the static point (None if there is none)."""
    b0, L = track.beta0, track.L
    omega = Omega + beta * V
    G = free_receptance(beta[:, None] - js[None, :] * b0, omega[:, None], track)
    Ks = support_stiffness(track, omega)
    S = np.empty(beta.shape, dtype=complex)
    near = np.zeros(beta.shape, dtype=bool)
    if static_j is not None:
        near = np.abs(beta - static_j * b0) < b0 / 2
    far = ~near
    if far.any():
        S[far] = periodic_sum(beta[far], omega[far], track)
    S_excl = None
    if near.any():
        S_excl = _sum_excluding(beta[near], omega[near], -static_j, track)
        S[near] = S_excl + free_receptance(beta[near] - static_j * b0, omega[near], track)
    denom = L + Ks * S
    # combined diagonal factor (L + K_s (S - g_j)) / (L + K_s S), stable at the static point
    diag_factor = (L + Ks[:, None] * (S[:, None] - G)) / denom[:, None]
    if near.any():
        col = int(np.where(js == static_j)[0][0])
        diag_factor[near, col] = (L + Ks[near] * S_excl) / denom[near]
    w = L * Ks / denom
    return G, w, diag_factor


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


def _integrate(track, V, Omega, js, offsets, static_j, rtol, cut, order=16, max_panels=40000, block=4096, filon=True):
    """Adaptive wavenumber quadrature of the receptance matrices (shared by the table and the
    single-frequency coefficients).  Returns (A, error, nodes).

    The rule adapts to the smooth factors of the integrands only (every column's diagonal integrand
    and the support weight); the oscillating factor exp(-i beta d) of an offset d != 0 is integrated
    exactly against the piecewise polynomial interpolant of those factors on the same nodes (Filon
    weights, rail.quadrature.filon_weights), so the cost does not grow with |d| (docs/track.md,
    "Quadrature"). ``filon=False`` multiplies the Gauss weights by exp(-i beta d) instead (for tests:
    on the nodes of the d = 0 rule that aliases the oscillation of a far offset)."""
    b0, L = track.beta0, track.L
    offsets = np.asarray(offsets, dtype=float)
    Bmap = (np.max(np.abs(js)) + 4) * b0
    beta_s = -Omega / V  # where omega = 0: hysteretic damping changes sign
    has_offsets = np.any(offsets != 0)

    def to_beta(th):
        return Bmap * np.tan(th), Bmap / np.cos(th) ** 2

    def proxy(th):
        beta, jac = to_beta(th)
        G, w, dfac = _node_tables(beta, Omega, V, js, track, static_j)
        # diagonal integrands (free-wave peaks of every column) and the support weight w
        # (Floquet-wave peaks) carry every feature of the off-diagonal integrands w h_k h_p
        return np.concatenate([G * dfac, (w * G[:, np.argmin(np.abs(js))])[:, None]], axis=1) * jac[:, None]

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
    J = len(js)
    M = np.zeros((len(offsets), J, J), dtype=complex)
    D = np.zeros((len(offsets), J), dtype=complex)
    for lo in range(0, len(th), block):
        sl = slice(lo, lo + block)
        G, w, dfac = _node_tables(beta[sl], Omega, V, js, track, static_j)
        D += W[:, sl] @ (G * dfac)
        for i in range(len(offsets)):
            M[i] += (G * (w * W[i, sl])[:, None]).T @ G  # M[k, p] = int w g_k g_p e^d_p (e^-i beta d in W)
    A = -np.swapaxes(M, 1, 2) / (2 * np.pi * L)  # A[p, k]
    A[:, np.arange(J), np.arange(J)] = D / (2 * np.pi)
    A *= np.exp(1j * js[None, :] * b0 * offsets[:, None])[:, :, None]  # row factor exp(i p beta0 d)
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
    fraction: float = 0.0,
) -> MovingReceptance:
    """Receptance matrices A_d[p, k] = a_{p-k}((k + nu) Omega_0, d) at one speed.

    With the Bloch fraction nu = 0 (default) |p|, |k| <= K: loads periodic over one bay. With
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
    A, err, n = _integrate(track, speed, Omega, js, offsets, 0 if fraction == 0 else None, rtol, cut)
    return MovingReceptance(float(speed), K, offsets, A, err, n, float(fraction))


def bloch_tables(track: Track, speed: float, harmonics: int, bays: int, offsets=(0.0,), rtol: float = 1e-4):
    """The receptance tables a roughness periodic over N bays needs: fractions nu = r / N for
    r = 0..floor(N/2) (the classes r > N/2 are the complex conjugates of N - r for a real load).

    Parameters
    ----------
    track : Track
    speed : float
        Speed V [m/s], > 0.
    harmonics : int
        K [-]: the force frequencies (k + nu) Omega_0 reach |K Omega_0|.
    bays : int
        N, the roughness period in bays [-], >= 1.
    offsets : sequence of float
        Offsets d [m] between the wheels.
    rtol : float
        Relative tolerance of the wavenumber quadrature [-].

    Returns
    -------
    tuple of MovingReceptance
        One table per r = 0..floor(N/2) [m/N].
    """
    if int(bays) != bays or bays < 1:
        raise ValueError(f"roughness.bays = {bays!r} is not allowed: it must be an integer >= 1.")
    return tuple(receptance_table(track, speed, harmonics, offsets, rtol, fraction=r / bays) for r in range(int(bays) // 2 + 1))


def moving_coefficients(track: Track, speed: float, Omega: float, n_max: int, offset: float = 0.0, rtol: float = 1e-6):
    """Moving-load coefficients a_n(Omega, d) for |n| <= n_max at any excitation frequency Omega, one speed.

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
        Largest harmonic order |n| [-].
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
    A, err, _ = _integrate(track, speed, Omega, js, [offset], static_j, rtol, cut)
    col = n_max  # j = 0 is the load's own column
    return ns, A[0, :, col], err[0, :, col]


def critical_speed(track: Track, v_min: float = 20.0, v_max: float = 1000.0, step: float = 10.0, rtol: float = 1e-5) -> float:
    """Critical speed of the track: where the mean rail deflection under a moving constant load is largest.

    The mean deflection is |a_0(0)| of the moving-load receptance (docs/track.md, "Critical speed").
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
