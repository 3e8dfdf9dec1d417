"""One scenario: every physical and numerical input of the model chain, as one frozen object (SI units).

A Scenario is built once from a resolved, validated configuration (``rail.setup.build.scenario``)
and handed to the model chain (``rail.chain``). It holds no defaults: every value comes from
config/config.yaml (and a scenario file), whose schema states its unit and valid range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .contact import ContactMaterial, ContactNumerics
from .growth import GrowthSettings
from .halfspace import ElasticMaterial
from .interaction import ContactSpring, Roughness, Wheels, read_roughness_coefficients
from .track import Track
from .wear import WearLaw

__all__ = ["TrackNumerics", "InitialRoughness", "Scenario"]

ROUGHNESS_KINDS = ("smooth", "harmonic", "file")


@dataclass(frozen=True)
class TrackNumerics:
    """Moving-load receptance numerics (config key ``numerics.track``).

    harmonics : K, harmonics of the sleeper-passing frequency [-], >= 1
    rtol      : relative tolerance of the wavenumber quadrature [-], in (0, 1)
    """

    harmonics: int
    rtol: float

    def __post_init__(self):
        if int(self.harmonics) != self.harmonics or self.harmonics < 1:
            raise ValueError(f"numerics.track.harmonics = {self.harmonics!r} is not allowed: it must be an integer >= 1.")
        if not (np.isfinite(self.rtol) and 0 < self.rtol < 1):
            raise ValueError(f"numerics.track.rtol = {self.rtol!r} is not allowed: it must lie in (0, 1).")


@dataclass(frozen=True)
class InitialRoughness:
    """The rail-head roughness a growth run starts from (config key ``roughness``, eqs 18-19).

    kind       : 'smooth', 'harmonic' (z = amplitude cos(2 pi x / wavelength), x = 0 at a support)
                 or 'file' (eq 18 coefficients per bay harmonic, CSV k,A_m,B_m)
    amplitude  : [m], kind 'harmonic'
    frequency  : excitation frequency V / wavelength [Hz], kind 'harmonic' without a wavelength
    wavelength : [m] or None, kind 'harmonic' (must divide the sleeper spacing)
    file       : path or None, kind 'file'
    """

    kind: str
    amplitude: float
    frequency: float
    wavelength: float | None
    file: str | None

    def __post_init__(self):
        if self.kind not in ROUGHNESS_KINDS:
            raise ValueError(f"roughness.kind = {self.kind!r} is not allowed: it must be one of {list(ROUGHNESS_KINDS)}.")
        if self.kind == "file" and not self.file:
            raise ValueError("roughness.kind = 'file' needs roughness.file, a CSV with header k,A_m,B_m.")

    def realise(self, speed: float, L: float, K: int) -> Roughness:
        """The roughness coefficients Z_k, k = -K..K [m] at train speed ``speed`` [m/s] on a bay of
        length L [m]."""
        if self.kind == "smooth":
            return Roughness.smooth(K)
        if self.kind == "file":
            k, A, B = read_roughness_coefficients(self.file)
            return Roughness.from_coefficients(k, A, B, K)
        wavelength = self.wavelength if self.wavelength is not None else speed / self.frequency
        return Roughness.harmonic(self.amplitude, float(wavelength), L, K)


@dataclass(frozen=True)
class Scenario:
    """Everything the model chain computes from (rail.chain), for one scenario.

    name             : scenario name (config/scenarios/<name>.yaml; 'default' for config.yaml)
    track            : Table 1 track (sec. 4.1)
    track_numerics   : harmonics and quadrature tolerance of the receptance table
    wheels           : the train's wheels
    spring           : linearised Hertz contact spring with its damping
    material         : contact parameters (secs 4.2-4.3)
    elastic          : rail steel as an elastic half-space (sec. 3)
    wear_law         : rho and K of eq 49
    contact_numerics : tangential-contact grid and closure
    growth           : growth-loop settings (sec. 5)
    roughness        : the initial roughness
    speeds           : train speeds of the scenario's studies [m/s]
    """

    name: str
    track: Track
    track_numerics: TrackNumerics
    wheels: Wheels
    spring: ContactSpring
    material: ContactMaterial
    elastic: ElasticMaterial
    wear_law: WearLaw
    contact_numerics: ContactNumerics
    growth: GrowthSettings
    roughness: InitialRoughness
    speeds: tuple

    @property
    def L(self) -> float:
        """Sleeper spacing, the roughness period [m]."""
        return self.track.L

    @property
    def harmonics(self) -> int:
        """K, harmonics of the sleeper-passing frequency [-]."""
        return self.track_numerics.harmonics
