"""Normal wheel/rail forces (report sec. 4.2, eq 21): limits, superposition and convergence."""

import numpy as np
import pytest

from rail import halfspace
from rail import interaction as I
from rail import moving
from rail import track as T


def table1(scale_stiff=1.0):
    return T.Track(
        T.Rail(2.1e11 * scale_stiff, 0.81e11 * scale_stiff, 7850.0, 7.69e-3, 30.55e-6, 0.4, loss_factor=0.01),
        T.Pad(3.5e8 * scale_stiff, 0.25),
        T.Sleeper(162.0, 0.6),
        T.Ballast(50e6 * scale_stiff, 1.0),
    )


@pytest.fixture(scope="module")
def track():
    return table1()


@pytest.fixture(scope="module")
def contact():
    steel = halfspace.ElasticMaterial(2.1e11, 0.3, 7850.0)
    om = 2 * np.pi * 1000.0
    return I.ContactSpring(1.4e9, halfspace.contact_loss_factor(om, 1.4e9, steel) / om)


@pytest.fixture(scope="module")
def wheel():
    return I.Wheels(1350.0, 0.575, 1.0e5, (0.0,))


def test_rigid_track_gives_the_wheel_on_contact_spring_result(contact, wheel):
    # Supports and rail 1e5 times stiffer: the rail barely moves, and each force harmonic is the
    # roughness over the wheel + contact receptance: P_p = Z_p / (1/k_H(w) - 1/(M w^2)).
    rigid = table1(scale_stiff=1e5)
    V, K = 40.0, 20
    tab = moving.receptance_table(rigid, V, K)
    rough = I.Roughness.harmonic(1e-5, V / 1000.0, rigid.L, K)  # 1000 Hz: harmonic 15
    r = I.solve_forces(tab, wheel, contact, rough, rigid.L)
    om = 2 * np.pi * 1000.0
    expected = (1e-5 / 2) / (1 / contact.stiffness(om) - 1 / (wheel.mass * om**2))
    # the residual is the (tiny, inertia-controlled) rail receptance against the contact's
    rail_over_contact = abs(tab.A[0, K + 15, K + 15]) * abs(contact.stiffness(om))
    assert rail_over_contact < 1e-3
    assert abs(r.P[0, K + 15] - expected) < 3 * rail_over_contact * abs(expected)
    others = np.delete(np.abs(r.P[0]), [K, K + 15, K - 15])
    assert others.max() < 1e-3 * abs(expected)  # parametric excitation vanishes with the stiff track


def test_the_force_path_reads_the_wheel_through_its_receptance(track, contact, wheel):
    # A wheel with a spring k_w between its mass and the contact (receptance -1/(M w^2) + 1/k_w) must give
    # the forces of the rigid wheel on the series contact spring 1/k = 1/k_H(w) + 1/k_w: two different
    # routes into eq 21 (the wheel's receptance method, the contact's stiffness), one answer.
    import dataclasses as dc

    k_w = 3.0e9

    @dc.dataclass(frozen=True)
    class SprungWheels(I.Wheels):
        def receptance(self, omega):
            return -1.0 / (self.mass * np.asarray(omega, dtype=float) ** 2) + 1.0 / k_w

    class SeriesContact:
        def stiffness(self, omega):
            return 1.0 / (1.0 / contact.stiffness(omega) + 1.0 / k_w)

    V, K = 40.0, 20
    tab = moving.receptance_table(track, V, K)
    rough = I.Roughness.harmonic(1e-6, 0.04, track.L, K)
    sprung = I.solve_forces(tab, SprungWheels(1350.0, 0.575, 1.0e5, (0.0,)), contact, rough, track.L)
    series = I.solve_forces(tab, wheel, SeriesContact(), rough, track.L)
    rigid = I.solve_forces(tab, wheel, contact, rough, track.L)
    dyn = np.abs(sprung.P[0] - rigid.P[0]).max()
    assert dyn > 0.05 * np.abs(np.delete(rigid.P[0], K)).max()  # the wheel's spring matters here
    assert np.abs(sprung.P - series.P).max() < 1e-10 * np.abs(rigid.P[0, K])
    om = np.array([2e3, 5e3])
    assert np.allclose(wheel.receptance(om), -1.0 / (1350.0 * om**2), rtol=0, atol=0)


