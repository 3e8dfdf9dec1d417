"""Hertz normal contact of the report (sec. 4.2-4.3, eqs 22-24) and the contact material.

Conventions
-----------
* Plane strain per unit width of a strip of width 2b (the report's 2D contact). Two steel bodies of
  Young's modulus E and Poisson's ratio nu: composite modulus E* = E / (2 (1 - nu^2)). The one
  compliance of the contact, k = 2 / (pi E*) = 4 (1 - nu^2) / (pi E), is that of the tangential
  problem (eq 29), of the normal surface approach (rail.contact.normal) and of the Hertz half-length
  (eq 23: a^2 = k P R / b); the report's rigid compliance per unit half-length (eq 33) is 2 k.
* Forces in N, lengths in m, pressures in Pa; the curvature kappa = -z'' of the rail head is
  positive for a convex rail (eq 24).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ContactError", "ContactMaterial", "FrictionLaw", "FRICTION_LAWS", "friction_law", "friction_law_of", "composite_modulus",
           "compliance", "report_rigid_compliance",
           "equivalent_radius", "hertz_half_length", "hertz_pressure"]


class ContactError(RuntimeError):
    """A physical assumption of the contact model no longer holds (multiple contact, no solution)."""


@dataclass(frozen=True)
class ContactMaterial:
    """Contact parameters (section 6).

    youngs_modulus   : E, Pa (both bodies)
    poisson_ratio    : nu, -
    half_width       : b, m (contact width 2b)
    wheel_radius     : R_w, m
    friction_dynamic : mu_d, -
    friction_static  : mu_s, -, >= mu_d
    creepage         : gamma_1, - (eq 25; negative for a driving wheel)
    friction_decay   : s_0, m/s, >= 0: friction falling with the slip velocity (rail.creepage.modes); 0 (default): the report's step
    longitudinal     : rail.creepage.modes.LongitudinalModes or None (default): the wheelset's rotation, u_bar of eq 26 (rail.creepage.wheelset)
    rail_flexibility : rail.creepage.rail_flexibility.RailHead or None (default): the rail head's longitudinal flexibility, its share of u_bar
    """

    youngs_modulus: float
    poisson_ratio: float
    half_width: float
    wheel_radius: float
    friction_dynamic: float
    friction_static: float
    creepage: float
    friction_decay: float = 0.0
    longitudinal: object = None
    rail_flexibility: object = None

    def __repr__(self):
        # the report's fields always; the dynamic-creepage ones only where set, so that the repr (and the
        # keys hashed from it, rail.setup.study_files.class_key) of every earlier material is unchanged
        base = ", ".join(f"{k}={getattr(self, k)!r}" for k in ("youngs_modulus", "poisson_ratio", "half_width", "wheel_radius",
                                                             "friction_dynamic", "friction_static", "creepage"))
        extra = "".join(f", {k}={getattr(self, k)!r}" for k, off in (("friction_decay", 0.0), ("longitudinal", None),
                                                                         ("rail_flexibility", None))
                        if getattr(self, k) != off)
        return f"ContactMaterial({base}{extra})"

    @property
    def friction_law(self):
        """The friction law (FrictionLaw): the report's step from mu_s to mu_d
        ('step'), friction falling with the slip velocity ('falling', friction_decay > 0), or, with
        mu_s = mu_d, constant friction ('constant': mu(s) = mu_d + (mu_s - mu_d) exp(-abs(s) / s_0) is
        then flat and s_0 changes nothing, the result is the step law's, which a header must not call
        falling); its description for results' headers and start-up notes."""
        return friction_law_of(self)

    def __post_init__(self):
        if not (np.isfinite(self.friction_decay) and 0 <= self.friction_decay <= 100):
            raise ValueError(f"contact.friction_decay = {self.friction_decay!r} m/s is not allowed: it must be a finite number "
                             "in [0, 100] (0: the report's step from mu_s to mu_d).")
        if not np.isfinite(self.friction_static):
            raise ValueError(f"contact.friction_static = {self.friction_static!r} is not allowed: it must be a finite number.")
        if self.friction_static < self.friction_dynamic:
            raise ValueError(
                f"contact.friction_static = {self.friction_static} is not allowed: it must be >= "
                f"contact.friction_dynamic = {self.friction_dynamic}."
            )
        for name in ("youngs_modulus", "half_width", "wheel_radius", "friction_dynamic"):
            if not (getattr(self, name) > 0 and np.isfinite(getattr(self, name))):
                key = {"wheel_radius": "wheels.radius", "youngs_modulus": "material.youngs_modulus"}.get(
                    name, f"contact.{name}")
                raise ValueError(f"{key} = {getattr(self, name)!r} is not allowed: it must be a finite number > 0.")
        if not (np.isfinite(self.poisson_ratio) and -1 < self.poisson_ratio < 0.5):
            raise ValueError(f"poisson_ratio = {self.poisson_ratio!r} is not allowed: it must lie in (-1, 0.5) "
                             "(an isotropic elastic solid).")
        if not (np.isfinite(self.creepage) and -1 <= self.creepage <= 1):
            raise ValueError(f"contact.creepage = {self.creepage!r} is not allowed: it must lie in [-1, 1].")


