"""Vertical track decay rate from transfer receptances along the rail, as EN 15461 measures it.

EN 15461:2008+A1:2010, *Railway applications - Noise emission - Characterisation of the dynamic
properties of track sections for pass by noise measurements*, estimates the spatial decay rate of
rail vibration in each one-third-octave band from the band-averaged transfer functions A(x_n)
between an excitation point x_0 and response points x_n running out along the rail:

    DR = 10 log10(e) / sum_n ( abs(A(x_n))^2 / abs(A(x_0))^2 ) dx_n        dB/m          (EN 15461)

10 log10(e) = 4.343.  For a single wave decaying as exp(-k_i x), abs(A)^2 falls as exp(-2 k_i x), the
sum tends to 1 / (2 k_i) and DR = 20 log10(e) k_i = 8.686 k_i dB/m.  Near the excitation the
evanescent (near-field) wave adds to abs(A(x_0))^2, so where it is not small against the propagating
wave the formula gives a larger decay rate than the propagating wave's own (it is a property of
the standard's estimator, which this module reproduces rather than corrects).

Here the transfer receptances come from the periodically supported rail model
(``rail.track.stationary_receptance``).  Positions are distances from the excitation point in the
+x direction (the track is symmetric about a sleeper and about mid-span, so one direction serves).
Units: Hz, m, m/N, dB/m. The one-third-octave bands are rail.bands.frequency_bands (IEC 61260-1).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .bands import NOMINAL_THIRD_OCTAVE_CENTRES, ThirdOctaveBands, frequency_bands
from .bands import frequency_bands as third_octave_bands  # the old name (rail.bands)
from .track import stationary_receptance

__all__ = [
    "LOG10_E_10",
    "NOMINAL_THIRD_OCTAVE_CENTRES",
    "ThirdOctaveBands",
    "third_octave_bands",
    "band_frequencies",
    "SCHEMES",
    "decay_distances",
    "trapezoid_weights",
    "en15461_decay_rate",
    "band_averaged_squared_transfer",
    "DecayRate",
    "track_decay_rate",
    "MeasuredDecayRate",
    "read_measured_decay_rate",
]

LOG10_E_10 = 10 * np.log10(np.e)  # 4.343 dB per neper of |A|^2 (EN 15461)

# The one-third-octave frequency bands (IEC 61260-1 base-ten) and their nominal centres are
# rail.bands's; NOMINAL_THIRD_OCTAVE_CENTRES, ThirdOctaveBands and third_octave_bands (= frequency_bands)
# stay importable from here.


def band_frequencies(lower, upper, per_band: int) -> np.ndarray:
    """Frequencies averaged in each band: the midpoints of ``per_band`` equal parts of [lower, upper].

    Equal weight in linear frequency, like the lines of a narrow-band spectrum that a measurement
    averages over the band.

    Parameters
    ----------
    lower : array_like, shape (bands,)
        Lower band edges [Hz].
    upper : array_like, shape (bands,)
        Upper band edges [Hz].
    per_band : int
        Frequencies per band [-], >= 1.

    Returns
    -------
    ndarray, shape (bands, per_band)
        Frequencies [Hz].

    Raises
    ------
    ValueError
        If per_band is not an integer >= 1.
    """
    if int(per_band) != per_band or per_band < 1:
        raise ValueError(f"per_band = {per_band!r} is not allowed: it must be an integer >= 1.")
    lower = np.asarray(lower, dtype=float)[:, None]
    upper = np.asarray(upper, dtype=float)[:, None]
    u = (np.arange(int(per_band)) + 0.5) / per_band
    return lower + (upper - lower) * u[None, :]


SCHEMES = ("en15461", "bay_sampled")


def decay_distances(spacing: float, max_bays: float = 128.0, scheme: str = "en15461") -> np.ndarray:
    """Response positions for the decay rate from the excitation point: fine near it, coarser further out.

    In sleeper bays L: steps of L/4 up to 4 L (the sleeper and the mid-span part of each bay near
    the source, where the near field and the bay-periodic pattern matter), L/2 up to 8 L, L up to
    32 L, then 16 positions per doubling of distance (steps of 2 L to 64 L, 4 L to 128 L, 8 L to
    256 L, ...), up to ``max_bays`` L.

    Scheme "en15461": beyond 8 L the positions are whole bays from the excitation point, so they
    sit at the same place in the bay as the excitation point (taken to be the practice of EN 15461
    measurements, whose far positions are whole numbers of bays; the standard's own list is not
    reproduced here).  Near the pinned-pinned frequency this aliases the bay-periodic pattern:
    Table 1 track, 1 kHz band, 0.81 dB/m above a sleeper and 1.22 dB/m at mid-span, against 0.60
    and 1.63 dB/m with the whole bay sampled.

    Scheme "bay_sampled": beyond 8 L the k-th position is moved on by (k mod 4) L / 4, so four
    consecutive positions sample four places in the bay and the sum integrates the bay-averaged
    response (no aliasing of the bay-periodic pattern, which near the pinned-pinned frequency is
    strong); within 3 % of a reference with positions every L/16 to 16 L and every L/4 to 64 L
    (Table 1 track, bands 0.8 to 5 kHz).

    Parameters
    ----------
    spacing : float
        Sleeper spacing L [m].
    max_bays : float, optional
        Extent of the positions [-] (number of sleeper bays), >= 8; default 128.
    scheme : str, optional
        "en15461" (default) or "bay_sampled" (one of SCHEMES), see above.

    Returns
    -------
    ndarray
        Distances from the excitation point [m], increasing from 0.

    Raises
    ------
    ValueError
        If scheme is not one of SCHEMES, if max_bays < 8, or if spacing is not a finite number > 0.
    """
    if not (np.isfinite(spacing) and spacing > 0):
        raise ValueError(f"spacing = {spacing!r} m is not allowed: the sleeper spacing must be a finite number > 0.")
    if scheme not in SCHEMES:
        raise ValueError(f"scheme = {scheme!r} is not allowed: it must be one of {', '.join(SCHEMES)}.")
    if not (np.isfinite(max_bays) and max_bays >= 8):
        raise ValueError(f"max_bays = {max_bays!r} is not allowed: it must be a finite number >= 8.")
    bays = [np.arange(0.0, 4.0, 0.25), np.arange(4.0, 8.0, 0.5), np.arange(8.0, 32.0, 1.0)]
    start = 32.0
    while start < max_bays:
        bays.append(np.arange(start, 2 * start, start / 16))
        start *= 2
    d = np.concatenate(bays)
    d = np.append(d[d < max_bays], max_bays)
    if scheme == "bay_sampled":
        far = d >= 8.0
        d[far] += (np.arange(far.sum()) % 4) / 4
    return d * spacing


def trapezoid_weights(distances) -> np.ndarray:
    """Weights dx_n of the EN 15461 sum: half the distance to each neighbour (trapezoidal rule).

    The sum then integrates abs(A)^2 exactly for a piecewise-linear response.

    Parameters
    ----------
    distances : array_like
        Response positions from the excitation point [m]: 1-D, increasing, starting at 0.

    Returns
    -------
    ndarray
        dx_n [m], shape of ``distances``.

    Raises
    ------
    ValueError
        If distances is not a 1-D increasing array of at least two values starting at 0.
    """
    d = np.asarray(distances, dtype=float)
    if d.ndim != 1 or len(d) < 2 or d[0] != 0.0 or np.any(np.diff(d) <= 0):
        raise ValueError("distances must be a 1-D increasing array starting at 0 (the excitation point), m.")
    w = np.empty_like(d)
    w[0] = 0.5 * (d[1] - d[0])
    w[-1] = 0.5 * (d[-1] - d[-2])
    w[1:-1] = 0.5 * (d[2:] - d[:-2])
    return w


def en15461_decay_rate(distances, squared_transfer) -> np.ndarray:
    """Decay rate DR = 4.343 / sum_n (abs(A(x_n))^2 / abs(A(x_0))^2) dx_n (EN 15461).

    4.343 = 10 log10(e); dx_n are the trapezoidal weights (``trapezoid_weights``).

    Parameters
    ----------
    distances : array_like, shape (positions,)
        Positions from the excitation point [m]: 0 first, increasing.
    squared_transfer : array_like, shape (..., positions)
        Band-averaged abs(A(x_n))^2 [m^2/N^2] (or any unit: only ratios enter).

    Returns
    -------
    ndarray, shape (...)
        Decay rate DR [dB/m].

    Raises
    ------
    ValueError
        If distances is not a 1-D increasing array starting at 0 (``trapezoid_weights``).
    """
    p = np.asarray(squared_transfer, dtype=float)
    ratio = p / p[..., :1]
    return LOG10_E_10 / np.sum(ratio * trapezoid_weights(distances), axis=-1)


def band_averaged_squared_transfer(track, x0: float, distances, frequencies, rtol: float = 1e-6) -> np.ndarray:
    """Mean of abs(A(x0 + d_n, x0; f))^2 over the frequencies of each band.

    A is the transfer receptance of the periodically supported rail
    (``rail.track.stationary_receptance``).

    Parameters
    ----------
    track : Track or rail.cell.TrackCell
        The track (a cell of N bays: ``rail.cell.cell_stationary_receptance``, all positions of one
        frequency from one zone quadrature).
    x0 : float
        Excitation point [m], measured from a support (of the cell: from its first support).
    distances : array_like, shape (positions,)
        Distances d_n [m] of the response points x0 + d_n.
    frequencies : array_like, shape (bands, per_band)
        Frequencies [Hz], e.g. from ``band_frequencies``.
    rtol : float, optional
        Relative tolerance of the zone quadrature of ``stationary_receptance`` [-] (its error is
        relative to the largest response, near the source); default 1e-6.

    Returns
    -------
    ndarray, shape (bands, positions)
        Band-averaged abs(A)^2 [m^2/N^2].
    """
    x = x0 + np.asarray(distances, dtype=float)
    f = np.asarray(frequencies, dtype=float)
    out = np.empty(f.shape + x.shape)
    from .cell import TrackCell, cell_stationary_receptance

    for idx in np.ndindex(f.shape):
        om = 2 * np.pi * f[idx]
        if isinstance(track, TrackCell):
            out[idx] = np.abs(cell_stationary_receptance(x, np.full(x.shape, float(x0)), om, track, rtol=rtol)) ** 2
        else:
            out[idx] = np.abs(stationary_receptance(x, x0, om, track, rtol=rtol)) ** 2
    return out.mean(axis=1)


@dataclass(frozen=True)
class DecayRate:
    """Track decay rates in one-third-octave bands (EN 15461 estimator on the track model).

    Attributes
    ----------
    bands : ThirdOctaveBands
    frequencies : Hz, (band, per_band): the frequencies averaged in each band
    excitation : m, (excitation,): excitation points x_0 measured from a support
    distances : m, (position,): every response point x_n - x_0 computed (union of the schemes)
    schemes : names of the position sets (``decay_distances``), or ("custom",)
    weights : m, (scheme, position): dx_n of each scheme's sum, 0 where a scheme does not
                   use the position
    level : dB, (excitation, band, position): 10 log10 of band-averaged abs(A(x_n))^2 / abs(A(x_0))^2
    decay_rate : dB/m, (scheme, excitation, band)
    """

    bands: ThirdOctaveBands
    frequencies: np.ndarray
    excitation: np.ndarray
    distances: np.ndarray
    schemes: tuple
    weights: np.ndarray
    level: np.ndarray
    decay_rate: np.ndarray

    @property
    def attenuation(self) -> np.ndarray:
        """dB, (scheme, excitation, band): how far the response has fallen at each scheme's last
        position."""
        last = [np.flatnonzero(w > 0)[-1] for w in self.weights]
        return np.stack([-self.level[..., i] for i in last])


def track_decay_rate(
    track,
    excitation=None,
    f_min: float = 100.0,
    f_max: float = 5000.0,
    per_band: int = 16,
    distances=None,
    min_attenuation: float = 40.0,
    max_bays: float = 1024.0,
    rtol: float = 1e-6,
) -> DecayRate:
    """Vertical track decay rate in the one-third-octave bands from f_min to f_max, EN 15461 estimator.

    The band-averaged transfer receptances of the track model (``band_averaged_squared_transfer``)
    enter the EN 15461 sum (``en15461_decay_rate``) for each excitation point and each set of
    response positions.

    Parameters
    ----------
    track : Track or rail.cell.TrackCell
        The track; a cell of N bays has a decay rate per excitation point (above each support, at
        each mid-bay), and its L is the mean spacing P / N.
    excitation : array_like, optional
        Excitation points x_0 [m] from a support; default: above a sleeper, 0, and at mid-span, L/2.
    f_min : float, optional
        Lowest nominal band centre [Hz]; default 100.
    f_max : float, optional
        Highest nominal band centre [Hz]; default 5000.
    per_band : int, optional
        Frequencies averaged per band [-] (``band_frequencies``); default 16.  Table 1 track, bands
        1, 2, 3.15 and 5 kHz: 16 per band is within 3 % of 64 (the worst is the 1 kHz band excited
        at mid-span, which holds the narrow pinned-pinned resonance), 32 within 0.1 %, 8 within 7 %.
    distances : array_like, optional
        One set of response positions from x_0 [m] (0 first), scheme "custom".  Default: both
        schemes of ``decay_distances`` out to 128 bays, doubled until the band-averaged response has
        fallen by ``min_attenuation`` dB at the last position in every band or ``max_bays`` is reached.
    min_attenuation : float, optional
        Wanted fall of the response at the last position [dB]; default 40.  The sum then misses a
        fraction of about 10^(-min_attenuation/10) of its value.
    max_bays : float, optional
        Largest extent of the default positions [-] (number of sleeper bays); default 1024.
    rtol : float, optional
        Relative tolerance of the zone quadrature of ``stationary_receptance`` [-]; default 1e-6.

    Returns
    -------
    DecayRate
        Decay rates [dB/m] per scheme, excitation point and band, with the levels [dB], positions
        [m] and weights [m] they come from.

    Raises
    ------
    ValueError
        If, with the default distances, the response has fallen by less than 30 dB at ``max_bays``
        bays (the sum would be truncated noticeably); also if no band lies in [f_min, f_max] or
        per_band is not an integer >= 1.
    """
    L = track.mean_spacing if hasattr(track, "mean_spacing") else track.L
    x0 = np.atleast_1d(np.asarray([0.0, L / 2] if excitation is None else excitation, dtype=float))
    bands = frequency_bands(f_min, f_max)
    freqs = band_frequencies(bands.lower, bands.upper, per_band)

    def squared(d):
        return np.stack([band_averaged_squared_transfer(track, x, d, freqs, rtol) for x in x0])

    def sets(bays):
        return {name: decay_distances(L, bays, name) for name in SCHEMES}

    if distances is not None:
        schemes = {"custom": np.asarray(distances, dtype=float)}
        d = schemes["custom"]
        p = squared(d)
    else:
        bays = min(128.0, max_bays)
        schemes = sets(bays)
        d = np.unique(np.concatenate(list(schemes.values())))
        p = squared(d)

        def worst_fall():
            lasts = [np.searchsorted(d, s[-1]) for s in schemes.values()]
            ratio = np.stack([p[..., i] / p[..., 0] for i in lasts])  # (scheme, excitation, band)
            return np.unravel_index(np.argmax(ratio), ratio.shape), -10 * np.log10(ratio.max())

        while worst_fall()[1] < min_attenuation and bays < max_bays:
            bays = min(2 * bays, max_bays)
            schemes = sets(bays)
            new = np.setdiff1d(np.unique(np.concatenate(list(schemes.values()))), d)
            p = np.concatenate([p, squared(new)], axis=-1)
            d = np.concatenate([d, new])
            order = np.argsort(d)
            d, p = d[order], p[..., order]
        (_, e, b), fall = worst_fall()
        if fall < 30.0:
            raise ValueError(
                f"track decay rate: in the {bands.nominal[b]:g} Hz band, excited at x0 = {x0[e]:g} m, the response "
                f"has fallen by only {fall:.1f} dB at {max_bays:g} sleeper bays ({max_bays * L:g} m); the EN 15461 "
                f"sum would be truncated. The track's decay is very low: raise max_bays."
            )
    weights = np.zeros((len(schemes), len(d)))
    rates = []
    for k, s in enumerate(schemes.values()):
        idx = np.searchsorted(d, s)
        weights[k, idx] = trapezoid_weights(s)
        rates.append(en15461_decay_rate(s, p[..., idx]))
    level = 10 * np.log10(p / p[..., :1])
    return DecayRate(bands, freqs, x0, d, tuple(schemes), weights, level, np.stack(rates))


@dataclass(frozen=True)
class MeasuredDecayRate:
    """A measured decay rate read from a CSV file: band_centre Hz, decay_rate dB/m, source path."""

    band_centre: np.ndarray
    decay_rate: np.ndarray
    source: str


_HEADER = ("band_centre_Hz", "decay_rate_dB_per_m")
# plausible values of a measured decay rate: one-third-octave band centres of the audible range (a
# track decay rate is measured over 100 Hz .. 5 kHz, EN 15461; centres in kHz under the Hz header are a
# thousand times too small), and rates up to 100 dB/m (measured rates are 0.1 .. 30 dB/m)
DECAY_FREQUENCY_RANGE_HZ = (10.0, 20000.0)
DECAY_RATE_MAX_DB_PER_M = 100.0


def read_measured_decay_rate(path) -> MeasuredDecayRate:
    """Read a measured track decay rate from a CSV file.

    The file has the header line ``band_centre_Hz,decay_rate_dB_per_m`` and one band per line
    (Hz, dB/m, both > 0).  Blank lines and lines starting with '#' are skipped.  The bands are
    returned in order of increasing centre frequency.

    Parameters
    ----------
    path : str or path-like
        The CSV file.

    Returns
    -------
    MeasuredDecayRate
        Band centres [Hz], decay rates [dB/m] and the source path.

    Raises
    ------
    ValueError
        If the file is empty, the header is wrong, there are no data lines, a line does not hold two
        values, a value is not a number or not > 0, a band centre lies outside DECAY_FREQUENCY_RANGE_HZ
        = 10 Hz .. 20 kHz (naming kHz where the value in kHz would lie inside), a rate exceeds
        DECAY_RATE_MAX_DB_PER_M = 100 dB/m, or a band is given twice.  Errors name the file
        and the line:
        ``config/measured/default_decay_rate.csv, line 4: decay_rate_dB_per_m = 'n/a' is not a number.``
    OSError
        If the file cannot be opened.
    """
    path = Path(path)
    where = str(path)
    with open(path, newline="", encoding="utf-8-sig") as fh:
        rows = [(i, row) for i, row in enumerate(csv.reader(fh), start=1) if row and "".join(row).strip() and not row[0].lstrip().startswith("#")]
    if not rows:
        raise ValueError(f"{where}: the file is empty; it needs the header line '{','.join(_HEADER)}' and one line per band.")
    line, header = rows[0]
    if tuple(h.strip() for h in header) != _HEADER:
        raise ValueError(f"{where}, line {line}: the header must be '{','.join(_HEADER)}', found '{','.join(header)}'.")
    if len(rows) < 2:
        raise ValueError(f"{where}: no data lines after the header; give one line per band: {','.join(_HEADER)}.")
    f, dr, lines = [], [], []
    for line, row in rows[1:]:
        if len(row) != 2:
            raise ValueError(f"{where}, line {line}: expected 2 values ({','.join(_HEADER)}), found {len(row)}: '{','.join(row)}'.")
        values = []
        for name, text in zip(_HEADER, row):
            try:
                v = float(text)
            except ValueError:
                raise ValueError(f"{where}, line {line}: {name} = '{text.strip()}' is not a number.") from None
            unit = "Hz" if name == "band_centre_Hz" else "dB/m"
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"{where}, line {line}: {name} = {v:g} {unit} is not allowed: it must be > 0 {unit}.")
            values.append(v)
        lo, hi = DECAY_FREQUENCY_RANGE_HZ
        if not lo <= values[0] <= hi:
            hint = f"it looks like kHz ({values[0]:g} kHz = {values[0] * 1000:g} Hz); " if lo <= values[0] * 1000 <= hi else ""
            raise ValueError(f"{where}, line {line}: band_centre_Hz = {values[0]:g} Hz is not allowed: {hint}a one-third-octave band "
                             f"centre of a track decay rate lies in [{lo:g}, {hi:g}] Hz; write the centres in Hz.")
        if not values[1] <= DECAY_RATE_MAX_DB_PER_M:
            raise ValueError(f"{where}, line {line}: decay_rate_dB_per_m = {values[1]:g} dB/m is not allowed: a track decay rate lies "
                             f"in (0, {DECAY_RATE_MAX_DB_PER_M:g}] dB/m (measured rates are 0.1 .. 30 dB/m).")
        first = [n for n, g in zip(lines, f) if np.isclose(g, values[0], rtol=1e-9, atol=0.0)]
        if first:
            raise ValueError(f"{where}, line {line}: band_centre_Hz = {values[0]:g} Hz is given twice (first at line {first[0]}); "
                             "give each band once.")
        f.append(values[0])
        dr.append(values[1])
        lines.append(line)
    order = np.argsort(f, kind="stable")
    return MeasuredDecayRate(np.asarray(f)[order], np.asarray(dr)[order], where)
