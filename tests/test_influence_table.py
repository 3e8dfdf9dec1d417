"""The influence matrix interpolated in the patch half-length a (rail.contact.influence, issue 44)
against the exact rebuild (rail.contact.basis._closure_matrix): per entry, on the march's outputs
(the wear per particle's harmonics along the bay and the tangential force Q(t)) and on the tangent
march's derivative, with the observed convergence order as the table is refined.

What the tolerances protect: growth is driven by a variation of the wear along the bay of a few
per cent of its mean, so each wear harmonic is judged against itself (amplitude relative to that
harmonic's, phase in radians), Q against its own variation along the bay."""

import numpy as np
import pytest

from rail import contact as C
from rail.contact import influence as I
from rail.contact.basis import _basis_workspace, _closure_matrix, _influence_arrays, chebyshev_hat_moments
from rail.contact.tangent import work_tangent

MAT = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.35, -0.002)
SPEED = 30.0
HARMONICS = (12, 46)  # of the load along the bay: 50 mm and 13 mm on a 0.6 m bay


def _cell_setup(M=32, delta=1e-4):
    nn = 2 * M + 1
    xi = (np.arange(nn) - M) * delta
    Mom, mu = chebyshev_hat_moments(nn)
    return dict(Mom=Mom, mu=mu, xi=xi, k=C.compliance(MAT), delta=delta, M=M, closure=0, closure_scale=1.0,
                report_coef=C.report_rigid_compliance(MAT))


def _exact(ai, s):
    nn = s["xi"].size
    Cm, r_edge, r_trail, w, AT, r_a, wu = _influence_arrays(nn)
    lead, trail = _closure_matrix(ai, s["Mom"], s["mu"], s["xi"], s["k"], s["delta"], s["M"], s["closure"], s["closure_scale"],
                                  s["report_coef"], Cm, r_edge, w, r_trail, AT, r_a, wu, _basis_workspace(nn))
    return lead, trail, Cm, r_edge, r_trail, w


def _table(s, cells, nodes, pieces):
    x0, bw = I._chebyshev_first_kind(nodes)
    T, Re, Rt, W, slot = I._build_table(np.asarray(cells, dtype=np.int64), x0, s["Mom"], s["mu"], s["xi"], s["k"], s["delta"],
                                        s["M"], s["closure"], s["closure_scale"], s["report_coef"], _basis_workspace(s["xi"].size),
                                        pieces)
    return T, Re, Rt, W, slot, x0, bw, pieces


def _interpolated(ai, s, table):
    nn = s["xi"].size
    Cm, r_edge, r_trail, w, AT, r_a, wu = _influence_arrays(nn)
    m = table[5].size
    lead, trail = I._influence_at(ai, table, s["Mom"], s["mu"], s["xi"], s["k"], s["delta"], s["M"], s["closure"],
                                  s["closure_scale"], s["report_coef"], Cm, r_edge, w, r_trail, AT, r_a, wu,
                                  _basis_workspace(nn), np.empty(m), np.empty(m))
    return lead, trail, Cm, r_edge, r_trail, w


# e across the cell, to both of its ends (e -> 0: a node just inside the edge, the outermost column's
# 1 / sqrt(e); e -> 1: the next node reaching the edge)
E_PROBES = (1e-7, 1e-4, 0.013, 0.1, 0.27, 0.5, 0.61, 0.9, 0.999, 1 - 1e-7)


def _entry_error(s, table, base=29):
    """The largest error of C, r_edge, r_trail and w over the loaded columns and E_PROBES, relative to
    the largest entry of the loaded columns of each."""
    worst = 0.0
    for e in E_PROBES:
        ai = s["delta"] * (base + e)
        ex, got = _exact(ai, s), _interpolated(ai, s, table)
        assert got[:2] == ex[:2]
        lo = slice(ex[1], ex[0] + 1)
        for X, Y in zip(ex[2:], got[2:]):
            X, Y = X[..., lo], Y[..., lo]
            worst = max(worst, float(np.abs(Y - X).max() / np.abs(X).max()))
    return worst


def test_table_matches_the_exact_rebuild_entry_by_entry():
    # Measured 4.6e-10 of the matrix's scale (at e = 1e-7; 1.6e-10 for e in [0.001, 0.999]): the exact
    # rebuild's own noise, its Chebyshev series being truncated at 1e-10. A table in sqrt(e) (the
    # (1 - e)^(3/2) ln(1 - e) of the edge columns near e = 1 left in) measured 2e-6 with 16 nodes in one
    # piece, 2e-4 with 12.
    s = _cell_setup()
    err = _entry_error(s, _table(s, [s["M"] + 29], I._TABLE_NODES, I._TABLE_PIECES))
    assert err < 2e-9, err


def test_table_converges_at_the_order_of_its_nodes():
    # Four nodes a piece: the error falls as pieces^-4 (measured 1.7e-4, 1.3e-5, 8.1e-7 at 4, 8, 16 pieces,
    # orders 3.8 and 3.9): the singular factor and the behaviour at both ends of the cell are taken out.
    s = _cell_setup()
    errs = [_entry_error(s, _table(s, [s["M"] + 29], 4, p)) for p in (4, 8, 16)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 3.5), (errs, orders)