@pytest.mark.slow
def test_wheels_far_apart_behave_as_independent_single_wheels(track, contact, wheel):
    # Two wheels a whole number of bays apart see the same track. Their interaction falls with
    # distance; at 100.2 m the transfer receptance is 8e-4 of the point receptance at the
    # roughness harmonic (1000 Hz, near pinned-pinned, where rail waves decay slowest) and at
    # most 2.3 % at any harmonic, so each wheel's force equals the single wheel's to ~1e-3.
    V, K = 40.0, 16
    rough = I.Roughness.harmonic(1e-5, V / 1000.0, track.L, K)
    x = np.linspace(0, track.L, 64, endpoint=False)
    diffs = []
    for d in (30.0, 100.2):
        tab = moving.receptance_table(track, V, K, offsets=(0.0, d, -d))
        single = I.solve_forces(tab, wheel, contact, rough, track.L)
        both = I.solve_forces(tab, I.Wheels(1350.0, 0.575, 1.0e5, (0.0, d)), contact, rough, track.L)
        Ps = I.force_history(single, x)[0]
        Pb = I.force_history(both, x)
        diffs.append(max(np.abs(Pb[l] - Ps).max() for l in range(2)) / np.ptp(Ps))
    assert diffs[1] < 2e-3
    assert diffs[1] < 0.5 * diffs[0]


def test_close_wheels_interact(track, contact):
    # and 3.3 m apart (a bogie) they do not: the transfer receptance changes the forces
    V, K = 40.0, 16
    tab = moving.receptance_table(track, V, K, offsets=(0.0, 3.3, -3.3))
    rough = I.Roughness.harmonic(1e-5, V / 1000.0, track.L, K)
    one = I.solve_forces(tab, I.Wheels(1350.0, 0.575, 1e5, (0.0,)), contact, rough, track.L)
    bogie = I.solve_forces(tab, I.Wheels(1350.0, 0.575, 1e5, (0.0, 3.3)), contact, rough, track.L)
    assert np.abs(bogie.P[0] - one.P[0]).max() > 1e-3 * np.abs(one.P[0, K + 15])


def test_dynamic_force_is_linear_in_roughness_and_mean_is_static_load(track, contact, wheel):
    V, K = 40.0, 24
    tab = moving.receptance_table(track, V, K)
    smooth = I.solve_forces(tab, wheel, contact, I.Roughness.smooth(K), track.L)
    r1 = I.solve_forces(tab, wheel, contact, I.Roughness.harmonic(1e-5, 0.04, track.L, K), track.L)
    r2 = I.solve_forces(tab, wheel, contact, I.Roughness.harmonic(2e-5, 0.04, track.L, K), track.L)
    np.testing.assert_allclose(r2.P - smooth.P, 2 * (r1.P - smooth.P), rtol=1e-10, atol=1e-9)
    x = np.linspace(0, track.L, 4096, endpoint=False)
    assert I.force_history(r1, x, tail=False).mean() == pytest.approx(1e5, rel=1e-12)
    assert np.abs(smooth.P[0] - r1.P[0]).max() > 1e3  # the roughness does change the force


@pytest.mark.parametrize("V", [20.0, 40.0])
@pytest.mark.slow
def test_force_at_the_sleeper_converges_in_harmonics_with_the_tail_model(track, contact, wheel, V):
    # Without the tail the error at the sleeper falls like 1/K (review notes); with the 1/p^2 tail
    # K = 64 agrees with K = 128 to < 0.2 % of the fluctuation over the bay (measured 0.05 %).
    x = np.array([0.0, 0.3])
    res = {}
    for K in (32, 64, 128):
        tab = moving.receptance_table(track, V, K)
        res[K] = I.solve_forces(tab, wheel, contact, I.Roughness.smooth(K), track.L)
    xs = np.linspace(0, track.L, 256, endpoint=False)
    fluct = np.ptp(I.force_history(res[128], xs)[0])
    with_tail = {K: I.force_history(r, x)[0] for K, r in res.items()}
    plain = {K: I.force_history(r, x, tail=False)[0] for K, r in res.items()}
    assert abs(with_tail[64][0] - with_tail[128][0]) < 2e-3 * fluct
    assert abs(plain[64][0] - plain[128][0]) > 3 * abs(with_tail[64][0] - with_tail[128][0])
    assert abs(with_tail[64][1] - with_tail[128][1]) < 1e-3 * fluct  # mid-span: smooth


