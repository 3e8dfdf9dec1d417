"""Grid-tied error and convergence of the unsteady tangential contact (converged-corrugation-band issue).

Growth is driven by a variation of the wear along the bay of only a few percent of the mean (about
+-1.8 % at 40 m/s from the sleeper-passing force), so every error is judged against the quantity it
is part of: the steady frictional work against Carter's exact value, a wear harmonic against that
harmonic (amplitude and phase), a sign as a sign.
"""

import functools

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from rail import contact as C

R, V, P0 = 0.575, 40.0, 1.0e5
PARAMETRIC_WEAR_VARIATION = 0.018  # of the mean wear, 40 m/s, smooth rail (issue; review notes)


def material(creepage=-0.001):
    return C.ContactMaterial(2.1e11, 0.3, 0.008, R, 0.3, 0.3, creepage)


def carter_work(m):
    """Steady frictional work per unit area of a rail point, |gamma| Q / (2b) (energy balance), J/m^2."""
    return abs(m.creepage * C.carter(np.zeros(1), P0, m, V, R)[2]) / (2 * m.half_width)


def steady(ratio, m, q0=None, transits=16, M=25):
    """Steady rolling at a / Delta = ratio: (work of a rail point / Carter's, the solution)."""
    a = float(C.hertz_half_length(P0, R, m))
    delta = a / ratio
    n_tr = int(np.ceil(2 * ratio))
    steps = transits * n_tr
    sol = C.solve_tangential(np.full(steps, P0), np.full(steps, a), m, V, delta, M, q0=q0)
    w = sol.work[(transits - 2) * n_tr:(transits - 1) * n_tr]
    assert w.std() < 1e-4 * w.mean()  # steady: every rail point gets the same work
    return w.mean() / carter_work(m), sol


def trapezoid_work(sol, m):
    """The previous rule, reconstructed from the same steady solution: the nodal tractions
    integrated along the path by the trapezoidal rule, the last segment falling to 0 at -a."""
    a = sol.a[-1]
    q, s = sol.q[-1], sol.s[-1]
    dw = np.abs(0.5 * (q + np.r_[q[1:], 0.0]) * s) * sol.delta / V
    trail = int(np.argmax(np.abs(sol.xi) < a))
    exit_ = abs(0.5 * q[trail] * s[trail]) * (sol.xi[trail] + a) / V
    return (dw.sum() + exit_) / carter_work(m)


def test_steady_work_is_continuous_when_the_patch_edges_cross_nodes():
    # At a / Delta = 21 both patch edges cross a node. With the trapezoidal rule the work jumps by
    # 0.17 % there (0.98618 -> 0.98789 of Carter's, measured on the same solutions); the exact path
    # integral of the Hertz pressure, the exit slip from the displacement at -a and the square-root
    # traction basis leave 6e-6 (the hat basis: 4e-5).
    m = material()
    below, sol_b = steady(21 - 1e-6, m)
    above, sol_a = steady(21 + 1e-6, m)
    assert abs(above - below) < 2e-5
    jump_trapezoid = abs(trapezoid_work(sol_a, m) - trapezoid_work(sol_b, m))
    assert jump_trapezoid > 1e-3
    assert jump_trapezoid > 20 * abs(above - below)


def test_steady_work_against_a_over_delta_has_no_step_far_below_the_parametric_variation():
    # 201 values over two units of a / Delta (about 41 nodes across the patch). Measured with the
    # square-root-weighted traction basis: total variation 0.039 % of Carter's work, largest step
    # between neighbours 0.0014 % (the hat basis: 0.46 % and 0.060 %, the step just after an edge
    # crossed a node, where the work rose like a square root of the edge's distance from the node);
    # the trapezoidal rule has steps of 0.49 % (as large as its variation, 0.96 %; with the hat
    # basis 0.43 % and 0.56 %). All are below the +-1.8 % parametric
    # wear variation, but a/Delta sweeps about 1.2 units over a bay, so growth.vary_grid_spacing
    # averages the periodic remainder out between updates (tests/test_growth.py).
    m = material()
    ratios = np.linspace(20.0, 22.0, 201)
    work, trap = [], []
    q0 = None
    for r in ratios:
        w, sol = steady(r, m, q0=q0, transits=16 if q0 is None else 8)
        q0 = sol.q[-1]
        work.append(w)
        trap.append(trapezoid_work(sol, m))
    work, trap = np.array(work), np.array(trap)
    step, variation = np.abs(np.diff(work)).max(), np.ptp(work)
    assert step < 0.05 * variation
    assert variation < 0.05 * PARAMETRIC_WEAR_VARIATION
    assert np.abs(np.diff(trap)).max() > 0.3 * np.ptp(trap)  # the trapezoidal rule jumps
    assert np.abs(work - 1).max() < 1e-3


