"""A growing band of a growth-rate spectrum: its peak, its edges and its width (issue 54).

A spectrum's lines sample the growth rate g(f) at the excitation frequencies f_j = V j / (N L). A band
is the run of lines around the fastest-growing one (inside an optional window of frequency); its
edges are where g crosses a level on either side of that peak, interpolated linearly in f between the
two lines that bracket the crossing:

- the zero edges (level 0): where the roughness stops growing, so the band is what grows;
- the half-peak edges (level g_peak / 2): the band's width at half its rate, which does not depend
  on where the rate falls below zero.

class_pair_spectrum computes a spectrum of many lines on a period of many bays one pair of Bloch classes at a
time (the memory of the linear method with dynamic creepage grows with the classes computed together).

An edge that no line brackets (the rate stays above the level up to the first or the last line of
the window) is not known: NaN, and the result says on which side. The rates may be in any unit
(per passage, dB per 100,000 axles): the edges and the width do not depend on it.
"""

import dataclasses
from dataclasses import dataclass

import numpy as np

from .creepage import has_creepage
from .probes import RateSpectrum
from .spectrum import rate_spectrum


@dataclass(frozen=True, slots=True)
class Band:
    """The band around the fastest-growing line of a spectrum (band_edges).

    Attributes
    ----------
    peak_frequency : float
        The fastest-growing line's frequency [Hz].
    peak_rate : float
        Its growth rate [the unit of the rates given].
    low, high : float
        The zero edges [Hz]: where the rate crosses 0 below and above the peak, interpolated between
        lines; NaN where the peak does not grow (peak_rate <= 0) or no line brackets the crossing.
    half_low, half_high : float
        The half-peak edges [Hz]: where the rate crosses peak_rate / 2; NaN as for low and high.
    lines_growing : int
        Lines of the run around the peak with a rate > 0 [-] (0 where the peak does not grow).
    spacing : float
        The largest spacing of neighbouring lines between the zero edges' bracketing lines [Hz]
        (NaN with fewer than two lines there): the resolution the edges rest on.
    """

    peak_frequency: float
    peak_rate: float
    low: float
    high: float
    half_low: float
    half_high: float
    lines_growing: int
    spacing: float

    @property
    def width(self) -> float:
        """The band's width between its zero edges, high - low [Hz] (NaN where an edge is not known)."""
        return self.high - self.low

    @property
    def half_width(self) -> float:
        """The band's width at half its peak rate, half_high - half_low [Hz] (NaN where an edge is not known)."""
        return self.half_high - self.half_low


def _crossing(f, g, i: int, level: float, step: int) -> tuple[float, int]:
    """From the line i (g[i] > level) walk by ``step`` (-1 or +1) to the first line with g <= level;
    the crossing interpolated linearly in f, and the index of the last line above the level (NaN and
    that index if the walk leaves the lines)."""
    k = i
    while 0 <= k + step < len(f) and g[k + step] > level:
        k += step
    n = k + step
    if not 0 <= n < len(f):
        return float("nan"), k
    t = (g[k] - level) / (g[k] - g[n])
    return float(f[k] + t * (f[n] - f[k])), k


def band_edges(frequency, rate, low: float | None = None, high: float | None = None) -> Band:
    """The peak, the edges and the width of the band around a spectrum's fastest-growing line.

    Parameters
    ----------
    frequency : array_like
        The lines' excitation frequencies V / wavelength [Hz], finite and > 0, distinct (any order).
    rate : array_like
        Their growth rates [any unit, > 0 grows], finite, the same length.
    low, high : float, optional
        A window of frequency [Hz]: only the lines inside [low, high] are considered (default: all).

    Returns
    -------
    Band
        The peak line, the zero and half-peak edges interpolated linearly between lines [Hz], the
        number of growing lines around the peak and the lines' spacing there.

    Raises
    ------
    ValueError
        Naming the argument: frequencies not finite and > 0, or repeated; rates not finite or of another
        length; a window with low >= high or holding fewer than one line.

    Notes
    -----
    Linear interpolation between lines puts an edge within one line spacing of the true crossing; with
    a rate that is smooth over a few lines the error is a small part of that spacing. The edges are
    those of the one run of lines around the peak: a second growing band elsewhere in the window is not
    reported (narrow the window to see it).
    """
    f = np.asarray(frequency, dtype=float).ravel()
    g = np.asarray(rate, dtype=float).ravel()
    if f.size == 0 or not np.all(np.isfinite(f) & (f > 0)):
        raise ValueError(f"frequency = {frequency!r} is not allowed: give the lines' frequencies, finite and > 0 Hz.")
    if g.shape != f.shape or not np.all(np.isfinite(g)):
        raise ValueError(f"rate has {g.size} values for {f.size} frequencies, or one is not finite: give one finite rate per line.")
    order = np.argsort(f)
    f, g = f[order], g[order]
    if np.any(np.diff(f) <= 0):
        raise ValueError(f"frequency holds a repeated line ({f[np.flatnonzero(np.diff(f) <= 0)[0]]:g} Hz): give each line once.")
    lo = -np.inf if low is None else float(low)
    hi = np.inf if high is None else float(high)
    if not lo < hi:
        raise ValueError(f"low = {low!r} Hz, high = {high!r} Hz are not allowed: low must be below high.")
    keep = (f >= lo) & (f <= hi)
    if not keep.any():
        raise ValueError(f"the window [{low!r}, {high!r}] Hz holds no line (lines from {f[0]:g} to {f[-1]:g} Hz).")
    f, g = f[keep], g[keep]
    i = int(np.argmax(g))
    peak = float(g[i])
    if peak <= 0:
        nan = float("nan")
        return Band(float(f[i]), peak, nan, nan, nan, nan, 0, nan)
    z_lo, k_lo = _crossing(f, g, i, 0.0, -1)
    z_hi, k_hi = _crossing(f, g, i, 0.0, +1)
    h_lo, _ = _crossing(f, g, i, 0.5 * peak, -1)
    h_hi, _ = _crossing(f, g, i, 0.5 * peak, +1)
    a, b = max(k_lo - 1, 0), min(k_hi + 1, len(f) - 1)
    spacing = float(np.max(np.diff(f[a:b + 1]))) if b > a else float("nan")
    return Band(float(f[i]), peak, z_lo, z_hi, h_lo, h_hi, k_hi - k_lo + 1, spacing)


