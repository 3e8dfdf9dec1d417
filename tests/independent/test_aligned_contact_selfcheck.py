"""Self-checks of the boundary-aligned partial-slip reference (tests/independent/aligned_contact.py).

Each compares with something the method does not contain: exact integrals by adaptive quadrature,
Carter's closed-form steady rolling, and a convergence study of its own wear harmonic.
"""

import numpy as np
import pytest
from scipy.integrate import quad

from . import aligned_contact as ac

E, NU, BW, R, MU, V, P0 = 2.1e11, 0.3, 0.008, 0.575, 0.3, 40.0, 1.0e5
K_C = ac.compliance(E, NU)


def test_product_integration_of_the_logarithm_is_exact_for_piecewise_linear_densities():
    z = np.array([-0.3, -0.1, 0.05, 0.4, 0.5])
    f = np.array([0.0, 1.0, -0.5, 2.0, 0.0])
    for x in (-0.2, 0.05, 0.33, 0.7):
        ref = quad(lambda t, x=x: np.interp(t, z, f) * np.log(abs(x - t)), z[0], z[-1],
                   points=sorted({*z, x} - {z[0], z[-1]}), limit=200, epsabs=1e-13)[0]
        assert (ac.log_matrix(x, z) @ f)[0] == pytest.approx(ref, rel=1e-9, abs=1e-12)


def test_hertz_log_integral_matches_quadrature():
    a = 3e-3
    for x in (0.0, -0.7 * a, 0.999 * a):
        ref = quad(lambda t, x=x: np.sqrt(1 - (t / a) ** 2) * np.log(abs(x - t)), -a, a, points=[x],
                   limit=200, epsabs=1e-15)[0]
        assert ac.hertz_log(x, a) == pytest.approx(ref, rel=1e-9)


@pytest.mark.slow
def test_steady_rolling_reproduces_carter_and_its_work_converges_at_second_order():
    # Constant load, creepage -0.001: the boundary is Carter's a - 2c, the force mu P (1 - c^2/a^2),
    # and the work of a rail point tends to Carter's |gamma| Q / (2 b_w). Measured at 41 and 81 nodes
    # after five transits: boundary -4e-9 a and -8e-9 a (the product integration, not the step),
    # force 1.5e-6, work +3.8e-4 and -7.4e-5 (order 2.4).
    g = -0.001
    a = float(ac.hertz_half_length(P0, R, K_C, BW))
    b_c = ac.carter_boundary(P0, a, K_C, MU, g, BW)
    c = 0.5 * (a - b_c)
    Q_c = MU * P0 * (1 - (c / a) ** 2)
    w_c = abs(g) * Q_c / (2 * BW)
    errs = []
    for nodes in (41, 81):
        delta = 2 * a / (nodes - 1) * 1.013
        M = int(np.ceil(a * 1.02 / delta)) + 1
        n_tr = int(np.ceil(2 * a / delta))
        w, Q, b, C = ac.solve(np.full(5 * n_tr, P0), np.full(5 * n_tr, a), k=K_C, mu=MU, creepage=g,
                           half_width=BW, speed=V, delta=delta, M=M)
        assert abs(b[-1] - b_c) < 3e-8 * a
        assert abs(Q[-1] / Q_c - 1) < 1e-5
        ww = w[3 * n_tr:4 * n_tr]
        assert ww.std() < 1e-6 * ww.mean()
        errs.append(abs(ww.mean() / w_c - 1))
        # the grid-free collection at wavenumber 0: the work over a step integrated over the patch,
        # |gamma| Q Delta / (2 b_w) in steady rolling (measured 4.1e-5 and 2.2e-5 at 41 and 81 nodes)
        cc = C[3 * n_tr:4 * n_tr].real
        assert np.ptp(cc) < 1e-9 * cc.mean()
        assert abs(cc.mean() / (delta * w_c) - 1) < 1e-4
    assert errs[0] < 1e-3
    assert np.log2(errs[0] / errs[1]) > 1.8


@pytest.mark.slow
def test_quadratic_entry_reduces_to_the_linear_one_in_steady_rolling():
    # With a constant edge displacement the three-step interpolation of the entry instant equals the
    # two-step one (its weights sum to one), so the steady solutions agree to the boundary solver's
    # tolerance; a wrong weight would shift the traction of every entering point by O(gamma Delta).
    g = -0.001
    a = float(ac.hertz_half_length(P0, R, K_C, BW))
    delta = 2 * a / 40 * 1.013
    M = int(np.ceil(a * 1.02 / delta)) + 1
    n = 3 * int(np.ceil(2 * a / delta))
    kw = {"k": K_C, "mu": MU, "creepage": g, "half_width": BW, "speed": V, "delta": delta, "M": M}
    lin = ac.solve(np.full(n, P0), np.full(n, a), **kw)
    qua = ac.solve(np.full(n, P0), np.full(n, a), entry="quadratic", **kw)
    assert abs(qua[2][-1] - lin[2][-1]) < 1e-9 * a
    assert abs(qua[1][-1] / lin[1][-1] - 1) < 1e-9
    with pytest.raises(ValueError, match="entry = 'cubic'"):
        ac.solve(np.full(2, P0), np.full(2, a), entry="cubic", **kw)
