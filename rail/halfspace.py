"""Elastic half-space under a vertical harmonic point load (report section 3).

Conventions
-----------
* Time dependence ``exp(+i omega t)``; the load ``P exp(i omega t)`` acts downwards on the
  surface at r = 0 and w is the vertical surface displacement in the direction of the load.
* Radiation condition for ``exp(+i omega t)``: ``alpha_j = sqrt(beta^2 - k_j^2)`` is taken with
  ``Re alpha_j >= 0`` and, where ``beta < k_j``, ``alpha_j = +i sqrt(k_j^2 - beta^2)``, i.e. the
  limit of a vanishing hysteretic material damping (moduli ``E (1 + i eta)``, ``eta -> 0+``).
  In that limit the Rayleigh pole lies just *below* the real beta axis, so the integral
  along the real axis is the principal value **minus** ``i pi`` times the residue.  The
  report's eq (14)/(16) keeps only the principal value; the residue term is the Rayleigh
  wave's share of the radiated power (about two thirds of it), see
  ``docs/paper-discrepancies.md``.
* All quantities in SI units: Pa, kg/m^3, rad/s, rad/m, m, N, W.
"""

from __future__ import annotations

import cmath
import functools
from dataclasses import dataclass

import numpy as np

__all__ = [
    "ElasticMaterial",
    "HalfSpaceNumerics",
    "lame_constants",
    "wave_speeds",
    "rayleigh_speed_ratio",
    "wavenumbers",
    "kernel_G",
    "static_limit_beta_G",
    "folded_integrand",
    "rayleigh_residue",
    "large_beta_coefficient",
    "boussinesq",
    "surface_displacement",
    "point_receptance_imag",
    "radiated_power",
    "contact_loss_factor",
]


def _check_range(name: str, value: float, low: float, high: float, low_open=True, high_open=True):
    """Raise ValueError naming the parameter, its value and the valid range."""
    ok_low = value > low if low_open else value >= low
    ok_high = value < high if high_open else value <= high
    if not (np.isfinite(value) and ok_low and ok_high):
        lb = "(" if low_open else "["
        hb = ")" if high_open else "]"
        raise ValueError(f"{name} = {value!r} is not allowed: it must lie in {lb}{low}, {high}{hb}.")


@dataclass(frozen=True, slots=True)
class ElasticMaterial:
    """Homogeneous isotropic elastic solid (report section 3).

    Attributes
    ----------
    youngs_modulus : Pa,     > 0
    poisson_ratio : -,      -1 < nu < 0.5
    density : kg/m^3, > 0
    loss_factor : -,      >= 0; hysteretic damping, moduli multiplied by (1 + i eta).
                     The report's half-space is undamped (0); a positive value is used only
                     by the independent radiation-condition check.
    """

    youngs_modulus: float
    poisson_ratio: float
    density: float
    loss_factor: float = 0.0

    def __post_init__(self):
        _check_range("youngs_modulus [Pa]", self.youngs_modulus, 0.0, np.inf)
        _check_range("poisson_ratio [-]", self.poisson_ratio, -1.0, 0.5)
        _check_range("density [kg/m^3]", self.density, 0.0, np.inf)
        _check_range("loss_factor [-]", self.loss_factor, 0.0, np.inf, low_open=False)


@dataclass(frozen=True, slots=True)
class HalfSpaceNumerics:
    """Quadrature settings for eqs (14)-(16).

    epsrel : -, relative tolerance handed to the adaptive Gauss-Kronrod quadrature (QUADPACK).
    limit  : -, maximum number of subintervals per quadrature call.
    """

    epsrel: float = 1e-10
    limit: int = 500

    def __post_init__(self):
        _check_range("numerics.halfspace.epsrel [-]", self.epsrel, 0.0, 1e-2)
        _check_range("numerics.halfspace.limit [-]", self.limit, 10, 100000, low_open=False)


