"""Roughness periodic over N bays (Sheng, Jones & Thompson 2007): the Bloch receptance tables, the
N independent force systems, and contact and wear over the N-bay period."""

import numpy as np
import pytest
from test_growth import MATERIAL, contact_spring, track

from rail import contact as C
from rail import interaction as I
from rail import moving
from rail import wear as W
from rail.contact.models import curvature_on_grid

V, K = 40.0, 16
WHEEL = I.Wheels(1350.0, 0.575, 1e5, (0.0,))


@pytest.fixture(scope="module")
def tr():
    return track()


@pytest.fixture(scope="module")
def tables4(tr):
    return moving.bloch_tables(tr, V, K, 4, offsets=(0.0, 1.9))


@pytest.mark.parametrize("nu", [0.25, 0.8])
@pytest.mark.slow
def test_bloch_table_against_direct_moving_load_coefficients(tr, nu):
    # column k of the table at fraction nu is a_n((k + nu) Omega_0) from an independent quadrature
    # at that single frequency (rail.moving.moving_coefficients), at the load and 1.9 m away
    tab = moving.receptance_table(tr, V, 6, offsets=(0.0, 1.9), rtol=1e-7, fraction=nu)
    Om0 = tr.beta0 * V
    assert list(tab.indices) == list(range(-6, 6))
    for i, d in enumerate((0.0, 1.9)):
        for k in (-6, 0, 5):
            n, a, _ = moving.moving_coefficients(tr, V, (k + nu) * Om0, 11, offset=d, rtol=1e-7)
            ok = (k + n >= -6) & (k + n <= 5)
            col = tab.A[i, k + n[ok] + 6, k + 6]
            assert np.abs(col - a[ok]).max() < 1e-6 * np.abs(a).max()


def test_bloch_fraction_outside_its_range_is_rejected(tr):
    with pytest.raises(ValueError, match=r"fraction = 1\.0 is not allowed: the Bloch fraction must lie in \[0, 1\)"):
        moving.receptance_table(tr, V, 4, fraction=1.0)
    with pytest.raises(ValueError, match=r"roughness\.bays = 0 is not allowed"):
        moving.bloch_tables(tr, V, 4, 0)


def test_one_bay_periodic_roughness_gives_the_same_forces_and_wear_with_any_n(tr, tables4):
    # a 0.12 m roughness (harmonic 5 of the bay) written over 1 and over 4 bays: the same force
    # along the track, and the wear over 4 bays is the one-bay wear at j = 4 k with nothing
    # (round-off) in the other classes
    r1 = I.Roughness.harmonic(1e-5, tr.L / 5, tr.L, K)
    r4 = I.Roughness.harmonic(1e-5, tr.L / 5, tr.L, K, bays=4)
    F1 = I.solve_forces(tables4[0], WHEEL, contact_spring(), r1, tr.L)
    F4 = I.solve_forces(tables4, WHEEL, contact_spring(), r4, tr.L)
    x = np.linspace(0.0, 4 * tr.L, 997)
    P1, P4 = I.force_history(F1, x)[0], I.force_history(F4, x)[0]
    assert np.abs(P1 - P4).max() < 1e-12 * np.ptp(P1)
    num, law = C.ContactNumerics(41, "default", 1.0, "report", "wheel"), W.WearLaw(7850.0, 2.5e-9)
    w1 = W.bay_wear(F1, 0, r1, MATERIAL, law, num)
    w4 = W.bay_wear(F4, 0, r4, MATERIAL, law, num)
    J = 4 * K
    Z1, Z4 = w1.Z[K + 1 :], w4.Z[J + 1 :]
    big = np.abs(Z1) > 1e-2 * np.abs(Z1).max()
    assert np.abs(Z4[3::4][big] / Z1[big] - 1).max() < 1e-9
    assert np.delete(np.abs(Z4), np.arange(3, J, 4)).max() < 1e-12 * np.abs(Z1).max()


def test_a_sinusoid_between_the_comb_lines_excites_only_its_own_bloch_class(tr, tables4):
    # wavelength 4 L / 5 (beta = 5 beta0 / 4, not a multiple of beta0): relative to the smooth
    # rail, the force changes only at beta + m beta0 (j = 5 + 4 m, class 1) and the conjugates
    # (class 3); the static class 0 and class 2 are untouched, exactly
    J = 4 * K
    rs = I.Roughness.harmonic(1e-6, 4 * tr.L / 5, tr.L, K, bays=4)
    Fs = I.solve_forces(tables4, WHEEL, contact_spring(), rs, tr.L)
    F0 = I.solve_forces(tables4, WHEEL, contact_spring(), I.Roughness.smooth(K, 4), tr.L)
    d = np.abs(Fs.P[0] - F0.P[0])
    j = np.arange(-J, J + 1)
    assert d[j % 4 == 0].max() == 0.0 and d[j % 4 == 2].max() == 0.0
    assert d[j % 4 == 1].max() > 10.0 and d[j % 4 == 3].max() > 10.0  # N: 1 um gives tens of N
    # the direct response at the roughness wavenumber dominates its class
    assert d[J + 5] == d[j % 4 == 1].max()
    # a real force: P_-j = conj(P_j)
    np.testing.assert_allclose(Fs.P[0][::-1], np.conj(Fs.P[0]), rtol=0, atol=1e-9 * np.abs(Fs.P[0]).max())


