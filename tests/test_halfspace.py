"""Elastic half-space under a harmonic point load (report section 3): analytic limits and
an independent check of the radiation condition."""

import numpy as np
import pytest
from scipy import integrate

from rail import halfspace

F_REPORT = 4000.0  # Hz, section 3
OMEGA = 2 * np.pi * F_REPORT


def test_wavenumbers_at_4000_hz_match_report(steel):
    # Report section 3: beta_R = 8.448, beta_1 = 4.188, beta_2 = 7.835 rad/m (printed to 3 decimals).
    b1, b2, bR = halfspace.wavenumbers(OMEGA, steel)
    assert b1 == pytest.approx(4.188, abs=5e-4)
    assert b2 == pytest.approx(7.835, abs=5e-4)
    assert bR == pytest.approx(8.448, abs=5e-4)


def test_rayleigh_root_solves_eq11(steel):
    # The root of the cubic eq (12) must make the Rayleigh function of eq (11) vanish.
    b1, b2, bR = halfspace.wavenumbers(OMEGA, steel)
    D = halfspace._denominator(bR, b1, b2)
    assert abs(D) < 1e-10 * bR**4


@pytest.mark.parametrize("nu, ratio", [(0.25, 0.919402), (0.5 - 1e-9, 0.955313)])
def test_rayleigh_speed_ratio_known_values(nu, ratio):
    # Classical values of c_R / c_2: 0.9194 for nu = 1/4 (Rayleigh 1885), 0.9553 for nu -> 1/2.
    assert halfspace.rayleigh_speed_ratio(nu) == pytest.approx(ratio, abs=2e-6)


def test_beta_G_tends_to_eq15_limit_at_large_wavenumber(steel):
    # Eq (15): beta G -> 2 (1 - nu^2) / E; the deviation is C / beta^2 (large_beta_coefficient).
    L = 2 * (1 - 0.3**2) / 2.1e11
    _, _, bR = halfspace.wavenumbers(OMEGA, steel)
    for factor in (1e3, 1e5):
        beta = factor * bR
        bG = beta * halfspace.kernel_G(beta, OMEGA, steel)
        assert abs(bG / L - 1) < 2.0 / factor**2  # C / bR^2 = 0.63 for nu = 0.3
        assert abs(bG.imag) == 0.0


def test_beta_G_tends_to_eq15_limit_as_frequency_vanishes(steel):
    L = 2 * (1 - 0.3**2) / 2.1e11
    beta = 3.0
    for omega in (1e-1, 1e-3):
        bG = beta * halfspace.kernel_G(beta, omega, steel)
        # relative deviation is O((omega / (c2 beta))^2)
        assert abs(bG / L - 1) < 10 * (omega / (3200.0 * beta)) ** 2


def test_large_beta_coefficient_matches_kernel(steel):
    # (beta G / L - 1) beta^2 -> C; the next term is O(beta^-2) relative.
    _, _, bR = halfspace.wavenumbers(OMEGA, steel)
    C = halfspace.large_beta_coefficient(OMEGA, steel)
    L = halfspace.static_limit_beta_G(steel)
    beta = 300 * bR
    est = ((beta * halfspace.kernel_G(beta, OMEGA, steel)).real / L - 1) * beta**2
    assert est == pytest.approx(C, rel=1e-3)


def test_eq16_tends_to_boussinesq_as_r_vanishes(steel):
    # Eq (16) -> eq (17) for beta_R r -> 0. The real part of the dynamic correction has no
    # constant term (Re w - w_B = O(r)), so the relative difference falls like r^2: two decades
    # per decade of r. Asserting at least one decade per decade keeps the test about the limit.
    r = np.array([1e-2, 1e-3, 1e-4])
    w = halfspace.surface_displacement(r, OMEGA, steel)
    rel = np.abs(w.real / halfspace.boussinesq(r, steel) - 1)
    assert rel[0] < 1e-2  # beta_R r = 0.08 at r = 10 mm
    assert rel[-1] < 1e-6
    assert rel[1] / rel[0] < 0.1
    assert rel[2] / rel[1] < 0.1


