"""The growth-rate spectrum under a fleet: the traffic-weighted sum of its classes' spectra."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .probes import RateSpectrum, sorted_eigenvalues
from .spectrum import rate_spectrum

__all__ = ["FleetRateSpectrum", "combine_spectra", "fleet_rate_spectrum", "fleet_spectrum_of"]


@dataclass(frozen=True)
class FleetRateSpectrum:
    """The growth-rate spectrum under a fleet (fleet_rate_spectrum).

    total   : the traffic-weighted spectrum, rates per fleet passage (one train drawn from the traffic)
    classes : the spectrum of each (vehicle, speed) class, rates per passage of that class's train
    weights : (c,) the classes' weights w_c [-], summing to 1
    labels  : (c,) '<vehicle> at <speed> m/s'
    speeds  : (c,) the classes' speeds [m/s]
    """

    total: RateSpectrum
    classes: tuple
    weights: np.ndarray
    labels: tuple
    speeds: np.ndarray


def combine_spectra(spectra, weights) -> RateSpectrum:
    """The weighted sum of growth-rate spectra on the same lines (the wear is linear about the smooth rail).

    At a free line the rate is sum_c w_c R_c; at a locked line the 2 x 2 operators are summed and the
    rates are the eigenvalues of sum_c w_c M_c (not the sum of the eigenvalues, unless the classes'
    operators commute). The smooth rail's source and the grid spread are summed with the weights: an
    upper bound, since the classes' smooth-rail wear and grid errors need not be in phase. The sideband
    ratio and the linearity are the largest over the classes.

    Parameters
    ----------
    spectra : sequence of RateSpectrum
        On the same lines and period.
    weights : sequence of float
        w_c [-].

    Returns
    -------
    RateSpectrum
    """
    first = spectra[0]
    w = np.asarray(weights, dtype=float)
    if any(not np.array_equal(s.line, first.line) or s.bays != first.bays for s in spectra):
        raise ValueError("the classes' spectra must share their lines and period (one spectrum_lines call).")
    rate = sum(wc * s.rate for wc, s in zip(w, spectra))
    other = np.conj(rate)
    held = np.flatnonzero(first.locked)
    operator = None
    if held.size:
        if any(s.operator is None for s in spectra):
            raise ValueError("a locked line needs the classes' 2 x 2 operators (RateSpectrum.operator).")
        operator = sum(wc * s.operator for wc, s in zip(w, spectra))
        for idx in held:
            rate[idx], other[idx] = sorted_eigenvalues(operator[idx])
    methods = sorted({s.method for s in spectra})
    return RateSpectrum(wavelength=first.wavelength, line=first.line, locked=first.locked, rate=rate, rate_other=other,
                        source=sum(wc * s.source for wc, s in zip(w, spectra)),
                        grid_spread=sum(wc * s.grid_spread for wc, s in zip(w, spectra)),
                        sideband=np.max([s.sideband for s in spectra], axis=0), linearity=max(s.linearity for s in spectra),
                        eps=first.eps, bays=first.bays, grid_phases=first.grid_phases, method="; ".join(methods), operator=operator)


def fleet_rate_spectrum(classes, tables: dict, lines, **kwargs) -> FleetRateSpectrum:
    """Growth-rate spectrum about the smooth rail under a fleet: the traffic-weighted rate per
    wavelength, sum_c w_c R_c per fleet passage (combine_spectra), with each class's spectrum kept.

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
        Each with roughness.bays = N (the lines' period).
    tables : dict
        {speed: the N-bay period's receptance tables} (rail.chain.fleet_tables), shared by the
        vehicles at a speed.
    lines : sequence of int
        Lines j, 1 <= j <= N K [-] (wavenumbers 2 pi j / (N L)).
    **kwargs
        Passed to rate_spectrum (eps, grid_phases, check_lines, method).

    Returns
    -------
    FleetRateSpectrum
    """
    return fleet_spectrum_of(classes, [rate_spectrum(c.scenario, tables[c.speed], lines, **kwargs) for c in classes])


def fleet_spectrum_of(classes, spectra) -> FleetRateSpectrum:
    """The fleet's spectrum from its classes' spectra computed apart (each a job of the workflow, shared
    by the fleets that hold the class): combine_spectra with the classes' weights.

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
    spectra : sequence of RateSpectrum
        rate_spectrum of each class on the same lines, in the order of classes (rates per passage of
        the class's train [-]).

    Returns
    -------
    FleetRateSpectrum
        Rates per fleet passage [-].
    """
    spectra = tuple(spectra)
    if len(spectra) != len(classes):
        raise ValueError(f"{len(spectra)} spectra for {len(classes)} classes: give one spectrum per class.")
    w = np.array([c.weight for c in classes])
    return FleetRateSpectrum(combine_spectra(spectra, w), spectra, w, tuple(c.label for c in classes),
                             np.array([c.speed for c in classes]))
