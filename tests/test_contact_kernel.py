"""The compiled contact time loop (rail.contact._march, numba) against the numpy implementation of
the same scheme (tests/reference/contact_numpy.py), step by step, in the regimes the physics tests
cover: steady rolling, quasi-static and fast load variation with several stick zones, a perturbed
start, saturated creepage (full slip), mu_s > mu_d, the closure family and the report's closure
up to the step where it diverges."""

from pathlib import Path

import numpy as np
import pytest

from rail import contact as C
from reference.contact_numpy import solve_tangential_numpy

R, V, P0 = 0.575, 40.0, 1.0e5


def material(creepage=-0.001, mu_s=0.3, mu_d=0.3):
    return C.ContactMaterial(2.1e11, 0.3, 0.008, R, mu_d, mu_s, creepage)


def _grid(m, P_max, nodes=41):
    a_max = float(C.hertz_half_length(P_max, R, m))
    return C.rolling_grid(1.05 * a_max, 0.6, nodes)


def _load(freq, amp, steps, delta):
    t = np.arange(steps) * delta / V
    return P0 * (1 + amp * np.sin(2 * np.pi * freq * t))


def _compare(P, m, delta, M, **kw):
    a = C.hertz_half_length(P, R, m)
    new = C.solve_tangential(P, a, m, V, delta, M, **kw)
    ref = solve_tangential_numpy(P, a, m, V, delta, M, **kw)
    scale_q = np.abs(ref.q).max()
    scale_s = max(np.abs(ref.s).max(), 1e-300)
    assert np.abs(new.q - ref.q).max() <= 1e-9 * scale_q
    assert np.abs(new.s - ref.s).max() <= 1e-9 * scale_s
    np.testing.assert_allclose(new.Q, ref.Q, rtol=0, atol=1e-9 * np.abs(ref.Q).max())
    np.testing.assert_allclose(new.work, ref.work, rtol=0, atol=1e-9 * ref.work.max())
    np.testing.assert_allclose(new.power, ref.power, rtol=0, atol=1e-9 * ref.power.max())
    np.testing.assert_array_equal(new.stick_nodes, ref.stick_nodes)
    assert new.iterations == ref.iterations
    return new


@pytest.mark.parametrize(
    "freq, amp, creepage, mu_s, kw",
    [
        (0.0, 0.0, -0.001, 0.3, {}),  # steady rolling (Carter)
        (10.0, 0.2, -0.001, 0.3, {}),  # quasi-static
        (2500.0, 0.6, -0.001, 0.3, {}),  # fast unloading: several stick zones
        (1000.0, 0.3, -0.001, 0.35, {}),  # static friction above dynamic
        (1000.0, 0.3, -0.01, 0.3, {}),  # saturated creepage: full slip
        (1000.0, 0.3, 0.002, 0.3, {}),  # braking wheel
        (1000.0, 0.3, -0.001, 0.3, {"closure_scale": 0.01}),  # quasi-static end of the family
        (1000.0, 0.3, -0.001, 0.3, {"closure_scale": 4.0}),  # soft end
    ],
)
def test_compiled_loop_equals_numpy_reference(freq, amp, creepage, mu_s, kw):
    m = material(creepage=creepage, mu_s=mu_s)
    delta, _, M = _grid(m, P0 * (1 + amp))
    P = _load(freq, amp, 3 * (2 * M + 1), delta)
    sol = _compare(P, m, delta, M, **kw)
    assert np.any(sol.q != 0)


def test_compiled_loop_equals_numpy_reference_from_a_perturbed_start():
    m = material()
    delta, _, M = _grid(m, P0)
    nn = 2 * M + 1
    a = float(C.hertz_half_length(P0, R, m))
    base = C.solve_tangential(np.full(5 * nn, P0), np.full(5 * nn, a), m, V, delta, M).q[-1]
    q0 = base * (1 + 0.01 * np.random.default_rng(3).standard_normal(nn))
    P = np.full(2 * nn, P0)
    new = C.solve_tangential(P, np.full(P.size, a), m, V, delta, M, q0=q0)
    ref = solve_tangential_numpy(P, np.full(P.size, a), m, V, delta, M, q0=q0)
    np.testing.assert_allclose(new.q, ref.q, rtol=0, atol=1e-9 * np.abs(ref.q).max())
    # The report's closure (ill-posed, docs/contact.md) diverges from this 1 % perturbation: both
    # loops agree up to that step and stop there with the same message.
    steps = 45
    new = C.solve_tangential(P[:steps], np.full(steps, a), m, V, delta, M, closure="report", q0=q0)
    ref = solve_tangential_numpy(P[:steps], np.full(steps, a), m, V, delta, M, closure="report", q0=q0)
    np.testing.assert_allclose(new.q, ref.q, rtol=0, atol=1e-9 * np.abs(ref.q).max())
    # With the square-root-weighted basis it reaches the divergence monitor at step 169 here (about
    # 3.8 transits of 45 steps; the hat basis: within about one transit): run 5 transits.
    P = np.full(5 * nn, P0)
    msgs = []
    for solver in (C.solve_tangential, solve_tangential_numpy):
        with pytest.raises(C.ContactError, match="diverged at step") as err:
            solver(P, np.full(P.size, a), m, V, delta, M, closure="report", q0=q0)
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


