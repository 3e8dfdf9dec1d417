"""One scenario: every physical and numerical input of the model chain, as one frozen object (SI units).

A Scenario is built once from a resolved, validated configuration (``rail.setup.build.scenario``)
and handed to the model chain (``rail.chain``). It holds no defaults: every value comes from
config/config.yaml (and a scenario file), whose schema states its unit and valid range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .contact import ContactMaterial, ContactNumerics, FrictionLaw, NormalContact, WearPath
from .creepage.choices import RailFlexibility, WheelsetModel, rail_flexibility_of, wheelset_model_of
from .growth import GrowthSettings
from .halfspace import ElasticMaterial
from .interaction import ContactSpring, Roughness, Wheels, read_roughness_coefficients
from .roughness import (RECORD_MODES, SPIKE_THRESHOLD, process_profile, profile_statement, read_profile_record, read_spectrum_table,
                        spectrum_coefficients)
from .track import Track
from .wear import WearLaw

__all__ = ["TrackNumerics", "InitialRoughness", "ModelChoices", "Scenario"]

ROUGHNESS_KINDS = ("smooth", "harmonic", "file", "profile", "spectrum")


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

    Attributes
    ----------
    kind : 'smooth', 'harmonic' (z = amplitude cos(2 pi x / wavelength), x = 0 at a support),
                 'file' (eq 18 coefficients per bay harmonic, CSV k,A_m,B_m), 'profile' (a measured
                 profile, CSV position_m,height_m) or 'spectrum' (a one-third-octave wavelength
                 spectrum, CSV wavelength_m,level_dB, realised with random phases; rail.roughness)
    amplitude : [m], kind 'harmonic'
    frequency : excitation frequency V / wavelength [Hz], kind 'harmonic' without a wavelength
    wavelength : [m] or None, kind 'harmonic' (must divide the period N L)
    file : path or None, kinds 'file', 'profile', 'spectrum'
    bays : N, the roughness period in sleeper bays [-], >= 1 (with record 'period': the bays
        the record holds, rail.setup.build takes them from the record)
    seed : seed of the random phases [-], kind 'spectrum'
    record : kind 'profile': 'average' (the whole record, its N L segments averaged) or 'period'
        (N L from the record's length) [-]; rail.roughness.process_profile
    spike_removal : kind 'profile': remove spikes and pits first (rail.roughness.remove_spikes) [-]
    spike_threshold : their curvature criterion, robust standard deviations [-], > 0
    """

    kind: str
    amplitude: float
    frequency: float
    wavelength: float | None
    file: str | None
    bays: int = 1
    seed: int = 0
    record: str = "average"
    spike_removal: bool = False
    spike_threshold: float = SPIKE_THRESHOLD

    def __post_init__(self):
        if self.kind not in ROUGHNESS_KINDS:
            raise ValueError(f"roughness.kind = {self.kind!r} is not allowed: it must be one of {list(ROUGHNESS_KINDS)}.")
        if self.kind in ("file", "profile", "spectrum") and not self.file:
            header = {"file": "k,A_m,B_m", "profile": "position_m,height_m", "spectrum": "wavelength_m,level_dB"}[self.kind]
            raise ValueError(f"roughness.kind = '{self.kind}' needs roughness.file, a CSV with header {header}.")
        if self.record not in RECORD_MODES:
            raise ValueError(f"roughness.record = {self.record!r} is not allowed: it must be one of {list(RECORD_MODES)}.")
        if self.kind != "profile" and (self.record != "average" or self.spike_removal):
            key = "roughness.spike_removal = true" if self.spike_removal else f"roughness.record = '{self.record}'"
            raise ValueError(f"{key} is not allowed with roughness.kind = '{self.kind}': it applies to a measured profile "
                             "(kind: profile) only.")
        if not (np.isfinite(self.spike_threshold) and self.spike_threshold > 0):
            raise ValueError(f"roughness.spike_threshold = {self.spike_threshold!r} is not allowed: it must be a finite number > 0.")
        if int(self.bays) != self.bays or self.bays < 1:
            raise ValueError(f"roughness.bays = {self.bays!r} is not allowed: it must be an integer >= 1.")
        if self.kind == "harmonic":
            if not (np.isfinite(self.amplitude) and self.amplitude >= 0):
                raise ValueError(f"roughness.amplitude = {self.amplitude!r} m is not allowed: it must be a finite number >= 0.")
            if self.wavelength is None and not (np.isfinite(self.frequency) and self.frequency > 0):
                raise ValueError(f"roughness.frequency = {self.frequency!r} Hz is not allowed: it must be a finite number > 0.")

    def realise(self, speed: float, L: float, K: int) -> Roughness:
        """The initial roughness at a train speed.

        Parameters
        ----------
        speed : float
            Train speed [m/s] (a harmonic roughness may be given by its excitation frequency).
        L : float
            Sleeper spacing [m]; the period is N L.
        K : int
            Harmonics of the sleeper-passing frequency [-]: Z_j for abs(j) <= N K.

        Returns
        -------
        Roughness
            Z_j [m] over N = bays bays.
        """
        N = int(self.bays)
        if self.kind == "smooth":
            return Roughness.smooth(K, N)
        if self.kind == "file":
            k, A, B = read_roughness_coefficients(self.file)
            return Roughness.from_coefficients(k, A, B, K, N)
        if self.kind == "profile":
            return Roughness(self._profile(L, K)[1].Z, N)
        if self.kind == "spectrum":
            t = read_spectrum_table(self.file)
            return Roughness(spectrum_coefficients(t.wavelength, t.level_dB, N * L, N * K, self.seed, source=str(self.file)), N)
        wavelength = self.wavelength if self.wavelength is not None else speed / self.frequency
        return Roughness.harmonic(self.amplitude, float(wavelength), L, K, N)


    def _profile(self, L: float, K: int):
        rec = read_profile_record(self.file)
        N = int(self.bays)
        return rec, process_profile(rec.x, rec.z, N * L, N * K, mode=self.record, spikes=bool(self.spike_removal),
                                    spike_threshold=float(self.spike_threshold), source=str(self.file))

    def statement(self, L: float, K: int) -> dict:
        """What the initial roughness was read from and how it was processed, as result attributes
        (rail.roughness.profile_statement for a measured profile; the file, units, rows and range for
        a spectrum; the kind otherwise).

        Parameters
        ----------
        L : float
            Sleeper spacing [m].
        K : int
            Harmonics of the sleeper-passing frequency [-].

        Returns
        -------
        dict
            Attribute name -> str, int or float ([m] where the name ends in _m).
        """
        out = {"roughness_kind": self.kind}
        if self.kind == "profile":
            rec, p = self._profile(L, K)
            out.update(profile_statement(rec, p, float(self.spike_threshold)))
        elif self.kind == "spectrum":
            out["roughness_input"] = read_spectrum_table(self.file).describe()
        return out


