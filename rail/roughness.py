"""Initial roughness over a period of N bays from a measured profile or a one-third-octave spectrum.

Both give the coefficients Z_j, j = -J..J, of z(x) = sum_j Z_j exp(i 2 pi j x / P) over the period
P = N L (rail.interaction.Roughness with bays = N); J = N K, so the shortest wavelength is L / K.

Units: every CSV states the unit of each column in its header (rail.csvinput: ``position_mm``,
``position [mm]``, ``wavelength_cm``, ``level [dB re 1 µm]``, ...): positions and wavelengths in m,
cm or mm, profile heights in m, mm or µm, spectrum levels in dB re 1 µm or rms µm. What was read
(file, units, rows, range) is stated back (ProfileRecord.describe, SpectrumTable.describe,
profile_statement). docs/roughness-input.md is the user's page.

Measured profile (CSV ``position_<unit>,height_<unit>``; process_profile): optionally cleaned of
spikes and pits (remove_spikes, roughness.spike_removal), then the whole record is used: it is cut
into its whole periods P from the start (the remainder is stated), each segment made periodic by
removing the straight line through its first and last point (so that the ends meet without a step,
the usual choice before a periodic transform; it removes the mean slope and nothing else),
resampled by linear interpolation onto 8 J uniform points, and transformed; the coefficients have
the segments' mean power and the first segment's phases. With roughness.record = period the
period N L is taken from the record (record_bays) instead. N samples at spacing d cover N d: a
record whose last sample lies one spacing (or less) short of a whole period is that period,
sampled periodically (its end value is its first; no seam). A profile shorter than P is made
periodic over its own period T, with a warning: a whole fraction T = P / m is repeated m times
(its lines are the lines m k of P), any other length has each of its own lines placed on the
nearest line of P (wavelengths moved by at most half a line, the largest move stated), so that no
line appears that the record does not have. The longest one-third-octave band the analysed length
resolves is stated (longest_resolved_band, resolved_bands).

One-third-octave wavelength spectrum (CSV ``wavelength_<unit>,level_<unit>``, centre wavelengths and rms
levels in dB re 1 um, as EN 15610 states a roughness spectrum): every band's mean square
(1e-6 10^(level / 20))^2 is shared equally between the wavenumbers 2 pi j / P whose wavelength
P / j falls in the band, with phases uniformly random from ``seed`` (numpy's default generator):
the realisation has exactly the band levels. The bands are those of the analysis (rail.bands, the
one edge rule): a centre on the base-ten series 10^(-n/10) m (within 1.5 %: every EN 15610 nominal
label) has the edges 10^((-n -+ 1/2)/10) m, and a line on an edge belongs to the band of the
shorter wavelengths (third_octave_edges, in_band); so the band view of the initial roughness gives
back every input level that holds a line, to rounding. A centre off that series has the edges of
band_edges (neighbouring bands meet at the geometric mean of their centres, the outermost edges
are 2^(+-1/6) from the centre). A band that
holds no wavenumber of the period (too long for P, or shorter than L / K) is left out, and named
in a warning; a spectrum none of whose bands holds one is refused (the rail would be smooth).

Plausible units (inputs in the wrong unit are refused when read, naming the likely unit):

* a profile whose median sample spacing exceeds PROFILE_MAX_SPACING_M = 0.05 m (rail roughness
  records are sampled at steps of about 1 mm; 1 mm steps written in mm are 1 "m") or whose record is
  longer than PROFILE_MAX_LENGTH_M = 1000 m (a 3 m record written in mm is 3000 "m");
* a spectrum wavelength outside SPECTRUM_WAVELENGTH_RANGE_M = 1 mm .. 10 m (EN 15610 centres 1 m ..
  3.15 mm written in mm are 1000 .. 3.15 "m");
* a limit spectrum (read_limit_spectrum) whose wavelength is not a band of the nominal
  one-third-octave series NOMINAL_WAVELENGTHS_M (1 m .. 3.15 mm) within NOMINAL_TOLERANCE = 1.5 %
  of its nominal label or of its exact centre 10^(-n/10) m (nominal_band).

* a profile height beyond PROFILE_MAX_HEIGHT_M = 10 mm either way (rail-head roughness is micrometres
  to a tenth of a millimetre; heights in µm written under a m or mm header are a million or a thousand
  times too large);
* a spectrum level outside SPECTRUM_LEVEL_RANGE_DB = -80 .. +60 dB re 1 µm (0.1 nm .. 1 mm rms: below
  any instrument's floor, above the worst corrugation), a level in µm converted first.

A spectrum in mm that happens to lie within 1 mm .. 10 m as metres (bands 10 mm .. 1 mm written
10 .. 1) cannot be told from one in metres and is not caught.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

# the band rule and the nominal series are rail.bands's; the names stay importable from here
from .bands import NOMINAL_TOLERANCE, NOMINAL_WAVELENGTHS_M, band_edges, in_band, nominal_band, third_octave_edges
from .csvinput import Column, unit_rows

__all__ = ["RoughnessInputWarning", "read_profile", "read_profile_record", "ProfileRecord", "read_spectrum_table",
           "SpectrumTable", "LENGTH_FACTORS", "PROFILE_COLUMNS", "SPECTRUM_COLUMNS", "RECORD_MODES", "SPIKE_THRESHOLD",
           "RECORD_CYCLES", "remove_spikes", "record_segments", "record_bays", "longest_resolved_band", "resolved_bands",
           "ProfileProcessing", "process_profile", "profile_statement", "profile_coefficients", "read_third_octave_spectrum",
           "band_edges", "third_octave_edges", "in_band", "spectrum_coefficients", "NOMINAL_WAVELENGTHS_M", "NOMINAL_TOLERANCE", "nominal_band",
           "read_limit_spectrum", "PROFILE_MAX_SPACING_M", "PROFILE_MAX_LENGTH_M", "SPECTRUM_WAVELENGTH_RANGE_M",
           "PROFILE_MAX_HEIGHT_M", "SPECTRUM_LEVEL_RANGE_DB"]

# plausible units (module docstring)
PROFILE_MAX_SPACING_M = 0.05
PROFILE_MAX_LENGTH_M = 1000.0
SPECTRUM_WAVELENGTH_RANGE_M = (1e-3, 10.0)
PROFILE_MAX_HEIGHT_M = 0.01
SPECTRUM_LEVEL_RANGE_DB = (-80.0, 60.0)

# units a header may state (rail.csvinput: the grammar), as factors to SI
LENGTH_FACTORS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "µm": 1e-6}
PROFILE_COLUMNS = (Column("position", ("distance",), ("m", "cm", "mm")),
                   Column("height", ("roughness", "displacement"), ("m", "mm", "µm")))
SPECTRUM_COLUMNS = (Column("wavelength", (), ("m", "cm", "mm")), Column("level", (), ("dB", "µm")))
# how a measured record longer than the period N L is used (config key roughness.record)
RECORD_MODES = ("average", "period")
# spike removal (remove_spikes): a sample is a spike where its curvature departs from the record's
# median by more than SPIKE_THRESHOLD robust standard deviations (1.4826 x median absolute deviation)
SPIKE_THRESHOLD = 6.0
# a one-third-octave band is resolved by a record at least RECORD_CYCLES times its upper band-edge
# wavelength long (longest_resolved_band)
RECORD_CYCLES = 3.0


class RoughnessInputWarning(UserWarning):
    """A roughness input covers less than asked for (a short profile, bands the period cannot hold)."""


def _read_two_columns(path, columns, example: str, what: str):
    """The header's units and two columns of numbers as written, with the file's line number of
    each row (blank lines are skipped; rail.csvinput.unit_rows: the header grammar)."""
    units, rows = unit_rows(path, columns, example)
    a, b, lines = [], [], []
    for n, row in rows:
        if len(row) != 2:
            raise ValueError(f"{path}, line {n}: expected 2 values {example}, got {len(row)}.")
        try:
            u, v = float(row[0]), float(row[1])
        except ValueError:
            raise ValueError(f"{path}, line {n}: {','.join(row)!r} is not two numbers ({what}).") from None
        if not (np.isfinite(u) and np.isfinite(v)):
            raise ValueError(f"{path}, line {n}: {','.join(row)!r} is not finite.")
        a.append(u)
        b.append(v)
        lines.append(n)
    if len(a) < 2:
        raise ValueError(f"{path}: needs at least two data lines, has {len(a)}.")
    return units, np.array(a), np.array(b), lines


@dataclass(frozen=True)
class ProfileRecord:
    """A measured roughness profile as read (read_profile_record), in SI units.

    x      : positions from the first [m], strictly increasing
    z      : rail-head heights [m]
    source : the file
    units  : (position unit, height unit) as its header states them
    """

    x: np.ndarray
    z: np.ndarray
    source: str
    units: tuple

    @property
    def length(self) -> float:
        """Record length x[-1] - x[0] [m]."""
        return float(self.x[-1])

    @property
    def spacing(self) -> float:
        """Median sample spacing [m]."""
        return float(np.median(np.diff(self.x)))

    def describe(self) -> str:
        """One line saying what was read: the file, the units, the rows and the record's range."""
        f = LENGTH_FACTORS[self.units[0]]
        return (f"{self.source}: measured profile, position in {self.units[0]}, height in {self.units[1]}, {self.x.size} rows, "
                f"position 0 .. {self.length / f:g} {self.units[0]} (record {self.length:g} m, median step "
                f"{1000 * float(np.median(np.diff(self.x))):.3g} mm)")


