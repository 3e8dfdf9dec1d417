"""Independent brute-force 2D rolling of a rigid wheel over a wavy rail, in the rail-fixed frame (issue 42).

Written without rail's tangential march (``rail.contact._march`` / ``solve_tangential``) and without its
normal solvers: from ``rail`` only the material constants (``ContactMaterial``, ``compliance``) and, in the
self-checks, Hertz/Carter are used. It measures what the production model leaves out when it keeps the
contact patch centred under the wheel and moving at the wheel's speed V (docs/contact.md, "The move of
the contact centre").

Model
-----
* A rigid wheel of radius R_w rolls in +x at speed V with a constant normal load P (strip of width 2b,
  plane strain) and a constant rigid creepage gamma (``ContactMaterial.creepage``; negative for a driving
  wheel, the traction on the rail q > 0 then). The rail is r(x) = Delta cos(beta x) (any profile object
  with ``height(x)`` and ``slope(x)``).
* Rail particles sit on a fixed lattice x_j = j h (piecewise-constant elements of length h centred there).
  The wheel centre is at x_w(n) = (n0 + n + phi) h at step n: it advances V dt = h per step; phi in [0, 1)
  is a constant sub-cell offset of the wheel against the lattice (the measurement averages over phi, see
  below).
* Normal contact (own brute force, not rail.normal): over a window of the lattice around the wheel, the
  undeformed vertical gap between the wheel's circle and the rail, g_j = R_w - sqrt(R_w^2 - (x_j - x_w)^2)
  - r(x_j) (or the parabola), and the complementarity problem g + k A p - delta >= 0, p >= 0, their product
  0, h sum p = P / (2b), with A the exact element integrals of -ln|x - s| and k = 4 (1 - nu^2) / (pi E)
  (= rail.contact.compliance). Kalker's active-set iteration, warm-started from the previous step; the
  patch lies wherever the gap puts it.
* Tangential contact (own, Kalker-type transient, rail-fixed frame): the relative tangential surface
  displacement at the particles u_j = -k sum_i q_i int_elem_i ln(|x_j - s| / L) ds (the same log kernel).
  A particle's slip velocity is the rigid slip plus the rate of change of its own displacement,
  s_j = gamma V + (u_j(t_n) - u_j(t_{n-1})) / dt: no transport term, the patch moves over the particles at
  whatever speed the normal contact gives it. Coulomb: stick s = 0 with |q| <= mu_s p, slip
  q = -mu_d p sign(s); an active-set iteration per step, the state carried by the particles (a particle
  entering the patch starts in stick from the displacement it had outside).
* The rigid term of the 2D kernel (its reference length L) is the closure; ``closure='fixed'`` keeps L
  constant in time, ``closure='moment'`` uses rail's default family l(t) = (a(t)/2) e^{2 s / pi}, s = 1,
  with a(t) = 2 sqrt(second central moment of p) (= a for the Hertz ellipse, a continuous functional of
  the brute-force pressure).
* Frictional work per unit area accumulated at each rail particle: sum over steps of |q_j s_j| dt.
* ``mode='centred'`` emulates the production model with the same machinery: the gap's tilt about the
  wheel, the Chebyshev-weighted mean slope of r over [x_w - a_ref, x_w + a_ref] (the part of the
  roughness that moves the single-zone patch, c = R_w <r'>), is removed from the rail at every step, so
  that the patch stays centred under the wheel and moves with it at V; the pressure and half-length
  change as before (a tilt only shifts the parabola). The difference of the two modes is the centre-move
  effect alone.

Why phase averaging
-------------------
Everything is on one lattice and the wheel moves one cell per step, so on a smooth rail every particle
sees the same discrete history (no grid-tied noise at all). On the wavy rail the patch edges move against
the lattice by c(x) ~ R_w r' and by the half-length change; the discretisation error depends on where the
edges fall in their cells, a periodic function e(o) of the sub-cell offset o, and its change e'(o) c is of
the order of the signal (a first-order-in-h error with an O(1) slope in o). In the linear regime the
measured response carries the gain error e'(o_0), whose mean over a full period of o_0 is zero; the wheel
offset phi moves o_0 through the period, so ``measure`` averages the complex harmonic over K equispaced
phi (the self-check shows the spread and the convergence in K).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.special import j0

from rail.contact import ContactMaterial, compliance

E_2PI = math.exp(2.0 / math.pi)


# --- geometry -----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Cosine:
    """Rail roughness r(x) = amplitude cos(beta x) [m]."""

    amplitude: float
    beta: float

    def height(self, x):
        return self.amplitude * np.cos(self.beta * x)

    def slope(self, x):
        return -self.amplitude * self.beta * np.sin(self.beta * x)


@dataclass(frozen=True)
class Parabola:
    """Rail of constant curvature r(x) = curvature x^2 / 2 [m]: the patch sweeps at V (1 + R_w curvature)."""

    curvature: float

    def height(self, x):
        return 0.5 * self.curvature * np.asarray(x, dtype=float) ** 2

    def slope(self, x):
        return self.curvature * np.asarray(x, dtype=float)


@dataclass(frozen=True)
class Smooth:
    def height(self, x):
        return np.zeros_like(np.asarray(x, dtype=float))

    def slope(self, x):
        return np.zeros_like(np.asarray(x, dtype=float))


def log_toeplitz(n: int, h: float) -> np.ndarray:
    """T[d] = -int_{-h/2}^{h/2} ln|d h - s| ds, d = 0..n-1: A_ij = T[|i - j|] for elements of length h [m]."""
    d = np.arange(n) * h

    def g(t):
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(t == 0, 0.0, t * np.log(np.abs(t)) - t)

    return -(g(d + h / 2) - g(d - h / 2))


class _ToeplitzInverse:
    """Cached inverses of the contiguous blocks T_n (any n contiguous elements give the same block)."""

    def __init__(self, row: np.ndarray):
        self.row = row
        self.cache: dict[int, tuple[np.ndarray, np.ndarray, float]] = {}

    def get(self, n: int):
        c = self.cache.get(n)
        if c is None:
            idx = np.arange(n)
            T = self.row[np.abs(idx[:, None] - idx[None, :])]
            Ti = np.linalg.inv(T)
            Ti1 = Ti.sum(axis=1)
            c = (Ti, Ti1, float(Ti1.sum()))
            self.cache[n] = c
        return c


def _contiguous(idx: np.ndarray) -> bool:
    return idx.size > 0 and idx[-1] - idx[0] == idx.size - 1


# --- the simulation ----------------------------------------------------------------------------------------

@dataclass
class Result:
    """One run. Arrays per rail particle (global lattice index j, x_j = j h) and per step n."""

    h: float
    x: np.ndarray                # particle positions [m]
    work: np.ndarray             # frictional work per unit area [J/m^2]
    passed: np.ndarray           # bool: the particle has been fully through the patch after the warm-up
    x_wheel: np.ndarray          # per step [m]
    centre: np.ndarray           # zone midpoint - x_wheel (edges by square-root extrapolation) [m]
    centroid: np.ndarray         # pressure centroid - x_wheel [m]
    a_moment: np.ndarray         # 2 sqrt(second central moment of p) [m]
    a_zone: np.ndarray           # half the extrapolated zone length [m]
    force: np.ndarray            # tangential force Q = 2b h sum q [N]
    zones: np.ndarray            # contact zones per step
    stick_cells: np.ndarray      # stick elements per step
    seconds: float = 0.0
    last: dict = field(default_factory=dict)  # the last step's p, q, s, stick (window) and its x_rel


def _edge_extrapolation(p: np.ndarray, lo: int, hi: int, h: float):
    """Zone edges (relative to element centres' index) from p^2 linear over the 2nd and 3rd cells inside.

    Returns (trailing edge, leading edge) in units of elements from index 0 (continuous)."""
    def one(i1, i2, outward):  # i1 nearer the edge, i2 one further in; p^2 = alpha (e - x)
        a2, b2 = p[i1] ** 2, p[i2] ** 2
        if b2 <= a2:
            return i1 + 0.5 * outward
        return i1 + outward * a2 / (b2 - a2)
    if hi - lo < 4:
        return lo - 0.5, hi + 0.5
    return one(lo + 1, lo + 2, -1), one(hi - 1, hi - 2, +1)


def normal_contact(gap, Pw, k, h, Aw, Tinv, active, tol, max_iter=200):
    """Brute-force 2D normal contact on the elements of a window (Kalker's active set).

    Solves gap + k A p - delta >= 0, p >= 0, (gap + k A p - delta) p = 0, h sum p = Pw, with A the
    element integrals of -ln|x - s| (Aw; Tinv: cached inverses of its contiguous blocks).
    gap [m], Pw load per unit width [N/m], k compliance [1/Pa], h element length [m], active: first
    guess (bool), tol: penetration tolerance [m]. Returns p [Pa], delta [m], the active set.
    """
    active = active.copy()
    nw = gap.size
    for _ in range(max_iter):
        ia = np.flatnonzero(active)
        if _contiguous(ia):
            Ti, Ti1, s1 = Tinv.get(ia.size)
            Tg = Ti @ gap[ia]
            delta = (k * Pw / h + Tg.sum()) / s1
            p_a = (delta * Ti1 - Tg) / k
        else:
            Kmat = np.zeros((ia.size + 1, ia.size + 1))
            Kmat[:-1, :-1] = k * Aw[np.ix_(ia, ia)]
            Kmat[:-1, -1] = -1.0
            Kmat[-1, :-1] = h
            sol = np.linalg.solve(Kmat, np.concatenate([-gap[ia], [Pw]]))
            p_a, delta = sol[:-1], sol[-1]
        if np.any(p_a < 0):
            active[ia[p_a < 0]] = False
            if not active.any():
                active[ia[np.argmax(p_a)]] = True
            continue
        pen = (~active) & (gap + k * (Aw[:, ia] @ p_a) - delta < -tol)
        if not pen.any():
            p = np.zeros(nw)
            p[ia] = p_a
            return p, float(delta), p > 0
        active |= pen
    raise RuntimeError("the normal active set did not settle")


def simulate(m: ContactMaterial, P: float, V: float, rail, h: float, steps: int, *, advance: float = 1.0,
             phi: float = 0.0, window: float = 1.6, mode: str = "exact", a_ref: float | None = None,
             closure: str = "fixed", L: float | None = None, profile: str = "circle", warmup: int = 0,
             x_start: float = 0.0, entry: str = "extrapolate", record_last: bool = False,
             tangential: bool = True, creep_factor=None, max_iter: int = 200) -> Result:
    """Roll the wheel over the rail for ``steps`` steps of V dt = advance h (see the module docstring).

    Parameters
    ----------
    m : ContactMaterial (E, nu, b, R_w, mu_d, mu_s, gamma)
    P : normal load [N]; V : speed [m/s] (the 2D quasi-static problem depends on s / V only)
    rail : object with height(x), slope(x) [m], [-]
    h : lattice spacing [m]
    steps : number of steps
    advance : cells the wheel advances per step (1; or (K + 1) / K, which cycles the wheel's sub-cell offset
        through K values every K steps: the grid-phase dither of ``measure``)
    phi : sub-cell offset of the wheel against the lattice at step 0 [-]
    window : half-width of the normal-contact window in units of the smooth Hertz half-length [-]
    mode : 'exact' (the patch where the gap puts it) or 'centred' (tilt removed: the patch under the wheel)
    a_ref : half-length of the tilt's Chebyshev mean in mode 'centred' [m] (default: Hertz with R_w)
    closure : 'fixed' (reference length L, default (a_0/2) e^{2/pi}), 'moment' (l(t) = (a(t)/2) e^{2/pi} with
        a(t) = 2 sqrt(second central moment of p)) or 'zone' (the same with a(t) = half the zone length, its edges
        extrapolated)
    profile : 'circle' (exact wheel) or 'parabola'
    warmup : particles that entered the patch before this step are not 'passed'
    x_start : wheel position at step 0 is about x_start (on the lattice, plus phi h) [m]
    entry : 'extrapolate': a particle that enters the patch during a step sticks from its entry time t_e
        (the fraction theta of the step at which the leading edge, linear in time between the steps,
        passes it), from its displacement there, extrapolated from its free motion over the two previous
        steps; 'step': it sticks over the whole step (first order in dt)
    tangential : False: the normal contact only (work and force stay 0)
    creep_factor : optional callable x_w -> factor on the rigid creepage at that step (a diagnostic)
    """
    t0 = time.process_time()
    R = m.wheel_radius
    k = compliance(m)
    Pw = P / (2 * m.half_width)  # load per unit width [N/m]
    a_h = math.sqrt(2 * k * Pw * R)  # Hertz half-length of the smooth rail (k = 2 / (pi E*))
    if a_ref is None:
        a_ref = a_h
    if L is None:
        L = 0.5 * a_h * E_2PI
    if mode not in ("exact", "centred") or closure not in ("fixed", "moment", "zone") \
            or profile not in ("circle", "parabola"):
        raise ValueError((mode, closure, profile))
    gam, mu_d, mu_s = m.creepage, m.friction_dynamic, m.friction_static
    dt = advance * h / V
    J = int(math.ceil(window * a_h / h)) + 2  # window half-width in cells
    nw = 2 * J + 1
    ahead = int(math.ceil(advance)) + 1  # cells beyond the window whose displacement the next step needs
    row = log_toeplitz(nw + ahead + 2, h)
    Tinv = _ToeplitzInverse(row)
    idx = np.arange(nw)
    Aw = row[np.abs(idx[:, None] - idx[None, :])]  # window influence (normal and tangential)
    Aahead = row[np.abs((nw - 1 + np.arange(1, ahead + 1))[:, None] - idx[None, :])]
    n0 = int(round(x_start / h))
    jbase = n0 - J - 1  # global lattice index of local particle 0
    npart = int(math.ceil(steps * advance)) + nw + ahead + 4
    xg = (jbase + np.arange(npart)) * h
    work = np.zeros(npart)
    first_in = np.full(npart, -1)
    last_in = np.full(npart, -2)
    stick = np.zeros(npart, dtype=bool)
    sgn = np.zeros(npart)  # traction direction in slip
    u_prev = np.zeros(npart)  # displacement at the previous step
    u_prev2 = np.zeros(npart)  # and the one before
    x_lead_prev = None  # leading edge at the previous step [m]
    q_last = np.zeros(npart)  # traction at the previous step
    prevC = np.zeros(0, dtype=int)  # particles in contact at the previous step
    out = {k_: np.zeros(steps) for k_ in ("x_wheel", "centre", "centroid", "a_moment", "a_zone", "force")}
    zones = np.zeros(steps, dtype=int)
    stick_cells = np.zeros(steps, dtype=int)
    tau = np.cos((np.arange(64) + 0.5) * np.pi / 64)  # Gauss-Chebyshev nodes (mode 'centred')
    active = None
    lnL = math.log(L)
    sg0 = -math.copysign(1.0, gam) if gam != 0 else 1.0
    last = {}
    for n in range(steps):
        pos = phi + n * advance
        xw = (n0 + pos) * h
        ic = n0 + int(math.floor(pos + 0.5))  # the wheel's nearest cell
        loc = ic - J - jbase  # local index of the window's first cell
        xs = xg[loc:loc + nw]
        xrel = xs - xw
        wheel = R - np.sqrt(R * R - xrel**2) if profile == "circle" else xrel**2 / (2 * R)
        r = rail.height(xs)
        if mode == "centred":
            tilt = float(np.mean(rail.slope(xw + a_ref * tau)))
            r = r - tilt * xrel
        gap = wheel - r
        # --- normal contact: Kalker's active set, warm-started (window coordinates follow the wheel) ----
        if active is None:
            active = gap < np.min(gap) + a_h**2 / (2 * R)
        p, delta, active = normal_contact(gap, Pw, k, h, Aw, Tinv, active, 1e-13 * a_h**2 / R, max_iter)
        C = np.flatnonzero(p > 0)
        active = p > 0
        zones[n] = int(np.sum(np.diff(np.concatenate([[0], active.astype(int), [0]])) == 1))
        Pt = p.sum()
        xc = (xrel * p).sum() / Pt
        a_mom = 2 * math.sqrt(((xrel - xc) ** 2 * p).sum() / Pt)
        lo_e, hi_e = _edge_extrapolation(p, C[0], C[-1], h)
        out["x_wheel"][n] = xw
        out["centroid"][n] = xc
        out["a_moment"][n] = a_mom
        out["centre"][n] = xrel[0] + 0.5 * (lo_e + hi_e) * h
        out["a_zone"][n] = 0.5 * (hi_e - lo_e) * h
        if not tangential:
            continue
        # --- tangential contact in the rail frame --------------------------------------------------------
        if closure == "moment":
            lnL = math.log(0.5 * a_mom * E_2PI)
        elif closure == "zone":
            lnL = math.log(0.5 * out["a_zone"][n] * E_2PI)
        cL = h * lnL  # u = -k int q ln(|x - s| / L) = k (A q + h ln(L) sum q)
        x_lead = xs[0] + hi_e * h
        if entry == "extrapolate":
            # an element whose centre lies beyond the (extrapolated) leading edge is not loaded yet: its
            # particle has not entered; it carries no traction this step
            C = C[xs[C] < x_lead]
        gC = loc + C  # particles in contact
        entering = last_in[gC] < n - 1
        first_in[gC[first_in[gC] < 0]] = n
        stick[gC[entering]] = True
        sgn[gC[entering]] = sg0
        last_in[gC] = n
        pC = p[C]
        up = u_prev[gC].copy()  # the displacement the particle starts its loaded time from
        tau_l = np.ones(C.size)  # loaded fraction of the step
        if entry == "extrapolate" and x_lead_prev is not None and entering.any():
            e = np.flatnonzero(entering)
            dx = x_lead - x_lead_prev
            th = np.clip((xs[C[e]] - x_lead_prev) / dx, 0.0, 1.0) if dx > 0 else np.zeros(e.size)
            up[e] += th * (u_prev[gC[e]] - u_prev2[gC[e]])
            tau_l[e] = 1.0 - th
        if creep_factor is not None:
            gam = m.creepage * float(creep_factor(xw))
        b = up - gam * V * dt * tau_l  # stick: zero slip over the loaded time
        st = stick[gC].copy()
        sg = sgn[gC].copy()
        AC = Aw[np.ix_(C, C)]
        for _ in range(max_iter):
            q = np.where(st, 0.0, mu_d * pC * sg)
            S = np.flatnonzero(st)
            F = np.flatnonzero(~st)
            if S.size:
                rhs = b[S] / k - AC[np.ix_(S, F)] @ q[F] - cL * q[F].sum()
                if _contiguous(S):
                    Ti, Ti1, s1 = Tinv.get(S.size)
                    y = Ti @ rhs
                    q[S] = y - cL * Ti1 * y.sum() / (1 + cL * s1)
                else:
                    q[S] = np.linalg.solve(AC[np.ix_(S, S)] + cL, rhs)
            u = k * (AC @ q + cL * q.sum())
            s = gam * V * tau_l + (u - up) / dt  # slip displacement over the step / dt
            over = st & (np.abs(q) > mu_s * pC * (1 + 1e-12))
            wrong = (~st) & (s * sg > 0)
            if not (over.any() or wrong.any()):
                break
            sg[over] = np.sign(q[over])
            st[over] = False
            st[wrong] = True
        else:
            raise RuntimeError(f"stick/slip iteration did not settle at step {n}")
        s = np.where(st, 0.0, s)
        stick[gC] = st
        sgn[gC] = sg
        # work over the step: mean traction of the step (trapezoid) times the mean slip velocity
        work[gC] += np.abs(0.5 * (q + q_last[gC]) * s) * dt
        out["force"][n] = 2 * m.half_width * h * q.sum()
        stick_cells[n] = int(st.sum())
        # displacement of every window particle and a few ahead, for the next step
        qs = q.sum()
        u_win = k * (Aw[:, C] @ q + cL * qs)
        u_ah = k * (Aahead[:, C] @ q + cL * qs)
        # particles that left the patch during the step: their last half-step of traction
        gone = np.setdiff1d(prevC, gC, assume_unique=True)
        if gone.size:
            lg = gone - loc
            if lg.min() < 0:
                raise RuntimeError("a particle left the patch behind the window: widen it")
            s_gone = gam * V + (u_win[lg] - u_prev[gone]) / dt
            work[gone] += np.abs(0.5 * q_last[gone] * s_gone) * dt
            q_last[gone] = 0.0
        u_prev2[loc:loc + nw + ahead] = u_prev[loc:loc + nw + ahead]
        u_prev[loc:loc + nw] = u_win
        u_prev[loc + nw:loc + nw + ahead] = u_ah
        q_last[gC] = q
        prevC = gC
        x_lead_prev = x_lead
        if record_last and n == steps - 1:
            full = np.zeros(nw)
            full[C] = q
            ss = np.zeros(nw)
            ss[C] = s
            stk = np.zeros(nw, dtype=bool)
            stk[C] = st
            last = dict(x_rel=xrel.copy(), p=p.copy(), q=full, s=ss, stick=stk)
    passed = (first_in >= warmup) & (last_in >= 0) & (last_in < steps - 1)
    return Result(h=h, x=xg, work=work, passed=passed, zones=zones, stick_cells=stick_cells,
                  seconds=time.process_time() - t0, last=last, **out)


# --- the measurement -----------------------------------------------------------------------------------------

def hertz_a(m: ContactMaterial, P: float) -> float:
    """Smooth-rail Hertz half-length a_0 = sqrt(2 k P' R_w) [m] (2D, the parabola)."""
    return math.sqrt(2 * compliance(m) * P / (2 * m.half_width) * m.wheel_radius)


def lattice(lam: float, a0: float, per_a: float, period: int | None = None):
    """Lattice for wavelength lam: N_lambda = M (K + 1) cells per wavelength, M >= 3, h about a0 / per_a.

    K + 1 is the period in cells of the grid-phase dither (advance (K + 1) / K): with it dividing N_lambda
    and M >= 3, every line of the dither pattern (wavenumbers 2 pi n / ((K + 1) h)) and its sidebands
    +-beta lie on DFT bins other than beta. Returns (h, N_lambda, K)."""
    n_target = lam / (a0 / per_a)
    if period is None:
        period = int(max(8, min(round(per_a / 2), round(n_target / 3))))
    M = max(3, int(round(n_target / period)))
    n_lam = M * period
    return lam / n_lam, n_lam, period - 1


def harmonic(values: np.ndarray, x: np.ndarray, beta: float) -> complex:
    """Complex amplitude H of values = mean + Re(H e^{i beta x}) over whole periods (uniform x)."""
    return complex(2.0 * np.mean(values * np.exp(-1j * beta * x)))


def fit_harmonic(values: np.ndarray, x: np.ndarray, beta: float) -> complex:
    """Least-squares fit values = c0 + Re(H e^{i beta x}); returns H."""
    A = np.column_stack([np.ones_like(x), np.cos(beta * x), -np.sin(beta * x)])
    c = np.linalg.lstsq(A, values, rcond=None)[0]
    return complex(c[1], c[2])


@dataclass
class Measurement:
    lam_over_2a: float
    per_a: float
    amplitude: float          # Delta [m]
    beta: float
    a0: float
    h: float
    dither: int               # K (advance (K + 1) / K)
    mean_work: float          # W-bar [J/m^2]
    H: complex                # work harmonic / (Delta W-bar R_w beta^2): wear depth in phase with r = +real
    centre: complex           # patch-centre harmonic / (R_w i beta Delta J0(beta a0)) (1 = the closed form)
    half_length: complex      # a-harmonic (a_zone) / (Delta a0 R_w beta^2)
    force: complex            # Q-harmonic / (Delta Q-bar R_w beta^2)
    seconds: float
    steps: int


def measure(m: ContactMaterial, P: float, lam_over_2a: float, *, per_a: float = 50, rwkb2: float = 1e-3,
            mode: str = "exact", closure: str = "zone", warmup_transits: float = 8.0, periods: int | None = None,
            dither: bool = True, period: int | None = None, phi: float = 0.0, V: float = 40.0,
            entry: str = "extrapolate", profile: str = "circle", creepage_modulation: bool = False) -> Measurement:
    """First harmonic of the frictional work on r = Delta cos(beta x), lambda = lam_over_2a 2 a_0.

    rwkb2 = R_w Delta beta^2 sets the amplitude (1e-3: the linear regime). The harmonic is taken over
    ``periods`` wavelengths (default: at least 8 a_0 and one wavelength) of particles that entered the
    patch after ``warmup_transits`` transits 2 a_0 of a cold start. creepage_modulation: the rigid creepage
    becomes gamma / (1 + dc/dx) at each step, dc/dx from the closed form c = R_w r' J0(beta a0) (a diagnostic
    for mode 'centred': the patch held under the wheel, moving at V, but with the effective creepage of the
    moving patch, rigid slip over its sweep speed)."""
    a0 = hertz_a(m, P)
    lam = lam_over_2a * 2 * a0
    beta = 2 * math.pi / lam
    delta = rwkb2 / (m.wheel_radius * beta**2)
    h, n_lam, K = lattice(lam, a0, per_a, period)
    adv = (K + 1) / K if dither else 1.0
    if periods is None:
        periods = max(1, int(math.ceil(8 * a0 / lam)))
    n_win = periods * n_lam
    warm_cells = int(math.ceil(warmup_transits * 2 * a0 / h))
    lead = int(math.ceil(2.2 * a0 / h))  # cells from the wheel to behind the trailing edge and margin
    steps = int(math.ceil((warm_cells + n_win + lead + 4) / adv)) + 2
    rail = Cosine(delta, beta)
    cf = None
    if creepage_modulation:
        jz = float(j0(beta * a0))
        def cf(x):  # 1 / (1 + dc/dx), dc/dx = R_w r'' J0(beta a0)
            return 1.0 / (1.0 - m.wheel_radius * beta**2 * jz * float(rail.height(x)))
    r = simulate(m, P, V, rail, h, steps, advance=adv, phi=phi, mode=mode, closure=closure,
                 warmup=int(warm_cells / adv), entry=entry, profile=profile, creep_factor=cf)
    idx = np.flatnonzero(r.passed)
    sel = idx[:n_win]
    if sel.size < n_win or sel[-1] - sel[0] != n_win - 1:
        raise RuntimeError("not enough passed particles for the harmonic")
    W = r.work[sel]
    x = r.x[sel]
    Wm = float(W.mean())
    H = harmonic(W, x, beta) / (delta * Wm * m.wheel_radius * beta**2)
    # per-step quantities over the steps whose wheel position covers the same particles
    xw = r.x_wheel
    ks = np.flatnonzero((xw >= x[0]) & (xw < x[0] + periods * lam))
    cen = fit_harmonic(r.centre[ks], xw[ks], beta) / (m.wheel_radius * 1j * beta * delta * j0(beta * a0))
    ahm = fit_harmonic(r.a_zone[ks], xw[ks], beta) / (delta * a0 * m.wheel_radius * beta**2)
    Qm = float(np.mean(r.force[ks]))
    Qh = fit_harmonic(r.force[ks], xw[ks], beta) / (delta * Qm * m.wheel_radius * beta**2)
    return Measurement(lam_over_2a, per_a, delta, beta, a0, h, K, Wm, H, cen, ahm, Qh, r.seconds, steps)


def production_centred(m: ContactMaterial, P: float, lam_over_2a: float, *, nodes: int = 81, rwkb2: float = 1e-3,
                       V: float = 40.0, grids: int = 4, spin_transits: float = 8.0) -> tuple[complex, float, float]:
    """The production model's work harmonic on the same rail, normalised like ``Measurement.H``.

    Not part of the simulator: rail.normal.patch_contact (exact single-zone pressure, patch centred under
    the wheel: its ``shift`` is not applied) and rail.contact.solve_tangential (the patch-fixed march, the
    default closure), constant load. Averaged over ``grids`` grid spacings whose a / Delta sweeps one unit
    (the production's own averaging of its grid-tied error). Returns (H, W-bar, seconds)."""
    from rail.contact import solve_tangential
    from rail.contact.normal import patch_contact

    t0 = time.process_time()
    a0 = hertz_a(m, P)
    lam = lam_over_2a * 2 * a0
    beta = 2 * math.pi / lam
    delta_r = rwkb2 / (m.wheel_radius * beta**2)
    rail = Cosine(delta_r, beta)
    periods = max(1, int(math.ceil(8 * a0 / lam)))
    Hs, Ws = [], []
    for g in range(grids):
        n_lam = int(round(lam / (2 * a0 / (nodes - 1)) + g * lam / (grids * a0)))
        d = lam / n_lam
        M = int(math.ceil(1.05 * a0 / d)) + 1
        spin = int(math.ceil(spin_transits * 2 * a0 / d))
        N = periods * n_lam
        steps = spin + N + 2 * M + 1
        xw = (np.arange(steps) - spin) * d
        xi = (np.arange(2 * M + 1) - M) * d
        pc = patch_contact(np.full(steps, P), xw, rail.slope, m, xi)
        sol = solve_tangential(np.full(steps, P), pc.a, m, V, d, M, shape=pc.shape)
        j = spin + M + np.arange(N)
        W = sol.work[j]
        x = np.arange(N) * d
        Wm = float(W.mean())
        Hs.append(harmonic(W, x, beta) / (delta_r * Wm * m.wheel_radius * beta**2))
        Ws.append(Wm)
    return complex(np.mean(Hs)), float(np.mean(Ws)), time.process_time() - t0


def normal_response(m: ContactMaterial, P: float, lam_over_2a: float, *, per_a: float = 50, rwkb2: float = 1e-3,
                    period: int | None = None, mode: str = "exact", phi: float = 0.0, profile: str = "circle"):
    """The brute-force normal contact alone along a dithered passage over whole wavelengths.

    Returns harmonics at beta (fitted over the wheel positions), each normalised by its closed form:
    zone midpoint / (R_w i beta Delta J0(beta a0)) (the single-zone shift c = R_w r' J0), pressure centroid /
    (R_w i beta Delta (J0 + J2)) (the centroid of the exact single-zone pressure: the shift plus the first
    moment of its shape), half-length / (-Delta a0 R_w beta^2 J1(beta a0) / (beta a0)) (the curvature filter
    2 J1 / (beta a) of rail.normal.half_length_filter), as complex numbers (1 = the closed form)."""
    from scipy.special import j1, jv

    a0 = hertz_a(m, P)
    lam = lam_over_2a * 2 * a0
    beta = 2 * math.pi / lam
    delta = rwkb2 / (m.wheel_radius * beta**2)
    h, n_lam, K = lattice(lam, a0, per_a, period)
    adv = (K + 1) / K
    periods = max(1, int(math.ceil(4 * a0 / lam)))
    steps = int(math.ceil(periods * n_lam / adv)) + 1
    r = simulate(m, P, 40.0, Cosine(delta, beta), h, steps, advance=adv, phi=phi, mode=mode, tangential=False,
                 profile=profile)
    xw = r.x_wheel
    ks = np.flatnonzero(xw - xw[0] < periods * lam)
    z = beta * a0
    Rw = m.wheel_radius
    mid = fit_harmonic(r.centre[ks], xw[ks], beta) / (Rw * 1j * beta * delta * j0(z))
    cen = fit_harmonic(r.centroid[ks], xw[ks], beta) / (Rw * 1j * beta * delta * (j0(z) + jv(2, z)))
    ahm = fit_harmonic(r.a_zone[ks], xw[ks], beta) / (-delta * a0 * Rw * beta**2 * j1(z) / z)
    return mid, cen, ahm, r