def test_static_load_gives_boussinesq(steel):
    r = np.array([0.001, 0.01])
    np.testing.assert_allclose(halfspace.surface_displacement(r, 0.0, steel).real, halfspace.boussinesq(r, steel))
    # Boussinesq eq (17) by hand: (1 - 0.09) / (pi 2.1e11 0.01) = 1.37934e-10 m per N.
    assert halfspace.boussinesq(0.01, steel) == pytest.approx(1.379343e-10, rel=1e-6)


def test_surface_displacement_converges_in_quadrature_tolerance(steel):
    r = np.array([0.001, 0.02, 0.1])
    coarse = halfspace.surface_displacement(r, OMEGA, steel, numerics=halfspace.HalfSpaceNumerics(epsrel=1e-6))
    fine = halfspace.surface_displacement(r, OMEGA, steel, numerics=halfspace.HalfSpaceNumerics(epsrel=1e-12))
    np.testing.assert_allclose(coarse, fine, rtol=1e-5)


def test_imaginary_part_is_smooth_near_the_load(steel):
    # Im w(r) is finite at r = 0 and continuous: Im w(1 mm) ~ Im w0(0) (beta_R r = 0.008).
    im0 = halfspace.point_receptance_imag(OMEGA, steel)
    im1 = halfspace.surface_displacement(1e-3, OMEGA, steel).imag
    assert im1 == pytest.approx(im0, rel=1e-4)
    assert im0 < 0  # power flows into the half-space


def test_loss_factor_grows_linearly_with_frequency(steel):
    f = np.array([50.0, 500.0, 1000.0, 2500.0, 5000.0])
    eta = halfspace.contact_loss_factor(2 * np.pi * f, 1.4e9, steel)
    slope = eta / f
    np.testing.assert_allclose(slope, slope[0], rtol=1e-8)
    assert np.all(eta > 0)


def test_radiated_power_equals_power_input_and_grows_as_frequency_squared(steel):
    f = np.array([1000.0, 2000.0])
    W = halfspace.radiated_power(2 * np.pi * f, steel, load=2.0)
    assert W[1] / W[0] == pytest.approx(4.0, rel=1e-8)
    # Power input of a 2 N load: 1/2 omega Im(conj(F) * w) with w = F * receptance.
    im = halfspace.point_receptance_imag(2 * np.pi * f[0], steel)
    assert W[0] == pytest.approx(-0.5 * 2 * np.pi * f[0] * 4.0 * im, rel=1e-12)


def test_power_and_loss_factor_from_a_given_receptance_are_those_of_the_quadrature(steel):
    # the radiation dataset computes Im w0(0) once and passes it to both (issue 33): the same values
    # as each computing it, and a receptance of another shape is refused
    omega = 2 * np.pi * np.array([300.0, 3000.0])
    im = halfspace.point_receptance_imag(omega, steel)
    np.testing.assert_array_equal(halfspace.radiated_power(omega, steel, 2.0, receptance_imag=im),
                                  halfspace.radiated_power(omega, steel, 2.0))
    np.testing.assert_array_equal(halfspace.contact_loss_factor(omega, 1.4e9, steel, receptance_imag=im),
                                  halfspace.contact_loss_factor(omega, 1.4e9, steel))
    with pytest.raises(ValueError, match="receptance_imag has shape"):
        halfspace.radiated_power(omega, steel, receptance_imag=im[:1])


def test_pointwise_kernel_of_the_quadrature_agrees_with_kernel_G_to_rounding(steel):
    # the adaptive quadrature of w(r) evaluates G point by point in Python's complex arithmetic
    # (issue 33: Fig. 4 in about 1 s CPU against 11 s): the same formulas as the vectorised kernel_G,
    # on both of _denominator's forms, across the P, S and Rayleigh wavenumbers and at omega = 0
    for f in (100.0, 3000.0, 20000.0):
        omega = 2 * np.pi * f
        b1, b2, bR = halfspace.wavenumbers(omega, steel)
        beta = np.concatenate([np.linspace(1e-6, 3 * bR, 1501), [b1, b2, 2 * b2 * (1 - 1e-12), 2 * b2 * (1 + 1e-12)]])
        G = halfspace._kernel_G_point(omega, steel)
        point = np.array([G(b) for b in beta])
        np.testing.assert_allclose(point, halfspace.kernel_G(beta, omega, steel), rtol=2e-15, atol=0.0)
    G0 = halfspace._kernel_G_point(0.0, steel)
    assert G0(3.0) == halfspace.kernel_G(3.0, 0.0, steel)