def test_contact_loss_is_detected_with_wheel_position_and_force(track, contact, wheel):
    V, K = 40.0, 24
    tab = moving.receptance_table(track, V, K)
    big = I.Roughness.harmonic(2e-4, 0.04, track.L, K)  # 200 um at 1000 Hz: the wheel jumps
    with pytest.raises(I.ContactLossError, match=r"contact lost: wheel 0 at x = \d\.\d{4} m in the bay, minimum force -\d+\.\d\d kN"):
        I.solve_forces(tab, wheel, contact, big, track.L)


def test_wavelength_that_does_not_fit_the_bay_names_the_nearest_allowed_ones():
    with pytest.raises(ValueError, match=r"wavelength = 0\.042 m does not fit .* nearest allowed wavelengths are 0\.04 m and 0\.0428571 m"):
        I.Roughness.harmonic(1e-5, 0.042, 0.6, 32)


def test_roughness_coefficients_follow_eq19():
    r = I.Roughness.from_coefficients([2], [3e-6], [4e-6], 4)
    x = np.linspace(0, 0.6, 7)
    b0 = 2 * np.pi / 0.6
    np.testing.assert_allclose(r.profile(x, 0.6), 3e-6 * np.cos(2 * b0 * x) + 4e-6 * np.sin(2 * b0 * x), atol=1e-18)


def test_roughness_from_a_file_and_its_errors(tmp_path):
    good = tmp_path / "rough.csv"
    good.write_text("k,A_m,B_m\n15,1e-5,0\n2,0,3e-6\n")
    k, A, B = I.read_roughness_coefficients(good)
    r = I.Roughness.from_coefficients(k, A, B, 20)
    x = np.linspace(0, 0.6, 9)
    b0 = 2 * np.pi / 0.6
    np.testing.assert_allclose(r.profile(x, 0.6), 1e-5 * np.cos(15 * b0 * x) + 3e-6 * np.sin(2 * b0 * x), atol=1e-18)
    bad = tmp_path / "bad.csv"
    bad.write_text("k,A_m,B_m\n3,1e-6,0\nfour,1e-6,0\n")
    with pytest.raises(ValueError, match=r"bad\.csv, line 3: 'four,1e-6,0' is not an integer k and two numbers in m"):
        I.read_roughness_coefficients(bad)
    header = tmp_path / "header.csv"
    header.write_text("harmonic,A,B\n")
    with pytest.raises(ValueError, match=r"header\.csv, line 1: the header must be 'k,A_m,B_m'"):
        I.read_roughness_coefficients(header)


def test_the_force_tails_phase_factors_are_kept_with_the_same_numbers():
    # force_tail keeps exp(-i q beta_P s_j) (it does not depend on the force): the tail is the direct formula's
    rng = np.random.default_rng(0)
    for N, K, supports in ((48, 4, None), (4, 6, np.array([0.0, 0.3, 0.61, 1.2, 1.75]))):
        J = N * K
        P = rng.standard_normal((2, 2 * J + 1)) + 1j * rng.standard_normal((2, 2 * J + 1))
        r = I.ForceResult(P=P, speed=40.0, L=0.6, positions=np.array([0.0, 2.5]), bays=N, supports=supports)
        q, T_kept = I.force_tail(r)
        q2, T_again = I.force_tail(r)  # from the kept factors
        s = np.arange(N) * 0.6 if supports is None else supports
        bP = r.beta0 / N
        qfit = np.arange(J - len(s) + 1, J + 1)
        rhs = (qfit[None, :] ** 2 * P[:, J + qfit] * np.exp(-1j * bP * np.outer(r.positions, qfit))).T
        C = np.linalg.lstsq(np.exp(-1j * bP * np.outer(qfit, s)), rhs, rcond=1e-12)[0].T
        direct = (C @ np.exp(-1j * bP * np.outer(s, q))) / q[None, :] ** 2
        assert np.array_equal(q, np.arange(J + 1, J + 16 * K * N + 1)) and np.array_equal(q2, q)
        assert np.array_equal(T_kept, direct) and np.array_equal(T_again, direct)