def test_report_closure_stops_at_the_same_step_in_both():
    # the report's closure diverges on 81 nodes (docs/contact.md); both stop with the same message
    m = material()
    delta, _, M = _grid(m, 1.3 * P0, nodes=81)
    P = _load(1000.0, 0.3, 12 * (2 * M + 1), delta)
    a = C.hertz_half_length(P, R, m)
    msgs = []
    for solver in (C.solve_tangential, solve_tangential_numpy):
        with pytest.raises(C.ContactError, match="diverged at step") as err:
            solver(P, a, m, V, delta, M, closure="report")
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


def test_unloaded_patch_is_refused():
    m = material()
    delta, _, M = _grid(m, P0)
    with pytest.raises(ValueError, match="P > 0, a > 0"):
        C.solve_tangential(np.array([P0, 0.0]), np.array([0.005, 0.0]), m, V, delta, M)


def test_particle_leaving_at_the_start_of_a_step_does_no_work():
    # 107 steps where the patch shrinks as fast as the particles move (|da/dx| up to 1.2, under a
    # 45 mm corrugation; P, a saved from the profile_example scenario at 90,000 passages, 61 nodes):
    # a particle leaves at the trailing edge with an exit fraction phi = 0 (xi_n + Delta and
    # xi_{n+1} differ by rounding). Without the THETA_EDGE guard its slip velocity divides the
    # rounding of u_exit - u_old by phi dt: infinite work (1e283 m of wear was seen in a growth
    # run); with it, the particle does no work in that step and its work is that of its neighbours.
    import reference.contact_numpy as R

    d = np.load(Path(__file__).parent / "data/edge_exit_case.npz")
    m = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)
    P, a, delta, M, j = d["P"], d["a"], float(d["delta"]), int(d["M"]), int(d["jrel"])
    on = C.solve_tangential(P, a, m, 40.0, delta, M).work
    assert np.all(np.isfinite(on))
    assert min(on[j - 1], on[j + 1]) <= on[j] <= max(on[j - 1], on[j + 1])
    guard = R.THETA_EDGE
    try:
        R.THETA_EDGE = 0.0
        with np.errstate(divide="ignore", invalid="ignore"):
            off = R.solve_tangential_numpy(P, a, m, 40.0, delta, M).work
    finally:
        R.THETA_EDGE = guard
    assert not np.isfinite(off[j]) or off[j] > 1e10 * on[j]
    np.testing.assert_allclose(np.delete(off, j), np.delete(on, j), rtol=1e-9)
    np.testing.assert_allclose(R.solve_tangential_numpy(P, a, m, 40.0, delta, M).work, on, rtol=1e-9)


def _rail_shape(M, delta, steps, amp=0.15, lam=0.008):
    # a non-Hertzian pressure factor fixed to the rail (a ripple under a moving patch): at step i the
    # node n lies at x = (i + n - M) delta on the rail
    i, n = np.meshgrid(np.arange(steps), np.arange(2 * M + 1), indexing="ij")
    return 1 + amp * np.cos(2 * np.pi * (i + n - M) * delta / lam)


@pytest.mark.parametrize("freq, amp", [(0.0, 0.0), (1000.0, 0.3)])
def test_compiled_loop_matches_numpy_with_a_non_hertzian_pressure(freq, amp):
    m = material()
    delta, _, M = _grid(m, P0 * (1 + amp))
    steps = 6 * (2 * M + 1)
    P = _load(freq, amp, steps, delta)
    a = C.hertz_half_length(P, R, m)
    shape = _rail_shape(M, delta, steps)
    new = C.solve_tangential(P, a, m, V, delta, M, shape=shape)
    ref = solve_tangential_numpy(P, a, m, V, delta, M, shape=shape)
    assert np.abs(new.q - ref.q).max() <= 1e-9 * np.abs(ref.q).max()
    np.testing.assert_allclose(new.work, ref.work, rtol=0, atol=1e-9 * ref.work.max())
    # and the shape is not ignored: the work differs from the Hertz ellipse's by about the ripple
    hertz = C.solve_tangential(P, a, m, V, delta, M)
    assert np.abs(new.work - hertz.work).max() > 0.05 * hertz.work.max()