def class_pair_spectrum(scn, table, lines, eps: float = 1e-9, grid_phases: int = 1, check_lines: int = 1, progress=None) -> RateSpectrum:
    """rate_spectrum on ``lines``, one pair of Bloch classes (r, N - r) per call, merged into one spectrum.

    About the smooth rail the classes do not couple (module docstring of rail.growth_spectrum), so a line's
    rate does not depend on the other lines computed with it. The linear method with dynamic creepage
    (rail.growth_spectrum.creepage) marches a basis of u_bar's harmonics of every class present at once:
    2 (2 K + 1) columns per pair of classes, so on 7-14 bays with lines in every class 4-8 times the 2-bay
    spectrum's, and its tangent march took over 10 GB on 8 bays at 40 m/s (K = 64, 41 nodes; measured
    2026-12-02). One pair per call keeps it to that pair's. The price: the probes' march inputs are
    repeated per call. The linearity check (probes of 2 eps by the nonlinear march over the N bays, with
    u_bar's Newton steps: over 7 min of CPU on 7 bays at 40 m/s with every mechanism, against 15-70 s for a pair's linear rates) is made in the first
    call that holds a free line only.

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N (the lines' period).
    table : tuple of MovingReceptance
        The receptance tables of the N-bay period at the speed (rail.chain.receptance_table).
    lines : sequence of int
        Lines j, 1 <= j <= N K [-].
    eps : float
        Amplitude of the probing cosines [m].
    grid_phases : int
        Contact grids averaged over [-].
    check_lines : int
        Free lines probed again with 2 eps (the linearity check) [-], in the first call that holds a free line
        (and the first locked line of each call before it).
    progress : callable, optional
        As rate_spectrum's, told of each pair too.

    Returns
    -------
    RateSpectrum
        As rate_spectrum's on all the lines (its method the calls' methods joined).
    """
    N = scn.roughness.bays
    lines = np.unique(np.asarray(lines, dtype=int))
    key = np.minimum(lines % N, (N - lines % N) % N)
    parts = []
    # with dynamic creepage the check's nonlinear march over the N bays needs the rail head's tables of every class (over
    # 7 min of CPU on 7 bays at 40 m/s, over 25 min at a load of 3): the check is made on the 2-bay period instead
    short = check_lines is not None and N > 2 and has_creepage(scn.material)
    checked = short
    for k in np.unique(key):
        mine = lines[key == k]
        if progress is not None:
            progress(f"class pair ({k}, {(N - k) % N}) of {N} bays: {mine.size} lines")
        free = k != 0 and 2 * k != N  # a pair of free classes (else the comb or the half-comb: locked lines)
        parts.append(rate_spectrum(scn, table, mine, eps=eps, grid_phases=grid_phases, check_lines=None if checked else check_lines,
                                   progress=progress))
        checked = checked or free
    checks = np.array([p.linearity for p in parts], dtype=float)
    linearity = (float(np.nanmax(checks)) if np.isfinite(checks).any() else float("nan")) if not short else short_period_linearity(
        scn, table, lines, eps, progress)
    order = np.argsort(np.concatenate([p.line for p in parts]))
    merged = {n: np.concatenate([getattr(p, n) for p in parts])[order]
              for n in ("wavelength", "line", "locked", "rate", "rate_other", "source", "grid_spread", "sideband", "operator")}
    method = "; ".join(sorted({p.method for p in parts})) + ("; linearity checked on the 2-bay period" if short else "")
    return dataclasses.replace(parts[0], **merged, linearity=linearity, method=method)


def short_period_linearity(scn, table, lines, eps: float, progress=None) -> float:
    """The linearity check of a spectrum with dynamic creepage on many bays, made on the 2-bay period at the same
    speed: the line of 2 bays nearest the lines' median wavelength (a comb or half-comb line, locked to the supports),
    its operator by probes of eps and 2 eps through the nonlinear march (rate_spectrum's check). The amplitude at
    which the chain stops being linear is a property of the contact, the speed and the probe, not of the period;
    the march over 2 bays needs the rail head's tables of 2 classes, not of N.

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N.
    table : tuple of MovingReceptance
        The N-bay period's tables (their speed is taken) [m/N].
    lines : sequence of int
        The spectrum's lines j of N bays [-].
    eps : float
        The probes' amplitude [m].
    progress : callable, optional
        Told of the check.

    Returns
    -------
    float
        abs(R(2 eps) / R(eps) - 1) at that line [-].
    """
    from .. import chain

    N = scn.roughness.bays
    s2 = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=2))
    lam = N * scn.L / np.asarray(lines, dtype=float)
    j2 = int(np.clip(round(2 * scn.L / float(np.median(lam))), 1, 2 * scn.harmonics))
    if progress is not None:
        progress(f"linearity check on the 2-bay period: line {j2} ({1e3 * 2 * scn.L / j2:.1f} mm)")
    t2 = chain.receptance_table(s2, chain.table_speed(table))
    return float(rate_spectrum(s2, t2, [j2], eps=eps, grid_phases=1, check_lines=1).linearity)