def composite_modulus(m: ContactMaterial) -> float:
    """Composite plane-strain modulus E* = E / (2 (1 - nu^2)) of two steel bodies [Pa].

    Parameters
    ----------
    m : ContactMaterial

    Returns
    -------
    float
        E* [Pa]; 2 / (pi E*) equals compliance(m).
    """
    return m.youngs_modulus / (2 * (1 - m.poisson_ratio**2))


def compliance(m: ContactMaterial) -> float:
    """Compliance of both bodies together, k = 2 / (pi E*) = 4 (1 - nu^2) / (pi E) (eqs 29-31).

    The one compliance of the contact: the tangential influence (eq 29), the normal surface approach
    (rail.contact.normal), the Hertz half-length (eq 23, a^2 = k P R / b) and the report's rigid
    compliance (eq 33, 2 k per unit half-length) are all this quantity.

    Parameters
    ----------
    m : ContactMaterial

    Returns
    -------
    float
        k [1/Pa].
    """
    return 2 / (np.pi * composite_modulus(m))


def report_rigid_compliance(m: ContactMaterial) -> float:
    """The report's rigid compliance per unit half-length, 1 / (sigma a) = 2 k (eq 33) [1/Pa].

    Parameters
    ----------
    m : ContactMaterial

    Returns
    -------
    float
        2 k [1/Pa], k = compliance(m).
    """
    return 2 * compliance(m)


def equivalent_radius(curvature, m: ContactMaterial):
    """Equivalent radius R from 1/R = 1/R_w + kappa (eq 24).

    Parameters
    ----------
    curvature : float or ndarray
        Rail-head curvature kappa = -z'' [1/m] (convex upwards positive).
    m : ContactMaterial
        Gives the wheel radius R_w [m].

    Returns
    -------
    float or ndarray
        R [m].

    Raises
    ------
    ContactError
        Where the rail is concave more sharply than the wheel (z'' >= 1/R_w): the wheel touches at
        more than one point.
    """
    curvature = np.asarray(curvature, dtype=float)
    inv = 1.0 / m.wheel_radius + curvature
    if np.any(inv <= 0):
        i = int(np.argmin(inv))
        raise ContactError(
            f"multiple contact: the rail curvature z'' = {-np.ravel(curvature)[i]:.4g} 1/m at sample {i} reaches "
            f"1/R_w = {1 / m.wheel_radius:.4g} 1/m; the wheel touches at more than one point (eq 24)."
        )
    return 1.0 / inv


def hertz_half_length(P, R, m: ContactMaterial):
    """Hertz contact half-length a = sqrt(k P R / b) = sqrt(4 (1 - nu^2) P R / (pi b E)) (eq 23), k = compliance(m).

    Parameters
    ----------
    P : float or ndarray
        Normal force [N], finite and >= 0 (P = 0 gives a = 0).
    R : float or ndarray
        Equivalent radius [m] (eq 24), finite and > 0.
    m : ContactMaterial

    Returns
    -------
    float or ndarray
        a [m].

    Raises
    ------
    ValueError
        If P is negative (the wheel has lost contact: a tension is no Hertz contact; rail.interaction
        reports contact loss before the contact is solved) or not finite, or R is not finite and > 0.
    """
    P = np.asarray(P, dtype=float)
    R = np.asarray(R, dtype=float)
    if not np.all(np.isfinite(P)) or np.any(P < 0):
        bad = np.ravel(P)[np.flatnonzero(~(np.isfinite(np.ravel(P)) & (np.ravel(P) >= 0)))[0]]
        raise ValueError(f"normal force P = {float(bad)!r} N is not allowed in the Hertz contact (eq 23): it must be a finite "
                         "number >= 0 (a negative force means the wheel has lost contact).")
    if not (np.all(np.isfinite(R)) and np.all(R > 0)):
        bad = np.ravel(R)[np.flatnonzero(~(np.isfinite(np.ravel(R)) & (np.ravel(R) > 0)))[0]]
        raise ValueError(f"equivalent radius R = {float(bad)!r} m is not allowed in the Hertz contact (eq 23): it must be a "
                         "finite number > 0.")
    return np.sqrt(compliance(m) * np.maximum(P, 0) * R / m.half_width)


