"""Carter's steady 2D rolling solution (report sec. 4.3, from eqs 26-30): the analytic limit of the
tangential march in steady rolling (rail.contact.march).

Conventions as rail.contact.march: the leading edge at xi = +a, q opposite to the creepage gamma.
"""

from __future__ import annotations

import numpy as np

from .hertz import ContactMaterial, compliance, hertz_half_length, hertz_pressure

__all__ = ["carter"]


def carter(xi, P, m: ContactMaterial, speed: float, R: float):
    """Carter's steady 2D rolling solution (from eqs 26-30).

    1 - c/a = abs(gamma) / (pi k mu p0), Q = mu P (1 - (c/a)^2), the sign of q opposite to gamma.
    Saturation (no stick) when abs(gamma) >= 4 (1 - nu^2) mu_d p0 / E.

    Parameters
    ----------
    xi : float or ndarray
        Positions in the patch [m], leading edge at +a.
    P : float
        Normal force [N].
    m : ContactMaterial
    speed : float
        Rolling speed V [m/s].
    R : float
        Equivalent radius [m].

    Returns
    -------
    q : ndarray
        Tangential traction at xi [Pa].
    s : ndarray
        Slip velocity at xi [m/s] (0 in stick and outside the patch).
    Q : float
        Total tangential force 2b int q [N].
    c : float
        Stick half-length [m]; the stick zone is [a - 2c, a].
    """
    for name, value, unit in (("speed", speed, "m/s"), ("P", P, "N"), ("R", R, "m")):
        if isinstance(value, bool) or not np.isscalar(value) or not (np.isfinite(value) and value > 0):
            raise ValueError(f"carter: {name} = {value!r} {unit} is not allowed: it must be a finite number > 0 "
                             "(valid range (0, inf)).")
    a = float(hertz_half_length(P, R, m))
    p0 = P / (np.pi * a * m.half_width)
    k = compliance(m)
    mu, g = m.friction_dynamic, m.creepage
    xi = np.asarray(xi, dtype=float)
    p = hertz_pressure(xi, P, a, m)
    sgn = -np.sign(g) if g != 0 else 0.0
    frac = abs(g) / (np.pi * k * mu * p0)
    c = a * max(1.0 - frac, 0.0)
    d = a - c  # centre of the stick zone
    inside_stick = np.abs(xi - d) < c
    q = sgn * mu * p.copy()
    if c > 0:
        q_stick = sgn * mu * p0 * (c / a) * np.sqrt(np.clip(1 - ((xi - d) / c) ** 2, 0, None))
    else:  # saturated: full slip, no stick zone
        q_stick = np.zeros_like(xi)
    q = q - np.where(inside_stick, q_stick, 0.0)
    # slip velocity s = V gamma - V du/dxi, du/dxi = -k PV int q / (xi - zeta)
    # full ellipse: PV int p0 sqrt(1 - z^2/a^2)/(xi - z) = pi p0 xi / a (|xi| < a)
    # stick ellipse outside its support: pi p0 (c/a) ((xi-d) - sign sqrt((xi-d)^2 - c^2)) / c
    t = xi - d
    outer = np.where(np.abs(t) > c, t - np.sign(t) * np.sqrt(np.clip(t * t - c * c, 0, None)), t)
    hilbert = np.pi * mu * p0 * (xi / a - (outer / a if c > 0 else 0.0))
    dudxi = -k * sgn * hilbert
    s = speed * g - speed * dudxi
    s = np.where(inside_stick | (np.abs(xi) >= a), 0.0, s)
    Q = sgn * mu * P * (1 - (c / a) ** 2)
    return q, s, Q, c
