"""Independent reference for 2D unsteady partial-slip rolling: the stick/slip boundary as an unknown.

Written without reference to ``rail/`` (only the continuous problem of report secs 4.3-5 is shared),
so that the production discretisation (``rail.contact.solve_tangential``) can be checked against a
method whose error does not come from the same place.

Why a second method
-------------------
The production scheme resolves the traction on a fixed grid of nodes moving with the contact. The
deviation of the traction from the sliding value, d = q - sigma mu p, has a square-root kink at the
stick/slip boundary b(t); on the fixed grid that boundary lies somewhere inside a cell, and where it
moves through the cells under a fast load variation the wear harmonic converges at order about 5/3
(docs/contact.md). Here the discretisation is aligned with b(t) instead, so the kink is represented
exactly. What that buys was measured, not assumed (issue 17, docs/contact.md): in the steady
(Carter) limit this method is second order (tests/independent/test_aligned_contact_selfcheck.py);
under the +-30 % load at 1600 Hz, with its quadrature adequate (nh = 30, K = 2000), its wear harmonic
converges at about order 1.5-1.6 over 81-161-321 nodes, no faster than the production scheme, and
the two agree at 321 nodes to 3e-4 (nh = 40, K = 3000 there). So aligning the boundary in space
alone does not give second order; the method serves as an independent traction discretisation.
With nh = 20, K = 1000 (the default, cheaper) its quadrature error becomes grid-dependent beyond
about 161 nodes.

Model (one stick zone at the leading side, one slip direction: the regime of partial slip under a
driving or braking creepage with a moderate load variation; anything else is detected and reported)
--------------------------------------------------------------------------------------------------
* Hertz pressure p = p0 sqrt(1 - x^2/a^2), a(t), p0(t) = P / (pi a b_w) (width 2 b_w) from the normal load P(t).
* Traction q = sigma mu p on the slip zone [-a, b), sigma = -sign(gamma), mu the friction
  coefficient (static = dynamic), and q = sigma mu p + d on the stick zone [b, a] with
  d(x) = sqrt(1 - x^2/a^2) sqrt(x - b) h(x), h a polynomial given by its values at ``nh`` Chebyshev
  points of (b, a). Both factors of d are exact: the first is the leading-edge behaviour of any
  bounded traction, the second the square-root departure from the slip zone.
* Displacement (default closure, docs/contact.md):
  u(x) = -k int q(z) ln(|x - z| / l) dz, k = 4 (1 - nu^2) / (pi E), l = (a/2) e^{2 s / pi}.
  The Hertz part is integrated in closed form; d by product integration (d piecewise linear on a
  cosine-graded mesh of K points on [b, a], the logarithm integrated exactly on each piece).
* Time stepping along particle paths, step dt = Delta / V (a particle at x was at x + Delta one step
  before): at the collocation points of the stick zone, u(x, t) - u(x + Delta, t - dt) = -gamma Delta
  (zero slip over the step, the displacement at t - dt evaluated from the previous traction anywhere,
  not only at nodes). A point that entered the patch during the step, at the fraction theta of it,
  starts from the leading-edge displacement interpolated in time and sticks for the rest:
  u(x) = theta u_new(a) + (1 - theta) (u_old(a) - gamma Delta). With ``entry='quadratic'`` the
  leading-edge displacement is interpolated through the last three steps instead (a diagnostic: it
  moves the 1600 Hz harmonic by 0.6 % at 41 nodes but not its order, docs/contact.md).
* The boundary b(t) solves zero slip velocity at x = b: gamma V + (u(b, t) - u(b + Delta, t - dt)) / dt
  = 0 (secant from the extrapolated b, bracketing fallback), so the stick/slip complementarity at the
  boundary is exact.
* Frictional work of rail points on a fixed grid x_n = n Delta: the same continuous path integral as
  the production rule (pressure integrated exactly along the path, slip velocity from the nodal
  displacements, the deviation d averaged over the step), written here from the traction functions.
  It checks the traction discretisation, not the work rule.
* Optionally (``wave``), the same work collected without a rail-point lattice: at every step the
  integral over the contact coordinate x of the work done over the step on the particle that ends at
  x, weighted by e^{-i wave x} (slip velocity and old traction evaluated at x + Delta anywhere; the
  slip zone split at the old boundary b - Delta, particles that left at the trailing edge during
  the step included; Gauss-Legendre in a cosine map that absorbs the square-root end behaviour).
  The harmonic of the wear at that wavenumber follows by a sum over one period of steps. It tells
  the error of collecting the work on a lattice from the error of the traction.

Cost: about 0.2-0.7 s per step (the product integration is rebuilt for every trial b): a reference,
not a production scheme. Units SI.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np
from scipy.optimize import brentq

__all__ = ["carter_boundary", "compliance", "hertz_half_length", "solve", "wear_harmonic", "wear_harmonics"]

THETA_EDGE = 1e-10  # a point leaving the patch within this fraction of a step is not counted


def compliance(youngs_modulus: float, poisson_ratio: float) -> float:
    """k = 4 (1 - nu^2) / (pi E) [1/Pa]."""
    return 4 * (1 - poisson_ratio**2) / (np.pi * youngs_modulus)


def hertz_half_length(P, R: float, k: float, half_width: float):
    """Hertz half-length a = sqrt(k P R / b_w) [m] for the normal load P [N], radius R [m]."""
    return np.sqrt(k * np.asarray(P, float) * R / half_width)


def carter_boundary(P: float, a: float, k: float, mu: float, creepage: float, half_width: float) -> float:
    """Steady-rolling stick/slip boundary b = a - 2c, c = a (1 - |gamma| / (pi k mu p0)) (Carter)."""
    p0 = P / (np.pi * a * half_width)
    c = a * (1 - abs(creepage) / (np.pi * k * mu * p0))
    return a - 2 * c


def _F0(t):
    at = np.abs(t)
    return np.where(at > 0, t * np.log(np.where(at > 0, at, 1.0)) - t, 0.0)


def _F1(t):
    at = np.abs(t)
    return np.where(at > 0, 0.5 * t * t * np.log(np.where(at > 0, at, 1.0)) - 0.25 * t * t, 0.0)


def log_matrix(x, z):
    """L with int f(zeta) ln|x - zeta| dzeta = L @ f(z) for f piecewise linear on the mesh z."""
    x = np.atleast_1d(x)
    t0 = z[None, :-1] - x[:, None]
    t1 = z[None, 1:] - x[:, None]
    h = z[1:] - z[:-1]
    I0 = _F0(t1) - _F0(t0)
    I1 = _F1(t1) - _F1(t0)
    right = (I1 - t0 * I0) / h
    L = np.zeros((x.size, z.size))
    L[:, :-1] += I0 - right
    L[:, 1:] += right
    return L


def _trapezoid_weights(z):
    w = np.zeros(z.size)
    h = np.diff(z)
    w[:-1] += h / 2
    w[1:] += h / 2
    return w


def hertz_log(x, a):
    """int_{-a}^{a} sqrt(1 - z^2/a^2) ln|x - z| dz for |x| <= a (closed form)."""
    return 0.5 * np.pi * a * (np.log(a / 2) - 0.5) + np.pi * x * x / (2 * a)


def _chebyshev_points(n):
    j = np.arange(n)
    return 0.5 * (1 - np.cos(np.pi * (j + 0.5) / n))


def _lagrange_matrix(tn, t):
    """Values at t of the Lagrange basis on the nodes tn (barycentric form)."""
    wb = np.array([1.0 / np.prod(tn[j] - np.delete(tn, j)) for j in range(tn.size)])
    D = t[:, None] - tn[None, :]
    exact = np.isclose(D, 0.0, atol=1e-15)
    T = wb[None, :] / np.where(exact, 1.0, D)
    T = T / T.sum(axis=1, keepdims=True)
    rows = exact.any(axis=1)
    T[rows] = exact[rows].astype(float)
    return T


class _State:
    """The traction at one instant and the displacement it produces."""

    def __init__(self, a, p0, b, z, d, k, log_l, smu):
        self.a, self.p0, self.b, self.z, self.d = a, p0, b, z, d
        self.k, self.log_l, self.smu = k, log_l, smu

    def u(self, x):
        x = np.atleast_1d(np.asarray(x, float))
        k, smu, p0, a = self.k, self.smu, self.p0, self.a
        out = -k * smu * p0 * hertz_log(x, a) + k * self.log_l * smu * p0 * np.pi * a / 2
        out = out - k * log_matrix(x, self.z) @ self.d + k * self.log_l * (_trapezoid_weights(self.z) @ self.d)
        return np.where(np.abs(x) <= a * (1 + 1e-12), out, np.nan)

    def dev(self, x):
        """The deviation d from the sliding traction (zero outside the stick zone)."""
        return np.interp(np.atleast_1d(x), self.z, self.d, left=0.0, right=0.0)

    def q(self, x):
        x = np.atleast_1d(x)
        p = self.p0 * np.sqrt(np.clip(1 - (x / self.a) ** 2, 0, None))
        return self.smu * p + self.dev(x)


def _ell(e):
    e = np.clip(e, -1, 1)
    return 0.5 * (e * np.sqrt(np.clip(1 - e * e, 0, None)) + np.arcsin(e))


def _path_load(x, delta, a_prev, a, p0_prev, p0, dt):
    """Along the step of the particle that ends at x: int p dt [Pa s] and the time in the patch [s].

    The particle moves from x + delta to x while a_prev -> a; in the normalised coordinate
    eta = x / a it moves linearly from e0 to e1, so the pressure integrates exactly (``_ell``).
    """
    e0, e1 = (x + delta) / a_prev, x / a
    span = e0 - e1
    int_p = 0.5 * (p0_prev + p0) * dt * (_ell(e0) - _ell(e1)) / span
    loaded = np.maximum(dt * (np.minimum(e0, 1) - np.maximum(e1, -1)) / span, 0)
    return int_p, loaded


def solve(P, a, *, k, mu, creepage, half_width, speed, delta, M, closure_scale=1.0, nh=20, K=1000, wave=0.0,
          nq=48, entry="linear"):
    """Unsteady partial-slip rolling under the load history P (one value per step).

    Parameters
    ----------
    P, a : ndarray
        Normal load [N] and Hertz half-length [m] at each step (the contact moves Delta per step).
    k : float
        Compliance 4 (1 - nu^2) / (pi E) [1/Pa].
    mu, creepage : float
        Friction coefficient [-] and longitudinal creepage gamma [-] (nonzero).
    half_width : float
        Half-width b_w of the contact [m].
    speed, delta : float
        Rolling speed V [m/s] and step Delta [m] (dt = Delta / V).
    M : int
        Nodes -M..M of the fixed grid n Delta on which the work is collected; M Delta > max a.
    closure_scale : float
        s of the closure length l = (a/2) e^{2 s / pi}.
    nh, K : int
        Collocation points of the stick-zone polynomial and points of the product-integration mesh.
    wave : float
        Wavenumber [rad/m] of the grid-free collection C.
    nq : int
        Gauss points per piece of the grid-free collection.
    entry : {'linear', 'quadratic'}
        Interpolation in time of the leading-edge displacement for a point that entered during the
        step (module docstring).

    Returns
    -------
    work : ndarray (len(P) + 2M + 1,)
        Frictional work per unit area [J/m^2] of rail point j, which is at x = (j - i - M) Delta at
        step i (the indexing of ``rail.contact.solve_tangential``).
    Q : ndarray
        Tangential force per step [N].
    b : ndarray
        Stick/slip boundary per step [m].
    C : ndarray (complex)
        Grid-free collection per step: int w_i(x) e^{-i wave x} dx [J/m], w_i(x) the work per unit
        area done over step i on the particle that ends at contact coordinate x.

    Raises
    ------
    RuntimeError
        If the solution leaves the regime of the method: the stick traction exceeds mu p, a slipping
        point slips against the traction, or no boundary is found.
    """
    if entry not in ("linear", "quadratic"):
        raise ValueError(f"entry = {entry!r}: must be 'linear' or 'quadratic'")
    quadratic = entry == "quadratic"
    P = np.asarray(P, float)
    a = np.asarray(a, float)
    nn = 2 * M + 1
    xi = (np.arange(nn) - M) * delta
    dt = delta / speed
    g = creepage
    sigma = -np.sign(g)
    smu = sigma * mu
    steps = P.size
    work = np.zeros(steps + nn)
    Q = np.zeros(steps)
    bh = np.zeros(steps)
    C = np.zeros(steps, complex)
    gx, gw = np.polynomial.legendre.leggauss(nq)
    th_q, gw = 0.5 * np.pi * (gx + 1), 0.25 * np.pi * gw * np.sin(0.5 * np.pi * (gx + 1))

    def piece(x0, x1):
        # nodes and weights on (x0, x1) in the map x = x0 + (x1 - x0) (1 - cos th) / 2
        return x0 + (x1 - x0) * 0.5 * (1 - np.cos(th_q)), gw * (x1 - x0)
    tn = _chebyshev_points(nh)

    def log_l(ai):
        return np.log(0.5 * ai * np.exp(2 * closure_scale / np.pi))

    def basis(ai, b):
        z = b + (ai - b) * 0.5 * (1 - np.cos(np.pi * np.linspace(0, 1, K)))
        W = np.sqrt(np.clip(1 - (z / ai) ** 2, 0, None)) * np.sqrt(np.clip(z - b, 0, None))
        return z, W[:, None] * _lagrange_matrix(tn, (z - b) / (ai - b))

    # start from Carter's steady traction at P[0]
    a0 = a[0]
    p00 = P[0] / (np.pi * a0 * half_width)
    b = carter_boundary(P[0], a0, k, mu, g, half_width)
    z, F = basis(a0, b)
    h0 = -smu * p00 / np.sqrt(a0 + (b + (a0 - b) * tn))
    prev = _State(a0, p00, b, z, F @ h0, k, log_l(a0), smu)
    ins0 = np.abs(xi) < a0
    u_old = np.full(nn, np.nan)
    u_old[ins0] = prev.u(xi[ins0])
    u_edge_old, u_trail_old = prev.u(a0)[0], prev.u(-a0)[0]
    u_edge_old2 = u_edge_old  # steady start: the edge displacement was constant
    a_prev, p0_prev = a0, p00
    p_prev = p00 * np.sqrt(np.clip(1 - (xi / a0) ** 2, 0, None))
    q_prev = np.where(ins0, prev.q(xi), 0.0)
    b_prev = b_prev2 = b
    for i in range(steps):
        ai = a[i]
        p0 = P[i] / (np.pi * ai * half_width)
        p = p0 * np.sqrt(np.clip(1 - (xi / ai) ** 2, 0, None))
        inside = p > 0

        def system(bb, final=False, ai=ai, p0=p0, a_prev=a_prev, prev=prev, u_edge_old=u_edge_old,
                   u_edge_old2=u_edge_old2):
            z, F = basis(ai, bb)
            xc = bb + (ai - bb) * tn
            rows = np.r_[xc, ai, bb]
            Ufix = -k * smu * p0 * hertz_log(rows, ai) + k * log_l(ai) * smu * p0 * np.pi * ai / 2
            G = -k * (log_matrix(rows, z) @ F) + k * log_l(ai) * (_trapezoid_weights(z) @ F)[None, :]
            A = G[:nh].copy()
            rhs = np.empty(nh)
            stay = xc + delta < a_prev
            rhs[stay] = prev.u(xc[stay] + delta) - g * delta - Ufix[:nh][stay]
            for r in np.where(~stay)[0]:
                e0, e1 = (xc[r] + delta) / a_prev, xc[r] / ai
                th = min(max((e0 - 1) / (e0 - e1), 0.0), 1.0)
                if quadratic:  # u_edge at the entry instant through steps i - 2, i - 1, i
                    c1, c0, cm = th * (th + 1) / 2, 1 - th * th, th * (th - 1) / 2
                    A[r] = G[r] - c1 * G[nh]
                    rhs[r] = c0 * u_edge_old + cm * u_edge_old2 - g * delta * (1 - th) - (Ufix[r] - c1 * Ufix[nh])
                else:
                    A[r] = (G[r] - th * G[nh]) / (1 - th)
                    rhs[r] = u_edge_old - g * delta - (Ufix[r] - th * Ufix[nh]) / (1 - th)
            hv = np.linalg.solve(A, rhs)
            if final:
                return _State(ai, p0, bb, z, F @ hv, k, log_l(ai), smu)
            ub = Ufix[-1] + G[-1] @ hv
            return g * speed + (ub - prev.u(bb + delta)[0]) / dt

        bb = None
        x0 = b_prev if i == 0 else 2 * b_prev - b_prev2
        x1 = x0 + 1e-3 * delta
        try:
            f0, f1 = system(x0), system(x1)
            for _ in range(30):
                if f1 == f0:
                    break
                x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
                if abs(x2 - x1) < 1e-10 * delta:
                    bb = x2
                    break
                x0, f0, x1, f1 = x1, f1, x2, system(x2)
        except (ValueError, np.linalg.LinAlgError, ZeroDivisionError, FloatingPointError):
            bb = None
        if bb is None or not (b_prev - 3 * delta < bb < ai):
            lo, hi = b_prev - 0.25 * delta, min(b_prev + 0.25 * delta, 0.5 * (b_prev + ai))
            flo, fhi = system(lo), system(hi)
            for _ in range(30):
                if flo * fhi <= 0:
                    break
                lo -= 0.25 * delta
                hi = min(hi + 0.25 * delta, 0.5 * (hi + ai))
                flo, fhi = system(lo), system(hi)
            if flo * fhi > 0:
                raise RuntimeError(f"step {i}: no stick/slip boundary found near b = {b_prev:.6g} m")
            bb = brentq(system, lo, hi, xtol=1e-10 * delta, rtol=1e-15)
        st = system(bb, final=True)
        bh[i] = bb
        qn = np.where(inside, st.q(xi), 0.0)
        stick = inside & (xi > bb)
        if np.any(np.abs(qn[stick]) > mu * p[stick] * (1 + 1e-9)):
            raise RuntimeError(f"step {i}: stick traction above mu p (outside the method's regime)")
        u_new = np.full(nn, np.nan)
        u_new[inside] = st.u(xi[inside])
        slip = inside & ~stick
        s = np.zeros(nn)
        idx = np.where(slip)[0]
        s[idx] = g * speed + (u_new[idx] - u_old[idx + 1]) / dt
        if np.any(s[slip] * sigma > 0):
            raise RuntimeError(f"step {i}: a point slips along its traction (outside the method's regime)")
        Q[i] = smu * P[i] + 2 * half_width * (_trapezoid_weights(st.z) @ st.d)
        # frictional work of the rail points over the step (path integral, see the module docstring)
        eta0, eta1 = (xi + delta) / a_prev, xi / ai
        was = np.zeros(nn, bool)
        was[:-1] = (p_prev > 0)[1:]
        q_old = np.zeros(nn)
        q_old[:-1] = q_prev[1:]
        q_old[~was] = 0
        p_old = np.zeros(nn)
        p_old[:-1] = p_prev[1:]
        u_trail_new = st.u(-ai)[0]
        left = was & ~inside
        phi = np.zeros(nn)
        phi[left] = np.clip((eta0[left] + 1) / (eta0[left] - eta1[left]), 0, 1)
        left &= phi >= THETA_EDGE
        s_exit = np.zeros(nn)
        for n in np.where(left)[0]:
            ue = (1 - phi[n]) * u_trail_old + phi[n] * u_trail_new
            s_exit[n] = g * speed + (ue - u_old[n + 1]) / (phi[n] * dt)
        s_bar = np.where(inside, s, s_exit)
        ref = np.where(inside & (qn != 0), qn, q_old)
        counted = (inside | was) & (s_bar != 0) & (ref != 0)
        sc = np.where(ref > 0, 1.0, -1.0)[counted]
        int_p, loaded = _path_load(xi[counted], delta, a_prev, ai, p0_prev, p0, dt)
        d_new = np.where(inside[counted], qn[counted] - sc * mu * p[counted], 0)
        d_old = np.where(was[counted], q_old[counted] - sc * mu * p_old[counted], 0)
        dw = np.zeros(nn)
        dw[counted] = np.abs(s_bar[counted] * (sc * mu * int_p + 0.5 * (d_old + d_new) * loaded))
        work[i:i + nn] += dw
        # grid-free collection (module docstring)
        total = 0.0j
        b_old = prev.b - delta
        cuts = [-ai, b_old, bb] if -ai < b_old < bb else [-ai, bb]
        for x0, x1 in pairwise(cuts):
            xq, wq = piece(x0, x1)
            sv = g * speed + (st.u(xq) - prev.u(xq + delta)) / dt
            ip, loaded = _path_load(xq, delta, a_prev, ai, p0_prev, p0, dt)
            d_old = prev.dev(xq + delta)
            total += np.sum(wq * np.abs(sv * (smu * ip + 0.5 * d_old * loaded)) * np.exp(-1j * wave * xq))
        if -ai > -a_prev - delta:  # particles that left at the trailing edge during the step
            xq, wq = piece(-a_prev - delta, -ai)
            e0, e1 = (xq + delta) / a_prev, xq / ai
            ph = np.clip((e0 + 1) / (e0 - e1), THETA_EDGE, 1)
            ue = (1 - ph) * u_trail_old + ph * u_trail_new
            sv = g * speed + (ue - prev.u(np.minimum(xq + delta, a_prev))) / (ph * dt)
            ip = _path_load(xq, delta, a_prev, ai, p0_prev, p0, dt)[0]
            total += np.sum(wq * np.abs(sv * smu * ip) * np.exp(-1j * wave * xq))
        C[i] = total
        prev, u_old = st, u_new
        u_edge_old2 = u_edge_old
        u_edge_old, u_trail_old = st.u(ai)[0], u_trail_new
        b_prev2 = b_prev
        a_prev, p0_prev, p_prev, q_prev, b_prev = ai, p0, p, qn, bb
    return work, Q, bh, C


def wear_harmonic(f, amp, nodes, *, P0, R, speed, youngs_modulus, poisson_ratio, half_width, mu, creepage,
                  closure_scale=1.0, spin=4, nh=20, K=1000, grid_free=False, entry="linear"):
    """The lattice harmonic of :func:`wear_harmonics`, or with ``grid_free`` the grid-free one."""
    both = wear_harmonics(f, amp, nodes, P0=P0, R=R, speed=speed, youngs_modulus=youngs_modulus,
                          poisson_ratio=poisson_ratio, half_width=half_width, mu=mu, creepage=creepage,
                          closure_scale=closure_scale, spin=spin, nh=nh, K=K, entry=entry)
    return both[1] if grid_free else both[0]


def wear_harmonics(f, amp, nodes, *, P0, R, speed, youngs_modulus, poisson_ratio, half_width, mu, creepage,
                   closure_scale=1.0, spin=4, nh=20, K=1000, entry="linear"):
    """Harmonic of the frictional work at the load frequency f under P0 (1 + amp cos 2 pi f t).

    ``nodes`` grid nodes across the largest patch (a grid spacing that fits one wavelength V / f an
    integer number of times); ``spin`` wavelengths of spin-up from Carter's steady state, then one
    measured wavelength. Returns (lattice, grid_free) [J/m^2] (complex): 2 mean(w e^{-i 2 pi x / lambda})
    over it, the work collected on the rail-point lattice, and the same harmonic from the grid-free
    collection, (2 / lambda) sum_i C_i e^{-i 2 pi i Delta / lambda} over one period.
    """
    k = compliance(youngs_modulus, poisson_ratio)
    lam = speed / f
    amax = float(hertz_half_length(P0 * (1 + amp), R, k, half_width))
    Ns = round(lam * (nodes - 1) / (2 * amax))
    delta = lam / Ns
    M = int(np.ceil(amax * 1.02 / delta)) + 1
    x = np.arange((spin + 1) * Ns + 2 * M + 1) * delta
    P = P0 * (1 + amp * np.cos(2 * np.pi * x / lam))
    w, _, _, C = solve(P, hertz_half_length(P, R, k, half_width), k=k, mu=mu, creepage=creepage,
                       half_width=half_width, speed=speed, delta=delta, M=M, closure_scale=closure_scale,
                       nh=nh, K=K, wave=2 * np.pi / lam, entry=entry)
    i = np.arange(spin * Ns, (spin + 1) * Ns)
    phase = np.exp(-2j * np.pi * i * delta / lam)
    return 2 * np.mean(w[i + M] * phase), 2 / lam * np.sum(C[i] * phase)