@dataclass(frozen=True)
class SpectrumTable:
    """A one-third-octave roughness spectrum as read (read_spectrum_table).

    wavelength : band centre wavelengths [m]
    level_dB   : rms band levels [dB re 1 µm]
    source     : the file
    units      : (wavelength unit, level unit) as its header states them ('dB' or 'µm')
    """

    wavelength: np.ndarray
    level_dB: np.ndarray
    source: str
    units: tuple

    def describe(self) -> str:
        """One line saying what was read: the file, the units, the rows and the wavelength range."""
        f = LENGTH_FACTORS[self.units[0]]
        lev = "dB re 1 µm" if self.units[1] == "dB" else "rms µm (read as dB re 1 µm)"
        return (f"{self.source}: one-third-octave spectrum, wavelength in {self.units[0]}, level in {lev}, {self.wavelength.size} "
                f"rows, wavelength {self.wavelength.max() / f:g} .. {self.wavelength.min() / f:g} {self.units[0]} "
                f"({self.wavelength.max():g} .. {self.wavelength.min():g} m)")


def read_profile_record(path) -> ProfileRecord:
    """Read a measured roughness profile, with the units its header states.

    Parameters
    ----------
    path : str or Path
        CSV with two columns: position [m, cm or mm] (strictly increasing) and rail-head height
        [m, mm or µm] (upwards positive), the units in the header (rail.csvinput: ``position_m,height_m``,
        ``position [mm],roughness [µm]``, ...; the names position or distance, height, roughness or
        displacement).

    Returns
    -------
    ProfileRecord
        Positions from 0 [m] and heights [m], the file and the units read.

    Raises
    ------
    ValueError
        Naming the file and the line of a wrong header, a missing or unknown unit (and the column),
        a row that is not two finite numbers, a position that does not increase or a height beyond
        PROFILE_MAX_HEIGHT_M = 10 mm either way (naming µm where the value in µm would lie inside); naming the file,
        when the positions look like a smaller unit than the header's: a median sample spacing above
        PROFILE_MAX_SPACING_M = 0.05 m (records are sampled at about 1 mm) or a record longer than
        PROFILE_MAX_LENGTH_M = 1000 m.
    """
    units, x, z, lines = _read_two_columns(path, PROFILE_COLUMNS, "position_m,height_m",
                                           "position and height")
    ux = units[0]
    bad = np.nonzero(np.diff(x) <= 0)[0]
    if bad.size:
        n = lines[int(bad[0]) + 1]  # the line of the second position
        raise ValueError(f"{path}, line {n}: position {float(x[bad[0] + 1]):g} {ux} does not increase (previous {float(x[bad[0]]):g} {ux}).")
    fx = LENGTH_FACTORS[ux]
    x, z = x * fx, z * LENGTH_FACTORS[units[1]]
    fix = "write position_m in metres" if ux == "m" else f"check the position unit of the header ({ux})"
    step = float(np.median(np.diff(x)))
    if step > PROFILE_MAX_SPACING_M:
        raise ValueError(f"{path}: the positions look like millimetres: the median sample spacing is {step:g} m, and a roughness "
                         f"record is sampled at steps of about 1 mm (at most {PROFILE_MAX_SPACING_M:g} m allowed); {fix}.")
    length = float(x[-1] - x[0])
    if length > PROFILE_MAX_LENGTH_M:
        raise ValueError(f"{path}, line {lines[-1]}: the positions look like millimetres: the record is {length:g} m long (at most "
                         f"{PROFILE_MAX_LENGTH_M:g} m allowed; in mm it would be {length / 1000:g} m); {fix}.")
    big = np.nonzero(~(np.abs(z) <= PROFILE_MAX_HEIGHT_M))[0]
    if big.size:
        i, uz = int(big[0]), units[1]
        v = float(z[i]) / LENGTH_FACTORS[uz]
        shown = f"{v:g} m" if uz == "m" else f"{v:g} {uz} = {float(z[i]):g} m"
        hint = (f"it looks like µm ({v:g} µm); " if uz != "µm" and abs(v) * 1e-6 <= PROFILE_MAX_HEIGHT_M else "")
        raise ValueError(f"{path}, line {lines[i]}: height {shown} is not allowed: {hint}a rail-head roughness profile lies "
                         f"within ±{PROFILE_MAX_HEIGHT_M * 1000:g} mm (valid range [-{PROFILE_MAX_HEIGHT_M:g}, "
                         f"{PROFILE_MAX_HEIGHT_M:g}] m); check the height unit of the header ({uz}).")
    return ProfileRecord(x - x[0], z, str(path), units)


