"""Initial roughness over a period of N bays from a measured profile or a one-third-octave spectrum.

Both give the coefficients Z_j, j = -J..J, of z(x) = sum_j Z_j exp(i 2 pi j x / P) over the period
P = N L (rail.interaction.Roughness with bays = N); J = N K, so the shortest wavelength is L / K.

Measured profile (CSV ``position_m,height_m``): the first P of the profile, made periodic by
removing the straight line through its first and last point (so that the ends meet without a
step, the usual choice before a periodic transform; it removes the mean slope and nothing else),
resampled by linear interpolation onto 8 J uniform points, and transformed. A profile shorter
than P is made periodic over its own length and repeated to fill P, with a warning: then only the
wavenumbers of its own period are present.

One-third-octave wavelength spectrum (CSV ``wavelength_m,level_dB``, centre wavelengths and rms
levels in dB re 1 um, as EN 15610 states a roughness spectrum): every band's mean square
(1e-6 10^(level / 20))^2 is shared equally between the wavenumbers 2 pi j / P whose wavelength
P / j falls in the band (band_edges: neighbouring bands meet at the geometric mean of their
centres, the outermost edges are 2^(+-1/6) from the centre), with phases uniformly random from
``seed`` (numpy's default generator): the realisation has exactly the band levels. A band that
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

A spectrum in mm that happens to lie within 1 mm .. 10 m as metres (bands 10 mm .. 1 mm written
10 .. 1) cannot be told from one in metres and is not caught.
"""

from __future__ import annotations

import warnings

import numpy as np

from .csvinput import data_rows

__all__ = ["RoughnessInputWarning", "read_profile", "profile_coefficients", "read_third_octave_spectrum",
           "band_edges", "spectrum_coefficients", "NOMINAL_WAVELENGTHS_M", "NOMINAL_TOLERANCE", "nominal_band",
           "read_limit_spectrum", "PROFILE_MAX_SPACING_M", "PROFILE_MAX_LENGTH_M", "SPECTRUM_WAVELENGTH_RANGE_M"]

# EN 15610 nominal centre wavelengths (m) of the exact series 10^(-n/10) m, n = 0..25
NOMINAL_WAVELENGTHS_M = np.array([1.0, 0.8, 0.63, 0.5, 0.4, 0.315, 0.25, 0.2, 0.16, 0.125, 0.1, 0.08, 0.063, 0.05,
                                  0.04, 0.0315, 0.025, 0.02, 0.016, 0.0125, 0.01, 0.008, 0.0063, 0.005, 0.004, 0.00315])
# a wavelength names a band when within this fraction of its nominal label or its exact centre
# (the labels are at most 0.95 % from the exact centres; neighbouring bands are 26 % apart)
NOMINAL_TOLERANCE = 0.015
# plausible units (module docstring)
PROFILE_MAX_SPACING_M = 0.05
PROFILE_MAX_LENGTH_M = 1000.0
SPECTRUM_WAVELENGTH_RANGE_M = (1e-3, 10.0)


class RoughnessInputWarning(UserWarning):
    """A roughness input covers less than asked for (a short profile, bands the period cannot hold)."""


def _read_two_columns(path, header: tuple[str, str], what: str):
    """Two columns of numbers and the file's line number of each row (blank lines are skipped)."""
    a, b, lines = [], [], []
    for n, row in data_rows(path, header):
        if len(row) != 2:
            raise ValueError(f"{path}, line {n}: expected 2 values {','.join(header)}, got {len(row)}.")
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
    return np.array(a), np.array(b), lines


def read_profile(path):
    """Read a measured roughness profile.

    Parameters
    ----------
    path : str or Path
        CSV with the header ``position_m,height_m``: positions along the rail [m], strictly
        increasing, and rail-head heights [m] (upwards positive).

    Returns
    -------
    x, z : ndarray
        Positions [m] from 0 and heights [m].

    Raises
    ------
    ValueError
        Naming the file and the line of a wrong header, a row that is not two finite numbers, or a
        position that does not increase; naming the file, when the positions look like millimetres:
        a median sample spacing above PROFILE_MAX_SPACING_M = 0.05 m (records are sampled at about
        1 mm) or a record longer than PROFILE_MAX_LENGTH_M = 1000 m.
    """
    x, z, lines = _read_two_columns(path, ("position_m", "height_m"), "position in m and height in m")
    bad = np.nonzero(np.diff(x) <= 0)[0]
    if bad.size:
        n = lines[int(bad[0]) + 1]  # the line of the second position
        raise ValueError(f"{path}, line {n}: position {float(x[bad[0] + 1]):g} m does not increase (previous {float(x[bad[0]]):g} m).")
    step = float(np.median(np.diff(x)))
    if step > PROFILE_MAX_SPACING_M:
        raise ValueError(f"{path}: the positions look like millimetres: the median sample spacing is {step:g} m, and a roughness "
                         f"record is sampled at steps of about 1 mm (at most {PROFILE_MAX_SPACING_M:g} m allowed); write position_m "
                         f"in metres.")
    length = float(x[-1] - x[0])
    if length > PROFILE_MAX_LENGTH_M:
        raise ValueError(f"{path}, line {len(x) + 1}: the positions look like millimetres: the record is {length:g} m long (at most "
                         f"{PROFILE_MAX_LENGTH_M:g} m allowed; in mm it would be {length / 1000:g} m); write position_m in metres.")
    return x - x[0], z