def test_a_uniform_pressure_factor_equals_a_scaled_load():
    # p = c x Hertz(P, a) is the pressure of the load c P on the same patch: the same solution
    m = material()
    delta, _, M = _grid(m, P0)
    steps = 4 * (2 * M + 1)
    P = _load(1000.0, 0.2, steps, delta)
    a = C.hertz_half_length(P, R, m)
    scaled = C.solve_tangential(P, a, m, V, delta, M, shape=np.full((steps, 2 * M + 1), 1.1))
    direct = C.solve_tangential(1.1 * P, a, m, V, delta, M)
    np.testing.assert_allclose(scaled.q, direct.q, rtol=0, atol=1e-12 * np.abs(direct.q).max())
    np.testing.assert_allclose(scaled.work, direct.work, rtol=0, atol=1e-12 * direct.work.max())


def test_compile_kernels_compiles_every_signature_the_production_calls_use():
    # The workflow compiles the marches once (rule compile_kernels) so that parallel jobs load numba's
    # cache; that only helps if the production calls use the same argument types. Calls in other
    # forms (no pressure shape, an initial traction, the report's closure, the tangent march without
    # a shape direction) must add no signature.
    from rail import kernels
    from rail.contact import _march, solve_tangential
    from rail.contact import tangent as contact_tangent

    listed = kernels.compile_kernels(tangent_too=True)
    assert any(s.startswith("rail.contact.march._march(") for s in listed)
    assert any(s.startswith("rail.contact.tangent._march_tangent(") for s in listed)
    before = (list(_march.signatures), list(contact_tangent._march_tangent.signatures))
    m = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.35, -0.002)
    M, steps, delta = 20, 40, 2.5e-4
    P, a = np.full(steps, 9e4), np.full(steps, 3e-3)
    solve_tangential(P, a, m, 30.0, delta, M, closure="report", q0=np.zeros(2 * M + 1))
    solve_tangential(P, a, m, 30.0, delta, M)
    contact_tangent.work_tangent(P, a, m, 30.0, delta, M, np.ones((steps, 2)), np.zeros((steps, 2)))
    assert (list(_march.signatures), list(contact_tangent._march_tangent.signatures)) == before


def test_the_steps_small_solve_agrees_with_lapack_and_pivots():
    """rail._linalg.solve_in_place (the stick solve's and the tangent's dense solve) against
    numpy's LAPACK solve: influence-like matrices of 1 to 61 unknowns, one and several right-hand
    sides, to 1e-12 of the solution relative to the conditioning; a matrix with a zero leading
    diagonal needs the row exchange; a singular one gives a non-finite answer (the march's
    finiteness check reports it)."""
    from rail._linalg import solve_in_place as _solve_in_place

    rng = np.random.default_rng(7)
    for n in (1, 2, 5, 30, 61):
        for m in (1, 3):
            A = rng.normal(size=(n, n)) + n * np.eye(n) * rng.uniform(0.1, 1.0)
            B = rng.normal(size=(n, m))
            want = np.linalg.solve(A, B)
            Aw, Bw = A.copy(), B.copy()
            _solve_in_place(Aw, Bw)
            tol = 1e-12 * np.linalg.cond(A) * np.abs(want).max()
            assert np.abs(Bw - want).max() < tol, n
    A = np.array([[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]])
    B = np.array([[1.0], [2.0], [3.0]])
    Aw, Bw = A.copy(), B.copy()
    _solve_in_place(Aw, Bw)
    assert np.allclose(A @ Bw, B, rtol=0, atol=1e-14)
    S, b = np.array([[1.0, 2.0], [2.0, 4.0]]), np.array([[1.0], [1.0]])
    _solve_in_place(S, b)
    assert not np.all(np.isfinite(b))


def _eliminate_along(A, B):
    """Gaussian elimination with partial pivoting applied to B along with A, then back substitution
    (the order of operations of rail._linalg.solve_in_place), in Python floats."""
    n = A.shape[0]
    for k in range(n):
        piv = max(range(k, n), key=lambda r: (abs(A[r, k]), -r))
        A[[k, piv]], B[[k, piv]] = A[[piv, k]], B[[piv, k]]
        inv = 1.0 / A[k, k]
        for r in range(k + 1, n):
            f = A[r, k] * inv
            for c in range(k + 1, n):
                A[r, c] = A[r, c] - f * A[k, c]
            B[r, 0] = B[r, 0] - f * B[k, 0]
    for k in range(n - 1, -1, -1):
        acc = B[k, 0]
        for j in range(k + 1, n):
            acc = acc - A[k, j] * B[j, 0]
        B[k, 0] = acc * (1.0 / A[k, k])


