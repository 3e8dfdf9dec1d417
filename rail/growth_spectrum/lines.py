"""The lines of a growth-rate spectrum: wavenumbers 2 pi j / (N L) spaced evenly in log wavelength."""

from __future__ import annotations

import numpy as np

__all__ = ["spectrum_lines", "band_lines", "settings_lines"]


def _whole_number(name: str, value) -> int:
    """value as an int if it is a whole number >= 1 (2 and 2.0, not True, 2.5 or nan); else a ValueError naming it."""
    ok = (not isinstance(value, (bool, np.bool_)) and isinstance(value, (int, np.integer, float, np.floating))
          and np.isfinite(value) and value >= 1 and value == int(value))
    if not ok:
        raise ValueError(f"{name} = {value!r} is not allowed: it must be an integer >= 1.")
    return int(value)


def spectrum_lines(L: float, bays: int, harmonics: int, shortest: float, longest: float, per_octave: int):
    """The lines j of an N-bay period nearest to wavelengths spaced evenly in log over [shortest, longest].

    Parameters
    ----------
    L : float
        Sleeper spacing [m].
    bays : int
        Roughness period N [bays]; the lines are the wavenumbers 2 pi j / (N L), 1 <= j <= N K.
    harmonics : int
        K of the receptance tables [-]: the shortest wavelength represented is L / K.
    shortest, longest : float
        Wavelength range [m], 0 < shortest < longest; shortest = 0 means L / K, the shortest
        wavelength the receptance tables represent.
    per_octave : int
        Wavelengths per octave asked for [-], 1 to 1e9 (30: a tenth of a one-third octave).

    Returns
    -------
    ndarray of int
        Distinct lines, increasing (wavelength decreasing).

    Raises
    ------
    ValueError
        If L, bays, harmonics or per_octave is out of range, the wavelength range is empty or reaches
        below L / K, or the period is too short for the resolution: the lines' relative spacing 1 / j
        at the first line (the one at or just beyond the longest wavelength) must not exceed
        2^(1 / per_octave) - 1.
    """
    bays, harmonics, per_octave = (_whole_number(name, value) for name, value in
                                   (("bays", bays), ("harmonics", harmonics), ("per_octave", per_octave)))
    if per_octave > 10**9:  # 2^(1 / per_octave) - 1 would drown in rounding
        raise ValueError(f"per_octave = {per_octave!r} is not allowed: it must be an integer from 1 to 1e9.")
    if not (np.isfinite(L) and L > 0):
        raise ValueError(f"L = {L!r} m is not allowed: the sleeper spacing must be finite and > 0.")
    if shortest == 0:
        shortest = L / harmonics
    if not (np.isfinite(shortest) and np.isfinite(longest) and 0 < shortest < longest):
        raise ValueError(f"wavelengths shortest = {shortest!r} m, longest = {longest!r} m are not allowed: they must be finite "
                         "with 0 < shortest < longest (shortest 0: down to L / K).")
    if shortest < L / harmonics * (1 - 1e-12):
        raise ValueError(f"shortest = {shortest:g} m is not allowed: it must be >= L / K = {L / harmonics:.4g} m, the shortest "
                         f"wavelength the receptance tables represent (raise numerics.track.harmonics).")
    # The first line is the one at or just beyond the longest wavelength: the floor of N L / longest,
    # with the rounding of the division forgiven (0.6 / 0.1 = 5.999...: line 6, 0.1 m, not line 5)
    ratio = 2 ** (1 / per_octave)
    step = ratio - 1
    # The walk below moves on from line j only if a line lies within a step, floor(j 2^(1/per_octave)) > j;
    # as that holds at the first line, it holds at every later one (j step grows with j).
    j = int(np.floor(bays * L / longest * (1 + 1e-9)))
    if j < 1 or int(np.floor(j * ratio)) <= j:
        first = int(np.ceil(1 / step))  # the lowest line whose relative spacing 1 / j is within a step
        while int(np.floor(first * ratio)) <= first:
            first += 1
        need = int(np.ceil(first * longest / L / (1 + 1e-9)))
        if j < 1:
            raise ValueError(f"a roughness period of {bays} bays ({bays * L:g} m) is shorter than longest = {longest:g} m: "
                             f"use at least {need} bays.")
        raise ValueError(f"a roughness period of {bays} bays spaces the lines by {100 / j:.2g} % at "
                         f"{bays * L / j:g} m, coarser than 1/{per_octave} octave ({100 * step:.2g} %): use at least {need} bays.")
    # From the longest wavelength on, each next line lies between half a step and a step beyond the
    # last (so that neighbours are never further apart than 2^(1 / per_octave)); among those, the one
    # whose pair of classes {r, N - r} holds the fewest lines so far: rate_spectrum probes one line
    # per pair of classes per wear evaluation, so balanced classes need fewer evaluations.
    j_last = bays * harmonics
    chosen, count = [j], {}
    count[min(j % bays, -j % bays)] = 1
    while bays * L / j > shortest and j < j_last:
        lo, hi = int(np.ceil(j * np.sqrt(ratio))), min(int(np.floor(j * ratio)), j_last)
        if hi <= j:  # cannot happen after the check above; a guard so that the walk always ends
            raise ValueError(f"spectrum_lines: no line within 1/{per_octave} octave beyond line {j} of {bays} bays.")
        cands = range(min(max(lo, j + 1), hi), hi + 1)
        j = min(cands, key=lambda c: (count.get(min(c % bays, -c % bays), 0), -c))
        chosen.append(j)
        key = min(j % bays, -j % bays)
        count[key] = count.get(key, 0) + 1
    return np.array(chosen)