def _check_period(period, J):
    """ValueError naming the roughness period [m] unless finite and > 0, or J unless a whole number >= 1."""
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period = {np.asarray(period).tolist()!r} m is not allowed: the roughness period N L must be a finite number > 0.")
    if isinstance(J, bool) or not (np.isfinite(J) and J >= 1 and J == int(J)):
        raise ValueError(f"J = {J!r} is not allowed: the highest index N K must be an integer >= 1.")


def profile_coefficients(x, z, period: float, J: int, source: str = "profile"):
    """Coefficients Z_j over the period of a measured profile (module docstring: the method).

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
    _check_period(period, J)
    n = 8 * J
    length = float(x[-1])
    if length < period * (1 - 1e-9):
        reps = int(np.ceil(period / length))
        warnings.warn(f"{source}: the profile is {length:.4g} m long, shorter than the roughness period N L = {period:.4g} m; "
                      f"it is made periodic over its own length and repeated {reps} times (only the wavenumbers of its own "
                      f"length are present).", RoughnessInputWarning, stacklevel=2)
        use = length
    else:
        use = period
    zi = np.interp(np.linspace(0.0, use, n + 1), x, z)
    zi = zi - (zi[0] + (zi[-1] - zi[0]) * np.linspace(0.0, 1.0, n + 1))  # ends meet without a step
    s = np.linspace(0.0, period, n, endpoint=False)
    zp = np.interp(s % use, np.linspace(0.0, use, n + 1), zi)
    F = np.fft.fft(zp) / n
    j = np.arange(-J, J + 1)
    Z = F[j % n]
    Z[J] = 0.0
    return Z


def read_third_octave_spectrum(path):
    """Read a one-third-octave roughness wavelength spectrum.

    Parameters
    ----------
    path : str or Path
        CSV with the header ``wavelength_m,level_dB``: band centre wavelengths [m] (> 0, each
        once) and rms levels [dB re 1 µm].

    Returns
    -------
    wavelength, level : ndarray
        [m] and [dB re 1 µm].

    Raises
    ------
    ValueError
        Naming the file and the line of a wrong header, row, non-positive or repeated wavelength, or
        a wavelength outside SPECTRUM_WAVELENGTH_RANGE_M = 1 mm .. 10 m (naming millimetres when
        the value in mm would lie inside).
    """
    lam, lev, lines = _read_two_columns(path, ("wavelength_m", "level_dB"), "centre wavelength in m and level in dB re 1 um")
    lo, hi = SPECTRUM_WAVELENGTH_RANGE_M
    for i, v in enumerate(lam):
        if v <= 0:
            raise ValueError(f"{path}, line {lines[i]}: wavelength {float(v):g} m is not allowed: it must be > 0.")
        same = np.nonzero(np.isclose(lam[:i], v, rtol=1e-9))[0]
        if same.size:
            raise ValueError(f"{path}, line {lines[i]}: wavelength {float(v):g} m appears twice (first at line {lines[same[0]]}); "
                             "give each band once.")
        if not (lo * (1 - 1e-9) <= v <= hi * (1 + 1e-9)):
            unit = (f"it looks like millimetres ({float(v) / 1000:g} m); " if v > hi and v / 1000 >= lo * (1 - 1e-9) else "")
            raise ValueError(f"{path}, line {lines[i]}: wavelength {float(v):g} m is not allowed: {unit}rail roughness wavelengths "
                             f"lie between {lo * 1000:g} mm and {hi:g} m; write wavelength_m in metres.")
    return lam, lev


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
    off = np.minimum(np.abs(wavelength / NOMINAL_WAVELENGTHS_M - 1), np.abs(wavelength / 10.0 ** (-n / 10) - 1))
    k = int(np.argmin(off))
    return k if off[k] <= NOMINAL_TOLERANCE else -1


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
    lo, hi = band_edges(wavelength)
    for lc, lev, a, b in zip(wavelength, level_dB, lo, hi):
        inside = (lam_j >= a) & (lam_j < b)
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