def test_steady_work_converges_to_carter():
    # Averaged over the position of the edges between nodes (a / Delta = r + j/4): errors of the
    # work against Carter's exact value 1.4e-3, 4.6e-4, 1.3e-4 at about 21, 41, 81 nodes
    # (orders 1.6, 1.9; 2.4e-5 at 161 nodes, order 2.4). The hat basis: 1.6e-2, 5.8e-3, 1.9e-3,
    # 5.3e-4 (orders 1.5, 1.6, 1.8).
    m = material()
    err = []
    for r in (10.0, 20.0, 40.0):
        err.append(abs(np.mean([steady(r + j / 4, m, M=int(r) + 3)[0] for j in range(4)]) - 1))
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(orders > 1.5), (err, orders)
    assert err[-1] < 3e-4


# ---- unsteady rolling in full slip: an analytic reference for the time integration


def full_slip_reference(f, amp, m, npts):
    """Work per rail point under P = P0 (1 + amp cos(2 pi x_w / lambda)) in full slip, by adaptive
    quadrature along each particle's path (independent of the solver). In full slip q = mu p, and
    for the Hertz ellipse the default closure's displacement is closed form,
    u = k mu P (1/2 + 2 s / pi) / (2 b) - mu xi^2 / (2 R), so the slip velocity is
    s = V gamma + mu V xi / R + k mu (dP/dt) (1/2 + 2 s / pi) / (2 b) (eq 26)."""
    lam = V / f
    k, mu, b = C.compliance(m), m.friction_dynamic, m.half_width
    Pf = lambda xw: P0 * (1 + amp * np.cos(2 * np.pi * xw / lam))  # noqa: E731
    dPdx = lambda xw: -P0 * amp * 2 * np.pi / lam * np.sin(2 * np.pi * xw / lam)  # noqa: E731
    af = lambda xw: float(C.hertz_half_length(Pf(xw), R, m))  # noqa: E731

    def work(x0):
        span = 3 * af(0.0)
        enter = brentq(lambda xw: x0 - xw - af(xw), x0 - span, x0 + span)
        leave = brentq(lambda xw: x0 - xw + af(xw), x0 - span, x0 + span)

        def integrand(xw):
            a, P, xi = af(xw), Pf(xw), x0 - xw
            p = P / (np.pi * a * b) * np.sqrt(max(1 - (xi / a) ** 2, 0.0))
            s = V * m.creepage + mu * V * xi / R + k * mu * V * dPdx(xw) / (2 * b) * (0.5 + 2 / np.pi)
            return mu * p * abs(s) / V

        return quad(integrand, enter, leave, epsabs=0, epsrel=1e-12, limit=200)[0]

    x = np.arange(npts) * lam / npts
    w = np.array([work(x0) for x0 in x])
    return 2 * np.mean(w * np.exp(-2j * np.pi * x / lam)), w.mean()


def work_harmonic(f, amp, m, span, steps, spin):
    """Wear harmonic at the load frequency f under P0 (1 + amp cos 2 pi f t): the contact solved
    over ``spin`` spans of spin-up and one measured span of length ``span`` (an integer number of
    wavelengths) in ``steps`` steps; returns the complex harmonic (2 mean(w e^{-i 2 pi x / lambda}))
    and the mean work over the measured span."""
    lam = V / f
    amax = float(C.hertz_half_length(P0 * (1 + amp), R, m))
    delta = span / steps
    M = int(np.ceil(amax * 1.02 / delta)) + 1
    x = np.arange((spin + 1) * steps + 2 * M + 1) * delta
    P = P0 * (1 + amp * np.cos(2 * np.pi * x / lam))
    sol = C.solve_tangential(P, C.hertz_half_length(P, R, m), m, V, delta, M)
    j = np.arange(spin * steps, (spin + 1) * steps) + M
    xs = (j - M) * delta
    w = sol.work[j]
    return 2 * np.mean(w * np.exp(-2j * np.pi * xs / lam)), w.mean()


def solver_harmonic(f, amp, nodes, m, spin=4):
    """Wear harmonic at the load frequency f over one wavelength after ``spin`` wavelengths."""
    lam = V / f
    amax = float(C.hertz_half_length(P0 * (1 + amp), R, m))
    n_per = int(np.ceil(lam * (nodes - 1) / (2 * amax)))
    c, mean = work_harmonic(f, amp, m, lam, n_per, spin)
    return c, mean, n_per