@pytest.mark.slow
def test_far_apart_wheels_over_n_bays_behave_as_single_wheels(tr):
    # two wheels 49.5 m apart (20.6 periods of 2.4 m) over a roughness between the comb lines: the
    # coupling phases of the Bloch classes are right when each wheel, at a given position in the
    # period, carries the roughness-induced force of a single wheel there. Measured: 4e-6 of its
    # range at 49.5 m, 8e-7 at 73.5 m (the parametric part, class 0, couples more: 3e-3 of its
    # range at 49.5 m, as in the one-bay test of test_interaction.py at 100 m). Compared on the solved
    # harmonics (tail=False): the kink tail extrapolates the top harmonics, where the coupling at
    # 49.5 m is real (1 kHz waves decay slowly; the top harmonic of class 1 differs by 2 % between
    # one and two wheels), so with a tail per support the histories differ by 2e-5..4e-5 of the range
    d = 49.5
    tabs = moving.bloch_tables(tr, V, K, 4, offsets=(0.0, -d, d))
    rs = I.Roughness.harmonic(1e-6, 4 * tr.L / 5, tr.L, K, bays=4)
    sm = I.Roughness.smooth(K, 4)
    x = np.linspace(0.0, 4 * tr.L, 800)

    def dynamic(wheels):
        return (I.force_history(I.solve_forces(tabs, wheels, contact_spring(), rs, tr.L), x, tail=False)
                - I.force_history(I.solve_forces(tabs, wheels, contact_spring(), sm, tr.L), x, tail=False))

    one = dynamic(WHEEL)[0]
    for P in dynamic(I.Wheels(1350.0, 0.575, 1e5, (0.0, d))):
        assert np.abs(P - one).max() < 2e-5 * np.ptp(one)


@pytest.fixture(scope="module")
def random_forces(tr):
    """Two wheels 1.9 m apart over a random roughness periodic over 4 bays: (its coefficients, the roughness, the
    forces); the same for both grids of the test below."""
    rng = np.random.default_rng(0)
    J = 4 * K
    Z = np.zeros(2 * J + 1, dtype=complex)
    Z[J + 1 :] = 1e-7 * (rng.standard_normal(J) + 1j * rng.standard_normal(J))
    Z[:J] = np.conj(Z[J + 1 :][::-1])
    rough = I.Roughness(Z, 4)
    tabs = moving.bloch_tables(tr, V, K, 4, offsets=(0.0, -1.9, 1.9))
    return Z, rough, I.solve_forces(tabs, I.Wheels(1350.0, 0.575, 1e5, (0.0, 1.9)), contact_spring(), rough, tr.L)


@pytest.mark.parametrize("n", [97, 3001])
def test_force_and_curvature_on_a_grid_by_fft_equal_the_direct_sums(random_forces, n):
    # at the n grid points of the period every harmonic (and the 1/p^2 tail up to 17 K, far above
    # n / 2 for n = 97) folds into n bins exactly: the FFT sums equal the direct sums to rounding
    J = 4 * K
    Z, rough, F = random_forces
    x = np.arange(n) * F.period / n
    direct, fast = I.force_history(F, x), I.force_on_grid(F, n)
    assert np.abs(direct - fast).max() < 1e-12 * np.ptp(direct)
    j = np.arange(-J, J + 1) * 2 * np.pi / F.period  # kappa = -z'' = sum (j beta)^2 Z_j e^{i j beta x} (eq 20), summed directly
    c1 = np.real(np.exp(1j * np.outer(x, j)) @ (j**2 * Z))
    c2 = curvature_on_grid(rough, n, F.period)
    assert np.abs(c1 - c2).max() < 1e-12 * np.abs(c1).max()


def test_worn_roughness_keeps_its_period_of_n_bays():
    # rail.wear.apply_wear returned a 1-bay roughness whatever the period: the next passage then read
    # an N-bay coefficient vector as harmonics of one bay (the chain had its own copy that kept it)
    r = I.Roughness.harmonic(1e-6, 0.8 * 3 * 0.6 / 4, 0.6, 4, bays=3)
    dZ = 1e-9 * np.ones_like(r.Z)
    worn = W.apply_wear(r, dZ, passages=2.0)
    assert worn.bays == 3
    np.testing.assert_array_equal(worn.Z, r.Z - 2.0 * dZ)