@dataclass(frozen=True)
class ModelChoices:
    """A scenario's model choices, each an object with ``name`` (the configuration's value) and
    ``description`` (Scenario.models; issue 54: no module outside a model's package compares a name).

    Attributes
    ----------
    normal_contact : rail.contact.NormalContact (contact.normal)
    wear_path : rail.contact.WearPath (contact.wear_path)
    wheelset : rail.creepage.choices.WheelsetModel (wheelset.model)
    rail_flexibility : rail.creepage.choices.RailFlexibility (rail_flexibility.model)
    friction_law : rail.contact.FrictionLaw (contact.friction_decay, friction_static, friction_dynamic)
    """

    normal_contact: NormalContact
    wear_path: WearPath
    wheelset: WheelsetModel
    rail_flexibility: RailFlexibility
    friction_law: FrictionLaw

    def attributes(self) -> dict:
        """The choices as a result's attributes: each value beside its description (``wear_path = "patch"``
        and ``wear_path_description``, with the flag contact_shift_modelled; normal_contact, wheelset_model,
        rail_flexibility, friction_law), read back by value (rail.contact.wear_path,
        rail.creepage.choices.wheelset_model, ...), never parsed.

        Returns
        -------
        dict
            Attribute name -> str [-] (contact_shift_modelled: int 0 or 1).
        """
        out = self.wear_path.attributes()  # with its flag contact_shift_modelled
        for key, choice in (("normal_contact", self.normal_contact), ("wheelset_model", self.wheelset),
                            ("rail_flexibility", self.rail_flexibility), ("friction_law", self.friction_law)):
            out[key] = choice.name
            out[f"{key}_description"] = choice.description
        return out


@dataclass(frozen=True)
class Scenario:
    """Everything the model chain computes from (rail.chain), for one scenario.

    Attributes
    ----------
    name : scenario name (config/scenarios/<name>.yaml; 'default' for config.yaml)
    track : Table 1 track (sec. 4.1)
    track_numerics : harmonics and quadrature tolerance of the receptance table
    wheels : the train's wheels
    spring : linearised Hertz contact spring with its damping
    material : contact parameters (secs 4.2-4.3)
    elastic : rail steel as an elastic half-space (sec. 3)
    wear_law : rho and K of eq 49
    contact_numerics : tangential-contact grid and closure
    growth : growth-loop settings (sec. 5)
    roughness : the initial roughness
    speeds : train speeds of the scenario's studies [m/s]
    axles_per_day : traffic over the rail, wheel passages per day on one rail [1/day]
    cell : the track's cell of N bays whose supports differ (rail.cell.TrackCell), or None
                       for identical supports at equal spacing; ``track`` is then its nominal track
                       with the mean spacing P / N
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
    axles_per_day: float
    cell: object = None

    @property
    def models(self) -> ModelChoices:
        """The scenario's model choices as objects, read from what the chain runs (the contact numerics'
        normal contact and wear path, the material's wheelset modes, rail head and friction), so that a
        scenario with another material or contact numerics (dataclasses.replace) names its own."""
        m = self.material
        return ModelChoices(self.contact_numerics.normal, self.contact_numerics.path, wheelset_model_of(m.longitudinal),
                            rail_flexibility_of(m.rail_flexibility), m.friction_law)

    @property
    def L(self) -> float:
        """Sleeper spacing, the roughness period [m]."""
        return self.track.L

    @property
    def harmonics(self) -> int:
        """K, harmonics of the sleeper-passing frequency [-]."""
        return self.track_numerics.harmonics
