"""The linear method with dynamic creepage: the periodic state with u_bar (rail.creepage.coupling.march_with_creepage)
linearised about the smooth rail, per Bloch class (method 'linear' of rate_spectrum).

The nonlinear passage over a period of N bays (n = N N_x steps) finds the u_bar of eq 26 in its
periodic steady state, u_bar = p + v_bar t at the steps: p the periodic part, v_bar the mean slip
rate of a free rotation (the torque balance), with

    p = R[F] + A_Q Q - A_P P + V int E_P P dt     (up to a constant),   F = (Q_{i-1} + Q_i) / 2 - Q_ref,

R the wheelset's periodic response (rail.creepage.modes.periodic_response; its free rotation takes
F less its time mean) and A_Q, A_P, E_P the rail head's (rail.creepage.rail_flexibility.HeadOperator); with a free
rotation, v_bar such that the time mean of F is 0. Q is the march's tangential force with u_bar given.

About the smooth rail (one bay, u_bar_0 = p_0 + v_bar_0 t from march_with_creepage) a probe of the
Bloch class r changes the march's inputs (force, half-length, pressure shape, step times: as
linear_rates finds them) and through them and through delta u_bar the force Q. The tangent march
(rail.contact.tangent.work_tangent, with u_bar as an input direction, the force's derivative
returned, the falling friction's slope) gives delta Q and the wear's derivative along the input
directions and along a basis of delta u_bar: the harmonics exp(2 pi i q k / n), k = i - spin the
step, of the class (q = m N + r, the head table's m, abs(q) <= N K; q = 0 left out: a constant u_bar
does not enter the slip), and for class 0 with a free rotation the slip rate (delta v_bar t). In
those harmonics the loop is a small linear solve per class:

    c = G (dQ_in + T c) + g_in,   G = diag(H_d(q) (1 + exp(-2 pi i q / n)) / 2) + A_Q (class r),

H_d the wheelset's exact response of the march's discrete modes to a force held over each step,
T[q', q] the harmonic q' of delta Q per unit u_bar harmonic q, and g_in the inputs' own part: the
rail head's -A_P dP + V int E_P dP, and the wheelset's response to the step times' change (the
periodic response depends on the step times: its tangent, periodic_response_dt). For class 0 the
torque balance adds delta v_bar and the row: the time mean of delta F (with delta Q_ref from the mean
load's change) is 0. The wear's derivative is then the inputs' plus the basis' weighted by c.

Left out: the wheelset's response above the head's harmonics N K (delta u_bar is taken in the
harmonics abs(q) <= N K; the modes' receptance falls as 1 / omega^2 there); the reference's u_bar is
converged to 1e-10 of the creep velocity (march_with_creepage's tol; REFERENCE_TOL), the probes' of method 'probe' to 1e-5.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._lazyjit import njit
from ..contact.hertz import ContactError
from ..contact.steady import carter
from ..creepage.rail_flexibility import head_operator
from ..creepage import coupling
from ..creepage.coupling import CreepageState, steady_material
from .probes import GridMismatch

__all__ = ["has_creepage", "CreepageReference", "creepage_reference", "closed_loop_wear", "discrete_mode_response",
           "periodic_response_dt", "cell_closed_loop_wear"]

# the smooth rail's u_bar and the linearity check's probes (warm_train_wear): Newton steps down to this fraction of the
# creep velocity. 1e-8 (until 2026-12-02) left the check's probes of 2 eps = 2 nm tolerance-bound (measured on the tests'
# motored wheelset at a comb line: a change of the rate of 1.2e-4 against 2.4e-6 at 1e-10, and 3.0e-6 from probes cold to 1e-9)
REFERENCE_TOL = 1e-10
# the most relative spread of the smooth rail's step times the harmonic basis takes as uniform (at their mean). A wheel
# behind the first rolls on the wheels' wear of one passage before it (of order 1e-12 m): on the patch's true path its
# step times vary by about 1e-8 of their mean (1.8e-8 and 6.3e-9 measured on a four-axle locomotive and coach at 36 m/s),
# which the basis's response changes by the same fraction, far below the grid's 1e-3 of the rate; 1e-9 (until
# 2026-12-02) sent every train of more than one wheel with the dynamic creepage to the probes.
STEP_TIMES_HELD = 1e-6
REFERENCE_STEPS = 60


def has_creepage(material) -> bool:
    """Whether the material carries a source of u_bar (the wheelset's modes or the rail head's flexibility).

    Parameters
    ----------
    material : rail.contact.ContactMaterial
        A wheel's contact parameters [SI] (rail.chain.wheel_material).

    Returns
    -------
    bool
        True with material.longitudinal or material.rail_flexibility [-].
    """
    return material.longitudinal is not None or material.rail_flexibility is not None


@dataclasses.dataclass(frozen=True)
class CreepageReference:
    """The smooth rail's periodic state with u_bar over one bay (march_with_creepage), as the tangent needs it.

    Attributes
    ----------
    ubar : (steps,) u_bar_0 at every step of the one-bay march (spin-up included) [m]
    vbar : v_bar_0 [m/s]
    Q : (N_x,) the tangential force at the bay's steps [N]
    q_ref : Q_ref [N] (None without the wheelset's modes)
    dt : the step time [s] (uniform on the smooth rail)
    P_mean : the mean force over the bay [N]
    p : (N_x,) the periodic part p_0 of u_bar_0 at the bay's steps [m] (where a probe's Newton steps start, warm_train_wear)
    work : (N_x,) the frictional work per unit area at the bay's points x_k [J/m^2] (the smooth rail's wear, the comb's source)
    """

    ubar: np.ndarray
    vbar: float
    Q: np.ndarray
    q_ref: float | None
    dt: float
    P_mean: float
    p: np.ndarray | None = None
    work: np.ndarray | None = None


def creepage_reference(mi, material, speed: float, numerics, harmonics: int) -> CreepageReference:
    """The smooth rail's u_bar_0 over its one-bay march inputs mi (march_with_creepage's Newton steps to REFERENCE_TOL,
    accelerated: _anderson_reference).

    Parameters
    ----------
    mi : rail.contact.passage.MarchInputs
        The smooth rail's inputs over one bay: force [N], half-length [m], grid, step times [s].
    material : rail.contact.ContactMaterial
        The wheel's contact parameters, with its sources of u_bar [SI].
    speed : float
        V [m/s].
    numerics : rail.contact.ContactNumerics
        The closure.
    harmonics : int
        K, the force table's harmonics per bay [-] (the rail head's operator).

    Returns
    -------
    CreepageReference
        u_bar_0 at every step [m], v_bar_0 [m/s], Q at the bay's steps [N], Q_ref [N], the step [s],
        the mean load [N], p_0 at the bay's steps [m] and the work at the bay's points [J/m^2].

    Raises
    ------
    GridMismatch
        Where the smooth rail's step times are not uniform (the harmonic basis's response of the modes
        assumes it; rate_spectrum then takes the probes).
    """
    steps = mi.P.size
    dt_all = np.full(steps, mi.delta / speed) if mi.dt is None else np.asarray(mi.dt, dtype=float)
    if np.ptp(dt_all) > STEP_TIMES_HELD * dt_all.mean():
        raise GridMismatch(f"the smooth rail's step times vary by {np.ptp(dt_all) / dt_all.mean():.2g} of their mean; the "
                           "linear method with dynamic creepage needs them uniform; use method='probe'.")
    sol, info = _anderson_reference(mi, material, speed, numerics, harmonics)
    st = info["state"]
    idx = (np.arange(steps) - mi.spin) % mi.Nx
    ubar = st.p[idx] + st.vbar * np.cumsum(dt_all)
    period = slice(mi.spin, mi.spin + mi.Nx)
    return CreepageReference(ubar, float(st.vbar), sol.Q[period].copy(), info["reference_force"], float(dt_all.mean()),
                             float(np.mean(mi.P[period])), p=st.p.copy(), work=sol.work[mi.spin + mi.M + np.arange(mi.Nx)].copy())


ANDERSON_DEPTH = 5  # the differences of past steps that creepage_reference's acceleration combines


def _anderson_reference(mi, material, speed: float, numerics, harmonics: int):
    """march_with_creepage's periodic state to REFERENCE_TOL with its Newton steps accelerated (Anderson mixing).

    Each step is march_with_creepage's own, one march from a given state (its ``lagged`` hand-on with an
    unbounded threshold: the state x = (p, v_bar) in, its step g(x) - x out, with the step's size of the creep
    velocity); the next state combines the last ANDERSON_DEPTH + 1 states and steps, the combination whose steps
    cancel best in the least-squares sense (type II Anderson mixing), instead of x + (g(x) - x). The answer is
    the same: the march of the first state whose step is below REFERENCE_TOL, as march_with_creepage's to that
    tol (measured to 1e-8: 9 marches against 10 on dynspeed_together at 40 m/s, 0-2 fewer on the tests' track,
    the most with the rail's flexibility; to 1e-10, 11). A step larger than the smallest so far clears
    the history (the next state is the plain step of the smallest step's state). Returns march_with_creepage's
    (solution, info) of that march, info's state the one marched."""
    Nx, spin = mi.Nx, mi.spin
    dtp = np.full(Nx, mi.delta / speed) if mi.dt is None else np.asarray(mi.dt, dtype=float)[spin:spin + Nx]
    T = float(np.sum(dtp))
    phase = (np.cumsum(dtp) - dtp[0]) / T  # as march_with_creepage's
    X, F = [], []  # states (p, v_bar T) [m] and their steps
    start, best = None, None
    for it in range(1, REFERENCE_STEPS + 1):
        sol, info = coupling.march_with_creepage(mi, material, speed, numerics, tol=REFERENCE_TOL, harmonics=harmonics, start=start,
                                        lagged=np.inf)
        stepped = info["state"]
        x = np.zeros(Nx + 1) if start is None else np.append(start.p, start.vbar * T)
        g = np.append(stepped.p, stepped.vbar * T)
        size = info["residual"]
        if size < REFERENCE_TOL:
            return sol, dict(info, iterations=it, state=CreepageState(phase, x[:Nx], x[Nx] / T, grid=Nx))
        if best is not None and size > best[0]:  # not contracting: the plain step of the best state
            X, F = [], []
            x, g, size = best[1], best[2], best[0]
        if best is None or size <= best[0]:
            best = (size, x, g)
        X.append(x)
        F.append(g - x)
        X, F = X[-(ANDERSON_DEPTH + 1):], F[-(ANDERSON_DEPTH + 1):]
        nxt = g
        if len(F) > 1:
            dF = np.array([F[i + 1] - F[i] for i in range(len(F) - 1)]).T
            dX = np.array([X[i + 1] - X[i] for i in range(len(X) - 1)]).T
            gam = np.linalg.lstsq(dF, F[-1], rcond=None)[0]
            nxt = g - (dX + dF) @ gam
        start = CreepageState(phase, nxt[:Nx], float(nxt[Nx] / T), grid=Nx)
    raise ContactError(f"the smooth rail's dynamic creepage did not settle to a periodic state in {REFERENCE_STEPS} accelerated Newton "
                       f"steps (last step {size:.2g} of the creep velocity).")


def _free_transition(om: float, ze: float, T: float):
    """The 2 x 2 transition of (x [m], v [m/s]) over T [s] of x'' + 2 zeta omega x' + omega^2 x = 0 (omega > 0),
    as rail.creepage.modes's march of the modes."""
    sg, wd = ze * om, om * np.sqrt(1 - ze * ze)
    ex, cs, sn = np.exp(-sg * T), np.cos(wd * T), np.sin(wd * T)
    return ex * np.array([[cs + sg / wd * sn, sn / wd], [-(om * om) / wd * sn, cs - sg / wd * sn]])


def discrete_mode_response(modes, dt: float, q, n: int):
    """H_d(q) [m/N]: the modes' periodic response at the end of each step to the force exp(2 pi i q k / n) held
    over step k (rail.creepage.modes.periodic_response with uniform steps of dt [s], exactly), q != 0 mod n.

    Parameters
    ----------
    modes : rail.creepage.modes.LongitudinalModes
        omega [rad/s], zeta [-] and participation [1/kg] of each mode.
    dt : float
        The uniform step [s].
    q : array_like of int
        The harmonics of the period of n steps [-].
    n : int
        Steps in the period [-].

    Returns
    -------
    ndarray, complex
        H_d(q) [m/N], the shape of q.
    """
    z = np.exp(2j * np.pi * np.asarray(q, dtype=float) / n)
    out = np.zeros(z.shape, dtype=complex)
    for om, ze, c in zip(modes.omega, modes.zeta, modes.participation):
        if om == 0:
            Phi = np.array([[1.0, dt], [0.0, 1.0]])
            Gam = np.array([0.5 * c * dt * dt, c * dt])
        else:
            Phi = _free_transition(om, ze, dt)
            xe = c / om**2  # the static response to a unit force: Gamma = (I - Phi) (xe, 0)
            Gam = xe * (np.array([1.0, 0.0]) - Phi[:, 0])
        # s = (I - Phi / z)^-1 Gamma, x its first entry
        a11, a12, a21, a22 = 1 - Phi[0, 0] / z, -Phi[0, 1] / z, -Phi[1, 0] / z, 1 - Phi[1, 1] / z
        det = a11 * a22 - a12 * a21
        out += (a22 * Gam[0] - a12 * Gam[1]) / det
    return out


@njit(cache=True)
def _dt_tangent_mode(F, dt, om, ze, c, ddt, dF0, out):
    """Add to out (n, nc) the tangent of one mode's periodic response (rail.creepage.modes.periodic_response's
    per-mode part, its force F held over each step) along the step-time directions ddt (n, nc), with the
    force changed by the constant dF0 (nc,) at every step (the free rotation's mean force)."""
    n = F.size
    nc = ddt.shape[1]
    T = 0.0
    for i in range(n):
        T += dt[i]
    dT = np.zeros(nc, dtype=np.complex128)
    for i in range(n):
        for cc in range(nc):
            dT[cc] += ddt[i, cc]
    w2 = om * om
    zw2 = 2.0 * ze * om
    sg = ze * om
    wd = om * np.sqrt(1.0 - ze * ze) if om > 0 else 0.0
    for sweep in range(2):  # from rest, then (elastic) from the periodic start
        if sweep == 0:
            x, v = 0.0, 0.0
            dx = np.zeros(nc, dtype=np.complex128)
            dv = np.zeros(nc, dtype=np.complex128)
        else:
            if om == 0.0:
                break
            ex = np.exp(-sg * T)
            cs, sn = np.cos(wd * T), np.sin(wd * T)
            P00, P01 = ex * (cs + sg / wd * sn), ex * sn / wd
            P10, P11 = -(om * om) / wd * ex * sn, ex * (cs - sg / wd * sn)
            # s0 = (I - Phi_T)^-1 s_end; d s0 = (I - Phi_T)^-1 (d s_end + A Phi_T s0 dT), A = [[0, 1], [-w2, -zw2]]
            b00, b01, b10, b11 = 1 - P00, -P01, -P10, 1 - P11
            det = b00 * b11 - b01 * b10
            x0 = (b11 * x - b01 * v) / det
            v0 = (-b10 * x + b00 * v) / det
            px, pv = P00 * x0 + P01 * v0, P10 * x0 + P11 * v0  # Phi_T s0
            ax, av = pv, -w2 * px - zw2 * pv
            for cc in range(nc):
                rx, rv = dx[cc] + ax * dT[cc], dv[cc] + av * dT[cc]
                dx[cc] = (b11 * rx - b01 * rv) / det
                dv[cc] = (-b10 * rx + b00 * rv) / det
            x, v = x0, v0
        xs_end = 0.0
        tcum = 0.0
        for i in range(n):
            h = dt[i]
            f = c * F[i]
            if om == 0.0:
                ph00, ph01, ph10, ph11 = 1.0, h, 0.0, 1.0
                x1 = x + v * h + 0.5 * f * h * h
                v1 = v + f * h
            else:
                ex = np.exp(-sg * h)
                cs, sn = np.cos(wd * h), np.sin(wd * h)
                ph00, ph01 = ex * (cs + sg / wd * sn), ex * sn / wd
                ph10, ph11 = -(om * om) / wd * ex * sn, ex * (cs - sg / wd * sn)
                xe = f / w2
                x1 = xe + ph00 * (x - xe) + ph01 * v
                v1 = ph10 * (x - xe) + ph11 * v
            # d s1 = Phi d s0 + (v1, f - w2 x1 - zw2 v1) ddt (the state's rate at the step's end)
            fx, fv = v1, f - w2 * x1 - zw2 * v1
            for cc in range(nc):
                nx = ph00 * dx[cc] + ph01 * dv[cc] + fx * ddt[i, cc]
                nv = ph10 * dx[cc] + ph11 * dv[cc] + fv * ddt[i, cc]
                if om == 0.0:  # the constant force's change (elastic modes: dF0 is 0)
                    nx += 0.5 * c * dF0[cc] * h * h
                    nv += c * dF0[cc] * h
                dx[cc], dv[cc] = nx, nv
                if sweep == 1 or om == 0.0:
                    out[i, cc] += nx
            x, v = x1, v1
            xs_end = x1
            tcum += h
        if om == 0.0:
            # xs - cumsum(dt) vm, vm = xs[-1] / T: d = dxs - cumsum(ddt) vm - cumsum(dt) dvm
            vm = xs_end / T
            for cc in range(nc):
                dvm = (dx[cc] - vm * dT[cc]) / T
                cum_dt = 0.0
                cum_ddt = 0.0 + 0.0j
                for i in range(n):
                    cum_dt += dt[i]
                    cum_ddt += ddt[i, cc]
                    out[i, cc] -= cum_ddt * vm + cum_dt * dvm


def periodic_response_dt(F, dt, modes, ddt):
    """The tangent of rail.creepage.modes.periodic_response(F, dt, modes)[0] along step-time directions ddt
    (n, nc), complex allowed, with F fixed [m per unit of the direction] (up to a constant per column):
    the wheelset's part of the step times' change; the free rotation's force is F less its time mean
    sum(F dt) / T, which the step times change too.

    Parameters
    ----------
    F : ndarray, (n,)
        The force held over each step [N].
    dt : ndarray, (n,)
        The steps [s].
    modes : rail.creepage.modes.LongitudinalModes
        omega [rad/s], zeta [-] and participation [1/kg] of each mode.
    ddt : ndarray, (n, nc)
        The step times' directions [s per unit of the column].

    Returns
    -------
    ndarray, complex, (n, nc)
        The response's derivative at the end of each step [m per unit of the column].
    """
    F = np.ascontiguousarray(F, dtype=float)
    dt = np.ascontiguousarray(dt, dtype=float)
    ddt = np.ascontiguousarray(ddt, dtype=complex)
    out = np.zeros(ddt.shape, dtype=complex)
    T = float(np.sum(dt))
    Fm = float(np.sum(F * dt) / T)
    dFm = (F @ ddt - Fm * ddt.sum(axis=0)) / T
    for om, ze, c in zip(modes.omega, modes.zeta, modes.participation):
        Fr = F - Fm if om == 0 else F
        dF0 = -dFm if om == 0 else np.zeros_like(dFm)
        _dt_tangent_mode(np.ascontiguousarray(Fr), dt, float(om), float(ze), float(c), ddt, np.ascontiguousarray(dF0), out)
    return out


def _class_harmonics(r: int, N: int, K: int):
    """The harmonics q = m N + r of the period of class r that the head's table holds (m = -K..K for r = 0,
    -K..K-1 otherwise; rail.creepage.rail_flexibility.HeadTable.indices) [-]."""
    m = np.arange(-K, K + (1 if r == 0 else 0))
    return m * N + r


def _bloch_dft(f, q, n: int):
    """Harmonics q of the n-periodic Bloch sequence whose first N_x samples (one bay) are f (N_x, ...):
    (1 / N_x) sum_k f_k exp(-2 pi i q k / n)."""
    Nx = f.shape[0]
    E = np.exp(-2j * np.pi * np.outer(q, np.arange(Nx)) / n) / Nx
    return E @ f


def _expand(f, r: int, N: int):
    """The n = N N_x samples over the period of the class-r Bloch sequence whose first bay is f (N_x, ...)."""
    w = np.exp(2j * np.pi * r * np.arange(N) / N)
    return (w[:, None, None] * f[None]).reshape((N * f.shape[0],) + f.shape[1:])


def _head_class_matrix(op, r: int, N: int, Qr):
    """The real-linear head operator A_Q on class r in its harmonics Qr [m/N] (rows and columns Qr):
    (A_r[q', q] + conj(A_{N-r}[-q', -q])) / 2, exactly what HeadOperator.from_force does to the real and
    imaginary parts of a class-r sequence (it takes the real part of its result)."""
    ta, tb = op.tables[r], op.tables[(N - r) % N]
    qa = ta.indices * N + r
    qb = tb.indices * N + (N - r) % N
    pos = {int(q): i for i, q in enumerate(Qr)}
    ia = np.array([pos[int(q)] for q in qa])
    ib = np.array([pos[int(-q)] for q in qb])
    G = np.zeros((len(Qr), len(Qr)), dtype=complex)
    G[np.ix_(ia, ia)] += 0.5 * ta.A_Q
    G[np.ix_(ib, ib)] += 0.5 * np.conj(tb.A_Q)
    return G


def closed_loop_wear(scn, wheel: int, mi1, speed: float, d: dict, groups, tangent, ref: CreepageReference | None = None,
                     predictions: dict | None = None):
    """The wear's derivative at the bay's points along probe directions with the loop of u_bar closed
    (module docstring), for one wheel.

    Parameters
    ----------
    scn : Scenario
        roughness.bays = N, harmonics K; the wheel's material (chain.wheel_material) with its sources of u_bar.
    wheel : int
    mi1 : rail.wear.MarchInputs
        The smooth rail's one-bay march inputs of the wheel.
    speed : float
        V [m/s].
    d : dict
        The input directions (as wear_tangent's d: 'P', 'a', optionally 'shape', 'dt'), ncol real columns.
    groups : list of (r, c_re, c_im)
        The probes: Bloch class r and the columns of the real and imaginary parts of a complex direction
        (c_im None: a real direction, of class 0 or N / 2).
    tangent : callable
        tangent(material, ubar, d, dubar) -> (dwork at the bay's points (N_x, nc), dQ at the bay's
        steps (N_x, nc)): the tangent march on mi1 (linear.wear_tangent's grid and chunks).

    Returns
    -------
    ndarray, shape (N_x, ncol)
        The derivative of the work per unit area at x_k [J/m^2 per unit column], real columns in the
        layout of d.
    """
    from ..chain import wheel_material  # chain imports rail.growth_spectrum's neighbours only through here

    N, K = scn.roughness.bays, scn.harmonics
    mat = wheel_material(scn, wheel)
    bare = dataclasses.replace(mat, longitudinal=None, rail_flexibility=None)
    modes, head = mat.longitudinal, mat.rail_flexibility
    Nx, spin = mi1.Nx, mi1.spin
    n = N * Nx
    steps = mi1.P.size
    if ref is None:
        ref = creepage_reference(mi1, mat, speed, scn.contact_numerics, K)
    ncol = next(iter(d.values())).shape[-1]
    # the inputs' tangent: u_bar_0's slip rate v_bar_0 over the changed step times, v_bar_0 int ddt
    dub_in = ref.vbar * np.cumsum(d["dt"], axis=0) if ("dt" in d and ref.vbar != 0.0) else None
    dW_in, dQ_in = tangent(bare, ref.ubar, d, dub_in)
    # the basis of delta u_bar: the harmonics of each class present, cosine and sine columns per pair of classes
    classes = sorted({int(r) % N for r, _, _ in groups})
    rigid = modes is not None and any(o == 0 for o in modes.omega)
    canon = {}
    for r in classes:
        key = min(r, (N - r) % N)
        if key not in canon:
            Qk = _class_harmonics(key, N, K)
            canon[key] = Qk[Qk > 0] if key == (N - key) % N else Qk
    qs = np.concatenate([canon[k] for k in sorted(canon)]) if canon else np.zeros(0)
    kk = np.arange(steps) - spin
    cols = [np.cos(2 * np.pi * q * kk / n) for q in qs] + [np.sin(2 * np.pi * q * kk / n) for q in qs]
    with_v = rigid and 0 in classes
    if with_v:
        cols.append(np.cumsum(np.full(steps, ref.dt)))
    nb = len(cols)
    zero = np.zeros((steps, nb))
    dW_b, dQ_b = tangent(bare, ref.ubar, {"P": zero, "a": zero}, np.array(cols).T) if nb else (None, None)
    where = {int(q): i for i, q in enumerate(qs)}

    def basis(q):
        """Complex (dwork, dQ) of the u_bar harmonic exp(2 pi i q k / n) from the cosine and sine columns."""
        if int(q) in where:
            i, sg = where[int(q)], 1.0
        else:
            i, sg = where[int(-q)], -1.0
        j = i + len(qs)
        return dW_b[:, i] + sg * 1j * dW_b[:, j], dQ_b[:, i] + sg * 1j * dQ_b[:, j]

    op = head_operator(head, speed, K, N) if head is not None else None
    F0 = 0.5 * (np.roll(ref.Q, 1) + ref.Q) - (ref.q_ref or 0.0)
    out = np.zeros((Nx, ncol))
    for r in classes:
        mine = [g for g in groups if int(g[0]) % N == r]
        Qr = _class_harmonics(r, N, K)
        U = Qr[Qr != 0]
        # the probes' complex columns
        cin = np.array([dW_in[:, g[1]] + (1j * dW_in[:, g[2]] if g[2] is not None else 0) for g in mine]).T
        qin = np.array([dQ_in[:, g[1]] + (1j * dQ_in[:, g[2]] if g[2] is not None else 0) for g in mine]).T

        def cplx(name):
            a = d[name][spin:spin + Nx]
            return np.array([a[:, g[1]] + (1j * a[:, g[2]] if g[2] is not None else 0) for g in mine]).T

        Wb, Qb = zip(*(basis(q) for q in U)) if U.size else ((), ())
        Wb, Qb = np.array(Wb).T, np.array(Qb).T  # (steps + 2M + 1 or N_x, |U|)
        T = _bloch_dft(Qb, Qr, n)  # (|Qr|, |U|)
        Qh = _bloch_dft(qin, Qr, n)  # (|Qr|, m)
        G = np.zeros((U.size, Qr.size), dtype=complex)
        rows = np.flatnonzero(Qr != 0)
        g_in = np.zeros((U.size, len(mine)), dtype=complex)
        if modes is not None:
            G[np.arange(U.size), rows] += discrete_mode_response(modes, ref.dt, U, n) * 0.5 * (1 + np.exp(-2j * np.pi * U / n))
            if "dt" in d:
                ddt_N = _expand(cplx("dt"), r, N)
                warp = periodic_response_dt(np.tile(F0, N), np.full(n, ref.dt), modes, ddt_N)
                g_in += (np.fft.fft(warp, axis=0) / n)[U % n]
        if op is not None:
            G += _head_class_matrix(op, r, N, Qr)[rows]
            dP_N = _expand(cplx("P"), r, N)
            uP = np.array([op.from_vertical(c.real) + 1j * op.from_vertical(c.imag) for c in dP_N.T]).T
            g_in -= (np.fft.fft(uP, axis=0) / n)[U % n]
        A = np.eye(U.size) - G @ T
        b = G @ Qh + g_in
        if with_v and r == 0:
            Wv, Qv = dW_b[:, -1], dQ_b[:, -1]
            Tv = _bloch_dft(Qv[:, None], Qr, n)[:, 0]
            # the torque balance: the time mean of delta F = delta Q - delta Q_ref (uniform steps) plus the step times' share
            dq_ref = 0.0
            if modes.reference_force is None:
                steady = steady_material(mat, speed)
                h = 1e-6 * ref.P_mean
                slope = (carter(0.0, ref.P_mean + h, steady, speed, mat.wheel_radius)[2]
                         - carter(0.0, ref.P_mean - h, steady, speed, mat.wheel_radius)[2]) / (2 * h)
                dq_ref = slope * np.mean(cplx("P"), axis=0)
            warp_mean = np.zeros(len(mine))
            if "dt" in d:  # sum(F0 ddt - Fm0 ddt) / T over the period (class 0: N times the bay's)
                ddt1 = cplx("dt")
                warp_mean = (F0 @ ddt1 - np.mean(F0) * ddt1.sum(axis=0)) / (Nx * ref.dt)
            A = np.block([[A, -(G @ Tv)[:, None]], [np.mean(Qb, axis=0)[None, :], np.array([[np.mean(Qv)]])]])
            b = np.vstack([b, (-(np.mean(qin, axis=0) - dq_ref + warp_mean))[None, :]])
            c = np.linalg.solve(A, b)
            dW = cin + Wb @ c[:-1] + np.outer(Wv, c[-1])
        else:
            c = np.linalg.solve(A, b) if U.size else np.zeros((0, len(mine)))
            dW = cin + Wb @ c
        if predictions is not None:
            u = np.exp(2j * np.pi * np.outer(np.arange(n), U) / n) @ c[:U.size]
            for i, g in enumerate(mine):
                predictions[g[1]] = (u[:, i], complex(c[-1, i]) if (with_v and r == 0) else 0j)
        for i, g in enumerate(mine):
            out[:, g[1]] = dW[:, i].real
            if g[2] is not None:
                out[:, g[2]] = dW[:, i].imag
    return out


def cell_closed_loop_wear(scn, wheel: int, mi, speed: float, d: dict, tangent, ref: CreepageReference, cache: dict | None = None):
    """The wear's derivative at the cell's points along probe directions with the loop of u_bar closed, for one
    wheel on a track cell (rail.growth_spectrum.cell.cell_linear_operators; closed_loop_wear's loop over the cell).

    On a cell of N bays whose supports differ the smooth rail's state is periodic over the cell, not over a bay, so
    there are no Bloch classes to keep apart: delta u_bar is taken in the real harmonics of the cell's period,
    cos and sin(2 pi q k / n) for q = 1..J (J = N K, the head's and the forces' harmonics; k = i - spin the step,
    n = N_x the cell's steps) and, with a free rotation, the slip rate (delta v_bar t). The tangent march gives
    delta Q and the wear's derivative along the inputs and along that basis; the loop

        c = Proj[ R[delta F] + A_Q delta Q ] + g_in,   delta Q = delta Q_in + T c,

    is one real solve of 2 J (+ 1) unknowns: Proj the cell's harmonics 1..J of a sequence (the coefficients of
    the basis), R the wheelset's response to F = (Q_{i-1} + Q_i) / 2 (exactly H_d(q) (1 + exp(-2 pi i q / n)) / 2
    per harmonic on the smooth rail's uniform steps: discrete_mode_response), A_Q the cell's head operator as the
    march applies it (rail.creepage.coupling.rail_operator: rail.creepage.rail_flexibility_cell.cell_head_operator), and g_in
    the inputs' own part: the head's -A_P dP + V int E_P dP and the wheelset's response to the step times' change
    (periodic_response_dt). With a free rotation the torque balance adds the row: the time mean of delta F (with
    delta Q_ref from the mean load's change) is 0. Left out, as in closed_loop_wear: the wheelset's response above
    the harmonic J.

    Parameters
    ----------
    scn : Scenario
        On a track cell of N = roughness.bays bays, K harmonics per bay; the wheel's material (chain.wheel_material)
        with its sources of u_bar.
    wheel : int
    mi : rail.wear.MarchInputs
        The smooth rail's march inputs of the wheel over the cell.
    speed : float
        V [m/s].
    d : dict
        The input directions (as wear_tangent's d: 'P', 'a', optionally 'shape', 'dt'), ncol real columns.
    tangent : callable
        tangent(material, ubar, d, dubar) -> (dwork at the cell's points (N_x, nc), dQ at the cell's steps
        (N_x, nc)): the tangent march on mi (linear.bay_tangent).
    ref : CreepageReference
        The smooth rail's state with u_bar over the cell (creepage_reference with harmonics J).
    cache : dict, optional
        Holds the basis's tangent and the loop's matrix between calls for one wheel and reference, so that the probes'
        columns can be handed over in chunks (each column's loop is its own: the chunks' results are the whole's).

    Returns
    -------
    ndarray, shape (N_x, ncol)
        The derivative of the work per unit area at the cell's points [J/m^2 per unit column].
    """
    from ..chain import wheel_material  # as closed_loop_wear

    J = scn.roughness.bays * scn.harmonics
    mat = wheel_material(scn, wheel)
    bare = dataclasses.replace(mat, longitudinal=None, rail_flexibility=None)
    modes, head = mat.longitudinal, mat.rail_flexibility
    n, spin, steps = mi.Nx, mi.spin, mi.P.size
    if not 2 * J < n:
        raise ValueError(f"the cell's {n} steps do not resolve its {J} harmonics.")
    dt_all = np.full(steps, mi.delta / speed) if mi.dt is None else np.asarray(mi.dt, dtype=float)
    dub_in = ref.vbar * np.cumsum(d["dt"], axis=0) if ("dt" in d and ref.vbar != 0.0) else None
    dW_in, dQ_in = tangent(bare, ref.ubar, d, dub_in)
    q = np.arange(1, J + 1)
    rigid = modes is not None and any(o == 0 for o in modes.omega)
    cache = {} if cache is None else cache
    if "dQ_b" not in cache:  # the tangent along the basis of delta u_bar, once per wheel
        ang = 2 * np.pi * np.outer(np.arange(steps) - spin, q) / n
        B = np.hstack([np.cos(ang), np.sin(ang)] + ([np.cumsum(dt_all)[:, None]] if rigid else []))
        zero = np.zeros_like(B)
        cache["dW_b"], cache["dQ_b"] = tangent(bare, ref.ubar, {"P": zero, "a": zero}, B)
    dW_b, dQ_b = cache["dW_b"], cache["dQ_b"]
    op = coupling.rail_operator(head, speed, J, mi) if head is not None else None
    Hm = (discrete_mode_response(modes, ref.dt, q, n) * 0.5 * (1 + np.exp(-2j * np.pi * q / n)) if modes is not None
          else np.zeros(J, dtype=complex))

    def proj(x):
        """The basis's coefficients (cos 1..J, sin 1..J) of the real sequences x (n, c) over the cell's steps."""
        X = np.fft.fft(x, axis=0)[1:J + 1] / n
        return np.vstack([2 * X.real, -2 * X.imag])

    def loop(dQ):
        """Proj[R[delta F] + A_Q delta Q] of the force changes dQ (n, c)."""
        X = np.fft.fft(dQ, axis=0)[1:J + 1] / n * Hm[:, None]
        out = np.vstack([2 * X.real, -2 * X.imag])
        if op is not None:
            out = out + proj(np.array([op.from_force(c) for c in dQ.T]).T)
        return out

    ncol = dQ_in.shape[1]
    g_in = loop(dQ_in)
    dP = d["P"][spin:spin + n]
    if op is not None:
        g_in -= proj(np.array([op.from_vertical(c) for c in dP.T]).T)
    F0 = 0.5 * (np.roll(ref.Q, 1) + ref.Q) - (ref.q_ref or 0.0)
    if modes is not None and "dt" in d:
        g_in += proj(np.real(periodic_response_dt(F0, dt_all[spin:spin + n], modes, d["dt"][spin:spin + n])))
    if "A" not in cache:
        A = np.eye(dQ_b.shape[1])
        A[:2 * J] -= loop(dQ_b)
        if rigid:
            A[-1] = np.mean(dQ_b, axis=0)
        cache["A"] = A
    A = cache["A"]
    b = g_in
    if rigid:
        # the torque balance: the time mean of delta F = delta Q - delta Q_ref plus the step times' share (uniform steps)
        dq_ref = np.zeros(ncol)
        if modes.reference_force is None:
            steady = steady_material(mat, speed)
            h = 1e-6 * ref.P_mean
            slope = (carter(0.0, ref.P_mean + h, steady, speed, mat.wheel_radius)[2]
                     - carter(0.0, ref.P_mean - h, steady, speed, mat.wheel_radius)[2]) / (2 * h)
            dq_ref = slope * np.mean(dP, axis=0)
        warp_mean = np.zeros(ncol)
        if "dt" in d:
            ddt = d["dt"][spin:spin + n]
            warp_mean = (F0 @ ddt - np.mean(F0) * ddt.sum(axis=0)) / (n * ref.dt)
        b = np.vstack([b, (-(np.mean(dQ_in, axis=0) - dq_ref + warp_mean))[None, :]])
    c = np.linalg.solve(A, b)
    return dW_in + dW_b @ c