def lame_constants(material: ElasticMaterial):
    """Lamé constants lambda and mu of the material (report eq 6).

    lambda = nu E / ((1 + nu) (1 - 2 nu)), mu = E / (2 (1 + nu)), with E replaced by E (1 + i eta)
    if the material is damped (loss factor eta > 0); the constants are then complex.

    Parameters
    ----------
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    lam : float or complex
        First Lamé constant lambda [Pa]; complex if the material is damped.
    mu : float or complex
        Second Lamé constant (shear modulus) mu [Pa]; complex if the material is damped.
    """
    E = material.youngs_modulus * (1 + 1j * material.loss_factor)
    nu = material.poisson_ratio
    lam = nu * E / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    if material.loss_factor == 0:
        return float(np.real(lam)), float(np.real(mu))
    return lam, mu


def wave_speeds(material: ElasticMaterial):
    """P- and S-wave speeds c1, c2 of the material (report eq 7).

    c1 = sqrt((lambda + 2 mu) / rho), c2 = sqrt(mu / rho), with the Lamé constants of eq (6)
    (``lame_constants``).

    Parameters
    ----------
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    c1 : float or complex
        P-wave speed [m/s]; complex if the material is damped.
    c2 : float or complex
        S-wave speed [m/s]; complex if the material is damped.
    """
    lam, mu = lame_constants(material)
    return np.sqrt((lam + 2 * mu) / material.density), np.sqrt(mu / material.density)


def rayleigh_speed_ratio(poisson_ratio: float) -> float:
    """Rayleigh-wave speed ratio c_R / c_2, the root in (0, 1) of the Rayleigh equation (report eq 12).

    Eq (12) is a cubic in x = (c_R/c_2)^2: x^3 - 8 x^2 + 8 (2-nu)/(1-nu) x - 8/(1-nu) = 0.
    It has exactly one root in (0, 1) for -1 < nu < 0.5.

    Parameters
    ----------
    poisson_ratio : float
        Poisson's ratio nu [-], -1 < nu < 0.5.

    Returns
    -------
    float
        c_R / c_2 [-], in (0, 1).

    Raises
    ------
    ValueError
        If poisson_ratio is outside (-1, 0.5), where the cubic has no unique root in (0, 1).
    """
    _check_range("poisson_ratio", poisson_ratio, -1.0, 0.5)
    return _rayleigh_root(float(poisson_ratio))


@functools.lru_cache(maxsize=64)
def _rayleigh_root(nu: float) -> float:
    """c_R / c_2 for a checked Poisson's ratio (see rayleigh_speed_ratio), computed once per value:
    the half-space quadratures ask for it at every integrand evaluation (43 000 times for Fig. 4)."""
    roots = np.roots([1.0, -8.0, 8.0 * (2 - nu) / (1 - nu), -8.0 / (1 - nu)])
    x = [r.real for r in roots if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0]
    if len(x) != 1:  # pragma: no cover - excluded by the range check on nu
        raise ValueError(f"poisson_ratio = {nu}: no unique Rayleigh root in (0, 1)")
    return float(np.sqrt(x[0]))


def wavenumbers(omega, material: ElasticMaterial):
    """P-, S- and Rayleigh wavenumbers beta_1, beta_2, beta_R (report eqs 7, 11-12).

    beta_1 = omega / c_1, beta_2 = omega / c_2 and, for the undamped material,
    beta_R = omega / (c_2 * rayleigh_speed_ratio).

    Parameters
    ----------
    omega : float or ndarray
        Angular frequency [rad/s].
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    beta_1 : float or ndarray
        P-wavenumber [rad/m]; complex if the material is damped.
    beta_2 : float or ndarray
        S-wavenumber [rad/m]; complex if the material is damped.
    beta_R : float or ndarray
        Rayleigh wavenumber [rad/m]; complex if the material is damped.
    """
    c1, c2 = wave_speeds(material)
    omega = np.asarray(omega, dtype=float)
    b1, b2 = omega / c1, omega / c2
    return b1, b2, b2 / rayleigh_speed_ratio(material.poisson_ratio)


def _alpha(beta, k):
    """sqrt(beta^2 - k^2) on the radiating branch (see module docstring)."""
    beta = np.asarray(beta, dtype=complex)
    d = beta**2 - np.asarray(k, dtype=complex) ** 2
    a = np.sqrt(d)
    # numpy's principal sqrt already gives Re >= 0; on the cut (d real negative) force +i.
    on_cut = (a.real == 0) & (a.imag < 0)
    return np.where(on_cut, -a, a)