def band_lines(L: float, bays: int, harmonics: int, speeds, low: float, high: float, spacing: float):
    """The lines j of an N-bay period that space a frequency band at most ``spacing`` apart at every speed.

    At speed V the line j excites f_j = V j / (N L), so neighbouring lines lie V / (N L) apart; a band
    [low, high] of frequencies is the wavelengths [V / high, V / low], which move with the speed. For
    each speed the lines inside the band are taken every s-th, s = floor(spacing N L / V) >= 1 (the
    first at or below ``low`` and the last at or above ``high``, so that the band's edges are covered);
    the union over the speeds is returned, so that one set of lines (a spectrum's lines are shared by
    its speeds) resolves the band at every speed.

    Parameters
    ----------
    L : float
        Sleeper spacing [m].
    bays : int
        Roughness period N [bays].
    harmonics : int
        K of the receptance tables [-]: lines up to N K.
    speeds : sequence of float
        Train speeds [m/s], finite and > 0.
    low, high : float
        The band's edges [Hz], 0 < low < high.
    spacing : float
        The largest spacing of neighbouring lines inside the band [Hz], > 0.

    Returns
    -------
    ndarray of int
        Distinct lines, increasing.

    Raises
    ------
    ValueError
        If an argument is out of range, or if the period is too short (V / (N L) > spacing at some speed:
        the error names the bays needed).

    Notes
    -----
    The band is resolved where the receptance tables reach: up to the shortest wavelength L / K, the
    frequency K V / L at each speed (a band beyond it at a low speed is cut there, and a speed whose
    K V / L lies below the band adds no line); the spectrum's lines, stored in its result, show it.
    """
    bays, harmonics = (_whole_number(name, value) for name, value in (("bays", bays), ("harmonics", harmonics)))
    if not (np.isfinite(L) and L > 0):
        raise ValueError(f"L = {L!r} m is not allowed: the sleeper spacing must be finite and > 0.")
    for name, value in (("band low", low), ("band high", high), ("band spacing", spacing)):
        if isinstance(value, (bool, np.bool_)) or not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} = {value!r} Hz is not allowed: it must be a finite number > 0.")
    if not low < high:
        raise ValueError(f"band low = {low!r} Hz, high = {high!r} Hz are not allowed: low must be below high.")
    V = np.atleast_1d(np.asarray(speeds, dtype=float))
    if V.size == 0 or not np.all(np.isfinite(V) & (V > 0)):
        raise ValueError(f"speeds = {speeds!r} are not allowed: give finite speeds > 0 m/s.")
    period = bays * L
    out = set()
    for v in np.sort(V)[::-1]:  # the fastest first: its spacing is the coarsest, and the error names it
        df = v / period  # the lines' spacing at this speed [Hz]
        if df > spacing * (1 + 1e-12):
            raise ValueError(f"a roughness period of {bays} bays spaces the lines {df:.3g} Hz apart at {v:g} m/s, coarser than "
                             f"the band's {spacing:g} Hz: use at least {int(np.ceil(v / (spacing * L)))} bays.")
        step = max(1, int(np.floor(spacing / df * (1 + 1e-12))))
        j_lo, j_hi = int(np.floor(low / df * (1 + 1e-12))), int(np.ceil(high / df * (1 - 1e-12)))
        j_lo, j_hi = max(j_lo, 1), min(j_hi, bays * harmonics)  # the tables reach L / K: K V / L at this speed
        if j_lo > j_hi:
            continue
        js = list(range(j_lo, j_hi + 1, step))
        if js[-1] != j_hi:
            js.append(j_hi)
        out.update(js)
    return np.array(sorted(out), dtype=int)


def settings_lines(L: float, bays: int, harmonics: int, settings: dict, speeds=None):
    """The lines of a spectrum's settings (figures.rate_spectrum, or a fleet's growth.fleet.spectrum):
    spectrum_lines over [shortest, longest] at per_octave, and where the settings hold a ``band``
    ({low, high, spacing} in Hz) the band_lines at the settings' speeds (or ``speeds``) added.

    Parameters
    ----------
    L : float
        Sleeper spacing [m].
    bays : int
        Roughness period N [bays].
    harmonics : int
        K of the receptance tables [-].
    settings : dict
        shortest [m], longest [m], per_octave [-]; optional band {low [Hz], high [Hz], spacing [Hz]} and speeds [m/s].
    speeds : sequence of float, optional
        The speeds the band must be resolved at [m/s] (default: settings['speeds']).

    Returns
    -------
    ndarray of int
        Distinct lines, increasing.
    """
    lines = spectrum_lines(L, bays, harmonics, float(settings["shortest"]), float(settings["longest"]), int(settings["per_octave"]))
    band = settings.get("band")
    if not band:
        return lines
    V = settings.get("speeds") if speeds is None else speeds
    extra = band_lines(L, bays, harmonics, V, float(band["low"]), float(band["high"]), float(band["spacing"]))
    return np.union1d(lines, extra).astype(int)
