"""Timoshenko rail on periodic discrete supports: stationary and moving-load receptances.

Report section 4.2 and its ref. [18]; the derivation is in ``docs/track.md``.

Conventions
-----------
* Time dependence ``exp(+i omega t)``; spatial Fourier transform
  ``W(beta) = int w(x) exp(+i beta x) dx``, ``w(x) = (1/2pi) int W(beta) exp(-i beta x) d beta``.
* Vertical displacement w and forces positive downwards (in the direction of the wheel load).
* Supports (railpad - sleeper mass - ballast) at x = j L, j integer.  Position x in a bay is
  measured from a support.
* Hysteretic damping: a stiffness k becomes k (1 + i eta sign(omega)) (report's choice).
  Viscous damping: k becomes k + i omega c; the rail's E and G become E (1 + i omega tau).
* Units SI throughout: m, kg, s, N, Pa, rad/s, rad/m; receptances in m/N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "Rail",
    "Pad",
    "Sleeper",
    "Ballast",
    "Track",
    "require_positive",
    "require_nonnegative",
    "damped_stiffness",
    "rail_stiffnesses",
    "support_stiffness",
    "support_rotational_stiffness",
    "beam_lattice_sums",
    "lattice_factors",
    "lattice_tails",
    "beam_lattice_sums_excluding",
    "free_beam_receptances",
    "free_receptance",
    "free_receptance_poles",
    "periodic_sum",
    "phased_periodic_sum",
    "free_green",
    "stationary_receptance",
    "continuous_support_receptance",
    "pinned_pinned_frequency",
    "characteristic_frequencies",
]


def require_positive(name: str, value: float) -> None:
    """Refuse a parameter that is not finite and > 0, with the one-line error of the schema.

    Parameters
    ----------
    name : str
        The parameter's configuration key, as the error names it (``track.pad.stiffness``).
    value : float
        The value [in the parameter's own unit].

    Returns
    -------
    None

    Raises
    ------
    ValueError
        ``<name> = <value> is not allowed: it must be > 0 (valid range (0, inf)).``
    """
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} = {value!r} is not allowed: it must be > 0 (valid range (0, inf)).")


def require_nonnegative(name: str, value: float) -> None:
    """Refuse a parameter that is not finite and >= 0, with the one-line error of the schema.

    Parameters
    ----------
    name : str
        The parameter's configuration key, as the error names it (``track.pad.loss_factor``).
    value : float
        The value [in the parameter's own unit].

    Returns
    -------
    None

    Raises
    ------
    ValueError
        ``<name> = <value> is not allowed: it must be >= 0 (valid range [0, inf)).``
    """
    if not (np.isfinite(value) and value >= 0):
        raise ValueError(f"{name} = {value!r} is not allowed: it must be >= 0 (valid range [0, inf)).")


# The stiffest moment spring a pad may have (the schema's maximum of track.pad.rotational_stiffness): 1e9 N m/rad is
# 50 times EI / L of UIC60 on 0.6 m bays (6.4e6 N m^2 / 0.6 m = 1.1e7 N m/rad), so the rail is clamped at the supports
# (the clamped-clamped limit; tests/test_rotational_pad.py).
MAX_ROTATIONAL_STIFFNESS = 1.0e9


@dataclass(frozen=True, slots=True)
class Rail:
    """Timoshenko rail (report Table 1).

    youngs_modulus        : E, Pa, > 0
    shear_modulus         : G, Pa, > 0
    density               : rho, kg/m^3, > 0
    area                  : A, m^2, > 0
    second_moment_of_area : I, m^4, > 0
    shear_coefficient     : kappa, -, > 0
    loss_factor           : eta_R, -, >= 0 (hysteretic model)
    damping_time          : tau_R, s, >= 0 (viscous model: E (1 + i omega tau_R), G likewise)
    """

    youngs_modulus: float
    shear_modulus: float
    density: float
    area: float
    second_moment_of_area: float
    shear_coefficient: float
    loss_factor: float = 0.0
    damping_time: float = 0.0

    def __post_init__(self):
        for name in ("youngs_modulus", "shear_modulus", "density", "area", "second_moment_of_area", "shear_coefficient"):
            require_positive(f"track.rail.{name}", getattr(self, name))
        require_nonnegative("track.rail.loss_factor", self.loss_factor)
        require_nonnegative("track.rail.damping_time", self.damping_time)


@dataclass(frozen=True, slots=True)
class Pad:
    """Railpad under one rail seat: stiffness N/m (> 0), loss_factor - (>= 0), viscous_damping N s/m (>= 0),
    rotational_stiffness k_theta N m/rad (>= 0; 0: the report's pad, a point spring without moment).

    k_theta is a moment spring between the rail's bending rotation psi and the sleeper, taken as held in
    rotation (``support_rotational_stiffness``); it is damped as the pad: loss factor ``loss_factor``
    (hysteretic) or the dashpot ``viscous_damping k_theta / stiffness`` (viscous: the pad's time constant).
    For a uniform (Winkler) pad of length l along the rail, k_theta = stiffness l^2 / 12.
    """

    stiffness: float
    loss_factor: float = 0.0
    viscous_damping: float = 0.0
    rotational_stiffness: float = 0.0

    def __post_init__(self):
        require_positive("track.pad.stiffness", self.stiffness)
        require_nonnegative("track.pad.loss_factor", self.loss_factor)
        require_nonnegative("track.pad.viscous_damping", self.viscous_damping)
        require_nonnegative("track.pad.rotational_stiffness", self.rotational_stiffness)
        if self.rotational_stiffness > MAX_ROTATIONAL_STIFFNESS:
            raise ValueError(f"track.pad.rotational_stiffness = {self.rotational_stiffness!r} N m/rad is not allowed: it must be "
                             f"in [0, {MAX_ROTATIONAL_STIFFNESS:g}] N m/rad (above it the rail is clamped at the supports).")

    def __repr__(self) -> str:
        """As the dataclass's, without rotational_stiffness where it is 0 (the report's pad): the hashes of what a
        spectrum reads (rail.setup.study_files.class_key) stay those of the results computed before the option."""
        extra = f", rotational_stiffness={self.rotational_stiffness!r}" if self.rotational_stiffness else ""
        return f"Pad(stiffness={self.stiffness!r}, loss_factor={self.loss_factor!r}, viscous_damping={self.viscous_damping!r}{extra})"


@dataclass(frozen=True, slots=True)
class Sleeper:
    """Half sleeper: mass kg (>= 0), spacing L m (> 0)."""

    mass: float
    spacing: float

    def __post_init__(self):
        require_nonnegative("track.sleeper.mass", self.mass)
        require_positive("track.sleeper.spacing", self.spacing)


@dataclass(frozen=True, slots=True)
class Ballast:
    """Ballast under half a sleeper: stiffness N/m (> 0), loss_factor - (>= 0), viscous_damping N s/m (>= 0)."""

    stiffness: float
    loss_factor: float = 0.0
    viscous_damping: float = 0.0

    def __post_init__(self):
        require_positive("track.ballast.stiffness", self.stiffness)
        require_nonnegative("track.ballast.loss_factor", self.loss_factor)
        require_nonnegative("track.ballast.viscous_damping", self.viscous_damping)


@dataclass(frozen=True, slots=True)
class Track:
    """One rail on half sleepers (Table 1). damping: 'hysteretic' (loss factors) or 'viscous'."""

    rail: Rail
    pad: Pad
    sleeper: Sleeper
    ballast: Ballast
    damping: str = "hysteretic"

    def __post_init__(self):
        if self.damping not in ("hysteretic", "viscous"):
            raise ValueError(f"track.damping = {self.damping!r} is not allowed: it must be 'hysteretic' or 'viscous'.")

    @property
    def L(self) -> float:
        """Sleeper spacing, m."""
        return self.sleeper.spacing

    @property
    def beta0(self) -> float:
        """Lattice wavenumber 2 pi / L, rad/m."""
        return 2 * np.pi / self.sleeper.spacing


# Smallest rail damping the moving-load wavenumber integrals accept. Without rail damping the
# free waves of the rail put poles on the real wavenumber axis and the integrals of docs/track.md
# are singular (the quadrature then returns numbers, but no converged ones). Down to this value
# the quadrature converges: at eta_R = 1e-4 the force harmonics at rtol 1e-4 and 1e-6 agree to
# 2e-8 of the force fluctuation (the stability study, README).
MIN_RAIL_LOSS_FACTOR = 1.0e-4
MIN_RAIL_DAMPING_TIME = MIN_RAIL_LOSS_FACTOR / (2 * np.pi * 1000.0)  # same loss factor at 1 kHz


def min_harmonics(track: Track, speed: float) -> int:
    """Least number of harmonics K of the sleeper-passing frequency V/L for a moving-load force calculation.

    K V / L must reach the pinned-pinned frequency, K >= f_pp L / V (docs/track.md, "How many
    harmonics").  Below it the track has its resonances and every harmonic is needed; above it the
    force harmonics fall like 1/p^2 (the quasi-static sleeper kink), which the tail model of
    rail.interaction adds.  Measured at 5 m/s: K = 64 (533 Hz) differs from K = 32 by 11 % of the
    force fluctuation, K = 128 (1067 Hz) from K = 64 by 0.6 % (the stability suite).

    Parameters
    ----------
    track : Track
        The track (its pinned-pinned frequency and sleeper spacing L are used).
    speed : float
        Speed V [m/s], > 0.

    Returns
    -------
    int
        K [-].

    Raises
    ------
    ValueError
        If speed is not a finite number > 0.
    """
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed = {np.asarray(speed).tolist()!r} m/s is not allowed in min_harmonics: it must be a finite number > 0.")
    ratio = pinned_pinned_frequency(track) * track.L / speed
    if not np.isfinite(ratio):  # a speed so small (2e-311 m/s) that f_pp L / V overflows
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it is so small that the harmonics needed, f_pp L / V, "
                         "are not a finite number; it must be > 0 and of the order of a train's speed.")
    return int(np.ceil(ratio - 1e-9))


def damping_problem(track: Track) -> str | None:
    """Why the track's rail damping is too small for the moving-load integrals, or None.

    Without rail damping the free waves of the rail put poles on the real wavenumber axis and the
    moving-load integrals of docs/track.md are singular.  They need rail.loss_factor >=
    MIN_RAIL_LOSS_FACTOR (1e-4) with hysteretic damping, or rail.damping_time >= MIN_RAIL_DAMPING_TIME
    (the same loss factor at 1 kHz) with viscous damping.

    Parameters
    ----------
    track : Track
        The track.

    Returns
    -------
    str or None
        A message naming the parameter, its value and the bound; None if the damping is sufficient.
    """
    r = track.rail
    if track.damping == "hysteretic" and not r.loss_factor >= MIN_RAIL_LOSS_FACTOR:
        return (f"track.rail.loss_factor = {r.loss_factor!r} is not allowed: the moving-load wavenumber integrals need "
                f"rail damping (undamped free waves put poles on the real wavenumber axis); it must be >= {MIN_RAIL_LOSS_FACTOR:g}.")
    if track.damping == "viscous" and not r.damping_time >= MIN_RAIL_DAMPING_TIME:
        return (f"track.rail.damping_time = {r.damping_time!r} s is not allowed with track.damping = 'viscous': the moving-load "
                f"wavenumber integrals need rail damping; it must be >= {MIN_RAIL_DAMPING_TIME:.3g} s "
                f"(loss factor {MIN_RAIL_LOSS_FACTOR:g} at 1 kHz).")
    return None


def damped_stiffness(k, eta, c, omega, model: str):
    """Complex stiffness of a damped spring: k (1 + i eta sign(omega)) (hysteretic) or k + i omega c (viscous).

    The damping rule of every support element (pad, ballast, damper; module docstring, Conventions).

    Parameters
    ----------
    k : float
        Stiffness [N/m].
    eta : float
        Loss factor, used by the hysteretic model [-].
    c : float
        Viscous damping coefficient, used by the viscous model [N s/m].
    omega : float or ndarray
        Angular frequency [rad/s].
    model : str
        ``"hysteretic"`` or ``"viscous"`` (``Track.damping``).

    Returns
    -------
    complex ndarray
        The complex stiffness at each omega [N/m].
    """
    omega = np.asarray(omega, dtype=float)
    if model == "hysteretic":
        return k * (1 + 1j * eta * np.sign(omega))
    return k + 1j * omega * c


def rail_stiffnesses(track: Track, omega):
    """Complex bending and shear stiffness (EI, kappa G A) of the rail.

    Both are multiplied by 1 + i eta_R sign(omega) (hysteretic damping) or by 1 + i omega tau_R
    (viscous damping), see the module docstring.

    Parameters
    ----------
    track : Track
        The track (rail properties and damping model).
    omega : float or ndarray
        Angular frequency [rad/s].

    Returns
    -------
    EI : complex or complex ndarray
        Bending stiffness [N m^2], shape of ``omega``.
    kGA : complex or complex ndarray
        Shear stiffness kappa G A [N], shape of ``omega``.
    """
    r = track.rail
    omega = np.asarray(omega, dtype=float)
    if track.damping == "hysteretic":
        f = 1 + 1j * r.loss_factor * np.sign(omega)
    else:
        f = 1 + 1j * omega * r.damping_time
    return r.youngs_modulus * r.second_moment_of_area * f, r.shear_coefficient * r.shear_modulus * r.area * f


def support_stiffness(track: Track, omega):
    """Dynamic stiffness K_s(omega) of one support seen by the rail (docs/track.md).

    Pad k_P in series with the sleeper mass m_S on ballast k_B:
    K_s = k_P (k_B - m_S omega^2) / (k_P + k_B - m_S omega^2), complex stiffnesses.

    Parameters
    ----------
    track : Track
        The track (pad, sleeper, ballast and damping model).
    omega : float or ndarray
        Angular frequency [rad/s].

    Returns
    -------
    complex or complex ndarray
        K_s [N/m], shape of ``omega``.
    """
    omega = np.asarray(omega, dtype=float)
    kp = damped_stiffness(track.pad.stiffness, track.pad.loss_factor, track.pad.viscous_damping, omega, track.damping)
    kb = damped_stiffness(track.ballast.stiffness, track.ballast.loss_factor, track.ballast.viscous_damping, omega, track.damping)
    kbm = kb - track.sleeper.mass * omega**2
    return kp * kbm / (kp + kbm)


def support_rotational_stiffness(track: Track, omega):
    """Dynamic moment stiffness of one pad seen by the rail's bending rotation psi (``Pad.rotational_stiffness``).

    k_theta (1 + i eta_P sign(omega)) (hysteretic) or k_theta + i omega c_P k_theta / k_P (viscous: the pad's
    time constant). The sleeper is held in rotation: its pitch (rotational inertia about the lateral axis,
    about m_S b^2 / 12 with the sleeper's width b = 0.25 m along the rail, on the ballast's rotational stiffness)
    is left out. At 1 kHz the half sleeper's pitch inertia (162 kg: 0.84 kg m^2, 3.3e7 N m/rad at 1 kHz) is
    about 35 times the sourced k_theta (9.45e5 N m/rad), so the series spring differs from k_theta by about 3 %.

    Parameters
    ----------
    track : Track
        The track (its pad and damping model).
    omega : float or ndarray
        Angular frequency [rad/s].

    Returns
    -------
    complex ndarray
        The moment stiffness [N m/rad], shape of ``omega``; 0 where the pad has no rotational stiffness.
    """
    p = track.pad
    c = p.viscous_damping * p.rotational_stiffness / p.stiffness
    return damped_stiffness(p.rotational_stiffness, p.loss_factor, c, np.asarray(omega, dtype=float), track.damping)


def free_beam_receptances(beta, omega, track: Track):
    """Free Timoshenko rail's 2 x 2 receptance from (F, M) to (W, Psi) in the wavenumber domain.

    With D = [[kGA b^2 - rho A w^2, -i b kGA], [i b kGA, EI b^2 + kGA - rho I w^2]] (the dynamic stiffness)
    H = D^-1: H_ww = (EI b^2 + kGA - rho I w^2) / det D (``free_receptance``), H_wM = i b kGA / det D = -H_psiF,
    H_psiM = (kGA b^2 - rho A w^2) / det D (rail.creepage.rail_flexibility.free_beam_matrix holds the same for the head).

    Parameters
    ----------
    beta : float or ndarray
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or ndarray
        Angular frequency [rad/s].
    track : Track
        The track (rail properties and damping model).

    Returns
    -------
    (H_ww, H_wM, H_psiF, H_psiM) : complex ndarrays
        [m^2/N, m/N, m/N, 1/N] per unit wavenumber.
    """
    b = np.asarray(beta, dtype=float)
    w = np.asarray(omega, dtype=float)
    EI, kGA = rail_stiffnesses(track, w)
    r = track.rail
    d11 = kGA * b**2 - r.density * r.area * w**2
    d22 = EI * b**2 + kGA - r.density * r.second_moment_of_area * w**2
    inv = 1.0 / (d11 * d22 - (b * kGA) ** 2)
    return d22 * inv, 1j * b * kGA * inv, -1j * b * kGA * inv, d11 * inv


def lattice_factors(p, beta, L):
    """The closed forms of the lattice sums of 1 / (b^2 - p^2) and b / (b^2 - p^2), b = beta + m 2 pi / L, without
    cancellation.

    With z = exp(i p L) (Im p >= 0) and D = 1 + z^2 - 2 z cos(beta L) (docs/track.md)::

        sum_m 1 / (b^2 - p^2) = (L / 2p) E,  E = (z^2 - 1) / (i D)
        sum_m b / (b^2 - p^2) = L O,         O = z sin(beta L) / D

    D is formed as (z - 1)^2 + 4 z sin^2(beta L / 2) and z - 1, z^2 - 1 by expm1: as written, 1 + z^2 - 2 z cos(beta L)
    loses the digits of D when p L and beta L are both small (near the static point, D ~ (beta L)^2 - (p L)^2 with
    an error of rounding 1), a relative error eps / (beta L)^2 in the sum that the wavenumber integrals near
    beta = 0 magnified as an adaptive rule refined there.

    Parameters
    ----------
    p : complex ndarray
        The pole [rad/m], Im p >= 0; broadcast with ``beta``.
    beta : float or ndarray
        Wavenumber [rad/m].
    L : float
        The period [m].

    Returns
    -------
    E, O : complex ndarray
        [-].
    """
    zm1 = np.expm1(1j * p * L)
    z = 1 + zm1
    den = zm1 * zm1 + 4 * z * np.sin(np.asarray(beta) * L / 2) ** 2
    return np.expm1(2j * p * L) / (1j * den), z * np.sin(np.asarray(beta) * L) / den


def beam_lattice_sums(beta, omega, track: Track):
    """Lattice sums of the free Timoshenko rail's 2 x 2 receptance from (F, M) to (W, Psi), closed form.

    S_rl(beta) = sum_m H_rl(beta + m beta0, omega), with (rail.creepage.rail_flexibility.free_beam_matrix)
    H_ww = (EI b^2 + kGA - rho I w^2) / det, H_wM = i b kGA / det = -H_psiF, H_psiM = (kGA b^2 - rho A w^2) / det.
    det = a (b^2 - s_1)(b^2 - s_2) (``free_receptance_poles``), so each entry is a sum of partial fractions
    over p_j = sqrt(s_j); with z = exp(i p L), C = cos(beta L) (docs/track.md)::

      sum_m 1 / ((beta + m b0)^2 - p^2)          = (L / 2p) (z^2 - 1) / (i (1 + z^2 - 2 z C))
      sum_m (beta + m b0) / ((beta + m b0)^2 - p^2) = L z sin(beta L) / (1 + z^2 - 2 z C)

    (the second summed symmetrically in m; the odd entries decay as 1 / b^3, so their sum converges absolutely).

    Parameters
    ----------
    beta : float or array_like
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or array_like
        Angular frequency [rad/s], != 0.
    track : Track
        The track.

    Returns
    -------
    S_ww, S_wM, S_psiF, S_psiM : complex ndarray
        [m^2/N], [m/N], [m/N], [1/N]: the lattice sums per unit wavenumber (S_ww is ``periodic_sum``).
    """
    beta, omega = np.broadcast_arrays(np.asarray(beta, dtype=float), np.asarray(omega, dtype=float))
    c, p = free_receptance_poles(omega, track)
    EI, kGA = rail_stiffnesses(track, omega)
    rA = track.rail.density * track.rail.area
    a = kGA * EI
    s = p * p
    L = track.L
    S_ww = S_wM = S_pM = 0j
    for j in (0, 1):
        k = 1 - j
        E, O = lattice_factors(p[j], beta, L)
        even = (L / (2 * p[j])) * E
        odd = L * O
        inv = 1.0 / (a * (s[j] - s[k]))
        S_ww = S_ww + c[j] * even
        S_pM = S_pM + (kGA * s[j] - rA * omega**2) * inv * even
        S_wM = S_wM + 1j * kGA * inv * odd
    return S_ww, S_wM, -S_wM, S_pM


def lattice_tails(beta, b0: float, explicit: int):
    """The explicit indices 0 < abs(m) <= ``explicit`` and the rest of the lattice sums of the static powers,
    sum over abs(m) > explicit of 1 / (beta + m b0)^n for n = 2, 3 (summed symmetrically) and 4, by polygamma:
    sum_{k>=0} 1/(z + k)^n = (-1)^n psi^(n-1)(z) / (n - 1)!, z = explicit + 1 +- beta / b0.

    Parameters
    ----------
    beta : ndarray
        Wavenumbers [rad/m], abs(beta) < b0 / 2.
    b0 : float
        The lattice's wavenumber 2 pi / period [rad/m].
    explicit : int
        The terms summed as they are on each side [-].

    Returns
    -------
    m : int ndarray (2 explicit,)
    s2, s3, s4 : ndarray of beta's shape
        [m^2], [m^3], [m^4].
    """
    from scipy import special

    m = np.concatenate([np.arange(-explicit, 0), np.arange(1, explicit + 1)])
    a = np.asarray(beta, dtype=float) / b0
    zp, zm = explicit + 1 + a, explicit + 1 - a  # the tails m > explicit (beta + m b0 = b0 (m + a)) and m < -explicit
    s2 = (special.polygamma(1, zp) + special.polygamma(1, zm)) / b0**2
    s3 = (-special.polygamma(2, zp) + special.polygamma(2, zm)) / (2 * b0**3)  # odd: the negative side's sign
    s4 = (special.polygamma(3, zp) + special.polygamma(3, zm)) / (6 * b0**4)
    return m, s2, s3, s4


def beam_lattice_sums_excluding(beta, omega, track: Track, explicit: int = 40):
    """The lattice sums of ``beam_lattice_sums`` without the m = 0 term, for wavenumbers near the static point.

    There (beta, omega -> 0) H_ww(beta) ~ 1/(EI beta^4), H_wM ~ i/(EI beta^3) and H_psiM ~ 1/(EI beta^2) diverge, and
    the closed form minus the m = 0 term loses the digits of S to the cancellation: an absolute error of the
    rounding of S, eps / (EI beta^4) for S_ww, which the wavenumber integrals near beta = 0 magnify without bound
    as an adaptive rule refines there. Here the sum is formed without the m = 0 term (as
    rail.cell.cell_lattice_sums_excluding does for S_ww on a cell): the free receptances for 0 < abs(m) <= ``explicit``,
    then their static forms (exact at omega = 0: det D = kGA EI b^4), H_ww = 1/(kGA b^2) + 1/(EI b^4),
    H_wM = i/(EI b^3) = -H_psiF, H_psiM = 1/(EI b^2), summed in closed form by polygamma (``lattice_tails``).

    Parameters
    ----------
    beta, omega : ndarray, 1-D, same length
        Wavenumbers [rad/m], abs(beta) < beta0 / 2, and angular frequencies [rad/s] (omega may be 0).
    track : Track
    explicit : int
        The terms summed as they are on each side [-].

    Returns
    -------
    S_ww, S_wM, S_psiF, S_psiM : complex ndarray (len(beta),)
        [m^2/N], [m/N], [m/N], [1/N].
    """
    beta = np.asarray(beta, dtype=float)
    omega = np.asarray(omega, dtype=float)
    b0 = track.beta0
    m, s2, s3, s4 = lattice_tails(beta, b0, explicit)
    Hww, HwM, HpF, HpM = free_beam_receptances(beta[:, None] + m[None, :] * b0, omega[:, None], track)
    EI, kGA = rail_stiffnesses(track, omega)
    S_ww = Hww.sum(1) + s4 / EI + s2 / kGA
    S_wM = HwM.sum(1) + 1j * s3 / EI
    S_pM = HpM.sum(1) + s2 / EI
    return S_ww, S_wM, -S_wM, S_pM


def free_receptance(beta, omega, track: Track):
    """Receptance H(beta, omega) of the free infinite Timoshenko rail in the wavenumber domain (docs/track.md).

    W(beta) = H F for a point force F at x = 0 (transform convention of the module docstring):

    H = (EI beta^2 + kGA - rho I omega^2) /
        (kGA beta^2 (EI beta^2 - rho I omega^2) - rho A omega^2 (EI beta^2 + kGA - rho I omega^2)).

    Parameters
    ----------
    beta : float or ndarray
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or ndarray
        Angular frequency [rad/s].
    track : Track
        The track (rail properties and damping model).

    Returns
    -------
    complex ndarray
        H [m^2/N]: the transform W(beta) [m^2] of the displacement per unit force.
    """
    beta = np.asarray(beta, dtype=float)
    omega = np.asarray(omega, dtype=float)
    EI, kGA = rail_stiffnesses(track, omega)
    rho, A, I = track.rail.density, track.rail.area, track.rail.second_moment_of_area
    b2 = beta**2
    bending = EI * b2  # EI beta^2 and rho I omega^2, each formed once
    inertia = rho * I * omega**2
    num = bending + kGA - inertia
    return num / (kGA * b2 * (bending - inertia) - rho * A * omega**2 * num)


def free_receptance_poles(omega, track: Track):
    """Partial fractions H = sum_j c_j / (beta^2 - s_j), j = 1, 2, of the free-rail receptance (docs/track.md).

    The denominator of H is a quadratic in B = beta^2, a B^2 + b B + c0 with a = kGA EI,
    b = -omega^2 (kGA rho I + rho A EI), c0 = -rho A omega^2 (kGA - rho I omega^2); s_j are its roots.
    p_j = sqrt(s_j) is chosen with Im p_j >= 0 (p_j real > 0 if undamped and propagating).

    Parameters
    ----------
    omega : float or array_like
        Angular frequency [rad/s], != 0.
    track : Track
        The track (rail properties and damping model).

    Returns
    -------
    c : complex ndarray, shape (2,) + shape(omega)
        Residues c_j [1/N] (H [m^2/N] times beta^2 [(rad/m)^2]).
    p : complex ndarray, shape (2,) + shape(omega)
        Pole wavenumbers p_j = sqrt(s_j) [rad/m], Im p_j >= 0.

    Raises
    ------
    ValueError
        If any omega == 0 (the static receptance has a double pole at 0).
    """
    omega = np.asarray(omega, dtype=float)
    if np.any(omega == 0.0):
        raise ValueError("free_receptance_poles needs omega != 0 (the static receptance has a double pole at 0).")
    EI, kGA = rail_stiffnesses(track, omega)
    rho, A, I = track.rail.density, track.rail.area, track.rail.second_moment_of_area
    a = kGA * EI
    b = -(omega**2) * (kGA * rho * I + rho * A * EI)
    c0 = -rho * A * omega**2 * (kGA - rho * I * omega**2)
    disc = np.sqrt(b * b - 4 * a * c0 + 0j)
    # numerically stable roots of the quadratic (no cancellation between -b and disc)
    q = -0.5 * (b + np.where(np.real(np.conj(b) * disc) >= 0, 1, -1) * disc)
    s = np.stack([q / a, c0 / q])
    numer = EI * s + kGA - rho * I * omega**2
    c = np.stack([numer[0] / (a * (s[0] - s[1])), numer[1] / (a * (s[1] - s[0]))])
    p = np.sqrt(s + 0j)
    p = np.where(p.imag < 0, -p, p)
    p = np.where((p.imag == 0) & (p.real < 0), -p, p)
    return c, p


def periodic_sum(beta, omega, track: Track):
    """Lattice sum S(beta, omega) = sum_m H(beta + m beta0, omega) in closed form (docs/track.md).

    sum_m 1/((beta + m beta0)^2 - p^2) = (L / (2p)) sin(pL) / (cos(pL) - cos(beta L)), evaluated as
    (L / (2p)) (z^2 - 1) / (i (1 + z^2 - 2 z cos(beta L))), z = exp(i p L), abs(z) <= 1 (``lattice_factors``).

    Parameters
    ----------
    beta : float or array_like
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or array_like
        Angular frequency [rad/s], != 0.
    track : Track
        The track.

    Returns
    -------
    complex ndarray
        S [m^2/N], broadcast shape of ``beta`` and ``omega``.

    Raises
    ------
    ValueError
        If any omega == 0 (from ``free_receptance_poles``).
    """
    beta, omega = np.broadcast_arrays(np.asarray(beta, dtype=float), np.asarray(omega, dtype=float))
    c, p = free_receptance_poles(omega, track)
    L = track.L
    out = 0j
    for cj, pj in zip(c, p):
        out = out + cj * (L / (2 * pj)) * lattice_factors(pj, beta, L)[0]
    return out


def phased_periodic_sum(kappa, x, omega, track: Track):
    """Phased lattice sum S_x(kappa) = sum_m H(kappa + m beta0, omega) exp(i (kappa + m beta0) x), closed form.

    For 0 < x < L each partial fraction gives (docs/track.md)::

      sum_m e^{i(kappa+m beta0)x}/(kappa+m beta0-p) =  i L e^{ipx} / (1 - e^{i(p-kappa)L})
      sum_m e^{i(kappa+m beta0)x}/(kappa+m beta0+p) = -i L e^{ip(L-x)} e^{i kappa L} / (1 - e^{i(p+kappa)L})

    x = 0 takes the mean of the limits from both sides (the sum of H itself is continuous);
    other x follow from S_{x+L} = e^{i kappa L} S_x.

    Parameters
    ----------
    kappa : float or array_like
        Wavenumber [rad/m].
    x : float
        Position [m], any real, measured from a support.
    omega : float
        Angular frequency [rad/s], a scalar != 0.
    track : Track
        The track.

    Returns
    -------
    complex ndarray
        S_x(kappa) [m^2/N], shape of ``kappa``.

    Raises
    ------
    ValueError
        If omega == 0 (from ``free_receptance_poles``).
    """
    kappa = np.asarray(kappa, dtype=float)
    L = track.L
    j = np.floor(x / L)
    xr = x - j * L
    c, p = free_receptance_poles(omega, track)
    eKL = np.exp(1j * kappa * L)

    def inside(xx):
        out = 0j
        for cj, pj in zip(c, p):
            t1 = 1j * L * np.exp(1j * pj * xx) / (1 - np.exp(1j * (pj - kappa) * L))
            t2 = -1j * L * np.exp(1j * pj * (L - xx)) * eKL / (1 - np.exp(1j * (pj + kappa) * L))
            out = out + cj / (2 * pj) * (t1 - t2)
        return out

    if xr == 0.0:
        val = 0.5 * (inside(0.0) + inside(L) / eKL)
    else:
        val = inside(xr)
    return val * np.exp(1j * kappa * L * j)


def free_green(x, omega, track: Track):
    """Displacement of the free infinite rail at x under a unit harmonic force at 0 (docs/track.md).

    Residues of H: closing the contour in the half-plane where exp(-i beta x) decays picks the
    pole -p_j for x > 0, so w(x) = sum_j c_j (i / (2 p_j)) exp(i p_j abs(x)), Im p_j > 0 (decaying).

    Parameters
    ----------
    x : float or array_like
        Position relative to the force [m].
    omega : float
        Angular frequency [rad/s], != 0.
    track : Track
        The track.

    Returns
    -------
    complex or complex ndarray
        Free-rail Green's function G(x) [m/N], shape of ``x``.

    Raises
    ------
    ValueError
        If omega == 0 (from ``free_receptance_poles``).
    """
    c, p = free_receptance_poles(omega, track)
    ax = np.abs(np.asarray(x, dtype=float))
    return sum(cj * (1j / (2 * pj)) * np.exp(1j * pj * ax) for cj, pj in zip(c, p))


def stationary_receptance(x, x0, omega, track: Track, rtol: float = 1e-7, return_error=False):
    """Receptance alpha(x, x0; omega) of the periodically supported rail (report sec. 4.2, ref. [18]).

    Harmonic unit force at x0, displacement at x (any positions), omega != 0::

      alpha = G(x - x0) - (K_s / 2pi) int_BZ S_{x0}(kappa) S_x(-kappa) / (L + K_s S(kappa)) d kappa

    over the Brillouin zone abs(kappa) <= beta0 / 2, with G the free-rail Green's function, S the
    periodic sum and S_x the phased sum (docs/track.md, "Stationary harmonic load at x_0").  The zone
    integrand has peaks at the Floquet waves of the track, as narrow as the damping allows; it is
    integrated adaptively (rail.quadrature) to ``rtol``.

    Parameters
    ----------
    x : float or array_like
        Response position [m], measured from a support; broadcast with ``x0``.
    x0 : float or array_like
        Force position [m], measured from a support.
    omega : float
        Angular frequency [rad/s], a finite scalar != 0.
    track : Track
        The track.
    rtol : float, optional
        Relative tolerance of the adaptive zone quadrature [-]; default 1e-7.
    return_error : bool, optional
        If true, return the estimated absolute quadrature error too; default False.

    Returns
    -------
    alpha : complex ndarray
        Receptance [m/N], broadcast shape of ``x`` and ``x0``.
    error : ndarray
        Estimated absolute error of ``alpha`` [m/N], same shape; returned only with ``return_error``.

    Raises
    ------
    ValueError
        If omega is not a finite scalar != 0.
    """
    from .quadrature import adaptive_panels

    if track.pad.rotational_stiffness > 0:
        raise ValueError(f"track.pad.rotational_stiffness = {track.pad.rotational_stiffness!r} N m/rad is not carried by the "
                         "stationary receptance (rail.track.stationary_receptance: noise, decay, characterisation): only the "
                         "moving-load tables and the head's tables (rail.moving, rail.creepage.rail_flexibility) hold the pads' moment springs; "
                         "set it to 0 for these results.")
    if np.ndim(omega) != 0 or not (np.isfinite(omega) and omega != 0):
        raise ValueError(f"omega = {np.asarray(omega).tolist()!r} rad/s is not allowed in the stationary receptance: it must be a finite scalar != 0 "
                         "(the static receptance has a double pole at 0).")
    x = np.asarray(x, dtype=float)
    x0 = np.asarray(x0, dtype=float)
    x, x0 = np.broadcast_arrays(x, x0)
    xs, x0s = x.ravel(), x0.ravel()
    Ks = complex(support_stiffness(track, omega))
    L = track.L

    def integrand(kap):
        S = periodic_sum(kap, omega, track)
        cols = [
            phased_periodic_sum(kap, float(b), omega, track) * phased_periodic_sum(-kap, float(a), omega, track)
            for a, b in zip(xs, x0s)
        ]
        return np.stack(cols, axis=1) / (L + Ks * S)[:, None]

    b0 = track.beta0
    q = adaptive_panels(integrand, np.linspace(-b0 / 2, b0 / 2, 9), rtol=rtol)
    alpha = (free_green(xs - x0s, omega, track) - Ks / (2 * np.pi) * q.integral).reshape(x.shape)
    if return_error:
        return alpha, (abs(Ks) / (2 * np.pi) * q.error).reshape(x.shape)
    return alpha


def continuous_support_receptance(omega, track: Track):
    """Point receptance of the rail on a continuous foundation of stiffness K_s(omega) / L per metre.

    Residues of 1 / (1/H + k_f), k_f = K_s / L: the denominator is again a quadratic in beta^2.

    Parameters
    ----------
    omega : float
        Angular frequency [rad/s].
    track : Track
        The track (rail, supports and sleeper spacing L).

    Returns
    -------
    complex
        Receptance at the load point [m/N].
    """
    omega = float(omega)
    EI, kGA = rail_stiffnesses(track, omega)
    rho, A, I = track.rail.density, track.rail.area, track.rail.second_moment_of_area
    kf = support_stiffness(track, omega) / track.L
    # 1/H + kf = [D(B) + kf N(B)] / N(B); D = a B^2 + b B + c0, N = EI B + kGA - rho I w^2
    a = kGA * EI
    b = -(omega**2) * (kGA * rho * I + rho * A * EI) + kf * EI
    n0 = kGA - rho * I * omega**2
    c0 = -rho * A * omega**2 * n0 + kf * n0
    disc = np.sqrt(b * b - 4 * a * c0 + 0j)
    s = np.array([(-b + disc) / (2 * a), (-b - disc) / (2 * a)])
    numer = EI * s + n0
    c = np.array([numer[0] / (a * (s[0] - s[1])), numer[1] / (a * (s[1] - s[0]))])
    p = np.sqrt(s + 0j)
    p = np.where(p.imag < 0, -p, p)
    return complex(np.sum(c * (1j / (2 * p))))


def pinned_pinned_frequency(track: Track) -> float:
    """First pinned-pinned frequency of the rail.

    Lowest bending mode of a simply supported, undamped Timoshenko beam of span L: with k = pi / L,
    the smaller root w^2 of the frequency equation for mode number 1::

      (rho I rho A / kGA) w^4 - (rho A + rho I k^2 + rho A EI k^2 / kGA) w^2 + EI k^4 = 0.

    Parameters
    ----------
    track : Track
        The track (rail properties and sleeper spacing L).

    Returns
    -------
    float
        Pinned-pinned frequency [Hz].
    """
    r = track.rail
    EI = r.youngs_modulus * r.second_moment_of_area
    kGA = r.shear_coefficient * r.shear_modulus * r.area
    rA, rI = r.density * r.area, r.density * r.second_moment_of_area
    k = np.pi / track.L
    a = rI * rA / kGA
    b = -(rA + rI * k**2 + rA * EI * k**2 / kGA)
    c = EI * k**4
    w2 = (-b - np.sqrt(b * b - 4 * a * c)) / (2 * a)
    return float(np.sqrt(w2) / (2 * np.pi))


def characteristic_frequencies(track: Track, f_min=20.0, f_max=3000.0, points=600) -> dict[str, float]:
    """Characteristic frequencies of the track, identified from its stationary point receptance.

    abs(alpha) (``stationary_receptance`` at rtol 1e-4) is computed above a sleeper and at mid-span on
    ``points`` log-spaced frequencies from f_min to f_max.  Each maximum is refined by a parabola
    (in log abs(alpha) against log f) through the three grid points around it.

    Parameters
    ----------
    track : Track
        The track.
    f_min : float, optional
        Lowest frequency of the scan [Hz]; default 20.
    f_max : float, optional
        Highest frequency of the scan [Hz]; default 3000.
    points : int, optional
        Number of frequencies in the scan [-]; default 600.

    Returns
    -------
    dict of str to float
        Frequencies [Hz]; NaN where the maximum is not found in the scan.

        track_on_ballast
            First maximum of abs(alpha) above a sleeper (track mass on the ballast).
        out_of_phase
            Second maximum of abs(alpha) above a sleeper (rail and sleepers out of phase).
        pinned_pinned
            Maximum of abs(alpha) at mid-span above the out-of-phase resonance.
    """
    f = np.geomspace(f_min, f_max, points)
    om = 2 * np.pi * f
    a_s = np.abs([stationary_receptance(0.0, 0.0, o, track, 1e-4) for o in om])
    a_m = np.abs([stationary_receptance(track.L / 2, track.L / 2, o, track, 1e-4) for o in om])

    def peaks(a):
        i = np.where((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:]))[0] + 1
        out = []
        for j in i:
            y0, y1, y2 = np.log(a[j - 1 : j + 2])
            d = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
            out.append(float(np.exp(np.log(f[j]) + d * np.log(f[j + 1] / f[j]))))
        return out

    ps = peaks(a_s)
    pm = [p for p in peaks(a_m) if len(ps) > 1 and p > ps[1]]
    return {
        "track_on_ballast": ps[0] if ps else float("nan"),
        "out_of_phase": ps[1] if len(ps) > 1 else float("nan"),
        "pinned_pinned": pm[0] if pm else float("nan"),
    }