def _denominator(beta, k1, k2):
    """Rayleigh function D(beta) = 4 alpha1 alpha2 beta^2 - (2 beta^2 - k2^2)^2 (eq 11).

    For beta well above k2 the two terms (each ~ 4 beta^4) cancel catastrophically; there
    D is evaluated in the rationalised form (multiply by the conjugate sum, expand in B = beta^2)
        D = [16 B^3 (k2^2 - k1^2) + 8 B^2 k2^2 (2 k1^2 - 3 k2^2) + 8 B k2^6 - k2^8]
            / [4 alpha1 alpha2 B + (2 B - k2^2)^2],
    which is exact and whose denominator is positive there.
    """
    beta = np.asarray(beta, dtype=complex)
    k1 = np.asarray(k1, dtype=complex)
    k2 = np.asarray(k2, dtype=complex)
    a1, a2 = _alpha(beta, k1), _alpha(beta, k2)
    B = beta**2
    direct = 4 * a1 * a2 * B - (2 * B - k2**2) ** 2
    num = 16 * B**3 * (k2**2 - k1**2) + 8 * B**2 * k2**2 * (2 * k1**2 - 3 * k2**2)
    num = num + 8 * B * k2**6 - k2**8
    rationalised = num / (4 * a1 * a2 * B + (2 * B - k2**2) ** 2)
    return np.where(beta.real > 2 * np.abs(k2), rationalised, direct)


def kernel_G(beta, omega, material: ElasticMaterial):
    """Kernel G(beta, omega) of the surface displacement integral (report eq 9).

    G = alpha1 omega^2 / (mu c2^2 [4 alpha1 alpha2 beta^2 - (2 beta^2 - omega^2/c2^2)^2]),
    with alpha_j = sqrt(beta^2 - omega^2/c_j^2) (eq 8) on the radiating branch (module docstring).
    G is the displacement per unit load per (rad/m)^2.  For omega = 0 the static limit
    2 (1 - nu^2) / (E beta) is returned (eq 15).

    Parameters
    ----------
    beta : float or ndarray
        Radial wavenumber [rad/m].
    omega : float
        Angular frequency [rad/s].
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    complex ndarray
        G(beta, omega) [m^3/N], shape of ``beta``.
    """
    beta = np.asarray(beta, dtype=float)
    omega = float(omega)
    if omega == 0.0:
        return static_limit_beta_G(material) / beta + 0j
    lam, mu = lame_constants(material)
    c1, c2 = wave_speeds(material)
    k1, k2 = omega / c1, omega / c2
    a1 = _alpha(beta, k1)
    return a1 * omega**2 / (mu * c2**2 * _denominator(beta, k1, k2))


def static_limit_beta_G(material: ElasticMaterial):
    """Limit L = 2 (1 - nu^2) / E of beta G for beta -> inf or omega -> 0 (report eq 15).

    E is replaced by E (1 + i eta) if the material is damped.

    Parameters
    ----------
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    float or complex
        L [m^2/N]; complex if the material is damped.
    """
    E = material.youngs_modulus * (1 + 1j * material.loss_factor)
    val = 2 * (1 - material.poisson_ratio**2) / E
    return float(np.real(val)) if material.loss_factor == 0 else val


def _integrand(beta, omega, r, material):
    """G(beta, omega) J0(beta r) beta, the integrand of eq (10)."""
    from scipy import special  # here, not at the top: importing scipy costs jobs that do not use it about 0.7 s CPU
    return kernel_G(beta, omega, material) * special.j0(np.asarray(beta) * r) * beta


def folded_integrand(beta, omega, r, material: ElasticMaterial):
    """Integrand of the first integral of report eq (14), for 0 < beta < beta_R.

    f(beta) + f(2 beta_R - beta) with f = G J0(beta r) beta: the Rayleigh-pole singularities
    of the two terms cancel, leaving the principal value (report Fig. 2).

    Parameters
    ----------
    beta : float or ndarray
        Radial wavenumber [rad/m], 0 < beta < beta_R.
    omega : float
        Angular frequency [rad/s].
    r : float
        Distance from the loading point [m].
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    complex ndarray
        The folded integrand [m^2/N], shape of ``beta``.
    """
    _, _, bR = wavenumbers(omega, material)
    beta = np.asarray(beta, dtype=float)
    return _integrand(beta, omega, r, material) + _integrand(2 * bR - beta, omega, r, material)


