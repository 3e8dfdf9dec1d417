"""Frequency weighting and level sums: the A-weighting of IEC 61672-1 and energy sums of levels.

Conventions: levels in dB; a sum of levels is an energy sum, 10 lg sum 10^(L/10); an empty band
(NaN) is refused, never taken as silence (-inf is silence and is allowed).

References
----------
IEC 61672-1:2013, *Electroacoustics - Sound level meters - Part 1: Specifications*: the A-weighting
(Annex E, its pole frequencies f_1 .. f_4 and the normalisation A_1000) and Table 3 (the weighting
at the nominal one-third-octave frequencies, rounded to 0.1 dB).
"""

from __future__ import annotations

import numpy as np

from .tables import A_WEIGHTING, FREQUENCY_LABELS_HZ

__all__ = ["IEC_61672_A1000_DB", "IEC_61672_POLES_HZ", "a_weighting", "a_weighting_analytic", "energy_sum",
           "overall_level"]

# IEC 61672-1:2013 Annex E: pole frequencies f_1, f_2, f_3, f_4 [Hz] of the A-weighting and
# the normalisation constant A_1000 [dB] that makes it 0 dB at 1 kHz
IEC_61672_POLES_HZ = (20.598997, 107.65265, 737.86223, 12194.217)
IEC_61672_A1000_DB = -2.000


def a_weighting_analytic(frequency):
    """A-weighting from its poles, IEC 61672-1:2013 Annex E:
    A(f) = 20 lg[f_4^2 f^4 / ((f^2 + f_1^2) sqrt(f^2 + f_2^2) sqrt(f^2 + f_3^2) (f^2 + f_4^2))] - A_1000.

    Parameters
    ----------
    frequency : array-like
        Frequencies [Hz], > 0.

    Returns
    -------
    ndarray
        A-weighting [dB].
    """
    f2 = np.asarray(frequency, dtype=float) ** 2
    f1, f2p, f3, f4 = (p * p for p in IEC_61672_POLES_HZ)
    ratio = f4 * f2 * f2 / ((f2 + f1) * np.sqrt(f2 + f2p) * np.sqrt(f2 + f3) * (f2 + f4))
    return 20 * np.log10(ratio) - IEC_61672_A1000_DB


def a_weighting(nominal_frequency):
    """A-weighting at nominal one-third-octave frequencies, the values of IEC 61672-1:2013 Table 3
    (rail.noise.tables.A_WEIGHTING, 50 Hz .. 10 kHz), as band weights are applied in practice.

    Parameters
    ----------
    nominal_frequency : array-like
        Nominal centre frequencies [Hz] among 50, 63, ..., 10000.

    Returns
    -------
    ndarray
        A-weighting [dB].

    Raises
    ------
    ValueError
        For a frequency that is not a nominal band of 50 Hz .. 10 kHz, naming it.
    """
    labels = np.array(FREQUENCY_LABELS_HZ)
    f = np.atleast_1d(np.asarray(nominal_frequency, dtype=float))
    k = np.argmin(np.abs(f[:, None] / labels[None, :] - 1), axis=1)
    bad = [v for v, j in zip(f, k) if not abs(v / labels[j] - 1) < 1e-6]
    if bad:
        raise ValueError(f"frequency = {bad[0]:g} Hz is not a nominal one-third-octave band of 50 Hz .. 10 kHz "
                         f"(IEC 61672-1 Table 3 as tabulated here): give one of {', '.join(f'{v:g}' for v in FREQUENCY_LABELS_HZ)}.")
    return np.array(A_WEIGHTING)[k]


def energy_sum(levels, axis=-1):
    """Energy sum of levels, 10 lg sum_i 10^(L_i / 10) [dB] (levels of incoherent sources or bands).

    Parameters
    ----------
    levels : array-like
        Levels [dB]; -inf (silence) is allowed, NaN is not.
    axis : int
        The axis summed over.

    Returns
    -------
    ndarray or float
        The summed level [dB], -inf where every term is -inf.

    Raises
    ------
    ValueError
        If a level is NaN or +inf (an empty or undefined band would otherwise vanish from the sum).
    """
    x = np.asarray(levels, dtype=float)
    if np.isnan(x).any() or np.isposinf(x).any():
        raise ValueError("levels holds NaN or +inf: an empty band cannot be summed as silence; fill or drop it first.")
    m = np.max(x, axis=axis, keepdims=True)
    m = np.where(np.isfinite(m), m, 0.0)
    with np.errstate(divide="ignore"):
        return np.squeeze(m, axis=axis) + 10 * np.log10(np.sum(10 ** ((x - m) / 10), axis=axis))


def overall_level(levels, nominal_frequency, weighting: str = "A"):
    """Overall level of a one-third-octave spectrum, 10 lg sum_i 10^((L_i + W_i) / 10) [dB]: A-weighted
    (W = IEC 61672-1 Table 3) or unweighted ("Z", W = 0).

    Parameters
    ----------
    levels : array-like, shape (..., bands)
        Band levels [dB] on the last axis.
    nominal_frequency : array-like, shape (bands,)
        Their nominal centre frequencies [Hz].
    weighting : str
        "A" or "Z".

    Returns
    -------
    ndarray or float
        The overall level [dB] (dB(A) for "A").

    Raises
    ------
    ValueError
        For another weighting, a band off the table, or a NaN level.
    """
    if weighting not in ("A", "Z"):
        raise ValueError(f"weighting = {weighting!r} is not allowed: it must be 'A' or 'Z'.")
    x = np.asarray(levels, dtype=float)
    w = a_weighting(nominal_frequency) if weighting == "A" else np.zeros(np.size(nominal_frequency))
    if x.shape[-1] != w.size:
        raise ValueError(f"levels has {x.shape[-1]} bands on its last axis but nominal_frequency has {w.size}.")
    return energy_sum(x + w, axis=-1)