def read_profile(path):
    """Read a measured roughness profile (read_profile_record: the header, its units and the checks).

    Parameters
    ----------
    path : str or Path
        CSV with the header ``position_<unit>,height_<unit>`` (e.g. ``position_m,height_m``).

    Returns
    -------
    x, z : ndarray
        Positions [m] from 0 and heights [m].
    """
    r = read_profile_record(path)
    return r.x, r.z


def _check_period(period, J):
    """ValueError naming the roughness period [m] unless finite and > 0, or J unless a whole number >= 1."""
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period = {np.asarray(period).tolist()!r} m is not allowed: the roughness period N L must be a finite number > 0.")
    if isinstance(J, bool) or not (np.isfinite(J) and J >= 1 and J == int(J)):
        raise ValueError(f"J = {J!r} is not allowed: the highest index N K must be an integer >= 1.")


def remove_spikes(x, z, threshold: float = SPIKE_THRESHOLD):
    """Spikes and pits of a measured profile replaced by straight lines (an EN 15610-style curvature
    criterion; docs/roughness-input.md states the variant).

    The curvature of the record at every inner sample is the three-point second derivative
    c_i = 2 [(z_{i+1} - z_i) / (x_{i+1} - x_i) - (z_i - z_{i-1}) / (x_i - x_{i-1})] / (x_{i+1} - x_{i-1}).
    A sample is a spike (upwards) or a pit (downwards) where abs(c_i - median(c)) exceeds ``threshold``
    robust standard deviations s = 1.4826 median(abs(c - median(c))) of the whole record (s is taken
    once, from the record as measured). Each run of neighbouring flagged samples is replaced by the
    straight line between the unflagged samples on either side; the curvature is then taken again
    and the test repeated (against the same s) until no sample is flagged (at most 10 passes). The
    first and last samples are never flagged.

    Parameters
    ----------
    x : ndarray
        Positions [m], strictly increasing.
    z : ndarray
        Heights [m].
    threshold : float
        Multiple [-] of the robust standard deviation of the curvature, > 0.

    Returns
    -------
    z : ndarray
        The heights with the spikes replaced [m].
    removed : ndarray of bool
        True at every replaced sample [-].
    """
    if not (np.isfinite(threshold) and threshold > 0):
        raise ValueError(f"spike threshold = {threshold!r} is not allowed: it must be a finite number > 0.")
    x = np.asarray(x, dtype=float)
    z = np.array(z, dtype=float)
    removed = np.zeros(z.size, dtype=bool)
    if z.size < 5:
        return z, removed

    def curvature(zz):
        d = np.diff(zz) / np.diff(x)
        return 2 * np.diff(d) / (x[2:] - x[:-2])

    c = curvature(z)
    centre = float(np.median(c))
    spread = 1.4826 * float(np.median(np.abs(c - centre)))
    if spread == 0:
        spread = float(np.finfo(float).tiny)
    for _ in range(10):
        flag = np.zeros(z.size, dtype=bool)
        flag[1:-1] = np.abs(curvature(z) - centre) > threshold * spread
        if not flag.any():
            break
        removed |= flag
        good = ~removed
        z[removed] = np.interp(x[removed], x[good], z[good])  # each run: the line between its good neighbours
    return z, removed