@pytest.mark.slow
def test_full_slip_wear_harmonic_converges_to_the_analytic_path_integral():
    # 1600 Hz, +-3 % load, creepage -0.01 (full slip): the mean work is exact (the pressure is
    # integrated exactly along the paths) and the harmonic, which is 1.4 % of the mean, converges
    # to the quadrature: amplitude errors 0.17 %, 0.044 %, 0.011 % of the harmonic at 41, 81, 161
    # nodes (orders 2.0, 2.0), phase errors below 2e-4 rad (the hat basis: 0.15 %, 0.042 %, 0.013 %,
    # below 4e-3 rad; the previous work rule: 1.6 %, 0.24 %, 0.05 %, with the mean wrong by 2.8e-3,
    # 1.0e-3, 3.8e-4).
    m = material(creepage=-0.01)
    amp_err, phase_err = [], []
    for nodes in (41, 81, 161):
        c, mean, n_per = solver_harmonic(1600.0, 0.03, nodes, m)
        ref, ref_mean = full_slip_reference(1600.0, 0.03, m, n_per)
        assert mean == pytest.approx(ref_mean, rel=1e-6)
        amp_err.append(abs(abs(c) / abs(ref) - 1))
        phase_err.append(abs(np.angle(c / ref)))
    assert amp_err[0] > amp_err[1] > amp_err[2]
    assert np.log2(amp_err[0] / amp_err[1]) > 1.8 and np.log2(amp_err[1] / amp_err[2]) > 1.8
    assert amp_err[1] < 1e-3
    assert max(phase_err) < 1e-3


@pytest.mark.slow
def test_full_slip_under_the_issues_large_load_variation_is_second_order_at_moving_edges():
    # The partial-slip case's +-30 % load at 1600 Hz, in full slip (creepage -0.01): the patch edges
    # sweep +-15 % of a, about 3 a / Delta units per cycle at 41 nodes, as in partial slip, but
    # there is no stick zone. Measured against the analytic path integral at 41, 81, 161 nodes:
    # harmonic amplitude errors 2.2e-3, 5.5e-4, 1.4e-4 (orders 2.0, 2.0), phase 2.7e-5, 7.2e-6,
    # 1.7e-6 rad (1.9, 2.0), mean 3.8e-5, 9.5e-6, 2.4e-6 (2.0, 2.0). So the time integration along
    # the paths, the entry and exit at moving edges and the rebuilt basis are second order; the
    # partial-slip shortfall (below) lies with the stick zone (docs/contact.md).
    m = material(creepage=-0.01)
    errs = []
    for nodes in (41, 81, 161):
        c, mean, n_per = solver_harmonic(1600.0, 0.3, nodes, m)
        ref, ref_mean = full_slip_reference(1600.0, 0.3, m, n_per)
        errs.append((abs(abs(c) / abs(ref) - 1), abs(np.angle(c / ref)), abs(mean / ref_mean - 1)))
    errs = np.array(errs)
    orders = np.log2(errs[:-1] / errs[1:])
    assert np.all(orders > 1.8), (errs, orders)
    assert errs[1, 0] < 1e-3 and errs[1, 1] < 1e-4


# ---- partial slip under a fast load variation: the wear harmonic against itself


@functools.cache  # the 161-node harmonic is used by two tests below: computed once
def averaged_harmonic(f, nodes, amp=0.3, spacings=4, Nw=4, spin_periods=2):
    """Wear harmonic at f under P0 (1 + amp cos 2 pi f t), averaged over ``spacings`` grid spacings
    that sweep a / Delta over one unit (as the growth loop does): each run spans Nw wavelengths
    with an integer number of steps, after ``spin_periods`` such spans of spin-up."""
    m = material()
    lam = V / f
    amax = float(C.hertz_half_length(P0 * (1 + amp), R, m))
    a0 = float(C.hertz_half_length(P0, R, m))
    period = Nw * lam
    out = []
    for j in range(spacings):
        Ns = int(round(period * (nodes - 1) / (2 * amax) + (j + 0.5) / spacings * period / a0))
        out.append(work_harmonic(f, amp, m, period, Ns, spin_periods)[0])
    return np.mean(out)


