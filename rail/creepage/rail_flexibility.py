"""The rail head's longitudinal displacement at the moving contact: the rail's share of u_bar in
eq 26 (report sec. 4.3: zero only for "a beam with no longitudinal flexibility"; issue 43).

Two parts, each a moving-load (Bloch) problem on periodic discrete supports, written as the
vertical track's (rail.moving, docs/track.md):

* **The axial rod** (E A, rho A; the rail's loss factor or damping time as for bending) on the
  pads' longitudinal (shear) springs, one per support, k_x (1 + i eta_x sign(omega)) (hysteretic)
  or k_x + i omega c_x (viscous); the sleeper is held longitudinally (the ballast's longitudinal
  stiffness in series is left out). u_n is the neutral axis' longitudinal displacement.
* **The head's motion from the bending rotation**: the Timoshenko rail (w, psi) of rail.track on the
  vertical supports K_s(omega). A longitudinal force F_x on the running surface, at the head height
  e above the neutral axis, is an axial force F_x and a moment e F_x (conjugate to psi); the head
  moves by u_head = u_n + e psi. So the vertical force P moves the head too (the cross receptance
  psi / P): the vertical dynamics move the contact longitudinally even at constant traction.

The pads' rotational stiffness (Pad.rotational_stiffness, a moment spring on psi at every support, the
sleeper held in rotation) enters the beam's tables when it is > 0 (_beam_nodes_rotational); the coupling of
the rod to the bending through the pads (the pad acts on the rail foot, e_f below the neutral axis) is left out.

Conventions
-----------
* Time exp(+i omega t), W(beta) = int w(x) exp(+i beta x) dx, as rail.track; x along the rail (the
  direction of travel), supports at x = j L.
* w and P positive downwards (rail.track). psi is the section's rotation with psi = dw/dx in the
  Euler-Bernoulli limit (the top of a section at x > 0 under a downward load moves towards the
  load: u_head = e psi < 0). The issue text's u = -e psi measures psi the other way round (the
  rotation about the lateral axis with z upwards); the physics is the same.
* Longitudinal forces and displacements positive in +x. The rail's u_head is driven by the force on
  the rail, -Q, where Q is the tangential force on the wheel of rail.creepage.modes (in +x, the
  traction of a driving wheel). With u_bar = u_wheel - u_rail (rail.creepage.modes) the rail adds

      u_bar_rail = -u_head(-Q, P) = A_Q Q - A_P P,

  with A_Q = A_rod + e^2 A_psiM the head's longitudinal receptance to a longitudinal force on the
  head and A_P = e A_psiF its longitudinal displacement per unit vertical force: the rail's
  longitudinal compliance acts in series with the wheelset's (same sign in u_bar).
* The slip sees the rail's material velocity at the contact, dU/dt at fixed x, not the rate of the head's
  displacement following the contact: dU/dt = d u_head(V t, t)/dt - V eps_head, eps_head = e dpsi/dx the
  head's longitudinal strain at the contact. So u_bar_rail = A_Q Q - A_P P + V int E_P P dt, with E_P the
  strain per unit vertical force. The strain's mean (-2.4e-4 under 100 kN on the default track: the head is
  compressed under the wheel) is a steady creepage, taken as part of contact.creepage (the creepage the
  contact sees) and left out; its variation over the bay is kept. The strain the tangential force makes at
  its own point (a jump of u_n' and psi' across the load) is the contact's local deformation and is left
  out.

Free-rail matrices (beam: from (F, M) to (W, Psi); D the inverse)::

    D = [[kGA b^2 - rho A w^2,  -i b kGA], [i b kGA,  EI b^2 + kGA - rho I w^2]],
    H_ww = (EI b^2 + kGA - rho I w^2) / det D,  H_wM = i b kGA / det D,
    H_psiF = -i b kGA / det D,  H_psiM = (kGA b^2 - rho A w^2) / det D;
    rod: H_u = 1 / (EA b^2 - rho A w^2).

Moving load F exp(i Omega t) at x = V t, response at the load (derivation as docs/track.md, with
the response r, the load l and the supported variable s, w or u_n)::

    a_n(Omega) = delta_n0 / 2pi int H_rl(b, w) db
                 - 1 / 2pi int H_sl(b, w) H_rs(b - n b0, w) / (L / K(w) + S(b, w)) db,  w = Omega + b V,

S(b, w) = sum_m H_ss(b + m b0, w), closed form (rail.track.periodic_sum for the beam; the rod's own,
rod_lattice_sum). For a passage over a period of N bays the harmonics (k + nu) Omega_0,
nu = r / N, form one table A[p, k] = a_{p-k}((k + nu) Omega_0) per class (head_table), one Gram
product over a single adaptive wavenumber rule (rail.quadrature), as rail.moving does.

References
----------
Sheng, Thompson & Jones, report sec. 4.3 (eq 26) and 6.1. The moving-load formula: the report's
ref. [18] and docs/track.md. UIC60 (60E1, EN 13674-1) section moduli for the head height.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..quadrature import adaptive_panels
from ..track import (Track, beam_lattice_sums_excluding, damped_stiffness, damping_problem, lattice_factors, lattice_tails,
                     periodic_sum, rail_stiffnesses, support_stiffness)

__all__ = ["RailHead", "HeadTable", "HeadOperator", "free_beam_matrix", "rod_receptance", "rod_lattice_sum",
           "longitudinal_support_stiffness", "moving_head_matrix", "head_table", "head_operator",
           "smeared_rod_receptance", "smeared_rotation_receptance", "DEFAULT_HEAD_HEIGHT",
           "DEFAULT_LONGITUDINAL_STIFFNESS", "MIN_LONGITUDINAL_STIFFNESS"]

# UIC60 (60E1): I_y = 3038 cm^4 and the section modulus of the head 333.6 cm^3 (EN 13674-1) give the
# running surface I / W = 91.1 mm above the neutral axis (and the foot I / W_foot = 3038 / 375.5 =
# 80.9 mm below it: 172 mm together, the rail's height).
DEFAULT_HEAD_HEIGHT = 0.0911
# A studded elastomer pad of 150 x 180 mm, 10 mm thick, shear modulus about 4 MPa: k_x = G A / t
# = 4e6 x 0.027 / 0.01 = 1.1e7 N/m; the clips' friction and the sleeper in the ballast are left out.
DEFAULT_LONGITUDINAL_STIFFNESS = 1.0e7
# The least k_x (the schema's minimum of track.pad.longitudinal_stiffness): the softest resilient pad sheared,
# G about 0.5 MPa over 180 x 150 x 15 mm: G A / t = 0.9e6 N/m; below it the clips' friction and the sleeper in the
# ballast, which the model leaves out, restrain the rail instead of the pad. The rail's static longitudinal
# displacement under the traction Q, Q / (2 sqrt(E A k_x / L)), grows without bound as k_x -> 0 (0.3 mm under
# 30 kN at 1e6 N/m on UIC60 with 0.6 m bays, 0.3 m at 1 N/m). Measured (issue 57, 40 m/s, 15 contact nodes,
# 36 harmonics): 1e7 runs; at 1e6 the coupled u_bar did not settle and the run stopped saying so; at 1e5 N/m and
# below the moving rod's wavenumber rule met omega = 0 exactly (a 0 / 0 in rod_lattice_sum) and the march
# failed with a non-finite u_bar after 80-170 s.
MIN_LONGITUDINAL_STIFFNESS = 1.0e6


@dataclass(frozen=True)
class RailHead:
    """The rail head's longitudinal flexibility at the contact (module docstring), SI units.

    Attributes
    ----------
    track : rail.track.Track (rail, vertical supports, sleeper spacing L, damping model)
    longitudinal_stiffness : k_x, the pad's longitudinal (shear) stiffness per support [N/m],
        in [MIN_LONGITUDINAL_STIFFNESS, 1e12]
    longitudinal_loss_factor : eta_x [-], >= 0 (hysteretic model)
    longitudinal_viscous_damping : c_x [N s/m], >= 0 (viscous model)
    head_height : e, the running surface above the neutral axis [m], in [0, 0.3]
    bending : whether the head's motion from the bending rotation is included (False: the rod alone)
    """

    track: Track
    longitudinal_stiffness: float = DEFAULT_LONGITUDINAL_STIFFNESS
    longitudinal_loss_factor: float = 0.25
    longitudinal_viscous_damping: float = 0.0
    head_height: float = DEFAULT_HEAD_HEIGHT
    bending: bool = True

    def __post_init__(self):
        if not isinstance(self.track, Track):
            raise TypeError(f"RailHead.track must be a rail.track.Track, not {type(self.track).__name__}.")
        k = self.longitudinal_stiffness
        if not (isinstance(k, (int, float)) and math.isfinite(k) and MIN_LONGITUDINAL_STIFFNESS <= k <= 1e12):
            raise ValueError(f"track.pad.longitudinal_stiffness = {k!r} N/m is not allowed: it must be a finite "
                             f"number in [{MIN_LONGITUDINAL_STIFFNESS:g}, 1e12] N/m (the softest resilient pad sheared "
                             "and up).")
        for name, v in (("track.pad.longitudinal_loss_factor", self.longitudinal_loss_factor),
                        ("track.pad.longitudinal_viscous_damping", self.longitudinal_viscous_damping)):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} = {v!r} is not allowed: it must be a finite number >= 0 (valid range [0, inf)).")
        e = self.head_height
        if not (isinstance(e, (int, float)) and math.isfinite(e) and 0 <= e <= 0.3):
            raise ValueError(f"track.rail.head_height = {e!r} m is not allowed: it must be a finite number in [0, 0.3].")
        if (problem := damping_problem(self.track)) is not None:
            raise ValueError(problem)

    @property
    def label(self) -> str:
        """What the model holds, for results and messages."""
        part = "rod on the pads' shear springs" + (f" and the head's bending rotation (e = {self.head_height * 1e3:.1f} mm)"
                                                   if self.bending else "")
        return f"rail's longitudinal flexibility ({part}, k_x = {self.longitudinal_stiffness:.3g} N/m per support)"


def free_beam_matrix(beta, omega, track: Track):
    """Free Timoshenko rail from (F, M) to (W, Psi) in the wavenumber domain (module docstring).

    Parameters
    ----------
    beta : float or ndarray
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or ndarray
        Angular frequency [rad/s].
    track : Track

    Returns
    -------
    (H_ww, H_wM, H_psiF, H_psiM, inv_det) : complex ndarrays
        [m^2/N, m/N, m/N, 1/N] per unit wavenumber, and 1 / det D = H_psiM H_ww - H_wM H_psiF.
    """
    b = np.asarray(beta, dtype=float)
    w = np.asarray(omega, dtype=float)
    EI, kGA = rail_stiffnesses(track, w)
    r = track.rail
    rA, rI = r.density * r.area, r.density * r.second_moment_of_area
    d11 = kGA * b**2 - rA * w**2
    d22 = EI * b**2 + kGA - rI * w**2
    det = d11 * d22 - (b * kGA) ** 2
    inv = 1.0 / det
    return d22 * inv, 1j * b * kGA * inv, -1j * b * kGA * inv, d11 * inv, inv


def _rod_EA(track: Track, omega):
    """Complex axial stiffness E A (1 + i eta_R sign(omega)) or E A (1 + i omega tau_R) [N]."""
    r = track.rail
    w = np.asarray(omega, dtype=float)
    f = 1 + 1j * r.loss_factor * np.sign(w) if track.damping == "hysteretic" else 1 + 1j * w * r.damping_time
    return r.youngs_modulus * r.area * f


def rod_receptance(beta, omega, track: Track):
    """H_u = 1 / (EA beta^2 - rho A omega^2) of the free rod (module docstring).

    Parameters
    ----------
    beta : float or ndarray
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or ndarray
        Angular frequency [rad/s].
    track : Track

    Returns
    -------
    complex ndarray
        H_u [m^2/N].
    """
    b = np.asarray(beta, dtype=float)
    w = np.asarray(omega, dtype=float)
    return 1.0 / (_rod_EA(track, w) * b**2 - track.rail.density * track.rail.area * w**2)


def rod_lattice_sum(beta, omega, track: Track):
    """S_u(beta, omega) = sum_m H_u(beta + m beta0, omega) in closed form [m^2/N].

    sum_m 1 / ((beta + m b0)^2 - p^2) = (L / 2p) (z^2 - 1) / (i (1 + z^2 - 2 z cos(beta L))), z = exp(i p L),
    with p^2 = rho A omega^2 / EA, Im p >= 0 (as rail.track.periodic_sum).

    Parameters
    ----------
    beta : float or ndarray
        Wavenumber [rad/m]; broadcast with ``omega``.
    omega : float or ndarray
        Angular frequency [rad/s], != 0.
    track : Track

    Returns
    -------
    complex ndarray
        S_u [m^2/N].
    """
    b, w = np.broadcast_arrays(np.asarray(beta, dtype=float), np.asarray(omega, dtype=float))
    EA = _rod_EA(track, w)
    p = np.sqrt(track.rail.density * track.rail.area * w**2 / EA + 0j)
    p = np.where(p.imag < 0, -p, p)
    L = track.L
    return (L / (2 * p)) * lattice_factors(p, b, L)[0] / EA


def rod_lattice_sum_excluding(beta, omega, track: Track, explicit: int = 40):
    """S_u(beta, omega) without the m = 0 term, for wavenumbers near the static point [m^2/N].

    There (beta, omega -> 0) H_u(beta) ~ 1 / (EA beta^2) diverges and ``rod_lattice_sum`` minus it loses the
    digits of S_u to the cancellation (an error eps / (EA beta^2), which the wavenumber integral near beta = 0
    magnifies as an adaptive rule refines there). Formed without it: H_u for 0 < abs(m) <= ``explicit``, then the
    static 1 / (EA q^2) (exact at omega = 0) summed by polygamma, as rail.track.beam_lattice_sums_excluding.

    Parameters
    ----------
    beta, omega : ndarray, 1-D, same length
        Wavenumbers [rad/m], abs(beta) < beta0 / 2, and angular frequencies [rad/s] (omega may be 0).
    track : Track
    explicit : int
        The terms summed as they are on each side [-].

    Returns
    -------
    complex ndarray (len(beta),)
        [m^2/N].
    """
    beta = np.asarray(beta, dtype=float)
    omega = np.asarray(omega, dtype=float)
    b0 = track.beta0
    m, s2, _, _ = lattice_tails(beta, b0, explicit)
    H = rod_receptance(beta[:, None] + m[None, :] * b0, omega[:, None], track)
    return H.sum(1) + s2 / _rod_EA(track, omega)


def longitudinal_support_stiffness(head: RailHead, omega):
    """The pad's longitudinal spring (the sleeper held): k_x (1 + i eta_x sign(omega)) or k_x + i omega c_x.

    Parameters
    ----------
    head : RailHead
    omega : float or ndarray
        Angular frequency [rad/s].

    Returns
    -------
    complex ndarray
        The complex stiffness [N/m] (Track.damping's model).
    """
    return damped_stiffness(head.longitudinal_stiffness, head.longitudinal_loss_factor, head.longitudinal_viscous_damping,
                            np.asarray(omega, dtype=float), head.track.damping)


def smeared_rod_receptance(head: RailHead, Omega: float, speed: float = 0.0) -> complex:
    """u_n at a load moving at V on the rod on a continuous foundation k_x / L per metre [m/N], closed form.

    The integrand 1 / (EA b^2 - rho A w^2 + k_f(w)), w = Omega + b V, is a quadratic in b with the
    viscous model (k_f = (k_x + i w c_x) / L and EA (1 + i w tau_R) taken at w = Omega: exact for
    tau_R = 0) or at V = 0 (any model): residues, (1 / 2pi) int = i / (a (b_1 - b_2)) with b_1 in the upper
    half-plane.

    Parameters
    ----------
    head : RailHead
    Omega : float
        The load's frequency [rad/s] (!= 0 at V = 0).
    speed : float, optional
        V [m/s], >= 0; V > 0 needs track.damping = 'viscous'.

    Returns
    -------
    complex
        u_n at the load per unit longitudinal force [m/N].
    """
    t = head.track
    rA, L = t.rail.density * t.rail.area, t.L
    EA = complex(_rod_EA(t, Omega))
    if speed == 0.0:
        kf = complex(longitudinal_support_stiffness(head, Omega)) / L
        lam = np.sqrt((kf - rA * Omega**2) / EA + 0j)
        lam = lam if lam.real > 0 else -lam
        return complex(1.0 / (2 * EA * lam))
    if t.damping != "viscous":
        raise ValueError("smeared_rod_receptance at V > 0 needs track.damping = 'viscous' (a polynomial integrand).")
    kx, cx = head.longitudinal_stiffness, head.longitudinal_viscous_damping
    V = speed
    a = EA - rA * V**2
    b1 = -2 * rA * Omega * V + 1j * cx * V / L
    c = -rA * Omega**2 + (kx + 1j * Omega * cx) / L
    disc = np.sqrt(b1 * b1 - 4 * a * c + 0j)
    r1, r2 = (-b1 + disc) / (2 * a), (-b1 - disc) / (2 * a)
    up, lo = (r1, r2) if r1.imag > 0 else (r2, r1)
    return complex(1j / (a * (up - lo)))


def smeared_rotation_receptance(track: Track, omega: float) -> complex:
    """psi at a stationary moment on the Timoshenko rail on a continuous foundation K_s / L [rad/(N m)].

    (1 / 2pi) int (kGA b^2 - rho A w^2 + k_f) / (det D + k_f (EI b^2 + kGA - rho I w^2)) db by residues: the
    denominator is a quadratic in b^2 (a b^4 + b' b^2 + c0), so the integral is sum_j n(s_j) / (a (s_j - s_k))
    i / (2 p_j), p_j = sqrt(s_j), Im p_j > 0.

    Parameters
    ----------
    track : Track
    omega : float
        Angular frequency [rad/s], != 0.

    Returns
    -------
    complex
        psi per unit moment [rad/(N m)].
    """
    EI, kGA = rail_stiffnesses(track, omega)
    r = track.rail
    rA, rI = r.density * r.area, r.density * r.second_moment_of_area
    kf = complex(support_stiffness(track, omega)) / track.L
    n0 = kGA - rI * omega**2
    a = kGA * EI
    bq = -(omega**2) * (kGA * rI + rA * EI) + kf * EI
    c0 = -rA * omega**2 * n0 + kf * n0
    disc = np.sqrt(bq * bq - 4 * a * c0 + 0j)
    s = np.array([(-bq + disc) / (2 * a), (-bq - disc) / (2 * a)])
    num = kGA * s - rA * omega**2 + kf
    c = np.array([num[0] / (a * (s[0] - s[1])), num[1] / (a * (s[1] - s[0]))])
    p = np.sqrt(s + 0j)
    p = np.where(p.imag < 0, -p, p)
    return complex(np.sum(c * 1j / (2 * p)))


# --------------------------------------------------------------------------------------------------
# the moving-load matrices


def _beam_nodes(beta, Omega, V, js, track: Track, static, want_wM=False):
    """Integrand tables of the beam at nodes beta for the columns js: Y = 1 / (L / K_s + S), the row
    factors H_psiF(beta - p b0), the column factors H_ww / H_wM(beta - k b0) and the diagonals of
    psi/F and psi/M (and w/M) in the combined form near the static point (module docstring)."""
    om = Omega + beta * V
    b = beta[:, None] - js[None, :] * track.beta0
    Hww, HwM, HpF, HpM, inv = free_beam_matrix(b, om[:, None], track)
    S = periodic_sum(beta, om, track)
    c = track.L / support_stiffness(track, om)
    Y = 1.0 / (c + S)
    dF = HpF - Hww * HpF * Y[:, None]
    dM = HpM - HwM * HpF * Y[:, None]
    dW = HwM - HwM * Hww * Y[:, None] if want_wM else None
    dx = -1j * b  # d/dx of a response at beta - j b0 (W = int w exp(+i beta x) dx)
    if static is not None:
        near = np.abs(beta) < track.beta0 / 2
        if near.any():
            k0 = int(np.where(js == static)[0][0])
            Sp = beam_lattice_sums_excluding(beta[near], om[near], track)[0]  # S without the divergent m = 0 term
            cs = c[near] + Sp
            dF[near, k0] = HpF[near, k0] * cs * Y[near]
            dM[near, k0] = (HpM[near, k0] * cs + inv[near, k0]) * Y[near]
            if want_wM:
                dW[near, k0] = HwM[near, k0] * cs * Y[near]
    return Y, HpF, Hww, HwM, dF, dM, dW, dx


def _beam_nodes_rotational(beta, Omega, V, js, track: Track, static):
    """The beam's integrand tables with the pads' moment springs (Pad.rotational_stiffness > 0): each support
    holds the rail by a force on w and a moment on psi, so the scalar 1 / (L / K_s + S) becomes the 2 x 2
    Y = (C + S)^-1, C = diag(L / K_s, L / k_theta), S the lattice sum of the 2 x 2 free receptance
    (rail.track.beam_lattice_sums); a load l at the contact reaches the supports as v_l = (H_wl, H_psil) and a
    support's (force, moment) the contact's response r as u_r = (H_rF, H_rM). Near the static point, with
    H_0 the divergent m = 0 term, B = C + S - H_0 and D_0 = H_0^-1, the static column's diagonal of r per l is
    [(I + B D_0)^-1 B]_rl (finite; rail.moving._rotational_tables). Returns Y (n, 2, 2), the rows
    u_psi = (H_psiF, H_psiM), u_w = (H_ww, H_wM) (n, 2, J) and the columns v_F = (H_ww, H_psiF),
    v_M = (H_wM, H_psiM) (n, 2, J), the diagonals of psi/F, psi/M, w/M and the derivative factor."""
    from ..track import beam_lattice_sums, support_rotational_stiffness

    om = Omega + beta * V
    b = beta[:, None] - js[None, :] * track.beta0
    Hww, HwM, HpF, HpM, inv = free_beam_matrix(b, om[:, None], track)
    Sww, SwM, SpF, SpM = beam_lattice_sums(beta, om, track)
    n = len(beta)
    Cm = np.zeros((n, 2, 2), dtype=complex)
    Cm[:, 0, 0] = track.L / support_stiffness(track, om)
    Cm[:, 1, 1] = track.L / support_rotational_stiffness(track, om)
    S = np.stack([np.stack([Sww, SwM], -1), np.stack([SpF, SpM], -1)], -2)
    Y = np.linalg.inv(Cm + S)
    u_psi, u_w = np.stack([HpF, HpM], 1), np.stack([Hww, HwM], 1)
    v_F, v_M = np.stack([Hww, HpF], 1), np.stack([HwM, HpM], 1)

    def quad(u, v):  # sum_{s, s'} u_s Y_ss' v_s' per node and column
        return np.einsum("nsj,nst,ntj->nj", u, Y, v)

    dF, dM, dW = HpF - quad(u_psi, v_F), HpM - quad(u_psi, v_M), HwM - quad(u_w, v_M)
    if static is not None:
        near = np.abs(beta) < track.beta0 / 2
        if near.any():
            k0 = int(np.where(js == static)[0][0])
            Xww, XwM, XpF, XpM = beam_lattice_sums_excluding(beta[near], om[near], track)  # S - H_0, formed without H_0
            B = Cm[near] + np.stack([np.stack([Xww, XwM], -1), np.stack([XpF, XpM], -1)], -2)
            bn, on = b[near, k0], om[near]
            EI, kGA = rail_stiffnesses(track, on)
            r = track.rail
            D0 = np.empty((len(bn), 2, 2), dtype=complex)
            D0[:, 0, 0] = kGA * bn**2 - r.density * r.area * on**2
            D0[:, 0, 1] = -1j * bn * kGA
            D0[:, 1, 0] = 1j * bn * kGA
            D0[:, 1, 1] = EI * bn**2 + kGA - r.density * r.second_moment_of_area * on**2
            Z = np.linalg.inv(np.eye(2)[None] + B @ D0) @ B  # = H_0 - H_0 (B + H_0)^-1 H_0
            dF[near, k0], dM[near, k0], dW[near, k0] = Z[:, 1, 0], Z[:, 1, 1], Z[:, 0, 1]
    return Y, u_psi, u_w, v_F, v_M, dF, dM, dW, -1j * b


def _rod_nodes(beta, Omega, V, js, head: RailHead, static):
    """Integrand tables of the rod: Y = 1 / (L / k_x + S_u), H_u(beta - j b0) and the diagonal."""
    t = head.track
    om = Omega + beta * V
    Hu = rod_receptance(beta[:, None] - js[None, :] * t.beta0, om[:, None], t)
    S = rod_lattice_sum(beta, om, t)
    c = t.L / longitudinal_support_stiffness(head, om)
    Y = 1.0 / (c + S)
    d = Hu - Hu * Hu * Y[:, None]
    if static is not None:
        near = np.abs(beta) < t.beta0 / 2
        if near.any():
            k0 = int(np.where(js == static)[0][0])  # S without its divergent m = 0 term, formed without it
            d[near, k0] = Hu[near, k0] * (c[near] + rod_lattice_sum_excluding(beta[near], om[near], t)) * Y[near]
    return Y, Hu, d


def moving_head_matrix(head: RailHead, speed: float, Omega: float, js, kinds=("rod", "psiM", "psiF"), rtol: float = 1e-4,
                       order: int = 16, max_panels: int = 40000, block: int = 2048):
    """The moving-load matrices A[p, k] = a_{p-k}(Omega + k Omega_0) of the module docstring, at the
    contact (offset 0), for the columns and rows ``js`` (integers, contiguous).

    Parameters
    ----------
    head : RailHead
    speed : float
        V [m/s], > 0.
    Omega : float
        Base frequency [rad/s]: column k is the load at Omega + k Omega_0, Omega_0 = 2 pi V / L.
    js : sequence of int
        The harmonic indices of the rows and columns.
    kinds : tuple of str
        Which matrices: 'rod' (u_n per longitudinal force on the neutral axis), 'psiM' (psi per
        moment), 'psiF' (psi per downward force), 'dpsiF' (d psi / dx at the contact per downward force
        [rad/(m N)]: the head's strain e d psi / dx), 'wM' (w per moment: the reciprocity check).
    rtol : float
        Relative tolerance of the adaptive wavenumber rule [-].

    Returns
    -------
    dict of str to complex ndarray (J, J)
        [m/N], [rad/(N m)], [rad/N], [m/(N m)]; and 'nodes': the quadrature nodes used (rod, beam).
    """
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it must be a finite number > 0.")
    if not (np.isfinite(Omega)):
        raise ValueError(f"Omega = {Omega!r} rad/s is not allowed: it must be finite.")
    js = np.asarray(js, dtype=int)
    t = head.track
    b0, V = t.beta0, float(speed)
    Om0 = b0 * V
    kk = Omega / Om0
    static = None  # the column whose h diverges at beta = 0 (omega = 0): column 0 when Omega = 0
    if abs(kk - round(kk)) < 1e-12 and -int(round(kk)) in js:
        if round(kk) != 0:
            raise ValueError("moving_head_matrix: Omega a nonzero whole multiple of Omega_0 puts the static point in "
                             "another column; pass Omega in [0, Omega_0) (a Bloch fraction) and shift js.")
        static = 0
    Bmap = (np.max(np.abs(js)) + 4) * b0
    beta_s = -Omega / V  # where omega = 0: the hysteretic damping changes sign
    th_edges = np.unique(np.concatenate([np.linspace(-np.pi / 2, np.pi / 2, 97), [np.arctan(beta_s / Bmap)],
                                         np.arctan((np.arange(-np.max(np.abs(js)) - 2, np.max(np.abs(js)) + 3) + 0.5) * b0 / Bmap)]))
    c0 = int(np.argmin(np.abs(js)))
    rotational = t.pad.rotational_stiffness > 0  # the pads' moment springs (_beam_nodes_rotational)

    def to_beta(th):
        return Bmap * np.tan(th), Bmap / np.cos(th) ** 2

    out = {"nodes": []}
    want_beam = [k for k in kinds if k != "rod"]
    groups = []
    if "rod" in kinds:
        groups.append("rod")
    if want_beam:
        groups.append("beam")
    for g in groups:
        def proxy(th, g=g):
            res = []
            for lo in range(0, len(th), block):
                beta, jac = to_beta(th[lo:lo + block])
                if g == "rod":
                    Y, Hu, d = _rod_nodes(beta, Omega, V, js, head, static)
                    res.append(np.concatenate([d, (Y * Hu[:, c0])[:, None]], axis=1) * jac[:, None])
                elif rotational:
                    Y, u_psi, u_w, v_F, v_M, dF, dM, dW, dx = _beam_nodes_rotational(beta, Omega, V, js, t, static)
                    res.append(np.concatenate([dF, dM, (Y[:, 0, :] * v_F[:, :, c0]).sum(1)[:, None]], axis=1) * jac[:, None])
                else:
                    Y, HpF, Hww, HwM, dF, dM, dW, dx = _beam_nodes(beta, Omega, V, js, t, static)
                    res.append(np.concatenate([dF, dM, (Y * Hww[:, c0])[:, None]], axis=1) * jac[:, None])
            return np.concatenate(res)

        q = adaptive_panels(proxy, th_edges, rtol=rtol, order=order, max_panels=max_panels)
        beta_all, jac_all = to_beta(q.nodes)
        W = q.weights * jac_all
        out["nodes"].append(len(q.nodes))
        J = len(js)
        mats = {k: np.zeros((J, J), dtype=complex) for k in (["rod"] if g == "rod" else want_beam)}
        diags = {k: np.zeros(J, dtype=complex) for k in mats}
        for lo in range(0, len(beta_all), block):
            sl = slice(lo, lo + block)
            beta, w = beta_all[sl], W[sl]
            if g == "rod":
                Y, Hu, d = _rod_nodes(beta, Omega, V, js, head, static)
                mats["rod"] += (Hu * (w * Y)[:, None]).T @ Hu
                diags["rod"] += w @ d
            elif rotational:  # the 2 x 2 reactions: sum over the channels s, s' of u_s Y_ss' v_s'
                Y, u_psi, u_w, v_F, v_M, dF, dM, dW, dx = _beam_nodes_rotational(beta, Omega, V, js, t, static)
                wY = Y * w[:, None, None]
                terms = {"dpsiF": (u_psi * dx[:, None, :], v_F, dF * dx), "psiF": (u_psi, v_F, dF), "psiM": (u_psi, v_M, dM),
                         "wM": (u_w, v_M, dW)}
                for k, (u, v, d) in terms.items():
                    if k in mats:
                        for a in (0, 1):
                            for c in (0, 1):
                                mats[k] += (u[:, a, :] * wY[:, a, c][:, None]).T @ v[:, c, :]
                        diags[k] += w @ d
            else:
                Y, HpF, Hww, HwM, dF, dM, dW, dx = _beam_nodes(beta, Omega, V, js, t, static, want_wM="wM" in kinds)
                wy = (w * Y)[:, None]
                if "dpsiF" in mats:
                    mats["dpsiF"] += (HpF * dx * wy).T @ Hww
                    diags["dpsiF"] += w @ (dF * dx)
                if "psiF" in mats:
                    mats["psiF"] += (HpF * wy).T @ Hww
                    diags["psiF"] += w @ dF
                if "psiM" in mats:
                    mats["psiM"] += (HpF * wy).T @ HwM
                    diags["psiM"] += w @ dM
                if "wM" in mats:
                    mats["wM"] += (Hww * wy).T @ HwM
                    diags["wM"] += w @ dW
        for k in mats:
            A = -mats[k] / (2 * np.pi)
            A[np.arange(J), np.arange(J)] = diags[k] / (2 * np.pi)
            out[k] = A
    return out


@dataclass(frozen=True)
class HeadTable:
    """The head's moving receptances of one Bloch class at one speed (module docstring).

    Attributes
    ----------
    speed : V [m/s]; fraction : nu [-]; harmonics : K (rows and columns k = -K..K, or -K..K-1 for nu > 0)
    A_Q : (J, J) u_head per unit longitudinal force on the head, A_rod + e^2 A_psiM [m/N]
    A_P : (J, J) u_head per unit downward vertical force, e A_psiF [m/N]
    E_P : (J, J) the head's longitudinal strain at the contact per unit downward force, e A_dpsiF [1/N]
    nodes : wavenumber nodes of the rules (rod, beam)
    """

    speed: float
    fraction: float
    harmonics: int
    A_Q: np.ndarray
    A_P: np.ndarray
    E_P: np.ndarray
    nodes: tuple

    @property
    def indices(self) -> np.ndarray:
        K = self.harmonics
        return np.arange(-K, K + (1 if self.fraction == 0 else 0))


@functools.lru_cache(maxsize=64)
def head_table(head: RailHead, speed: float, harmonics: int, fraction: float = 0.0, rtol: float = 1e-4) -> HeadTable:
    """The class nu = ``fraction`` of the head's moving receptances at speed V (cached per argument set).

    Parameters
    ----------
    head : RailHead
    speed : float
        V [m/s], > 0.
    harmonics : int
        K [-], >= 0.
    fraction : float
        Bloch fraction nu in [0, 1) [-].
    rtol : float
        Relative tolerance of the wavenumber rule [-].

    Returns
    -------
    HeadTable
    """
    if int(harmonics) != harmonics or harmonics < 0:
        raise ValueError(f"harmonics = {harmonics!r} is not allowed: it must be an integer >= 0.")
    if not (np.isfinite(fraction) and 0 <= fraction < 1):
        raise ValueError(f"fraction = {fraction!r} is not allowed: the Bloch fraction must lie in [0, 1).")
    K = int(harmonics)
    js = np.arange(-K, K + (1 if fraction == 0 else 0))
    kinds = ("rod", "psiM", "psiF", "dpsiF") if head.bending else ("rod",)
    m = moving_head_matrix(head, speed, fraction * head.track.beta0 * speed, js, kinds, rtol)
    e = head.head_height
    A_Q = m["rod"] + (e * e * m["psiM"] if head.bending else 0)
    A_P = e * m["psiF"] if head.bending else np.zeros_like(m["rod"])
    E_P = e * m["dpsiF"] if head.bending else np.zeros_like(m["rod"])
    return HeadTable(float(speed), float(fraction), K, A_Q, A_P, E_P, tuple(m["nodes"]))


@dataclass(frozen=True)
class HeadOperator:
    """u_bar_rail over a period of N bays from the contact's Q and P there (module docstring).

    Samples are at the contact positions x_k = k L N / n, k = 0..n-1 (x = 0 above a support), the load
    at x = V t. Harmonics of the period above N K are left out (the tables' range).

    Attributes
    ----------
    tables : one HeadTable per class r = 0..N-1 (nu = r / N)
    bays : N
    spacing : L [m]
    strain : whether the head's strain at the contact enters (the rail's material velocity; default True)
    """

    tables: tuple
    bays: int
    spacing: float = 0.6
    strain: bool = True

    def _apply(self, A_name, f, speed=None):
        f = np.asarray(f, dtype=float)
        n, N = f.size, self.bays
        F = np.fft.fft(f) / n
        U = np.zeros(n, dtype=complex)
        for r, tab in enumerate(self.tables):
            q = tab.indices * N + r
            if np.any(np.abs(q) >= n / 2):
                raise ValueError(f"the period's {n} samples do not resolve the rail's {tab.harmonics} harmonics per bay.")
            if speed is None:
                U[q % n] += getattr(tab, A_name) @ F[q % n]
            else:  # V times the time integral of the strain: V E_q / (i omega_q), the mean left out
                w = (q / N) * tab_speed_omega0(tab, self.spacing)
                E = getattr(tab, A_name) @ F[q % n]
                ok = q != 0
                U[(q % n)[ok]] += speed * E[ok] / (1j * w[ok])
        return np.real(np.fft.ifft(U) * n)

    def __call__(self, Q, P):
        """u_bar_rail [m] at the samples (Q the force on the wheel in +x [N], P downward [N]): module docstring."""
        return self.from_force(Q) - self.from_vertical(P)

    def from_force(self, Q):
        """A_Q Q [m]: the part of u_bar_rail that the tangential force drives."""
        return self._apply("A_Q", Q)

    def from_vertical(self, P):
        """The part of -u_bar_rail that the vertical force drives [m]: A_P P (the head's displacement at the
        contact) less V times the time integral of the head's strain E_P P at the contact (its periodic part)."""
        out = self._apply("A_P", P)
        if self.strain:
            out = out - self._apply("E_P", P, speed=self.tables[0].speed)
        return out

    def diagonal(self, n: int) -> np.ndarray:
        """The time-invariant part of A_Q at the period's harmonics q = 0..n//2 (rfft order) [m/N]."""
        N = self.bays
        out = np.zeros(n // 2 + 1, dtype=complex)
        for r, tab in enumerate(self.tables):
            q = tab.indices * N + r
            ok = (q >= 0) & (q <= n // 2)
            out[q[ok]] = np.diag(tab.A_Q)[ok]
        return out


def head_operator(head: RailHead, speed: float, harmonics: int, bays: int, rtol: float = 1e-4) -> HeadOperator:
    """The HeadOperator of a period of N bays (one HeadTable per class nu = r / N, cached).

    Parameters
    ----------
    head : RailHead
    speed : float
        V [m/s], > 0.
    harmonics : int
        K per bay [-].
    bays : int
        N [-], >= 1.
    rtol : float
        Relative tolerance of the wavenumber rule [-].

    Returns
    -------
    HeadOperator
    """
    if int(bays) != bays or bays < 1:
        raise ValueError(f"bays = {bays!r} is not allowed: it must be an integer >= 1.")
    N = int(bays)
    return HeadOperator(tuple(head_table(head, float(speed), int(harmonics), r / N, rtol) for r in range(N)), N, head.track.L)


def tab_speed_omega0(tab: HeadTable, spacing: float) -> float:
    """Omega_0 = 2 pi V / L [rad/s] of a table at the spacing L [m].

    Parameters
    ----------
    tab : HeadTable
    spacing : float
        L [m].

    Returns
    -------
    float
        Omega_0 [rad/s].
    """
    return 2 * np.pi * tab.speed / spacing