def rayleigh_residue(omega, material: ElasticMaterial):
    """Residue of beta G(beta, omega) at the Rayleigh pole beta_R (from report eqs 9, 11).

    beta G = N(beta)/D(beta) with N = alpha1 omega^2 beta / (mu c2^2); residue = N/D'(beta_R), where::

      D'(beta) = 4 beta^2 (alpha1' alpha2 + alpha1 alpha2') + 8 beta alpha1 alpha2
                 - 8 beta (2 beta^2 - k2^2),  alpha_j' = beta / alpha_j.

    Real and negative for the undamped material (D decreases through its root).

    Parameters
    ----------
    omega : float or ndarray
        Angular frequency [rad/s].
    material : ElasticMaterial
        The half-space material; must be undamped.

    Returns
    -------
    float or ndarray
        The residue [m/N].

    Raises
    ------
    ValueError
        If the material is damped (loss_factor != 0).
    """
    if material.loss_factor != 0:
        raise ValueError("rayleigh_residue needs an undamped material (loss_factor = 0).")
    _, mu = lame_constants(material)
    c1, c2 = wave_speeds(material)
    k1, k2 = omega / c1, omega / c2
    b = omega / c2 / rayleigh_speed_ratio(material.poisson_ratio)
    a1, a2 = np.sqrt(b**2 - k1**2), np.sqrt(b**2 - k2**2)
    dD = 4 * b**2 * (b / a1 * a2 + a1 * b / a2) + 8 * b * a1 * a2 - 8 * b * (2 * b**2 - k2**2)
    N = a1 * omega**2 * b / (mu * c2**2)
    return N / dD


def large_beta_coefficient(omega, material: ElasticMaterial) -> float:
    """Coefficient C of the large-beta expansion of beta G (derived from report eq 9).

    beta G(beta, omega) = L (1 + C / beta^2) + O(beta^-4), L the limit of eq (15).
    Expanding alpha_j = beta sqrt(1 - k_j^2 / beta^2) in eq (9), with k_j = omega / c_j:
    C = -k1^2/2 - k2^2 (2 k1^2 - 3 k2^2) / (2 (k2^2 - k1^2)) - (k1^2 + 3 k2^2) / 4.

    Parameters
    ----------
    omega : float
        Angular frequency [rad/s].
    material : ElasticMaterial
        The half-space material.

    Returns
    -------
    float
        C [rad^2/m^2] (its real part, if the material is damped).
    """
    c1, c2 = wave_speeds(material)
    k1, k2 = omega / c1, omega / c2
    return float(
        np.real(-(k1**2) / 2 - k2**2 * (2 * k1**2 - 3 * k2**2) / (2 * (k2**2 - k1**2)) - (k1**2 + 3 * k2**2) / 4)
    )


def _int_j0_over_x2(y: float, numerics) -> float:
    """I(y) = int_y^inf J0(x) / x^2 dx = J0(y)/y - 1 + int_0^y J1(x)/x dx (by parts), y > 0."""
    from scipy import integrate, special
    inner, _ = integrate.quad(
        lambda x: special.j1(x) / x if x > 0 else 0.5, 0.0, y, epsabs=0.0, epsrel=numerics.epsrel
    )
    return special.j0(y) / y - 1.0 + inner


def boussinesq(r, material: ElasticMaterial, load=1.0):
    """Static surface displacement under a point load, Boussinesq's formula (report eq 17).

    w = (1 - nu^2) P / (pi E r).

    Parameters
    ----------
    r : float or ndarray
        Distance from the loading point [m], finite and > 0 (w is singular at r = 0).
    material : ElasticMaterial
        The half-space material (E and nu are used).
    load : float, optional
        Load P [N]; default 1.

    Returns
    -------
    float or ndarray
        Surface displacement w [m] in the direction of the load, shape of ``r``.

    Raises
    ------
    ValueError
        If any r is not finite and > 0.
    """
    r = np.asarray(r, dtype=float)
    bad = ~(np.isfinite(r) & (r > 0))
    if np.any(bad):
        raise ValueError(f"r = {float(r[bad].flat[0])!r} m is not allowed in Boussinesq's formula (eq 17): it must be a finite "
                         "number > 0.")
    return (1 - material.poisson_ratio**2) * load / (np.pi * material.youngs_modulus * r)