def _im_w0_with_material_damping(omega, material, eta):
    """Im w0(0) for a half-space with hysteretic damping eta, integrated straight along the real
    beta axis: no principal value, no residue. The static (omega = 0) part, which does not radiate
    but whose imaginary part diverges at r = 0 when eta > 0, is subtracted: it is the large-beta
    limit of the same integrand."""
    md = halfspace.ElasticMaterial(material.youngs_modulus, material.poisson_ratio, material.density, eta)
    b1, b2, bR = halfspace.wavenumbers(omega, material)
    L = halfspace.static_limit_beta_G(md)
    c1, c2 = halfspace.wave_speeds(md)
    k1, k2 = omega / c1, omega / c2
    C = -(k1**2) / 2 - k2**2 * (2 * k1**2 - 3 * k2**2) / (2 * (k2**2 - k1**2)) - (k1**2 + 3 * k2**2) / 4

    def f(b):
        return (halfspace.kernel_G(b, omega, md) * b - L).imag

    w = 50 * eta * bR  # width of the damped Rayleigh peak is ~ eta bR / 2
    pts = [0.0, b1, b2, bR - w, bR - w / 50, bR, bR + w / 50, bR + w, 2 * bR, 50 * bR]
    total = sum(integrate.quad(f, a, b, epsabs=0, epsrel=1e-11, limit=1000)[0] for a, b in zip(pts[:-1], pts[1:]))
    total += (L * C / (50 * bR)).imag  # tail beyond 50 bR, where beta G - L = L C / beta^2
    return total / (2 * np.pi)


def test_radiation_condition_matches_vanishing_material_damping(steel):
    # Independent check of the Rayleigh-pole treatment: the damped integral along the real axis
    # must tend to PV - i pi Res as eta -> 0, while the principal value alone does not.
    omega = 2 * np.pi * 1000.0
    ref = halfspace.point_receptance_imag(omega, steel)
    errors = [abs(_im_w0_with_material_damping(omega, steel, eta) / ref - 1) for eta in (1e-2, 1e-3, 1e-4)]
    assert errors[-1] < 1e-6
    assert errors[0] > errors[1] > errors[2]  # converging as damping vanishes
    res_part = -np.pi * halfspace.rayleigh_residue(omega, steel) / (2 * np.pi)
    principal_value_only = ref - res_part
    assert abs(principal_value_only / ref - 1) > 0.5  # the PV alone misses most of the power


def test_rayleigh_share_of_radiated_power_matches_miller_pursey(steel):
    # Miller & Pursey (1955): a vertical point source on a half-space with nu = 1/4 radiates
    # 67 % of its power as Rayleigh waves (26 % S, 7 % P). The residue term is that share.
    m = halfspace.ElasticMaterial(2.1e11, 0.25, 7850.0)
    omega = 2 * np.pi * 1000.0
    share = (-np.pi * halfspace.rayleigh_residue(omega, m) / (2 * np.pi)) / halfspace.point_receptance_imag(omega, m)
    assert share == pytest.approx(0.67, abs=0.01)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"youngs_modulus": -2.1e11, "poisson_ratio": 0.3, "density": 7850.0},
         r"youngs_modulus \[Pa\] = -210000000000.0 is not allowed: it must lie in \(0.0, inf\)"),
        ({"youngs_modulus": 2.1e11, "poisson_ratio": 0.5, "density": 7850.0}, r"poisson_ratio \[-\] = 0.5 .*\(-1.0, 0.5\)"),
        ({"youngs_modulus": 2.1e11, "poisson_ratio": 0.3, "density": 0.0}, r"density \[kg/m\^3\] = 0.0"),
    ],
)
def test_material_rejects_unphysical_values(kwargs, match):
    with pytest.raises(ValueError, match=match):
        halfspace.ElasticMaterial(**kwargs)
