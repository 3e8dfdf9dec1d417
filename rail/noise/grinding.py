"""Grinding by noise: when the rolling noise of a growing roughness trips a criterion (issue 56).

Beside the roughness limit of the band view (rail.studies.bands.grinding_interval), three criteria:

(a) **rise**: the overall A-weighted level L_A has risen by more than ``rise_dB`` over its value at
    the start of the run (the post-grinding state);
(b) **cycle average**: the energy mean of L_A over the grinding cycle from the start,
    L_avg(n) = 10 lg( 1/(n - n0) int_n0^n 10^(L_A(n')/10) dn' ), is above a target (the Dutch practice
    of a noise-averaged grinding cycle); L_avg(n0) = L_A(n0);
(c) **band rms**: the rms roughness over a wavelength range, from the bands' mean squares
    (sqrt of their sum), is above its limit (Grassie, Saxon & Smith 1999: 3, 7, 7, 45, 100 µm rms in
    10-30, 30-100, 100-300, 300-1000, 1000-3000 mm).

Conventions
-----------
* Passages are axle (wheel) passages on the rail, as in the growth run; levels in dB (L_A in
  dB(A), whatever reference the caller's ``level_of`` uses), roughness mean squares in m^2.
* Between two saves a band's rms amplitude is interpolated linearly in ln(amplitude) (a band with
  no roughness at one end: linearly in amplitude), the rule of the roughness grinding interval, and
  the noise is computed from the interpolated bands (so at a save it is the save's noise exactly).
* Beyond the last save (only up to ``extrapolation_max`` times the run's passages from the start,
  the factor stated with every trip found there): each band the run resolves grows by its own
  fitted law from its level at the last save (rail.growth.band_growth: exponential or straight line
  in amplitude), as the roughness grinding interval extrapolates; a band whose law has a rate <= 0
  is **held** at its last level, never decayed. A criterion the held-or-growing trend does not reach
  within the factor is 'not reached'. With fewer than rail.growth.BAND_GROWTH_SAVES saves there is
  no law: nothing is extrapolated.
* A band with no model level (longer than the period, shorter than the record's shortest
  wavelength) keeps its fill level at every passage count (rail.app.api.noise's ``fill``).
* A band-rms range is assessed only if at least one of its bands is the model's; a range whose
  bands are all filled is 'not assessed' (the model says nothing about it).
* A range holds the one-third-octave bands whose exact centre lambda_c lies in [low, high): the five
  bands 10-25 mm for 10-30 mm, 31.5-80 mm for 30-100 mm, and so on (their edges span
  low 10^(-1/20) .. high 10^(-1/20) x 10^(1/20) in steps of the bands; 31.6 mm, not 30 mm, is the
  edge between the first two).
* "Exceeds" is strictly above; the first crossing is located by bisection to 1e-6 of the run's
  passages, inside the first interval of the evaluation grid (the saves, ``subdivisions`` points in
  each interval between them, and ``extrapolation_points`` beyond the last) where the criterion
  holds at its end. The cycle average is the trapezoidal energy integral on that grid (exact
  where L_A is linear in n between grid points); its crossing is linear between grid points.

References
----------
S. L. Grassie, M. J. Saxon and J. D. Smith, Measurement of longitudinal rail irregularities and
criteria for acceptable grinding, Journal of Sound and Vibration 227(5) (1999) 949-964 (abstract:
"Limits of 3, 7, 7, 45 and 100 microns should be exceeded over less than 5% of the length of ground
track in the wavelength ranges 10-30 mm, 30-100 mm, 100-300 mm, 300-1000 mm and 1000-3000 mm").
Their rms is a statistic along a measured track; railgrowth's roughness is periodic and the same
over every period, so its rms over a range is the one value of the whole track (the 5 % fraction
is 0 % or 100 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..growth import BAND_GROWTH_SAVES, band_growth

__all__ = ["GRASSIE_1999", "BandTrend", "Trip", "NoiseCurve", "band_trend", "noise_curve", "range_bands", "trip_rise",
           "trip_average", "trip_band_rms", "cycle_average"]

# (low [m], high [m], rms limit [m]) of Grassie, Saxon & Smith (1999)
GRASSIE_1999 = ((0.010, 0.030, 3e-6), (0.030, 0.100, 7e-6), (0.100, 0.300, 7e-6), (0.300, 1.000, 45e-6), (1.000, 3.000, 100e-6))


@dataclass(frozen=True)
class BandTrend:
    """The rail roughness per band at any passage count from the saves (module docstring).

    passages    : saved passage counts n [-], increasing, shape (s,)
    ms          : band mean squares at the saves [m^2], shape (s, B); NaN where the model has no level
    fill        : mean square of a band without a model level [m^2], shape (B,) (NaN: none)
    law         : the band's growth law, "exponential", "linear" or "" (none: held), shape (B,)
    exp_rate    : e-folding rate of the rms amplitude [1 per 1e5 passages], shape (B,)
    linear_rate : rms amplitude growth [m per 1e5 passages], shape (B,)
    """

    passages: np.ndarray
    ms: np.ndarray
    fill: np.ndarray
    law: np.ndarray
    exp_rate: np.ndarray
    linear_rate: np.ndarray

    @property
    def model(self) -> np.ndarray:
        """Which bands the model gives (a level at every save), shape (B,)."""
        return np.all(np.isfinite(self.ms), axis=0)

    @property
    def extrapolates(self) -> bool:
        """Whether a growth law was fitted (enough saves)."""
        return bool(np.any(self.law != ""))

    def mean_square(self, n: float) -> np.ndarray:
        """Band mean squares at the passage count n >= passages[0] [m^2], shape (B,)."""
        p = self.passages
        if not n >= p[0]:
            raise ValueError(f"passages = {n!r} is before the first save ({p[0]:g}).")
        model = self.model
        out = np.where(model, 0.0, self.fill)
        a = np.sqrt(np.where(model, self.ms, 0.0))
        if n <= p[-1]:
            k = min(int(np.searchsorted(p, n, side="right")) - 1, len(p) - 2) if len(p) > 1 else 0
            if len(p) == 1:
                amp = a[0]
            else:
                t = (n - p[k]) / (p[k + 1] - p[k])
                a0, a1 = a[k], a[k + 1]
                both = (a0 > 0) & (a1 > 0)
                with np.errstate(divide="ignore", invalid="ignore"):
                    geo = np.exp((1 - t) * np.log(np.where(both, a0, 1.0)) + t * np.log(np.where(both, a1, 1.0)))
                amp = np.where(both, geo, (1 - t) * a0 + t * a1)
        else:
            dn = (n - p[-1]) / 1e5
            last = a[-1]
            grow_e = (self.law == "exponential") & (self.exp_rate > 0)
            grow_l = (self.law == "linear") & (self.linear_rate > 0)
            amp = np.where(grow_e, last * np.exp(np.where(grow_e, self.exp_rate, 0.0) * dn),
                           np.where(grow_l, last + np.where(grow_l, self.linear_rate, 0.0) * dn, last))
        return np.where(model, amp ** 2, out)


def band_trend(passages, ms, fill=None) -> BandTrend:
    """A BandTrend from the saves: each band's growth law fitted by rail.growth.band_growth (with at
    least BAND_GROWTH_SAVES saves; else no law and nothing extrapolated).

    Parameters
    ----------
    passages : array-like, shape (s,)
        Saved passage counts [-], increasing.
    ms : array-like, shape (s, B)
        Band mean squares [m^2]; NaN where the model gives no level.
    fill : array-like, shape (B,), optional
        Mean square [m^2] of the bands without a model level (NaN: none).

    Returns
    -------
    BandTrend
    """
    n = np.asarray(passages, dtype=float)
    ms = np.atleast_2d(np.asarray(ms, dtype=float))
    if n.ndim != 1 or ms.shape[0] != n.size or n.size == 0:
        raise ValueError(f"passages ({n.shape}) and ms ({ms.shape}) do not match: one row of ms per save.")
    if n.size > 1 and not np.all(np.diff(n) > 0):
        raise ValueError("passages must increase from save to save.")
    B = ms.shape[1]
    fill = np.full(B, np.nan) if fill is None else np.asarray(fill, dtype=float)
    if n.size >= BAND_GROWTH_SAVES:
        g = band_growth(n, ms)
        law, er, lr = np.asarray(g.law, dtype=str), np.nan_to_num(g.exp_rate), np.nan_to_num(g.linear_rate)
    else:
        law, er, lr = np.full(B, "", dtype=str), np.zeros(B), np.zeros(B)
    model = np.all(np.isfinite(ms), axis=0)
    law = np.where(model, law, "")
    return BandTrend(n, ms, fill, law, er, lr)


@dataclass(frozen=True)
class NoiseCurve:
    """The noise on the evaluation grid (noise_curve).

    passages     : grid of passage counts [-] (the saves among them), shape (g,)
    level        : overall A-weighted level L_A at each [dB(A)], shape (g,)
    band_energy  : A-weighted energy per frequency band, 10^(L/10), shape (g, F)
    extrapolated : True beyond the last save, shape (g,)
    saves        : index of each save in the grid, shape (s,)
    average      : cycle average L_avg from the first grid point [dB(A)], shape (g,)
    end          : the last passage count evaluated (the horizon) [-]
    factor_max   : extrapolation_max used [-]
    """

    passages: np.ndarray
    level: np.ndarray
    band_energy: np.ndarray
    extrapolated: np.ndarray
    saves: np.ndarray
    average: np.ndarray
    end: float
    factor_max: float


def cycle_average(passages, level) -> np.ndarray:
    """The energy mean of a level from the first passage count to each, 10 lg(1/(n - n0) int 10^(L/10) dn),
    trapezoidal in energy (exact for an energy linear between the points) [dB]; L at n0 itself.

    Parameters
    ----------
    passages : array-like, shape (g,)
        Increasing passage counts [-].
    level : array-like, shape (g,)
        Levels [dB].

    Returns
    -------
    ndarray, shape (g,)
    """
    n = np.asarray(passages, dtype=float)
    e = 10 ** (np.asarray(level, dtype=float) / 10)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (e[1:] + e[:-1]) * np.diff(n))])
    out = np.empty_like(e)
    out[0] = 10 * np.log10(e[0])
    out[1:] = 10 * np.log10(integral[1:] / (n[1:] - n[0]))
    return out


def noise_curve(trend: BandTrend, level_of, extrapolation_max: float = 10.0, subdivisions: int = 4,
                extrapolation_points: int = 96) -> NoiseCurve:
    """The noise of a band trend on the evaluation grid (module docstring).

    Parameters
    ----------
    trend : BandTrend
    level_of : callable
        level_of(ms) -> (L_A [dB(A)], A-weighted band levels [dB], shape (F,)) from the band mean squares [m^2].
    extrapolation_max : float
        The grid reaches n0 + extrapolation_max (n_last - n0) [-], >= 1 (1: the run only).
    subdivisions : int
        Grid points in each interval between two saves, >= 1.
    extrapolation_points : int
        Grid points beyond the last save, >= 1.

    Returns
    -------
    NoiseCurve
    """
    if not (math.isfinite(extrapolation_max) and extrapolation_max >= 1):
        raise ValueError(f"extrapolation_max = {extrapolation_max!r} is not allowed: it must be a finite number >= 1.")
    p = trend.passages
    grid = [p[:1]]
    for a, b in zip(p[:-1], p[1:]):
        grid.append(np.linspace(a, b, subdivisions + 1)[1:])
    end = float(p[0] + extrapolation_max * (p[-1] - p[0])) if trend.extrapolates else float(p[-1])
    if end > p[-1]:
        grid.append(np.linspace(p[-1], end, extrapolation_points + 1)[1:])
    n = np.concatenate(grid)
    levels, bands = zip(*(level_of(trend.mean_square(x)) for x in n))
    level = np.asarray(levels, dtype=float)
    saves = np.searchsorted(n, p)
    return NoiseCurve(n, level, 10 ** (np.asarray(bands, dtype=float) / 10), n > p[-1], saves, cycle_average(n, level), end,
                      float(extrapolation_max))


@dataclass(frozen=True)
class Trip:
    """When a criterion trips.

    Attributes
    ----------
    criterion : str
        "rise", "average" or "band_rms".
    threshold : float
        The criterion's value (dB, dB(A) or the range's limit in m).
    passages : float
        Axle passages at the trip [-] (inf: not reached; NaN: not assessed).
    status : str
        "at the start", "within the run", "extrapolated", "not reached", "not assessed".
    extrapolation_factor : float
        (passages - n0) / (n_last - n0) where extrapolated, else NaN [-].
    band_index : int
        The frequency band (rise, average: its A-weighted energy rose most by the trip; at the start the
        loudest) or wavelength band (band_rms: the range's largest) that drives it, -1 if none.
    range_index : int
        The band-rms range that trips first (band_rms), -1 else.
    note : str
        Why not reached or not assessed, and the horizon.
    """

    criterion: str
    threshold: float
    passages: float
    status: str
    extrapolation_factor: float
    band_index: int
    range_index: int = -1
    note: str = ""


def _status(trend, n):
    p = trend.passages
    if n <= p[0]:
        return "at the start", math.nan
    if n <= p[-1]:
        return "within the run", math.nan
    return "extrapolated", float((n - p[0]) / (p[-1] - p[0]))


def _bisect(f, lo: float, hi: float, tol: float) -> float:
    """The crossing of f from <= 0 at lo to > 0 at hi, to tol [-]."""
    for _ in range(200):
        if hi - lo <= tol:
            break
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) <= 0 else (lo, mid)
    return hi


def _first_crossing(grid, values, threshold, f_exact, tol):
    """First passage count where values (on grid) exceed threshold, refined by bisection on f_exact
    (f_exact(n) > 0 where exceeded); None if never on the grid."""
    over = np.nonzero(values > threshold)[0]
    if over.size == 0:
        return None
    k = int(over[0])
    if k == 0:
        return float(grid[0])
    return _bisect(f_exact, float(grid[k - 1]), float(grid[k]), tol)


def _not_reached(trend, curve, what):
    if not trend.extrapolates:
        return (f"{what} is not reached within the run; nothing is extrapolated (fewer than {BAND_GROWTH_SAVES} saves: no "
                "growth law)")
    return (f"{what} is not reached within {curve.factor_max:g} x the run's passages ({curve.end:,.0f} axle passages), "
            "with each band grown by its own law from the last save and the bands that do not grow held")


def _driver(curve, n):
    """The frequency band whose A-weighted energy has risen most from the start to n (at the start
    itself: the loudest band there)."""
    if n <= curve.passages[0]:
        return int(np.argmax(curve.band_energy[0]))
    e = np.array([np.interp(n, curve.passages, curve.band_energy[:, f]) for f in range(curve.band_energy.shape[1])])
    return int(np.argmax(e - curve.band_energy[0]))


def trip_rise(trend: BandTrend, curve: NoiseCurve, level_of, rise_dB: float) -> Trip:
    """(a) The first passage count where L_A exceeds its start value by more than rise_dB.

    Parameters
    ----------
    trend : BandTrend
    curve : NoiseCurve
        Of the trend (noise_curve).
    level_of : callable
        As noise_curve.
    rise_dB : float
        [dB], > 0.

    Returns
    -------
    Trip
        band_index: the frequency band whose A-weighted energy rose most by the trip.
    """
    if not (math.isfinite(rise_dB) and rise_dB > 0):
        raise ValueError(f"rise_dB = {rise_dB!r} is not allowed: it must be a finite number > 0 (dB).")
    start = curve.level[0]
    tol = 1e-6 * max(trend.passages[-1] - trend.passages[0], 1.0)
    n = _first_crossing(curve.passages, curve.level - start, rise_dB,
                        lambda x: level_of(trend.mean_square(x))[0] - start - rise_dB, tol)
    if n is None:
        return Trip("rise", float(rise_dB), math.inf, "not reached", math.nan, -1,
                    note=_not_reached(trend, curve, f"a rise of {rise_dB:g} dB"))
    status, factor = _status(trend, n)
    return Trip("rise", float(rise_dB), n, status, factor, _driver(curve, n))


def trip_average(trend: BandTrend, curve: NoiseCurve, target: float) -> Trip:
    """(b) The first passage count where the cycle average of L_A from the start exceeds target.

    Parameters
    ----------
    trend : BandTrend
    curve : NoiseCurve
    target : float
        [dB(A)], finite.

    Returns
    -------
    Trip
        Linear between grid points; band_index as trip_rise.
    """
    if not math.isfinite(target):
        raise ValueError(f"average target = {target!r} is not allowed: it must be a finite level in dB(A).")
    avg, n_grid = curve.average, curve.passages
    over = np.nonzero(avg > target)[0]
    if over.size == 0:
        return Trip("average", float(target), math.inf, "not reached", math.nan, -1,
                    note=_not_reached(trend, curve, f"a cycle average of {target:g} dB(A)"))
    k = int(over[0])
    if k == 0:
        n = float(n_grid[0])
    else:
        t = (target - avg[k - 1]) / (avg[k] - avg[k - 1])
        n = float(n_grid[k - 1] + t * (n_grid[k] - n_grid[k - 1]))
    status, factor = _status(trend, n)
    return Trip("average", float(target), n, status, factor, _driver(curve, n))


def range_bands(centre, low: float, high: float) -> np.ndarray:
    """The bands whose exact centre [m] lies in [low, high) [m] (module docstring), as a bool mask.

    Parameters
    ----------
    centre : array-like, shape (B,)
        Exact centre wavelength of each band [m].
    low, high : float
        The range's shortest and longest wavelength [m] (high excluded; both to a relative 1e-9).

    Returns
    -------
    ndarray of bool, shape (B,)
        True for the bands of the range [-].
    """
    c = np.asarray(centre, dtype=float)
    return (c >= low * (1 - 1e-9)) & (c < high * (1 - 1e-9))


def trip_band_rms(trend: BandTrend, curve: NoiseCurve, centre, limits=GRASSIE_1999) -> Trip:
    """(c) The first passage count where a range's rms roughness exceeds its limit (the earliest range).

    Parameters
    ----------
    trend : BandTrend
    curve : NoiseCurve
        Of the trend (its grid is searched).
    centre : array-like, shape (B,)
        Exact centre wavelength of each band [m].
    limits : sequence of (low [m], high [m], rms limit [m])

    Returns
    -------
    Trip
        threshold: the tripping range's limit [m]; range_index: that range; band_index: its band of
        the largest mean square at the trip.
    """
    model = trend.model
    tol = 1e-6 * max(trend.passages[-1] - trend.passages[0], 1.0)
    ms_grid = np.array([trend.mean_square(x) for x in curve.passages])
    best, which, notes = math.inf, -1, []
    for r, (lo, hi, lim) in enumerate(limits):
        inside = range_bands(centre, lo, hi)
        if not (inside & model).any():
            notes.append(f"{1e3 * lo:g}-{1e3 * hi:g} mm not assessed (no band of the range is the model's)")
            continue
        rms = np.sqrt(np.nansum(ms_grid[:, inside], axis=1))
        n = _first_crossing(curve.passages, rms, lim, lambda x: np.sqrt(np.nansum(trend.mean_square(x)[inside])) - lim, tol)
        if n is not None and n < best:
            best, which = n, r
    if which < 0:
        assessed = len(notes) < len(limits)
        note = "; ".join(notes + ([_not_reached(trend, curve, "no range's limit")] if assessed else []))
        return Trip("band_rms", math.nan, math.inf if assessed else math.nan, "not reached" if assessed else "not assessed",
                    math.nan, -1, -1, note)
    inside = range_bands(centre, *limits[which][:2])
    ms = np.where(inside, trend.mean_square(best), -np.inf)
    status, factor = _status(trend, best)
    return Trip("band_rms", float(limits[which][2]), best, status, factor, int(np.argmax(np.nan_to_num(ms, nan=-np.inf))), which,
                "; ".join(notes))
