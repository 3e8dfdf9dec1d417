"""One-third-octave bands in frequency and in wavelength: one edge rule, one membership rule.

Every band the package uses is defined here: the frequency bands of the track decay rate
(rail.decay), the wavelength bands of the roughness input (rail.roughness), of the band view of a
growth run (rail.studies.bands) and of the rolling-noise export (rail.studies.exports).

Conventions
-----------
* The edge rule (IEC 61260-1:2014, base-ten one-third-octave bands, octave ratio G = 10^(3/10)):
  the exact centres are f_n = 1000 Hz 10^(n/10) in frequency and lambda_n = 1 m 10^(-n/10) in
  wavelength, n an integer, and a band's edges are its exact centre times 10^(-+1/20), the series
  at the half-integer indices n -+ 1/2 (exact_edges, each edge computed once from its own index).
  Neighbouring bands therefore meet exactly and partition the axis. The rule is its own image
  under lambda = V / f: the band at f Hz seen at a speed V m/s is the wavelength band V / f, with
  lower_lambda = V / upper_f and upper_lambda = V / lower_f.
* Nominal labels: a band is named by its nominal centre, not its exact one. In frequency, IEC
  61260-1's preferred values (100, 125, 160, ..., 800 Hz in each decade,
  NOMINAL_THIRD_OCTAVE_CENTRES); in wavelength, EN 15610:2019 and EN ISO 3095:2013's labels
  1 m, 0.8 m, 0.63 m, ..., 3.15 mm (NOMINAL_WAVELENGTHS_M; CNOSSOS-EU extends them to 2 m .. 0.8 mm,
  rail.studies.exports). Every label is within 0.95 % of its exact centre; a wavelength names a
  band when it is within NOMINAL_TOLERANCE = 1.5 % of either (nominal_band); neighbouring
  bands are 26 % apart.
* Membership (in_band): a wavelength lam lies in a band when lower < lam <= upper, so a line on
  an edge belongs to the band of the shorter wavelengths (in frequency: lower <= f < upper, the
  band of the higher frequencies). The spectrum synthesis (rail.roughness.spectrum_coefficients)
  and every analysis (rail.studies.bands, fleet, ensemble) use it, so a realised spectrum is
  analysed back to its levels.
* Centres off the base-ten series (a user's spectrum may use any centres): band_edges puts the
  edge between neighbouring bands at the geometric mean of their centres (for exact centres that
  is the edge rule above) and the outermost edges 2^(+-1/6) from their centres;
  third_octave_edges uses the exact edges for every centre on the series and band_edges for the
  rest.
* Units: frequency bands in Hz, wavelength bands in m (ThirdOctaveBands.unit).

References
----------
IEC 61260-1:2014, *Electroacoustics - Octave-band and fractional-octave-band filters - Part 1:
Specifications*: the base-ten octave ratio, the exact mid-band and band-edge frequencies of
fractional-octave bands, and the nominal mid-band frequencies that label them.

EN 15610:2019, *Railway applications - Acoustics - Rail and wheel roughness measurement related to
noise generation*: one-third-octave wavelength bands and their nominal centre wavelengths.

EN ISO 3095:2013, *Acoustics - Railway applications - Measurement of noise emitted by railbound
vehicles*: its rail roughness limit spectrum, in the same wavelength bands.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["NOMINAL_THIRD_OCTAVE_CENTRES", "NOMINAL_WAVELENGTHS_M", "NOMINAL_TOLERANCE",
           "ThirdOctaveBands", "exact_centres", "exact_edges", "frequency_bands", "wavelength_bands", "nominal_band",
           "band_edges", "third_octave_edges", "in_band"]

# IEC 61260-1 nominal one-third-octave centres of one decade [Hz]; other decades scale by 10.
NOMINAL_THIRD_OCTAVE_CENTRES = (100, 125, 160, 200, 250, 315, 400, 500, 630, 800)

# EN 15610 nominal centre wavelengths [m] of the exact series 10^(-n/10) m, n = 0..25
NOMINAL_WAVELENGTHS_M = np.array([1.0, 0.8, 0.63, 0.5, 0.4, 0.315, 0.25, 0.2, 0.16, 0.125, 0.1, 0.08, 0.063, 0.05,
                                  0.04, 0.0315, 0.025, 0.02, 0.016, 0.0125, 0.01, 0.008, 0.0063, 0.005, 0.004, 0.00315])
# a wavelength names a band when within this fraction of its nominal label or its exact centre
# (the labels are at most 0.95 % from the exact centres; neighbouring bands are 26 % apart)
NOMINAL_TOLERANCE = 0.015

_UNITS = ("Hz", "m")


@dataclass(frozen=True, kw_only=True)
class ThirdOctaveBands:
    """One-third-octave bands, in frequency (unit "Hz") or in wavelength (unit "m").

    centre  : exact centres, 1000 Hz 10^(n/10) or 1 m 10^(-n/10)
    nominal : nominal labels (IEC 61260-1 in Hz; EN 15610 in m)
    lower   : lower edges, centre 10^(-1/20) (exact_edges)
    upper   : upper edges, centre 10^(+1/20)
    (wavelength bands longest first: lower[k] is upper[k + 1]; frequency bands lowest first:
    upper[k] is lower[k + 1])
    unit    : "Hz" or "m", the unit of all four
    """

    centre: np.ndarray
    nominal: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    unit: str

    def __post_init__(self):
        if self.unit not in _UNITS:
            raise ValueError(f"ThirdOctaveBands unit = {self.unit!r} is not allowed: it must be 'Hz' (frequency bands) or 'm' (wavelength bands).")

    def select(self, keep) -> ThirdOctaveBands:
        """The bands where ``keep`` (a boolean mask or index array over the bands) holds."""
        return ThirdOctaveBands(centre=self.centre[keep], nominal=self.nominal[keep], lower=self.lower[keep],
                                upper=self.upper[keep], unit=self.unit)


def exact_centres(n, unit: str):
    """Exact centres of base-ten one-third-octave bands n (IEC 61260-1:2014): 1000 Hz 10^(n/10) in
    frequency, 1 m 10^(-n/10) in wavelength.

    Parameters
    ----------
    n : array-like of int
        Band indices [-] (n = 0: 1000 Hz, or 1 m).
    unit : str
        "Hz" (frequency bands) or "m" (wavelength bands).

    Returns
    -------
    ndarray
        Centres [unit].
    """
    n = np.asarray(n, dtype=float)
    if unit == "Hz":
        return 1000.0 * 10 ** (n / 10)
    if unit == "m":
        return 10.0 ** (-n / 10)
    raise ValueError(f"unit = {unit!r} is not allowed: it must be 'Hz' (frequency bands) or 'm' (wavelength bands).")


def exact_edges(n, unit: str):
    """The one edge rule (IEC 61260-1:2014, base-ten): band n's edges are the exact series at the
    half-integer indices n -+ 1/2, its exact centre times 10^(-+1/20): 1000 Hz 10^((2n -+ 1)/20) in
    frequency, 1 m 10^(-(2n +- 1)/20) in wavelength.

    Each edge is computed from its own (odd) index 2n +- 1, so the upper edge of one band and the
    lower edge of its neighbour are the same number: the bands partition the axis exactly.

    Parameters
    ----------
    n : array-like of int
        Band indices [-] (n = 0: 1000 Hz, or 1 m).
    unit : str
        "Hz" (frequency bands) or "m" (wavelength bands).

    Returns
    -------
    lower, upper : ndarray
        Band edges [unit].
    """
    n = np.asarray(n, dtype=float)
    if unit == "Hz":
        return 1000.0 * 10 ** ((2 * n - 1) / 20), 1000.0 * 10 ** ((2 * n + 1) / 20)
    if unit == "m":
        return 10.0 ** (-(2 * n + 1) / 20), 10.0 ** (-(2 * n - 1) / 20)
    raise ValueError(f"unit = {unit!r} is not allowed: it must be 'Hz' (frequency bands) or 'm' (wavelength bands).")


def frequency_bands(f_min: float = 100.0, f_max: float = 5000.0) -> ThirdOctaveBands:
    """The one-third-octave frequency bands (base-10, IEC 61260-1) whose nominal centres lie in
    [f_min, f_max].

    Parameters
    ----------
    f_min : float, optional
        Lowest nominal centre frequency [Hz]; default 100.
    f_max : float, optional
        Highest nominal centre frequency [Hz]; default 5000.

    Returns
    -------
    ThirdOctaveBands
        Nominal and exact centre frequencies 1000 * 10^(n/10) and band edges [Hz].

    Raises
    ------
    ValueError
        If no band has its nominal centre in [f_min, f_max].
    """
    n = np.arange(-30, 31)  # 1 Hz to 1 MHz
    nominal = np.array([NOMINAL_THIRD_OCTAVE_CENTRES[i % 10] * 10.0 ** (i // 10 - 1) for i in n + 20])
    keep = (nominal >= f_min * (1 - 1e-9)) & (nominal <= f_max * (1 + 1e-9))
    if not keep.any():
        raise ValueError(f"no one-third-octave band has its nominal centre in [{f_min}, {f_max}] Hz.")
    lower, upper = exact_edges(n[keep], "Hz")
    return ThirdOctaveBands(centre=exact_centres(n[keep], "Hz"), nominal=nominal[keep], lower=lower, upper=upper, unit="Hz")


def wavelength_bands(longest: float = 1.0, shortest: float = 0.00315) -> ThirdOctaveBands:
    """The one-third-octave wavelength bands (EN 15610 labels) from ``longest`` to ``shortest``
    centre wavelength.

    Parameters
    ----------
    longest, shortest : float
        Range of the centre wavelengths [m], within 1 m .. 3.15 mm.

    Returns
    -------
    ThirdOctaveBands
        Exact centres 10^(-n/10) m, their EN 15610 labels and edges [m], longest first.

    Raises
    ------
    ValueError
        If no band of 1 m .. 3.15 mm lies between ``longest`` and ``shortest``.
    """
    n = np.arange(len(NOMINAL_WAVELENGTHS_M))
    sel = (NOMINAL_WAVELENGTHS_M <= longest * 1.0001) & (NOMINAL_WAVELENGTHS_M >= shortest * 0.9999)
    if not sel.any():
        raise ValueError(f"no third-octave band between {longest} m and {shortest} m.")
    lower, upper = exact_edges(n[sel], "m")
    return ThirdOctaveBands(centre=exact_centres(n[sel], "m"), nominal=NOMINAL_WAVELENGTHS_M[sel], lower=lower, upper=upper, unit="m")


def nominal_band(wavelength: float) -> int:
    """Index in NOMINAL_WAVELENGTHS_M of the one-third-octave band a wavelength names, or -1.

    A wavelength names band n when it lies within NOMINAL_TOLERANCE (1.5 %) of its nominal label
    (1, 0.8, 0.63, ... m) or of its exact centre 10^(-n/10) m.

    Parameters
    ----------
    wavelength : float
        [m].

    Returns
    -------
    int
    """
    n = np.arange(len(NOMINAL_WAVELENGTHS_M))
    off = np.minimum(np.abs(wavelength / NOMINAL_WAVELENGTHS_M - 1), np.abs(wavelength / exact_centres(n, "m") - 1))
    k = int(np.argmin(off))
    return k if off[k] <= NOMINAL_TOLERANCE else -1


def band_edges(wavelength):
    """Edges of one-third-octave wavelength bands from their (nominal) centres.

    Neighbouring bands (centres a third octave apart, within 5 %) meet at the geometric mean of
    their centres (for exact centres that is 2^(1/6) from each), so that nominal centres such as
    0.315 m and 0.25 m still partition the wavelength axis; other edges are 2^(+-1/6) from their
    centres.

    Parameters
    ----------
    wavelength : ndarray
        Band centre wavelengths [m], distinct.

    Returns
    -------
    lower, upper : ndarray
        Band edges [m], in the order of ``wavelength``.
    """
    lam = np.asarray(wavelength, dtype=float)
    order = np.argsort(lam)
    s = lam[order]
    adjacent = s[1:] / s[:-1] < 1.05 * 2 ** (1 / 3)  # neighbouring third-octave bands
    mid = np.sqrt(s[1:] * s[:-1])
    lo_s = np.r_[s[0] * 2 ** (-1 / 6), np.where(adjacent, mid, s[1:] * 2 ** (-1 / 6))]
    hi_s = np.r_[np.where(adjacent, mid, s[:-1] * 2 ** (1 / 6)), s[-1] * 2 ** (1 / 6)]
    lo, hi = np.empty_like(lam), np.empty_like(lam)
    lo[order], hi[order] = lo_s, hi_s
    return lo, hi


def third_octave_edges(wavelength):
    """Edges of the bands a spectrum's centre wavelengths name, by the one edge rule: a centre
    within NOMINAL_TOLERANCE of an exact base-ten centre 10^(-n/10) m (every EN 15610 and
    CNOSSOS-EU nominal label is, 2 m .. 0.8 mm) has the edges 10^(-(2n +- 1)/20) m (exact_edges);
    any other centre has the edges of band_edges.

    Parameters
    ----------
    wavelength : ndarray
        Band centre wavelengths [m], distinct.

    Returns
    -------
    lower, upper : ndarray
        Band edges [m]; a wavelength lam lies in a band when lower < lam <= upper (in_band).
    """
    lam = np.asarray(wavelength, dtype=float)
    lo, hi = band_edges(lam)
    n = np.round(-10 * np.log10(lam))
    on = np.abs(lam / exact_centres(n, "m") - 1) <= NOMINAL_TOLERANCE
    exact_lo, exact_hi = exact_edges(n, "m")
    return np.where(on, exact_lo, lo), np.where(on, exact_hi, hi)


def in_band(lam, lower, upper):
    """Whether wavelengths lie in a band: lower < lam <= upper (a line on an edge belongs to the band of
    the shorter wavelengths), the one rule of the synthesis (rail.roughness.spectrum_coefficients) and
    the analysis (rail.studies.bands.band_mean_square), so that a realised spectrum is analysed back to
    its levels.

    Parameters
    ----------
    lam : ndarray
        Wavelengths [m].
    lower, upper : float
        Band edges [m].

    Returns
    -------
    ndarray of bool
    """
    lam = np.asarray(lam)
    return (lam > lower) & (lam <= upper)
