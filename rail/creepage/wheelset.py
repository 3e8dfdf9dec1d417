"""The wheelset's rotational dynamics about its axle, in modal form at the contact (the source of
u_bar in eq 26 that the report leaves out, sec. 4.3 and 6.1; rail.creepage.modes).

Model: a torsional chain of rigid inertias on the axle's line (angles theta in rad, torques in N m)::

    wheel A (J_w) --2 k_a-- centre (J_c) --2 k_a-- wheel B (J_w)
                               |
                              k_c
                               |
                  drive (J_m, the motor and gear reflected to the axle; absent for a trailer)

k_a is the axle's torsional stiffness from wheel to wheel (each half 2 k_a), J_c the inertia on the
axle between the wheels (gear wheel, brake discs), k_c the drive's flexible coupling. Wheel A rolls
on the modelled rail; a tangential force Q on its tread (in +x, at radius R_w below the axle) is a
torque R_w Q, and moves the tread by R_w theta_A. With the free-free modes K phi = omega^2 J phi,
phi^T J phi = 1, the tread receptance is

    H(omega) = R_w^2 sum_r phi_A,r (phi_A,r + s phi_B,r) / (omega_r^2 - omega^2 + 2 i zeta_r omega_r omega)

with s = 1 when the other wheel sees the same traction at the same time (``other_wheel: in_phase``:
the same roughness on both rails, in phase; only the modes symmetric about the axle's middle are
excited) and s = 0 when its traction is independent of this wheel's (``independent``: the other
rail's roughness is uncorrelated; the antisymmetric torsion, the wheels twisting against each
other, is excited too; what the other wheel's own force does to this wheel is incoherent with this
rail's roughness and left out). The rigid spin (omega = 0) is the wheelset turning as one under the
drive or brake torque, which holds the steady traction Q_ref (rail.creepage.modes). Elastic modes
have the damping ratio zeta; the rigid spin has none.

The report's rigid wheel at a fixed creepage is the limit of infinite inertia (H -> 0). A rigid
wheelset (k_a, k_c -> infinity) has the rigid spin alone, participation R_w^2 (1 + s) / J_total.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg

from .modes import LongitudinalModes

__all__ = ["Wheelset", "WHEELSET_MODELS", "OTHER_WHEEL", "RANGES", "wheelset_modes", "chain_modes", "hz_text",
           "tread_receptance"]

# 'fixed_creepage': the report's rigid wheel at a fixed creepage (u_bar = 0); 'rigid': a rigid wheelset
# spinning under the drive torque (the rigid spin alone); 'torsional': the elastic axle and the drive
WHEELSET_MODELS = ("fixed_creepage", "rigid", "torsional")
OTHER_WHEEL = ("in_phase", "independent")
# The valid range of each parameter, by its configuration key: the same closed ranges as
# config/schema/config.schema.yaml states (tests/test_wheelset_input.py checks that they agree), so that
# the schema refuses a value, naming its file, before this class ever sees it. The wheel radius is
# wheels.radius, the radius of the contact too: 0.1 to 1.5 m holds every railway wheel (0.18 m: the
# 360 mm wheels of low-floor car-carrier wagons; 0.23-0.33 m: tram and low-floor wheels; 0.46-0.625 m:
# coaches and locomotives; 1.15 m: the largest steam driving wheels).
RANGES = {"radius": ("wheels.radius", 0.1, 1.5), "wheel_inertia": ("wheelset.wheel_inertia", 1.0, 1e4),
          "centre_inertia": ("wheelset.centre_inertia", 1e-3, 1e5),
          "axle_stiffness": ("wheelset.axle_stiffness", 1e4, 1e9),
          "coupling_stiffness": ("wheelset.coupling_stiffness", 1e3, 1e9),
          "motor_inertia": ("wheelset.motor_inertia", 0.0, 1e5)}
UNITS = {"radius": "m", "wheel_inertia": "kg m^2", "centre_inertia": "kg m^2", "axle_stiffness": "N m/rad",
         "coupling_stiffness": "N m/rad", "motor_inertia": "kg m^2"}


@dataclass(frozen=True)
class Wheelset:
    """A wheelset's torsional chain (module docstring), SI units.

    Attributes
    ----------
    model : one of WHEELSET_MODELS
    radius : R_w [m], > 0
    wheel_inertia : J_w, polar inertia of one wheel [kg m^2], > 0
    centre_inertia : J_c, inertia on the axle between the wheels (gear wheel, brake discs) [kg m^2], > 0
    axle_stiffness : k_a, torsional stiffness of the axle from wheel to wheel [N m/rad], > 0
    motor_inertia : J_m, the motor's and gear's inertia reflected to the axle [kg m^2], >= 0 (0: a trailer)
    coupling_stiffness : k_c, torsional stiffness of the drive's coupling at the axle [N m/rad], > 0
    damping : zeta, the damping ratio of every elastic mode [-], in [0, 1)
    other_wheel : one of OTHER_WHEEL
    """

    model: str
    radius: float
    wheel_inertia: float = 40.0
    centre_inertia: float = 10.0
    axle_stiffness: float = 5.0e6
    motor_inertia: float = 0.0
    coupling_stiffness: float = 1.0e6
    damping: float = 0.02
    other_wheel: str = "in_phase"

    def __post_init__(self):
        if self.model not in WHEELSET_MODELS:
            raise ValueError(f"wheelset.model = {self.model!r} is not allowed: it must be one of {list(WHEELSET_MODELS)}.")
        if self.other_wheel not in OTHER_WHEEL:
            raise ValueError(f"wheelset.other_wheel = {self.other_wheel!r} is not allowed: it must be one of {list(OTHER_WHEEL)}.")
        for name, (key, low, high) in RANGES.items():
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and low <= v <= high):
                extra = " (0: a trailer)" if name == "motor_inertia" else ""
                raise ValueError(f"{key} = {v!r} {UNITS[name]} is not allowed: it must be a finite number in "
                                 f"[{low:g}, {high:g}] {UNITS[name]}{extra}.")
        if not (isinstance(self.damping, (int, float)) and math.isfinite(self.damping) and 0 <= self.damping < 1):
            raise ValueError(f"wheelset.damping = {self.damping!r} is not allowed: it must lie in [0, 1).")

    @property
    def driven(self) -> bool:
        """Whether a drive (motor and gear) hangs on the axle."""
        return self.motor_inertia > 0

    def matrices(self):
        """(J, K): the inertia [kg m^2] and stiffness [N m/rad] matrices of the chain, DOFs (A, centre, B[, drive])."""
        ka2 = 2.0 * self.axle_stiffness
        J = [self.wheel_inertia, self.centre_inertia, self.wheel_inertia]
        springs = [(0, 1, ka2), (1, 2, ka2)]
        if self.driven:
            J.append(self.motor_inertia)
            springs.append((1, 3, self.coupling_stiffness))
        n = len(J)
        K = np.zeros((n, n))
        for i, j, k in springs:
            K[i, i] += k
            K[j, j] += k
            K[i, j] -= k
            K[j, i] -= k
        return np.diag(J), K


def chain_modes(ws: Wheelset):
    """The free-free modes of the chain, K phi = omega^2 J phi with phi^T J phi = 1.

    The chain is connected (every stiffness > 0), so it has exactly one rigid mode, the lowest: its
    eigenvalue is set to 0 (it is rounding), and the elastic ones are kept as they are, however far
    apart the scales (a threshold relative to the largest eigenvalue zeroed an 80 Hz mode beside the
    5 MHz of a 1e-9 kg m^2 motor on its coupling).

    Parameters
    ----------
    ws : Wheelset

    Returns
    -------
    omega : ndarray, shape (n,)
        Natural angular frequencies [rad/s], ascending; omega[0] = 0 (the rigid spin).
    phi : ndarray, shape (n, n)
        Mass-normalised mode shapes, one per column [rad / sqrt(kg m^2)], DOFs (A, centre, B[, drive]).
    """
    J, K = ws.matrices()
    lam, phi = linalg.eigh(K, J)  # ascending, phi^T J phi = I
    lam = lam.copy()
    lam[0] = 0.0
    return np.sqrt(np.clip(lam, 0.0, None)), phi


def wheelset_modes(ws: Wheelset, reference_force: float | None = None) -> LongitudinalModes | None:
    """The tread receptance of wheel A in modal form (module docstring), or None for 'fixed_creepage'.

    Parameters
    ----------
    ws : Wheelset
    reference_force : float, optional
        Q_ref [N], the steady traction the torque holds (default: Carter's at the mean load, set by the march).

    Returns
    -------
    LongitudinalModes or None
        omega_r [rad/s], zeta_r [-], c_r = R_w^2 phi_A (phi_A + s phi_B) [1/kg]; the modes that the chosen
        other wheel leaves unexcited (c_r below 1e-12 of the largest: the antisymmetric torsion with
        ``in_phase``, a drive's mode far above the wheel's) are left out, their frequencies [Hz] kept in
        ``unexcited`` for the headers.
    """
    if ws.model == "fixed_creepage":
        return None
    R2 = ws.radius**2
    s = 1.0 if ws.other_wheel == "in_phase" else 0.0
    J, K = ws.matrices()
    if ws.model == "rigid":
        return LongitudinalModes((0.0,), (0.0,), (R2 * (1 + s) / float(np.trace(J)),), reference_force, "rigid wheelset",
                                  model=ws.model)
    om, phi = chain_modes(ws)
    c = np.clip(R2 * phi[0] * (phi[0] + s * phi[2]), 0.0, None)
    keep = c > 1e-12 * c.max()
    zeta = np.where(om > 0, ws.damping, 0.0)
    label = f"torsional wheelset ({'driven' if ws.driven else 'trailer'}, other wheel {ws.other_wheel})"
    return LongitudinalModes(tuple(om[keep]), tuple(zeta[keep]), tuple(c[keep]), reference_force, label,
                             tuple(float(w) / (2 * np.pi) for w in om[~keep]), model=ws.model)


def hz_text(f: float) -> str:
    """A natural frequency as results and messages write it: whole hertz below 100 kHz, else three
    significant digits (5.03e+06).

    Parameters
    ----------
    f : float
        Frequency [Hz], >= 0.

    Returns
    -------
    str
        The number, without its unit [Hz].
    """
    return f"{f:.0f}" if f < 1e5 else f"{f:.3g}"


def tread_receptance(ws: Wheelset, omega):
    """H(omega) [m/N] at the tread of wheel A by a direct solve of the chain (the modal form's check):
    R_w^2 e_A^T (K - omega^2 J + i omega C)^-1 (e_A + s e_B), with C the modal damping matrix
    J Phi diag(2 zeta omega_r) Phi^T J of the elastic modes.

    Parameters
    ----------
    ws : Wheelset
    omega : float or ndarray
        Angular frequencies [rad/s], not 0.

    Returns
    -------
    ndarray of complex
        H(omega) [m/N].
    """
    J, K = ws.matrices()
    om, phi = chain_modes(ws)
    C = J @ phi @ np.diag(2 * ws.damping * om) @ phi.T @ J
    s = 1.0 if ws.other_wheel == "in_phase" else 0.0
    f = np.zeros(J.shape[0])
    f[0], f[2] = 1.0, s
    out = []
    for w in np.atleast_1d(np.asarray(omega, dtype=float)):
        out.append(ws.radius**2 * np.linalg.solve(K - w**2 * J + 1j * w * C, f)[0])
    return np.array(out)
