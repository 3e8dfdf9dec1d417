"""Published roughness spectra by name (CNOSSOS-EU Tables G-1a and G-1b) and a one-third-octave roughness
spectrum as an object: the wheels' roughness of the wheels' source (rail.growth_spectrum.source, issue 58) and the
ground rail it starts from."""

from __future__ import annotations

import numpy as np

from ..bands import nominal_band

__all__ = ["RoughnessSpectrum", "named_spectrum"]


class RoughnessSpectrum:
    """A one-third-octave roughness spectrum (band centres [m], levels [dB re 1 µm]) and where it comes from.

    Parameters
    ----------
    centres : array_like
        Band centre wavelengths [m].
    levels : array_like
        Band levels [dB re 1 µm rms], finite.
    label : str
        Its name and source, for the results' attributes.
    """

    def __init__(self, centres, levels, label: str):
        self.centres = np.asarray(centres, dtype=float)
        self.levels = np.asarray(levels, dtype=float)
        if self.centres.shape != self.levels.shape or self.centres.ndim != 1 or not np.all(np.isfinite(self.levels)):
            raise ValueError(f"{label}: a roughness spectrum needs one finite level per band centre "
                             f"({self.centres.size} centres, {self.levels.size} levels).")
        self.label = label

    def at(self, centres):
        """The levels at other band centres [dB re 1 µm] (by the nominal band each names; NaN where this spectrum has none).

        Parameters
        ----------
        centres : array_like
            Band centre wavelengths [m].

        Returns
        -------
        ndarray
            [dB re 1 µm].
        """
        own = {nominal_band(c): v for c, v in zip(self.centres, self.levels)}
        return np.array([own.get(nominal_band(c), np.nan) for c in np.atleast_1d(centres)])


def named_spectrum(name: str, kind: str = "wheel") -> RoughnessSpectrum:
    """A published spectrum by name: a wheel roughness of CNOSSOS-EU Table G-1a by brake type
    ("cast_iron", "composite", "disc"; Delegated Directive (EU) 2021/1226, rail.noise.tables) or a rail
    roughness of Table G-1b ("E": EN ISO 3095:2013, well maintained and very smooth; "M": the average
    network), on the 35 bands 2000 mm .. 0.8 mm.

    Parameters
    ----------
    name : str
        The brake type (kind 'wheel') or the rail class (kind 'rail').
    kind : str
        'wheel' or 'rail'.

    Returns
    -------
    RoughnessSpectrum
        Centres [m] and levels [dB re 1 µm].
    """
    from . import cnossos

    bands = cnossos.cnossos_wavelength_bands()
    if kind == "wheel":
        return RoughnessSpectrum(bands.centre, cnossos.wheel_roughness(name), f"{name} (CNOSSOS-EU Table G-1a, Delegated Directive (EU) 2021/1226)")
    if kind == "rail":
        return RoughnessSpectrum(bands.centre, cnossos.rail_roughness_class(name),
                             f"class {name} (CNOSSOS-EU Table G-1b, Delegated Directive (EU) 2021/1226)")
    raise ValueError(f"kind = {kind!r} is not allowed: 'wheel' or 'rail'.")