def _quad(f, a, b, numerics: HalfSpaceNumerics, scale: float):
    """Adaptive quadrature of a complex function; absolute tolerance epsrel * scale."""
    from scipy import integrate
    val, _ = integrate.quad(
        f, a, b, complex_func=True, epsabs=numerics.epsrel * scale, epsrel=numerics.epsrel,
        limit=numerics.limit,
    )
    return val


def _quad_re(f, a, b, numerics: HalfSpaceNumerics, scale: float):
    """Adaptive quadrature of a real function; absolute tolerance epsrel * scale."""
    from scipy import integrate
    val, _ = integrate.quad(
        f, a, b, epsabs=numerics.epsrel * scale, epsrel=numerics.epsrel, limit=numerics.limit
    )
    return val


def _kernel_G_point(omega, material: ElasticMaterial):
    """G(beta, omega) of kernel_G for one real beta at a time, in Python's complex arithmetic: the
    same formulas (_alpha's branch, _denominator's two forms) without numpy's cost per call, which
    was most of the adaptive quadrature's time (it calls the integrand point by point). Agrees with
    kernel_G to rounding (tests/test_halfspace.py)."""
    if omega == 0.0:
        L = static_limit_beta_G(material)
        return lambda beta: L / beta + 0j
    lam, mu = lame_constants(material)
    c1, c2 = wave_speeds(material)
    k1, k2 = complex(omega / c1), complex(omega / c2)
    mu_c2 = complex(mu * c2**2)  # kernel_G's factors, in its order of operations
    om2 = float(omega) ** 2
    two_k2 = 2 * abs(k2)

    def alpha(b, k):
        a = cmath.sqrt(b**2 - k**2)
        return -a if (a.real == 0 and a.imag < 0) else a

    def G(beta):
        b = complex(beta)
        a1, a2 = alpha(b, k1), alpha(b, k2)
        B = b**2
        if b.real > two_k2:
            num = 16 * B**3 * (k2**2 - k1**2) + 8 * B**2 * k2**2 * (2 * k1**2 - 3 * k2**2)
            num = num + 8 * B * k2**6 - k2**8
            D = num / (4 * a1 * a2 * B + (2 * B - k2**2) ** 2)
        else:
            D = 4 * a1 * a2 * B - (2 * B - k2**2) ** 2
        return a1 * om2 / (mu_c2 * D)

    return G


def _surface_displacement_scalar(r, omega, material, numerics):
    """One value of w(r) per unit load: eq (16) + Rayleigh residue (see surface_displacement)."""
    from scipy import special
    b1, b2, bR = wavenumbers(omega, material)
    L = static_limit_beta_G(material)
    G = _kernel_G_point(omega, material)
    j0 = special.j0

    def f(beta):  # _integrand at one point
        beta = float(beta)
        return G(beta) * float(j0(beta * r)) * beta

    def folded(beta):  # folded_integrand at one point
        return f(beta) + f(2 * bR - beta)

    # First three integrals of eq (16): 0 < beta < beta_R, folded across the pole.
    if r == 0.0:
        # Only the imaginary part is finite at r = 0: for beta > beta_2 (outside the pole)
        # the integrand is real, so the imaginary part comes from [0, beta_2] only.
        scale = abs(rayleigh_residue(omega, material))
        im = _quad_re(lambda b: f(b).imag, 0.0, b1, numerics, scale)
        im += _quad_re(lambda b: f(b).imag, b1, b2, numerics, scale)
        res = -np.pi * rayleigh_residue(omega, material) * 1.0  # J0(0) = 1
        return complex(np.inf, (im + res) / (2 * np.pi))
    # magnitude of 2 pi w: the larger of the static term L / r and the wave term L beta_R
    scale = L * max(1.0 / r, bR)
    total = _quad(folded, 0.0, b1, numerics, scale)
    total += _quad(folded, b1, b2, numerics, scale)
    total += _quad(folded, b2, bR, numerics, scale)
    # Fourth and fifth terms of eq (16), done without truncation: for beta > 2 beta_R write
    # beta G = L (1 + C / beta^2) + O(beta^-4) (see large_beta_coefficient). Then
    #   int_{2bR}^inf beta G J0 = int_{2bR}^{B} (beta G - L - L C / beta^2) J0      [numerical]
    #                           + L int_{2bR}^inf J0(beta r) d beta                   [eq 16]
    #                           + L C r I(2 bR r),  I(y) = int_y^inf J0(x) / x^2 dx  [closed form]
    # and the dropped remainder beyond B = 20 beta_R is O(L beta_R / 24000).
    C = large_beta_coefficient(omega, material)
    rem = lambda b: ((kernel_G(b, omega, material) * b - L * (1 + C / b**2)) * special.j0(b * r)).real  # noqa: E731
    tail = _quad_re(rem, 2 * bR, 20 * bR, numerics, scale)
    y = 2 * bR * r
    tail += L / r * (1.0 - special.itj0y0(y)[0])
    tail += L * C * r * _int_j0_over_x2(y, numerics)
    total += tail
    # Radiation condition: the Rayleigh pole lies below the real axis -> - i pi Res.
    total += -1j * np.pi * rayleigh_residue(omega, material) * special.j0(bR * r)
    return total / (2 * np.pi)