@pytest.mark.parametrize("f, limit", [(1000.0, 118.5), (1600.0, 33.5)])
@pytest.mark.slow
def test_wear_harmonic_under_a_fast_load_converges_towards_the_independent_solver(f, limit):
    # +-30 % load at 1000 and 1600 Hz, 40 m/s, s = 1 (the issue's case; arbitrary units as there).
    # Measured (41, 81, 161, 321 nodes): 1000 Hz 117.76, 118.22, 118.36, 118.41 (amplitude orders
    # 1.7, 1.6; the phase, -0.3041 to -0.3043 rad, is converged to 1e-4 rad on every grid); 1600 Hz
    # 32.23, 33.15, 33.42, 33.51 (orders 1.7, 1.65; phase -1.1711, -1.1590, -1.1553, -1.1541 rad,
    # orders 1.7, 1.7). The issue's order 1.8 is not reached in partial slip (it is in full slip,
    # above): the stick/slip boundary inside the patch is resolved only to the cell
    # (docs/contact.md). The independent second-order solver of the issue converges to about
    # 118.5 and 33.5; at 81 nodes the hat basis gave 118.33 and 32.65, the earlier discretisation
    # 125.9 and 44.8.
    c = [averaged_harmonic(f, n) for n in (41, 81, 161)]
    amp = np.abs(c)
    d1, d2 = abs(amp[0] - amp[1]), abs(amp[1] - amp[2])
    assert np.log2(d1 / d2) > 1.5
    assert abs(amp[2] / limit - 1) < 0.01
    ph = np.angle(c)
    assert abs(ph[1] - ph[2]) < 5e-3


@pytest.mark.slow
@pytest.mark.parametrize("f", [1000.0, 1600.0])
def test_production_agrees_with_a_boundary_aligned_discretisation_in_partial_slip(f):
    # The issue's case (+-30 % load, s = 1, creepage -0.001) against the independent reference of
    # tests/independent/aligned_contact.py, whose stick zone [b(t), a] carries the square-root
    # departure from the slip zone exactly and whose boundary b(t) is solved for (zero slip velocity
    # there): a traction discretisation whose error does not come from the production grid.
    # Measured (161 nodes, one spacing for the reference, four for production): 1000 Hz 118.347 vs
    # 118.36 (1e-4), 1600 Hz 33.412 vs 33.423 (3e-4; 8e-4 against the reference's finer quadrature,
    # nh = 30, K = 2000: 33.395); at 321 nodes 33.502 (nh = 40, K = 3000) vs 33.511.
    # The reference converges no faster than production (about order 1.5 once its quadrature is
    # adequate, docs/contact.md), so no order is asserted: this checks the limit both converge to, in
    # amplitude and phase, well inside the production default's error (1.1 % at 81 nodes, 1600 Hz).
    from independent import aligned_contact as ac

    m = material()
    ref = ac.wear_harmonic(f, 0.3, 161, P0=P0, R=R, speed=V, youngs_modulus=m.youngs_modulus,
                           poisson_ratio=m.poisson_ratio, half_width=m.half_width,
                           mu=m.friction_dynamic, creepage=m.creepage)
    production = averaged_harmonic(f, 161)
    assert abs(abs(production) / abs(ref) - 1) < 3e-3
    assert abs(np.angle(production / ref)) < 3e-3


@pytest.mark.slow
def test_the_references_grid_tied_spread_comes_from_collecting_the_work_on_a_lattice():
    # The boundary-aligned reference at 81 nodes, 1600 Hz, +-30 %, over four grid spacings that sweep
    # a/Delta over one unit (Delta falls by 2 % across them). Collected on the rail-point lattice the
    # harmonic is 33.075, 33.105, 33.119, 33.110: not monotone in Delta (second differences -0.015,
    # -0.024, 5e-4 and 7e-4 of itself). Collected without a lattice (the patch integral of the work
    # over each step) it is 33.083, 33.089, 33.095, 33.102: the convergence trend alone, second
    # differences 1e-4 (3e-6 of itself). Phases: lattice spread 1e-3 rad, grid-free 3e-4 rad, monotone.
    from independent import aligned_contact as ac

    m = material()
    lam = V / 1600.0
    amax = float(C.hertz_half_length(P0 * 1.3, R, m))
    a0 = float(C.hertz_half_length(P0, R, m))
    Ns = [round(lam * 80 / (2 * amax) + (j + 0.5) / 4 * lam / a0) for j in range(4)]
    assert Ns == sorted(set(Ns))
    lat, free = np.array([ac.wear_harmonics(1600.0, 0.3, 1 + n * 2 * amax / lam, P0=P0, R=R, speed=V,
                                            youngs_modulus=m.youngs_modulus, poisson_ratio=m.poisson_ratio,
                                            half_width=m.half_width, mu=m.friction_dynamic,
                                            creepage=m.creepage) for n in Ns]).T
    scale = abs(free.mean())
    assert np.abs(np.diff(np.abs(lat), 2)).max() > 2e-4 * scale
    assert np.abs(np.diff(np.abs(free), 2)).max() < 2e-5 * scale
    assert np.all(np.diff(np.abs(free)) > 0)
