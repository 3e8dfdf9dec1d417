"""Turn a validated configuration mapping into frozen parameter dataclasses (SI units).

This is the one place where dictionaries become dataclasses; everything below takes
dataclasses and arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .halfspace import ElasticMaterial, HalfSpaceNumerics
from .contact import ContactMaterial
from .interaction import ContactSpring, Roughness, Wheels
from .track import Ballast, Pad, Rail, Sleeper, Track

__all__ = [
    "HalfSpaceFigureSettings", "material", "halfspace_numerics", "halfspace_figures", "track",
    "wheels", "contact_spring", "roughness", "harmonics", "contact_material", "growth_settings",
]


@dataclass(frozen=True, slots=True)
class HalfSpaceFigureSettings:
    """What Figs 2-6 show.

    frequency       : Hz, frequency of Figs 2-4
    radius          : m, observer distance of Fig. 2
    radii           : m, observer distances of Fig. 4
    frequencies     : Hz, frequencies of Figs 5-6 (from 0)
    hertz_stiffness : N/m, k_H of Fig. 6
    """

    frequency: float
    radius: float
    radii: np.ndarray
    frequencies: np.ndarray
    hertz_stiffness: float


def material(cfg: dict) -> ElasticMaterial:
    """Rail steel as an elastic half-space (config key ``material``)."""
    m = cfg["material"]
    return ElasticMaterial(float(m["youngs_modulus"]), float(m["poisson_ratio"]), float(m["density"]))


def halfspace_numerics(cfg: dict) -> HalfSpaceNumerics:
    """Quadrature settings of eq (16) (config key ``numerics.halfspace``)."""
    n = cfg["numerics"]["halfspace"]
    return HalfSpaceNumerics(epsrel=float(n["epsrel"]), limit=int(n["limit"]))


def halfspace_figures(cfg: dict) -> HalfSpaceFigureSettings:
    """Settings of Figs 2-6 (config key ``figures.halfspace`` and ``contact.hertz_stiffness``)."""
    f = cfg["figures"]["halfspace"]
    return HalfSpaceFigureSettings(
        frequency=float(f["frequency"]),
        radius=float(f["radius"]),
        radii=np.linspace(float(f["radius_min"]), float(f["radius_max"]), int(f["radius_count"])),
        frequencies=np.linspace(0.0, float(f["frequency_max"]), int(f["frequency_count"])),
        hertz_stiffness=float(cfg["contact"]["hertz_stiffness"]),
    )


def track(cfg: dict) -> Track:
    """Table 1 track (config key ``track``)."""
    t = cfg["track"]
    r, p, s, b = t["rail"], t["pad"], t["sleeper"], t["ballast"]
    return Track(
        rail=Rail(
            youngs_modulus=float(r["youngs_modulus"]),
            shear_modulus=float(r["shear_modulus"]),
            density=float(r["density"]),
            area=float(r["area"]),
            second_moment_of_area=float(r["second_moment_of_area"]),
            shear_coefficient=float(r["shear_coefficient"]),
            loss_factor=float(r["loss_factor"]),
            damping_time=float(r["damping_time"]),
        ),
        pad=Pad(float(p["stiffness"]), float(p["loss_factor"]), float(p["viscous_damping"])),
        sleeper=Sleeper(float(s["mass"]), float(s["spacing"])),
        ballast=Ballast(float(b["stiffness"]), float(b["loss_factor"]), float(b["viscous_damping"])),
        damping=str(t["damping"]),
    )


def harmonics(cfg: dict) -> int:
    """K, the number of sleeper-passing harmonics (config key ``numerics.track.harmonics``)."""
    return int(cfg["numerics"]["track"]["harmonics"])


def wheels(cfg: dict) -> Wheels:
    """The train's wheels (config key ``wheels``)."""
    w = cfg["wheels"]
    return Wheels(float(w["mass"]), float(w["radius"]), float(w["static_load"]), tuple(float(a) for a in w["positions"]))


def contact_spring(cfg: dict) -> ContactSpring:
    """Linearised Hertz spring; its damping from the half-space model (Fig. 6), a constant or none."""
    from .halfspace import contact_loss_factor

    c = cfg["contact"]
    kH = float(c["hertz_stiffness"])
    model = c["loss_factor_model"]
    if model == "halfspace":
        om = 2 * np.pi * 1000.0  # eta_H is exactly proportional to frequency: one value gives the slope
        return ContactSpring(kH, loss_slope=float(contact_loss_factor(om, kH, material(cfg)) / om))
    if model == "constant":
        return ContactSpring(kH, loss_factor=float(c["loss_factor"]))
    return ContactSpring(kH)


def roughness(cfg: dict, speed: float, L: float, K: int) -> Roughness:
    """Initial roughness (config key ``roughness``) at the given speed, m."""
    r = cfg["roughness"]
    if r["kind"] == "smooth":
        return Roughness.smooth(K)
    if r["kind"] == "file":
        from .interaction import read_roughness_coefficients

        k, A, B = read_roughness_coefficients(r["file"])
        return Roughness.from_coefficients(k, A, B, K)
    wavelength = r.get("wavelength")
    if wavelength is None:
        wavelength = speed / float(r["frequency"])
    return Roughness.harmonic(float(r["amplitude"]), float(wavelength), L, K)


def contact_material(cfg: dict) -> ContactMaterial:
    """Contact parameters of sections 4.2-4.3 (config keys ``material``, ``contact``, ``wheels``)."""
    c, mat = cfg["contact"], cfg["material"]
    return ContactMaterial(
        youngs_modulus=float(mat["youngs_modulus"]),
        poisson_ratio=float(mat["poisson_ratio"]),
        half_width=float(c["half_width"]),
        wheel_radius=float(cfg["wheels"]["radius"]),
        friction_dynamic=float(c["friction_dynamic"]),
        friction_static=float(c["friction_static"]),
        creepage=float(c["creepage"]),
    )


def growth_settings(cfg: dict):
    """Growth loop settings (config keys ``growth``, ``numerics.contact``, ``contact.closure``)."""
    from .growth import GrowthSettings

    g, c = cfg["growth"], cfg["contact"]
    return GrowthSettings(
        passages=int(g["passages"]),
        passages_per_update=int(g["passages_per_update"]),
        save_every=int(g["save_every"]),
        nodes=int(cfg["numerics"]["contact"]["nodes"]),
        closure=str(c["closure"]),
        closure_scale=float(c["closure_scale"]),
        vary_grid_spacing=bool(g["vary_grid_spacing"]),
        step_tolerance=float(g["step_tolerance"]),
    )