def surface_displacement(r, omega, material: ElasticMaterial, load=1.0, numerics=None):
    """Vertical surface displacement amplitude w(r) under a point load P e^{i omega t} (report eqs 10-16).

    Report eqs (10)-(16), with two changes, both exact:

    * the Rayleigh pole is passed on the radiating side: w = PV + (P/2pi)(-i pi) Res,
      Res = residue of beta G J0(beta r) at beta_R (the report's eq 16 is the PV alone);
    * beyond 2 beta_R the static limit (eq 15) is subtracted and the remainder integrated
      to infinity instead of being truncated at 10 beta_R.

    At r = 0 the real part is infinite (returned as +inf), the imaginary part is finite.
    At omega = 0 the Boussinesq result (eq 17) is returned.

    Parameters
    ----------
    r : float or array_like
        Distance from the loading point [m], >= 0.
    omega : float
        Angular frequency [rad/s], a scalar >= 0.
    material : ElasticMaterial
        The half-space material; must be undamped.
    load : float, optional
        Load amplitude P [N]; default 1.
    numerics : HalfSpaceNumerics, optional
        Quadrature settings; default ``HalfSpaceNumerics()``.

    Returns
    -------
    complex or complex ndarray
        Displacement amplitude w(r) [m] in the direction of the load: a complex for scalar ``r``,
        otherwise an array of the shape of ``r``.

    Raises
    ------
    ValueError
        If the material is damped (loss_factor != 0), if any r < 0, or if omega < 0.
    """
    numerics = numerics or HalfSpaceNumerics()
    if material.loss_factor != 0:
        raise ValueError("surface_displacement implements eq (16) for an undamped half-space.")
    r_arr = np.atleast_1d(np.asarray(r, dtype=float))
    bad = r_arr[~(np.isfinite(r_arr) & (r_arr >= 0))]
    if bad.size:
        raise ValueError(f"r = {bad[0]!r} m is not allowed: it must be a finite number >= 0 (valid range [0, inf)).")
    if not (np.isfinite(omega) and omega >= 0):
        raise ValueError(f"omega = {omega!r} rad/s is not allowed: it must be a finite number >= 0 (valid range [0, inf)).")
    if omega == 0:  # Boussinesq, infinite at the load point
        out = np.full(r_arr.shape, np.inf, dtype=complex)
        out[r_arr > 0] = boussinesq(r_arr[r_arr > 0], material, load)
    else:
        out = np.array([_surface_displacement_scalar(ri, omega, material, numerics) for ri in r_arr])
        out = out * load
    return out.reshape(np.shape(r)) if np.ndim(r) else complex(out[0])