def record_segments(length: float, period: float) -> tuple[int, float]:
    """How many whole periods a record holds, and the remainder.

    Parameters
    ----------
    length : float
        Record length [m], finite and >= 0.
    period : float
        P = N L [m], finite and > 0.

    Returns
    -------
    segments : int
        floor(length / P) [-] (0 for a record shorter than P).
    remainder : float
        length - segments P [m].
    """
    if not (np.isfinite(length) and length >= 0):
        raise ValueError(f"length = {length!r} m is not allowed: it must be a finite number >= 0 (valid range [0, inf)).")
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period = {period!r} m is not allowed: it must be a finite number > 0 (valid range (0, inf)).")
    n = int(np.floor(length / period * (1 + 1e-9)))
    return n, max(0.0, float(length - n * period))


def record_bays(length: float, L: float, spacing: float = 0.0) -> int:
    """The roughness period in bays a record supports (roughness.record = 'period'): the whole bays
    it holds, at least 1; a record whose last sample lies within one sample spacing short of a
    further whole bay holds that bay too (N samples at spacing d cover N d: process_profile).

    Parameters
    ----------
    length : float
        Record length, its last position [m].
    L : float
        Sleeper spacing [m], > 0.
    spacing : float
        Sample spacing d [m] (the median), >= 0; 0 counts the bays up to the last sample only.

    Returns
    -------
    int
        N = max(1, floor(length / L)), plus one where (N + 1) L <= length + d [-].
    """
    N = int(np.floor(length / L * (1 + 1e-9)))
    if spacing > 0 and length < (N + 1) * L * (1 - 1e-9) and (N + 1) * L <= length + spacing * (1 + 1e-6):
        N += 1
    return max(1, N)


def longest_resolved_band(length: float, cycles: float = RECORD_CYCLES) -> float:
    """The longest one-third-octave wavelength band a record length resolves.

    A band is resolved when the length holds ``cycles`` wavelengths of its upper band edge, the
    exact edge of the one band rule, 10^(1/20) lambda_c (rail.bands.exact_edges; EN 15610 asks for a
    record several times the longest wavelength analysed; docs/roughness-input.md). Bands are those of the exact series lambda_c = 10^(-n/10) m (n any
    integer; the nominal labels of rail.bands.NOMINAL_WAVELENGTHS_M are within 1 % of them).

    Parameters
    ----------
    length : float
        Record (or analysed segment) length [m], > 0.
    cycles : float
        Upper band-edge wavelengths the length must hold [-], > 0.

    Returns
    -------
    float
        Exact centre wavelength 10^(-n/10) [m] of the longest resolved band.
    """
    if not (np.isfinite(length) and length > 0):
        raise ValueError(f"record length = {length!r} m is not allowed: it must be a finite number > 0.")
    # band n's upper edge 10^(-(2n - 1)/20) m <= length / cycles
    n = int(np.ceil((1.0 - 20.0 * np.log10(length / cycles)) / 2.0 - 1e-9))
    return float(10.0 ** (-n / 10))


def resolved_bands(wavelength, length: float, cycles: float = RECORD_CYCLES):
    """Which one-third-octave bands a record length resolves (longest_resolved_band); bands longer
    are unresolved and their levels should be flagged so in an export.

    Parameters
    ----------
    wavelength : array-like
        Band centre wavelengths [m], nominal or exact.
    length : float
        Record (or analysed segment) length [m].
    cycles : float
        As longest_resolved_band [-].

    Returns
    -------
    ndarray of bool
        True where the band is resolved [-].
    """
    longest = longest_resolved_band(length, cycles)
    return np.asarray(wavelength, dtype=float) <= longest * (1 + NOMINAL_TOLERANCE)