def hertz_pressure(xi, P, a, m: ContactMaterial):
    """Hertz pressure p = P / (pi a b) sqrt(1 - (xi/a)^2) inside the patch, 0 outside (eq 22).

    Parameters
    ----------
    xi : float or ndarray
        Position in the patch from its centre [m], leading edge at +a.
    P : float
        Normal force [N], finite and >= 0.
    a : float
        Half-length [m], finite and > 0.
    m : ContactMaterial
        Gives the half-width b [m].

    Returns
    -------
    ndarray
        p [Pa].

    Raises
    ------
    ValueError
        If P is negative or not finite, or a is not finite and > 0.
    """
    if not np.all(np.isfinite(P) & (np.asarray(P) >= 0)):
        raise ValueError(f"normal force P = {np.asarray(P).tolist()!r} N is not allowed in the Hertz pressure (eq 22): it must be "
                         "a finite number >= 0.")
    if not np.all(np.isfinite(a) & (np.asarray(a) > 0)):
        raise ValueError(f"half-length a = {np.asarray(a).tolist()!r} m is not allowed in the Hertz pressure (eq 22): it must be "
                         "a finite number > 0.")
    xi = np.asarray(xi, dtype=float)
    r = np.clip(1 - (xi / a) ** 2, 0, None)
    return P / (np.pi * a * m.half_width) * np.sqrt(r)


@dataclass(frozen=True)
class FrictionLaw:
    """The friction law of a contact material (config keys contact.friction_decay, friction_static,
    friction_dynamic; rail.creepage.modes).

    Attributes
    ----------
    name : 'step' (the report's: mu_s in stick, mu_d in slip; friction_decay = 0), 'falling'
        (mu(s) = mu_d + (mu_s - mu_d) exp(-abs(s) / s_0), friction_decay > 0 and mu_s > mu_d) or
        'constant' (friction_decay > 0 with mu_s = mu_d: the falling law is flat and runs the step
        law's result)
    description : the law with its coefficients, in words (a result's friction_law_description)
    """

    name: str
    description: str

    def __post_init__(self):
        if self.name not in FRICTION_LAWS:
            raise ValueError(f"friction law {self.name!r} is not allowed: it must be one of {list(FRICTION_LAWS)}.")

    def __str__(self) -> str:
        return self.name

    @property
    def falling(self) -> bool:
        """Whether the friction falls with the slip velocity (a dynamic-creepage mechanism of its own)."""
        return self.name == "falling"

    @property
    def flat(self) -> bool:
        """Whether contact.friction_decay is set but changes nothing (mu_s = mu_d), which a valid scenario says at start-up."""
        return self.name == "constant"


FRICTION_LAWS = ("step", "falling", "constant")


def friction_law_of(material: ContactMaterial) -> FrictionLaw:
    """The friction law of a contact material, named and described.

    Parameters
    ----------
    material : ContactMaterial
        Its friction_decay s_0 [m/s], friction_static mu_s and friction_dynamic mu_d [-].

    Returns
    -------
    FrictionLaw
    """
    return friction_law(material.friction_decay, material.friction_static, material.friction_dynamic)


def friction_law(friction_decay: float, friction_static: float, friction_dynamic: float) -> FrictionLaw:
    """The friction law of the coefficients (config keys contact.friction_decay, friction_static, friction_dynamic).

    Parameters
    ----------
    friction_decay : float
        s_0 [m/s], >= 0 (0: the report's step).
    friction_static : float
        mu_s [-].
    friction_dynamic : float
        mu_d [-].

    Returns
    -------
    FrictionLaw
    """
    s0, mus, mud = float(friction_decay), float(friction_static), float(friction_dynamic)
    if s0 == 0:
        return FrictionLaw("step", f"friction stepping from mu_s = {mus:g} in stick to mu_d = {mud:g} in slip (the report's)")
    if mus > mud:
        return FrictionLaw("falling", f"friction falling with slip, s_0 = {s0:g} m/s (mu_s = {mus:g}, mu_d = {mud:g})")
    return FrictionLaw("constant", f"friction constant, mu = {mud:g} (contact.friction_decay = {s0:g} m/s has no effect: "
                                   "contact.friction_static = contact.friction_dynamic, so the falling law is flat)")
