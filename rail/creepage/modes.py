"""Dynamic creepage: the global longitudinal relative displacement u_bar(t) of eq 26, and friction
that falls with the slip velocity (report sec. 4.3 and 6.1: "must be considered in future work").

Slip velocity with u_bar (eq 26 with its global term)::

    s(xi, t) = V gamma + d u_bar / dt - V du/dxi + du/dt.

u_bar is the wheel's longitudinal displacement at the contact minus the rail's, beyond the local
(half-space) deformation u. It is driven by the tangential force Q on the wheel (Q = 2b int q, in
+x, the traction q > 0 of a driving wheel): u_bar = H(omega) (Q - Q_ref), with H a point receptance
at the contact, positive real part of i omega H (a passive structure), given here in modal form::

    H(omega) = sum_r c_r / (omega_r^2 - omega^2 + 2 i zeta_r omega_r omega)   [m/N],

c_r [1/kg] the participation of mode r at the contact (1 / modal mass at the tread). A mode with
omega_r = 0 is a free rotation (the wheelset's rigid spin): its force is then Q - Q_ref, with Q_ref
the steady traction the drive (or brake) torque holds, so that the creepage settles where the mean
traction balances the torque (torque control); the other modes see the same Q - Q_ref (a constant
offset of the force moves them by a constant, which does not enter the slip).

Time stepping (rail.contact.march): the force over step i is extrapolated from steps i - 1 and
i - 2, 1.5 Q_{i-1} - 0.5 Q_{i-2} (explicit, second order in the step; holding Q_{i-1} lags the
response by half a step, a phase error of 0.03 rad at 1 kHz on the default grid), and each mode is
advanced exactly for that constant force. The coupling's
own time scale (m_r / dQ/dV_slip, about 0.5 ms for a 150 kg tread mass at 0.1 % creepage) is 100
steps or more, so the lag is far inside the stability limit (tested against the closed-form
transfer function, tests/test_creep.py).

Friction that falls with the slip velocity (option): mu(s) = mu_d + (mu_s - mu_d) exp(-abs(s) / s_0),
from mu_s at rest to mu_d in gross slip; s_0 -> 0 is the report's step (mu_s in stick, mu_d in slip).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._lazyjit import njit

__all__ = ["LongitudinalModes", "modal_receptance"]


def _finite_tuple(name, values, low=None, low_open=None, high_open=None):
    out = tuple(float(v) for v in values)
    for v in out:
        bad = not math.isfinite(v) or (low is not None and v < low) or (low_open is not None and v <= low_open) or (
            high_open is not None and v >= high_open)
        if bad:
            rng = (f">= {low}" if low is not None else f"> {low_open}") + (f" and < {high_open}" if high_open is not None else "")
            raise ValueError(f"{name} = {v!r} is not allowed: every value must be a finite number {rng}.")
    return out


@dataclass(frozen=True)
class LongitudinalModes:
    """The longitudinal point receptance at the contact in modal form (module docstring).

    Attributes
    ----------
    omega : (R,) natural angular frequencies omega_r [rad/s], >= 0 (0: a free rotation)
    zeta : (R,) modal damping ratios [-], in [0, 1)
    participation : (R,) c_r [1/kg]: the displacement at the contact per unit force, per mode
    reference_force : Q_ref [N], the steady traction the drive or brake torque holds (the force is
        Q - Q_ref); None: Carter's steady traction at the mean load and the scenario's creepage
        (rail.wear.bay_wear sets it)
    label : what the modes are (for results and messages)
    unexcited : the natural frequencies [Hz] of the modes left out (their participation at the contact
        below 1e-12 of the largest), named in results' headers
    model : the wheelset model the modes are of (config key wheelset.model, rail.creepage.choices), or ''
        for modes given directly
    """

    omega: tuple
    zeta: tuple
    participation: tuple
    reference_force: float | None = None
    label: str = ""
    # the frequencies [Hz] of the modes left out as not excited at the contact, for results' headers; out of
    # the repr (hashed into the keys of class spectra) and of comparisons: what the march runs is unchanged
    unexcited: tuple = field(default=(), repr=False, compare=False)
    # the model's name (rail.creepage.wheelset.wheelset_modes sets it), for results' wheelset_model: out of the repr and
    # of comparisons as ``unexcited`` is
    model: str = field(default="", repr=False, compare=False)

    def __post_init__(self):
        om = _finite_tuple("wheelset mode frequency (rad/s)", self.omega, low=0.0)
        ze = _finite_tuple("wheelset modal damping ratio", self.zeta, low=0.0, high_open=1.0)
        cp = _finite_tuple("wheelset modal participation (1/kg)", self.participation, low=0.0)
        if not (len(om) == len(ze) == len(cp)):
            raise ValueError(f"the modal form needs one damping ratio and one participation per mode; got {len(om)} "
                             f"frequencies, {len(ze)} damping ratios and {len(cp)} participations.")
        object.__setattr__(self, "omega", om)
        object.__setattr__(self, "zeta", ze)
        object.__setattr__(self, "participation", cp)
        if self.reference_force is not None and not math.isfinite(self.reference_force):
            raise ValueError(f"reference_force = {self.reference_force!r} N is not allowed: it must be finite.")

    def receptance(self, omega):
        """H(omega) [m/N] at angular frequencies omega [rad/s] (module docstring); a free rotation
        gives -c / omega^2 (omega != 0)."""
        return modal_receptance(omega, self.omega, self.zeta, self.participation)

    def arrays(self):
        """(omega, zeta, participation) as float64 arrays for the compiled march."""
        return (np.array(self.omega, dtype=float), np.array(self.zeta, dtype=float), np.array(self.participation, dtype=float))


def modal_receptance(omega, omega_r, zeta_r, c_r):
    """sum_r c_r / (omega_r^2 - omega^2 + 2 i zeta_r omega_r omega) [m/N] at omega [rad/s].

    Parameters
    ----------
    omega : array-like
        Angular frequencies [rad/s].
    omega_r : array-like, (R,)
        Natural angular frequencies of the modes [rad/s], >= 0 (0: a free rotation).
    zeta_r : array-like, (R,)
        Modal damping ratios [-].
    c_r : array-like, (R,)
        Modal participations [1/kg] (displacement at the contact per unit force, per mode).

    Returns
    -------
    ndarray, complex, shape of omega
        The receptance H(omega) [m/N].
    """
    w = np.asarray(omega, dtype=float)[..., None]
    om, ze, c = (np.asarray(v, dtype=float) for v in (omega_r, zeta_r, c_r))
    return np.sum(c / (om**2 - w**2 + 2j * ze * om * w), axis=-1)


@njit(cache=True)
def advance_modes(x, v, om, ze, c, force, dt):
    """Advance each mode in place over one step under a constant force: x'' + 2 zeta omega x' + omega^2 x = c F,
    exactly (compiled; the contact's march calls it at every step, rail.contact.march).

    Parameters
    ----------
    x, v : ndarray
        Each mode's displacement [m] and velocity [m/s], advanced in place.
    om, ze, c : ndarray
        Each mode's omega [rad/s], zeta [-] and participation [1/kg].
    force : float
        The force held over the step [N].
    dt : float
        The step [s].

    Returns
    -------
    float
        The change of sum_r x_r over the step [m].
    """
    total = 0.0
    for r in range(om.size):
        w = om[r]
        cf = c[r] * force
        x0, v0 = x[r], v[r]
        if w == 0.0:
            x1 = x0 + v0 * dt + 0.5 * cf * dt * dt
            v1 = v0 + cf * dt
        else:
            xe = cf / (w * w)
            y0 = x0 - xe
            sg = ze[r] * w
            wd = w * math.sqrt(1.0 - ze[r] * ze[r])
            ex = math.exp(-sg * dt)
            cs, sn = math.cos(wd * dt), math.sin(wd * dt)
            x1 = xe + ex * (y0 * cs + (v0 + sg * y0) / wd * sn)
            v1 = ex * (v0 * cs - (w * w * y0 + sg * v0) / wd * sn)
        total += x1 - x0
        x[r] = x1
        v[r] = v1
    return total


def periodic_response(force, dt, modes: LongitudinalModes):
    """u_bar [m] at the end of each step of one period under the periodic force [N] held over each step
    (force[i] over step i, of dt[i] s), exactly (the modes' periodic solution). A free rotation
    (omega_r = 0) takes the force less its time mean (a periodic spin needs a zero mean force; the
    mean is the torque balance's, rail.wear), its velocity with zero time mean.

    Parameters
    ----------
    force : array-like, (steps,)
        The longitudinal force held over each step [N].
    dt : array-like, (steps,)
        The steps' durations [s], > 0; their sum is the period.
    modes : LongitudinalModes
        The modal receptance at the contact.

    Returns
    -------
    ubar : ndarray, (steps,)
        The displacement [m] at the end of each step, up to a constant.
    mean_force : float
        The time mean of the force [N].
    """
    F = np.asarray(force, dtype=float)
    dt = np.asarray(dt, dtype=float)
    T = float(np.sum(dt))
    Fm = float(np.sum(F * dt) / T)
    out = np.zeros(F.size)
    for r, (om, ze, c) in enumerate(zip(modes.omega, modes.zeta, modes.participation)):
        o, z, cc = (np.array([v], dtype=float) for v in (om, ze, c))
        Fr = F - Fm if om == 0 else F
        x, v = np.zeros(1), np.zeros(1)
        xs = _march_mode(x, v, o, z, cc, Fr, dt)  # from rest
        if om == 0:
            # a periodic velocity: v(T) = v(0) already (zero mean force); take the velocity's time mean out
            vel = np.diff(np.concatenate([[0.0], xs])) / dt
            vm = float(np.sum(vel * dt) / T)
            xs = xs - np.cumsum(dt) * vm
        else:
            # the periodic start s0 = (I - Phi_T)^-1 s(T) with Phi_T the free transition over T
            Phi = _free_transition(om, ze, T)
            s0 = np.linalg.solve(np.eye(2) - Phi, np.array([x[0], v[0]]))
            x, v = np.array([s0[0]]), np.array([s0[1]])
            xs = _march_mode(x, v, o, z, cc, Fr, dt)
        out += xs
    return out, Fm


@njit(cache=True)
def _march_mode(x, v, om, ze, c, F, dt):
    """The modes' displacement x[0] [m] at the end of each step under the force F [N] held over each step of dt [s],
    from (x, v) (advanced in place); compiled, as advance_modes: a growth update calls it for every mode and Newton
    step, over every step of the period (in Python 10 % of the growth loop's time, tests/benchmarks/bench_growth_creepage.py)."""
    xs = np.empty(F.size)
    for i in range(F.size):
        advance_modes(x, v, om, ze, c, F[i], dt[i])
        xs[i] = x[0]
    return xs


def _free_transition(om: float, ze: float, T: float):
    """The 2 x 2 transition of (x, v) over T [s] of x'' + 2 zeta omega x' + omega^2 x = 0."""
    sg, wd = ze * om, om * np.sqrt(1 - ze * ze)
    ex, cs, sn = np.exp(-sg * T), np.cos(wd * T), np.sin(wd * T)
    return ex * np.array([[cs + sg / wd * sn, sn / wd], [-(om * om) / wd * sn, cs - sg / wd * sn]])


def precondition(residual, T: float, modes: LongitudinalModes | None, slope_over_speed: float, extra=None,
                 lag: float = 0.0):
    """The Newton step of the periodic u_bar from a residual r over the period's steps (taken as equally
    spaced in time over T [s]): per harmonic k != 0, r_k / (1 - H(omega_k) i omega_k dQ/dgamma / V), with
    the contact's traction response to u_bar that of quasi-steady rolling (Carter's creep slope). H is the
    modes' receptance (none: 0) plus ``extra``, a receptance [m/N] at the rfft harmonics k = 0..n//2 (the
    rail's time-invariant part, rail.creepage.rail_flexibility.HeadOperator.diagonal), if given. ``lag`` [s] > 0 lets the
    contact's response lag as a first-order relaxation, i omega dQ/dgamma / V / (1 + i omega lag) (a / V: the
    traction builds up over a rolling distance of about the half-length; a stiff contact spring at high
    frequency instead of a creep damper growing without bound); 0 (default): quasi-steady.

    Parameters
    ----------
    residual : array-like, (n,)
        The residual of u_bar over the period's steps [m].
    T : float
        The period [s], > 0.
    modes : LongitudinalModes or None
        The wheelset's modal receptance (None: none).
    slope_over_speed : float
        Carter's creep slope over the speed, dQ/dgamma / V [N s/m] (carter_creep_slope).
    extra : array-like, (n//2 + 1,), optional
        A receptance [m/N] added at the rfft harmonics k = 0..n//2.
    lag : float
        The contact's relaxation time [s], >= 0 (0: quasi-steady).

    Returns
    -------
    ndarray, (n,)
        The Newton step of u_bar [m]; its time mean (k = 0) is the residual's.
    """
    r = np.fft.rfft(np.asarray(residual, dtype=float))
    w = 2 * np.pi * np.arange(r.size) / T
    H = np.zeros(r.size, dtype=complex)
    if modes is not None:
        H[1:] = modes.receptance(w[1:])
    if extra is not None:
        H = H + np.asarray(extra)
    if lag > 0:
        d = 1 - H * 1j * w * slope_over_speed / (1 + 1j * w * lag)
    else:
        d = 1 - H * 1j * w * slope_over_speed
    d[0] = 1.0
    return np.fft.irfft(r / d, n=len(residual))