@dataclass(frozen=True)
class ProfileProcessing:
    """A measured profile made into coefficients over the period (process_profile), and what was done.

    Attributes
    ----------
    Z : coefficients Z_j [m], j = -J..J
    period : P = N L [m]
    record : record length, the last position [m]
    mode : 'average' or 'period' (roughness.record)
    segments : whole periods of the record averaged [-] (1 for a record shorter than P)
    remainder : record length after the last whole period, not used [m]
    spikes_removed : samples replaced by remove_spikes [-], or None when spike removal is off
    analysed : length of one analysed segment: P, or a short record's own period T [m]
    longest_band : longest_resolved_band(analysed) [m]
    record_longest_band : longest_resolved_band(record) [m]
    spacing : median sample spacing d [m]
    sampled_period : True where the last analysed piece ends less than one spacing after the last
        sample (N samples at spacing d cover N d): its samples are taken as one period [-]
    repeats : a short record whose own period T is P / m: m (the record repeated m times); 0 for a
        short record that is no whole fraction of P, and for a record of at least one period [-]
    wavelength_shift : a short record that is no whole fraction of P: the largest relative move
        abs(lambda_placed / lambda_own - 1) of a line the record resolves (placed on the nearest line
        of P); 0 otherwise [-]
    """

    Z: np.ndarray
    period: float
    record: float
    mode: str
    segments: int
    remainder: float
    spikes_removed: int | None
    analysed: float
    longest_band: float
    record_longest_band: float
    spacing: float = float("nan")
    sampled_period: bool = False
    repeats: int = 0
    wavelength_shift: float = 0.0


def _periodic_piece(x, z, start: float, length: float, n: int):
    """A piece [start, start + length] of a record made periodic and transformed: F_k, k = 0..n-1,
    of n uniform samples (linear interpolation), the straight line through the piece's end values
    removed. Where the piece ends after the last sample (by at most one spacing: sampled_period of
    process_profile), its end value is its first: the samples are one period of themselves."""
    t = np.linspace(0.0, 1.0, n + 1)
    xs, zs = x, z
    end = start + length
    if end > x[-1]:  # N samples at spacing d cover N d: the sample after the last is the piece's first
        xs, zs = np.append(x, end), np.append(z, np.interp(start, x, z))
    zi = np.interp(start + length * t, xs, zs)
    zi = zi - (zi[0] + (zi[-1] - zi[0]) * t)  # ends meet without a step
    return np.fft.fft(zi[:n]) / n


