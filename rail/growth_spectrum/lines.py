"""The lines of a growth-rate spectrum: wavenumbers 2 pi j / (N L) spaced evenly in log wavelength."""

from __future__ import annotations

import numpy as np

__all__ = ["spectrum_lines"]


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