def _bay(periods=2, nodes=61, L=0.6):
    """A varying-load bay (harmonics HARMONICS of the load, 5 % and 2 %), ``periods`` bays long."""
    a0 = float(C.hertz_half_length(9e4, MAT.wheel_radius, MAT))
    delta, Nx, M = C.rolling_grid(1.08 * a0, L, nodes)
    x = np.arange(periods * Nx) * delta
    P = 9e4 * (1 + 0.05 * np.sin(2 * np.pi * HARMONICS[0] * x / L) + 0.02 * np.sin(2 * np.pi * HARMONICS[1] * x / L + 1.0))
    return P, C.hertz_half_length(P, MAT.wheel_radius, MAT), delta, Nx, M


def _bay_harmonics(work, Nx, M):
    """The wear's harmonics HARMONICS along the last bay's particles (complex, per particle's work)."""
    nn = 2 * M + 1
    spec = np.fft.rfft(work[-Nx - nn:-nn]) / Nx
    return spec[list(HARMONICS)], spec[0]


def _march_errors(P, a, delta, Nx, M, exact):
    got = C.solve_tangential(P, a, MAT, SPEED, delta, M)
    hx, mean = _bay_harmonics(exact.work, Nx, M)
    hg, _ = _bay_harmonics(got.work, Nx, M)
    Qx, Qg = exact.Q[-Nx:], got.Q[-Nx:]
    return dict(amplitude=float(np.max(np.abs(np.abs(hg) - np.abs(hx)) / np.abs(hx))),
                phase=float(np.max(np.abs(np.angle(hg / hx)))),
                Q=float(np.abs(Qg - Qx).max() / np.ptp(Qx)),
                variation=float(np.min(2 * np.abs(hx) / abs(mean))))


@pytest.fixture(scope="module")
def bay():
    P, a, delta, Nx, M = _bay()
    exact = C.solve_tangential(P, a, MAT, SPEED, delta, M, influence="exact")
    return P, a, delta, Nx, M, exact


def test_march_with_the_table_keeps_the_wear_harmonics_and_the_force(bay):
    # Growth follows the wear's variation along the bay (here at least 0.66 % of the mean wear, peak to
    # peak, in each harmonic): the table changes each harmonic's amplitude by at most 1e-7 of itself
    # (measured 1.4e-10) and its phase by 1e-7 rad (measured 2.8e-10), and Q(t) by 1e-7 of its variation
    # along the bay (measured 9.8e-10).
    P, a, delta, Nx, M, exact = bay
    assert I.table_cells(a, delta, M).size >= 3  # the table is used, over several cells
    err = _march_errors(P, a, delta, Nx, M, exact)
    assert err["variation"] > 1e-3  # the harmonics judged are a variation of the wear, not rounding
    assert err["amplitude"] < 1e-7 and err["phase"] < 1e-7 and err["Q"] < 1e-7, err


def test_march_outputs_converge_as_the_table_is_refined(bay, monkeypatch):
    # Four nodes a piece, 4, 8, 16 pieces: the outputs' errors fall with the matrix's (order 4). Measured:
    # the harmonics' amplitude 4.7e-4, 4.5e-5, 9.6e-7 of itself (orders 3.4, 5.6), Q 1.7e-3, 1.6e-4, 4.2e-6 of
    # its variation (orders 3.4, 5.2).
    P, a, delta, Nx, M, exact = bay
    monkeypatch.setattr(I, "_TABLE_NODES", 4)
    errs = []
    for p in (4, 8, 16):
        monkeypatch.setattr(I, "_TABLE_PIECES", p)
        errs.append(_march_errors(P, a, delta, Nx, M, exact))
    for key in ("amplitude", "Q"):
        e = np.array([x[key] for x in errs])
        orders = np.log2(e[:-1] / e[1:])
        assert np.all(orders > 2.5), (key, e, orders)


def test_tangent_march_with_the_table_keeps_the_derivative(bay):
    # The derivative of the wear along a load direction of harmonic 20, its harmonic 20 along the bay (what
    # rail.growth_spectrum's linear method takes): the table's (the interpolant differentiated) against
    # the exact rebuild's central difference in a, relative to the harmonic: measured 1.8e-7, the exact
    # one's own noise (its step 1e-9 a amplifies the rebuild's rounding); the work itself 1.9e-10.
    P, a, delta, Nx, M, _ = bay
    L = Nx * delta
    x = np.arange(P.size) * delta
    dP = 1e3 * np.stack([np.cos(2 * np.pi * 20 * x / L), np.sin(2 * np.pi * 20 * x / L)], axis=1)
    da = dP * (a / (2 * P))[:, None]  # the Hertz half-length's change with the force
    nn = 2 * M + 1
    res = {}
    for how in ("exact", "table"):
        w, dw = work_tangent(P, a, MAT, SPEED, delta, M, dP, da, influence=how)
        res[how] = (w, np.fft.rfft(dw[-Nx - nn:-nn], axis=0)[20] / Nx)
    (wx, hx), (wt, ht) = res["exact"], res["table"]
    assert np.abs(wt - wx).max() < 1e-7 * np.abs(wx).max()
    assert np.all(np.abs(ht - hx) < 1e-5 * np.abs(hx)), (ht, hx)