def process_profile(x, z, period: float, J: int, *, mode: str = "average", spikes: bool = False,
                    spike_threshold: float = SPIKE_THRESHOLD, source: str = "profile") -> ProfileProcessing:
    """Coefficients Z_j over the period from a whole measured record (module docstring: the method).

    Spikes (remove_spikes) are removed first if asked. A record holding S >= 1 whole periods P is cut
    into S segments [s P, (s + 1) P] from its start (the remainder after the last is not used and is
    stated); each is made periodic (the line through its end points removed), resampled linearly
    onto 8 J points and transformed, F_s,j. The coefficients have the mean power of the segments and
    the phases of the first: Z_j = sqrt(mean_s abs(F_s,j)^2) exp(i arg F_1,j), so that every band
    level is the record's mean (the one-third-octave spectrum EN 15610 averages over a record) and a
    record of one period gives its own coefficients.

    Sampled periods: N samples at spacing d cover N d. A record whose last sample lies less than one
    spacing (or exactly one) short of the end of a whole period S P, or of a whole fraction P / m, is
    a record of that length sampled periodically: the sample after its last would be its first, so
    its end value is its first value and no line is removed (a 2,400-sample record at 1 mm is one
    period of 2.4 m, not a record 1 mm short of it).

    A record shorter than P is made periodic over its own period T (the line through its end points
    removed; T = P / m where the record is a sampled fraction, else its length) and transformed, F_k.
    Where T = P / m its lines k are the lines j = m k of the period (the record repeated m times:
    nothing else is present). Otherwise each line k is placed on the nearest line of the period,
    j = floor(k P / T + 1/2), with its amplitude and phase: no line appears that the record does not
    have, and each wavelength moves by at most half a line of the period (lambda^2 / (2 P)); the
    largest move of a line the record resolves is stated (a warning either way: the record covers
    less than the period).

    Parameters
    ----------
    x, z : ndarray
        Positions from 0 [m] (increasing) and heights [m].
    period : float
        P = N L [m], finite and > 0.
    J : int
        Highest index j [-] (N K).
    mode : str
        'average' (the segments averaged) or 'period' (the caller chose P from the record,
        record_bays; computed the same way, named in the statement) [-].
    spikes : bool
        Remove spikes and pits first (remove_spikes) [-].
    spike_threshold : float
        remove_spikes' threshold [-].
    source : str
        Name of the profile, for the warning.

    Returns
    -------
    ProfileProcessing
        Z_j [m], Z_0 = 0, and the numbers the statement names.
    """
    _check_period(period, J)
    if mode not in RECORD_MODES:
        raise ValueError(f"roughness.record = {mode!r} is not allowed: it must be one of {list(RECORD_MODES)}.")
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    removed = None
    if spikes:
        z, flags = remove_spikes(x, z, spike_threshold)
        removed = int(flags.sum())
    n = 8 * J
    length = float(x[-1])
    d = float(np.median(np.diff(x)))

    def sampled(end: float) -> bool:
        """The record's last sample lies within one spacing short of ``end`` (exactly one included)."""
        return length < end * (1 - 1e-9) and end <= length + d * (1 + 1e-6)

    segments, remainder = record_segments(length, period)
    last_sampled = sampled((segments + 1) * period)
    if last_sampled:
        segments, remainder = segments + 1, 0.0
    j = np.arange(-J, J + 1)
    repeats, shift = 0, 0.0
    if segments == 0:
        m = int(np.floor(period / length))  # the whole fraction P / m nearest above the record, if sampled
        if abs(period / m - length) <= 1e-9 * length:
            own, repeats = period / m, m  # the record is P / m, closed: its ends are the period's
        elif sampled(period / m):
            own, repeats, last_sampled = period / m, m, True
        else:
            own = length
        F = _periodic_piece(x, z, 0.0, own, n)
        k = np.arange(1, n // 2)
        jk = np.floor(k * period / own + 0.5).astype(int)  # the nearest line of the period, distinct for P > T
        keep = jk <= J
        Z = np.zeros(2 * J + 1, dtype=complex)
        Z[J + jk[keep]] = F[k[keep]]
        Z[J - jk[keep]] = np.conj(F[k[keep]])
        if not repeats:
            resolved = own / k[keep] <= longest_resolved_band(own) * (1 + NOMINAL_TOLERANCE)
            ratio = (k[keep] * period / own) / jk[keep]  # lambda_placed / lambda_own
            shift = float(np.max(np.abs(ratio[resolved] - 1))) if resolved.any() else float(np.max(np.abs(ratio - 1)))
        if repeats:
            how = (f"it is made periodic over its own length{' (its samples cover ' + f'{own:.4g} m)' if last_sampled else ''} "
                   f"and repeated {repeats} times: its wavenumbers 2 pi k / {own:.4g} m are the lines j = {repeats} k of the period, "
                   "no other line is present")
        else:
            how = (f"it is no whole fraction of N L, so it is not repeated: it is made periodic over its own length (the line "
                   f"through its ends removed) and each of its lines 2 pi k / {own:.4g} m is placed on the nearest line 2 pi j / "
                   f"(N L) with its amplitude and phase, no other line is present; the lines it resolves move by at most "
                   f"{100 * shift:.2g} % in wavelength (half a line of the period: lambda^2 / (2 N L))")
        warnings.warn(f"{source}: the profile is {own:.4g} m long, shorter than the roughness period N L = {period:.4g} m; "
                      f"{how}.", RoughnessInputWarning, stacklevel=2)
        segments, remainder, analysed = 1, 0.0, own
    else:
        power = np.zeros(2 * J + 1)
        for s in range(segments):
            F = _periodic_piece(x, z, s * period, period, n)[j % n]
            power += np.abs(F) ** 2
            if s == 0:
                phase = np.exp(1j * np.angle(F))
        Z = np.sqrt(power / segments) * phase
        analysed = period
    Z[J] = 0.0
    return ProfileProcessing(Z, float(period), length, mode, segments, remainder, removed, analysed,
                             longest_resolved_band(analysed), longest_resolved_band(length), d, bool(last_sampled), repeats,
                             shift)


def profile_statement(record: ProfileRecord, p: ProfileProcessing, spike_threshold: float = SPIKE_THRESHOLD) -> dict:
    """What was read and done to a measured profile, as result attributes (and log lines).

    Parameters
    ----------
    record : ProfileRecord
        As read.
    p : ProfileProcessing
        As processed.
    spike_threshold : float
        The threshold used [-] (named when spikes were removed).

    Returns
    -------
    dict
        ``roughness_input`` (file, units, rows, range), ``roughness_processing`` (segments, remainder,
        period, spikes), ``roughness_record_length_m`` [m], ``roughness_segments`` [-],
        ``roughness_remainder_m`` [m], ``roughness_spikes_removed`` [-] (-1: off),
        ``roughness_longest_resolved_band_m`` [m] (of one analysed segment) and
        ``roughness_record_longest_band_m`` [m] (of the whole record).
    """
    how = ("the period N L taken from the record (roughness.record = period)" if p.mode == "period"
           else "the whole record averaged (roughness.record = average)")
    covers = (f" (its last sample {1e3 * p.spacing:.3g} mm, one sample spacing, short of the end: its samples cover "
              f"{p.analysed if p.analysed < p.period else p.segments * p.period:.4g} m, taken as periodic)" if p.sampled_period else "")
    if p.analysed < p.period * (1 - 1e-9) and p.repeats:
        use = (f"record {p.analysed:.4g} m{covers} shorter than N L = {p.period:.4g} m, a whole fraction of it: made periodic "
               f"over its length and repeated {p.repeats} times (its lines are the lines j = {p.repeats} k of the period)")
    elif p.analysed < p.period * (1 - 1e-9):
        use = (f"record {p.analysed:.4g} m shorter than N L = {p.period:.4g} m and no whole fraction of it: made periodic over "
               f"its length (the line through its ends removed), each of its lines placed on the nearest line of the period "
               f"(the lines it resolves moved by at most {100 * p.wavelength_shift:.2g} % in wavelength), not repeated")
    else:
        use = (f"{how}: {p.segments} segment(s) of N L = {p.period:.4g} m{covers}, power averaged, phases of the first; "
               f"{p.remainder:.4g} m at the end of the {p.record:.4g} m record not used")
    spikes = ("spike removal off" if p.spikes_removed is None
              else f"spike removal on (curvature beyond {spike_threshold:g} robust standard deviations): {p.spikes_removed} samples replaced")
    band = (f"longest resolved one-third-octave band {p.longest_band:.3g} m (a segment of {p.analysed:.4g} m holds "
            f"{RECORD_CYCLES:g} upper band-edge wavelengths; the whole record's {p.record_longest_band:.3g} m); longer bands "
            f"are unresolved")
    return {
        "roughness_input": record.describe(),
        "roughness_processing": f"{use}; {spikes}; {band}.",
        "roughness_record_length_m": p.record,
        "roughness_segments": p.segments,
        "roughness_remainder_m": p.remainder,
        "roughness_spikes_removed": -1 if p.spikes_removed is None else p.spikes_removed,
        "roughness_longest_resolved_band_m": p.longest_band,
        "roughness_record_longest_band_m": p.record_longest_band,
    }


def profile_coefficients(x, z, period: float, J: int, source: str = "profile"):
    """Coefficients Z_j over the period of a measured profile, the whole record averaged
    (process_profile with its defaults: no spike removal).

    Parameters
    ----------
    x, z : ndarray
        Positions from 0 [m] (increasing) and heights [m].
    period : float
        P = N L [m], finite and > 0.
    J : int
        Highest index j [-] (N K).
    source : str
        Name of the profile, for the warning.

    Returns
    -------
    ndarray, shape (2J + 1,)
        Z_j [m], Z_0 = 0.
    """
    return process_profile(x, z, period, J, source=source).Z


def read_spectrum_table(path) -> SpectrumTable:
    """Read a one-third-octave roughness wavelength spectrum, with the units its header states.

    Parameters
    ----------
    path : str or Path
        CSV with two columns: band centre wavelength [m, cm or mm] (> 0, each once) and rms level
        [dB re 1 µm, or rms µm], the units in the header (rail.csvinput: ``wavelength_m,level_dB``,
        ``wavelength_cm,level_dB``, ``wavelength [mm],level [µm]``, ...).

    Returns
    -------
    SpectrumTable
        Wavelengths [m] and levels [dB re 1 µm] (a level in µm is 20 log10(level / 1 µm)).

    Raises
    ------
    ValueError
        Naming the file and the line of a wrong header, a missing or unknown unit (and the column), a
        row that is not two finite numbers, a non-positive or repeated wavelength, a level in µm
        that is not > 0, a wavelength outside SPECTRUM_WAVELENGTH_RANGE_M = 1 mm .. 10 m (naming
        millimetres when the value in mm would lie inside), or a level outside SPECTRUM_LEVEL_RANGE_DB =
        -80 .. +60 dB re 1 µm.
    """
    units, lam, lev, lines = _read_two_columns(path, SPECTRUM_COLUMNS, "wavelength_m,level_dB",
                                               "centre wavelength and level")
    ul, uv = units
    lo, hi = SPECTRUM_WAVELENGTH_RANGE_M
    f = LENGTH_FACTORS[ul]
    for i, v in enumerate(lam):
        if v <= 0:
            raise ValueError(f"{path}, line {lines[i]}: wavelength {float(v):g} {ul} is not allowed: it must be > 0.")
        same = np.nonzero(np.isclose(lam[:i], v, rtol=1e-9))[0]
        if same.size:
            raise ValueError(f"{path}, line {lines[i]}: wavelength {float(v):g} {ul} appears twice (first at line {lines[same[0]]}); "
                             "give each band once.")
        vm = v * f
        if not (lo * (1 - 1e-9) <= vm <= hi * (1 + 1e-9)):
            unit = (f"it looks like millimetres ({float(vm) / 1000:g} m); " if vm > hi and vm / 1000 >= lo * (1 - 1e-9) else "")
            fix = "write wavelength_m in metres" if ul == "m" else f"check the wavelength unit of the header ({ul})"
            shown = f"{float(v):g} m" if ul == "m" else f"{float(v):g} {ul} = {float(vm):g} m"
            raise ValueError(f"{path}, line {lines[i]}: wavelength {shown} is not allowed: {unit}rail roughness wavelengths "
                             f"lie between {lo * 1000:g} mm and {hi:g} m; {fix}.")
        if uv == "µm" and not lev[i] > 0:
            raise ValueError(f"{path}, line {lines[i]}: level {float(lev[i]):g} µm is not allowed: an rms level in µm must be > 0 "
                             "(or give the column in dB re 1 µm).")
    level = 20 * np.log10(lev) if uv == "µm" else lev
    lo_db, hi_db = SPECTRUM_LEVEL_RANGE_DB
    for i, v in enumerate(level):
        if not lo_db <= v <= hi_db:
            shown = f"{float(v):g} dB re 1 µm" if uv == "dB" else f"{float(lev[i]):g} µm = {float(v):.4g} dB re 1 µm"
            raise ValueError(f"{path}, line {lines[i]}: level {shown} is not allowed: a rail or wheel roughness level lies in "
                             f"[{lo_db:g}, {hi_db:g}] dB re 1 µm (0.1 nm .. 1 mm rms); check the level unit of the header ({uv}).")
    return SpectrumTable(lam * f, level, str(path), units)


def read_third_octave_spectrum(path):
    """Read a one-third-octave roughness wavelength spectrum (read_spectrum_table: the header, its
    units and the checks).

    Parameters
    ----------
    path : str or Path
        CSV with the header ``wavelength_<unit>,level_<unit>`` (e.g. ``wavelength_m,level_dB``).

    Returns
    -------
    wavelength, level : ndarray
        [m] and [dB re 1 µm].
    """
    t = read_spectrum_table(path)
    return t.wavelength, t.level_dB


def read_limit_spectrum(path):
    """Read a limit spectrum for the grinding interval (rail.studies.bands, figures.bands.limit).

    As read_third_octave_spectrum, and every wavelength must name a band of the nominal series
    1 m .. 3.15 mm (nominal_band: within 1.5 % of its nominal label or exact centre), each band once.

    Parameters
    ----------
    path : str or Path
        CSV with the header ``wavelength_m,level_dB``.

    Returns
    -------
    wavelength, level : ndarray
        [m] and [dB re 1 µm], as written.

    Raises
    ------
    ValueError
        As read_third_octave_spectrum; naming the file, the line, the value and the nearest nominal
        band of a wavelength off the series (and millimetres when the value in mm is on it), or a
        band given twice.
    """
    lam, lev = read_third_octave_spectrum(path)
    seen = {}
    for i, v in enumerate(lam):
        k = nominal_band(v)
        if k < 0:
            near = int(np.argmin(np.abs(np.log(v / NOMINAL_WAVELENGTHS_M))))
            nom = NOMINAL_WAVELENGTHS_M[near]
            unit = "it looks like millimetres; " if nominal_band(v / 1000) >= 0 else ""
            raise ValueError(f"{path}, line {i + 2}: wavelength {float(v):g} m is not a one-third-octave band centre: {unit}the nearest "
                             f"band is {nom:g} m ({100 * (v / nom - 1):+.1f} %); a limit spectrum's wavelengths must be the nominal "
                             f"centres 1 m .. 3.15 mm (1, 0.8, 0.63, ... m) or the exact 10^(-n/10) m, within "
                             f"{100 * NOMINAL_TOLERANCE:g} %.")
        if k in seen:
            raise ValueError(f"{path}, line {i + 2}: wavelength {float(v):g} m names the band {NOMINAL_WAVELENGTHS_M[k]:g} m of line "
                             f"{seen[k]} again.")
        seen[k] = i + 2
    return lam, lev


def spectrum_coefficients(wavelength, level_dB, period: float, J: int, seed: int, source: str = "spectrum"):
    """Random-phase realisation of a one-third-octave spectrum over the period (module docstring).

    Parameters
    ----------
    wavelength : ndarray
        Band centre wavelengths [m].
    level_dB : ndarray
        rms band levels [dB re 1 µm].
    period : float
        P = N L [m], finite and > 0.
    J : int
        Highest index j [-] (N K); shorter wavelengths than P / J are not represented.
    seed : int
        Seed of the random phases.
    source : str
        Name of the spectrum, for the warning.

    Returns
    -------
    ndarray, shape (2J + 1,)
        Z_j [m], Z_0 = 0, Z_{-j} = conj(Z_j); sum over the band's j of 2 abs(Z_j)^2 is its mean square.
    """
    _check_period(period, J)
    rng = np.random.default_rng(int(seed))
    j = np.arange(1, J + 1)
    lam_j = period / j
    Z = np.zeros(2 * J + 1, dtype=complex)
    empty = []
    phases = rng.uniform(0.0, 2 * np.pi, J)  # one per wavenumber, drawn in order: reproducible
    lo, hi = third_octave_edges(wavelength)
    for lc, lev, a, b in zip(wavelength, level_dB, lo, hi):
        inside = in_band(lam_j, a, b)
        if not inside.any():
            empty.append(f"{lc:g} m")
            continue
        ms = (1e-6 * 10 ** (lev / 20)) ** 2
        amp = np.sqrt(ms / (2 * inside.sum()))
        Z[J + j[inside]] = amp * np.exp(1j * phases[inside])
    Z[:J] = np.conj(Z[J + 1 :][::-1])
    if len(empty) == len(wavelength):
        lam = np.asarray(wavelength, dtype=float)
        unit = ""
        if np.any((lam / 1000 >= period / J / 2 ** (1 / 6)) & (lam / 1000 < period * 2 ** (1 / 6))):
            unit = "; the wavelengths look like millimetres, wavelength_m is in metres"
        raise ValueError(f"{source}: no band of the spectrum ({lam.max():g} m .. {lam.min():g} m) holds a wavenumber 2 pi j / (N L) of "
                         f"the period N L = {period:.4g} m with j <= {J} (wavelengths {period:.4g} m .. {period / J:.4g} m): the rail "
                         f"would be smooth{unit}.")
    if empty:
        warnings.warn(f"{source}: the bands {', '.join(empty)} hold no wavenumber 2 pi j / (N L) of the period N L = "
                      f"{period:.4g} m with j <= {J}; they are left out (raise roughness.bays for long wavelengths, "
                      f"numerics.track.harmonics for short ones).", RoughnessInputWarning, stacklevel=2)
    return Z