def test_the_solves_agree_and_the_bordered_solve_equals_a_fresh_one():
    """rail._linalg.solve_in_place gives the bits of the elimination written out (the right-hand side
    eliminated along with the matrix); LAPACK's factors on a row-major block (getrf_rows / getrs_rows,
    the stick solve's) solve to the rounding of the conditioning, several right-hand sides at once,
    with a row exchange, and a singular block gives a non-finite answer; the stick solve's bordered pass
    (rail.contact.steps._bordered_solve: the stick set less up to two released nodes, from the factors
    of the larger set) equals a fresh solve of the smaller set to the rounding of its conditioning, and
    a changed set it cannot serve (a node added) is refused by _stick_subset."""
    from rail._linalg import solve_in_place
    from rail.contact import steps

    rng = np.random.default_rng(11)
    nn = 41
    x = np.linspace(-1, 1, nn)
    E = -np.log(np.abs(x[:, None] - x[None, :]) + 0.01) + 0.05 * rng.normal(size=(nn, nn))  # log-kernel-like
    h = rng.normal(size=nn)
    for ns in (1, 7, 30):
        S = np.sort(rng.choice(nn, ns, replace=False)).astype(np.int64)
        A, b = E[np.ix_(S, S)].copy(), h[S].copy()
        A1, b1 = A.copy(), b.copy()[:, None]
        _eliminate_along(A1, b1)  # the right-hand side eliminated along with the matrix, in Python floats
        A3, b3 = A.copy(), b.copy()[:, None]
        solve_in_place(A3, b3)
        assert np.array_equal(b3, b1)
    from rail._linalg import getrf_rows, getrs_rows

    for ns in (1, 2, 7, 41):
        S = np.sort(rng.choice(nn, ns, replace=False)).astype(np.int64)
        A = E[np.ix_(S, S)]
        B = rng.normal(size=(ns, 3))
        LU, piv, X = np.zeros((nn, nn)), np.zeros(nn, dtype=np.int32), np.zeros((nn, 3))
        LU[:ns, :ns], X[:ns] = A, B
        assert getrf_rows(LU, ns, piv) == 0
        getrs_rows(LU, ns, piv, X)
        want = np.linalg.solve(A, B)
        assert np.abs(X[:ns] - want).max() < 1e-13 * np.linalg.cond(A) * np.abs(want).max(), ns
    A = np.array([[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]])  # needs the exchange
    LU, piv, X = A.copy(), np.zeros(3, dtype=np.int32), np.array([[1.0], [2.0], [3.0]])
    getrf_rows(LU, 3, piv)
    getrs_rows(LU, 3, piv, X)
    assert np.allclose(A @ X, [[1.0], [2.0], [3.0]], rtol=0, atol=1e-14)
    LU, piv, X = np.array([[1.0, 2.0], [2.0, 4.0]]), np.zeros(2, dtype=np.int32), np.ones((2, 1))
    assert getrf_rows(LU, 2, piv) > 0
    getrs_rows(LU, 2, piv, X)
    assert not np.all(np.isfinite(X))
    Sf = np.arange(5, 35, dtype=np.int64)
    nf = Sf.size
    for released in ((), (12,), (5, 34), (20, 21)):
        stick = np.zeros(nn, dtype=np.bool_)
        stick[Sf] = True
        stick[list(released)] = False
        qn = np.where(stick, 0.0, 0.3 * rng.normal(size=nn))  # the slip nodes' tractions
        LU, piv, pos = np.zeros((nn, nn)), np.zeros(nn, dtype=np.int32), np.zeros(nn, dtype=np.int64)
        steps._factor_stick(E, Sf, nf, LU, piv, pos)
        S = np.flatnonzero(stick).astype(np.int64)
        assert steps._stick_subset(S, S.size, pos, nf, nf - S.size)
        q = qn.copy()
        ok = steps._bordered_solve(h, E @ qn, q, stick, S.size, LU, piv, Sf, nf, np.zeros((nn, 1)),
                                   np.zeros((2, nn, 1)))
        assert ok
        want = np.linalg.solve(E[np.ix_(S, S)], h[S] - E[np.ix_(S, np.flatnonzero(~stick))] @ qn[~stick])
        tol = 1e-13 * np.linalg.cond(E[np.ix_(S, S)]) * np.abs(want).max()
        assert np.abs(q[S] - want).max() < tol, released
        assert np.array_equal(q[~stick], qn[~stick])  # the slip nodes untouched
    # a node added to the set, or three released: factor afresh
    pos = np.full(nn, -1, dtype=np.int64)
    pos[Sf] = np.arange(nf)
    assert not steps._stick_subset(np.append(Sf, 40), nf + 1, pos, nf, -1)
    assert not steps._stick_subset(Sf[3:], nf - 3, pos, nf, 3)