def point_receptance_imag(omega, material: ElasticMaterial, numerics=None):
    """Im w0(0): imaginary part of the driving-point receptance of the half-space (report sec. 3).

    Negative for omega > 0 (power flows into the half-space); 0 at omega = 0.
    By dimensional analysis Im w0(0) = -C(nu) omega / (mu c2); it is computed here from the
    integral at each frequency, so that the linearity is a check and not an assumption.

    Parameters
    ----------
    omega : float or array_like
        Angular frequency [rad/s], >= 0.
    material : ElasticMaterial
        The half-space material; must be undamped.
    numerics : HalfSpaceNumerics, optional
        Quadrature settings; default ``HalfSpaceNumerics()``.

    Returns
    -------
    float or ndarray
        Im w0(0) [m/N]: a float for scalar ``omega``, otherwise an array of the shape of ``omega``.

    Raises
    ------
    ValueError
        If any omega < 0, or (for omega > 0) if the material is damped.
    """
    numerics = numerics or HalfSpaceNumerics()
    om = np.atleast_1d(np.asarray(omega, dtype=float))
    bad = om[~(np.isfinite(om) & (om >= 0))]
    if bad.size:
        raise ValueError(f"omega = {bad[0]!r} rad/s is not allowed: it must be a finite number >= 0 (valid range [0, inf)).")
    out = np.array(
        [0.0 if o == 0 else _surface_displacement_scalar(0.0, o, material, numerics).imag for o in om]
    )
    return out.reshape(np.shape(omega)) if np.ndim(omega) else float(out[0])


def radiated_power(omega, material: ElasticMaterial, load=1.0, numerics=None, receptance_imag=None):
    """Time-averaged power radiated into the half-space by a point load (report sec. 3, Fig. 5).

    The power done by the load, -1/2 P^2 omega Im w0(0) (``point_receptance_imag``).

    Parameters
    ----------
    omega : float or array_like
        Angular frequency [rad/s], >= 0.
    material : ElasticMaterial
        The half-space material; must be undamped.
    load : float, optional
        Load amplitude P [N]; default 1.
    numerics : HalfSpaceNumerics, optional
        Quadrature settings; default ``HalfSpaceNumerics()``.
    receptance_imag : float or array_like, optional
        Im w0(0) at ``omega`` [m/N] if already computed (``point_receptance_imag``; its quadrature
        is the whole cost); computed here if not given.

    Returns
    -------
    float or ndarray
        Radiated power [W], shape of ``omega``.

    Raises
    ------
    ValueError
        If any omega < 0, or (for omega > 0) if the material is damped (``point_receptance_imag``).
    """
    om = np.asarray(omega, dtype=float)
    return -0.5 * load**2 * om * _receptance_imag(om, material, numerics, receptance_imag)


def _receptance_imag(omega, material, numerics, given):
    """Im w0(0) [m/N] at ``omega``: ``given`` (checked to have the shape of ``omega``) if not None,
    else point_receptance_imag."""
    if given is None:
        return point_receptance_imag(omega, material, numerics)
    im = np.asarray(given, dtype=float)
    if im.shape != np.shape(omega):
        raise ValueError(f"receptance_imag has shape {im.shape}; it must have the shape of omega, {np.shape(omega)}.")
    return im


def contact_loss_factor(omega, hertz_stiffness, material: ElasticMaterial, numerics=None, receptance_imag=None):
    """Loss factor of the Hertz contact spring, eta_H = -2 k_H Im w0(0) (report sec. 3, Fig. 6).

    The spring k_H (1 + i eta_H) dissipates the power radiated into two half-spaces (wheel
    and rail, same material).  Proportional to frequency.

    Parameters
    ----------
    omega : float or array_like
        Angular frequency [rad/s], >= 0.
    hertz_stiffness : float
        Hertz contact stiffness k_H [N/m], > 0.
    material : ElasticMaterial
        The material of wheel and rail; must be undamped.
    numerics : HalfSpaceNumerics, optional
        Quadrature settings; default ``HalfSpaceNumerics()``.
    receptance_imag : float or array_like, optional
        Im w0(0) at ``omega`` [m/N] if already computed; computed here if not given.

    Returns
    -------
    float or ndarray
        eta_H [-], shape of ``omega``.

    Raises
    ------
    ValueError
        If hertz_stiffness is not finite and > 0, if any omega < 0, or (for omega > 0) if the
        material is damped.
    """
    _check_range("hertz_stiffness [N/m]", hertz_stiffness, 0.0, np.inf)
    return -2.0 * hertz_stiffness * _receptance_imag(omega, material, numerics, receptance_imag)
