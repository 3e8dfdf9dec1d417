"""Convergence study: the error of what the figures show against a refined reference, with CPU time.

Three quantities, one per stage of the model:

* ``force``  : the normal force along the bay on a smooth rail (Fig. 22), at ``points`` positions.
  Error: max |P - P_ref| over the fluctuation max P_ref - min P_ref.
* ``wear``   : the wear spectrum of one passage over a 10 um harmonic roughness (Figs 13-19),
  Delta Z_k for k <= K. Error: harmonic_error, each harmonic against itself.
* ``growth`` : the roughness coefficients Z_k after the growth run from a smooth rail (Fig. 23).
  Errors: harmonic_error (the plotted one), and the largest level difference in dB over the
  harmonics within 40 dB of the highest level.

Every error of a spectrum is judged per harmonic against that harmonic, never against a larger
total such as the mean wear: an error of 0.3 % of the mean wear can be 30 % of the harmonic that
decides whether roughness grows.

Each ``*_quantity`` function returns (values, cpu_seconds) and measures only its own stage (the
receptance table is timed for the track settings, not for the contact and growth settings).
"""

from __future__ import annotations

import io
import time

import numpy as np

from . import growth, interaction, moving, wear

__all__ = ["force_quantity", "wear_quantity", "growth_quantity", "force_error", "harmonic_error", "level_error_dB",
           "pareto_front"]

WITHIN_DB = 40.0  # harmonics within this many dB of the largest are judged


def force_quantity(track, wheels, spring, speed: float, harmonics: int, rtol: float, points: int = 601):
    """Force (N) on a smooth rail at ``points`` positions over the bay, and the CPU time (s) of the
    receptance table and the force solution."""
    t0 = time.process_time()
    tab = moving.receptance_table(track, speed, harmonics, rtol=rtol)
    one = interaction.Wheels(wheels.mass, wheels.radius, wheels.static_load, (0.0,))
    F = interaction.solve_forces(tab, one, spring, interaction.Roughness.smooth(harmonics), track.beta0, track.L)
    x = np.linspace(0.0, track.L, points, endpoint=False)
    P = interaction.force_history(F, x, track.beta0)[0]
    return P, time.process_time() - t0


def wear_quantity(table, track, wheels, spring, material, density, wear_coefficient, frequency: float,
                  amplitude: float, nodes: int, closure: str = "default", closure_scale: float = 1.0):
    """Wear spectrum Delta Z_k (k = -K..K, m) of one passage over a harmonic roughness, its mean
    wear depth (m), and the CPU time (s) of the forces, contact and wear."""
    t0 = time.process_time()
    K = table.harmonics
    one = interaction.Wheels(wheels.mass, wheels.radius, wheels.static_load, (0.0,))
    rough = interaction.Roughness.harmonic(amplitude, table.speed / frequency, track.L, K)
    F = interaction.solve_forces(table, one, spring, rough, track.beta0, track.L)
    w = wear.bay_wear(F, 0, rough, material, density, wear_coefficient, track.beta0, track.L, nodes=nodes,
                      closure=closure, closure_scale=closure_scale)
    return w.Z, float(w.depth.mean()), time.process_time() - t0


def growth_quantity(table, track, wheels, spring, material, density, wear_coefficient, settings):
    """Roughness Z_k (m) after settings.passages from a smooth rail, and the CPU time (s)."""
    t0 = time.process_time()
    h = growth.run_growth(table, wheels, spring, material, density, wear_coefficient,
                          interaction.Roughness.smooth(table.harmonics), track.beta0, track.L, settings, progress=io.StringIO())
    return h.Z[-1], time.process_time() - t0


def force_error(P, P_ref) -> float:
    """max |P - P_ref| over the fluctuation of P_ref, -."""
    return float(np.max(np.abs(np.asarray(P) - P_ref)) / np.ptp(P_ref))


def harmonic_error(Z, Z_ref, within_dB: float = WITHIN_DB, k_max: int | None = None) -> float:
    """Largest relative error of a harmonic against itself, max_k |Z_k / Z_k,ref - 1|, over the
    harmonics 1 <= k <= k_max whose reference amplitude is within ``within_dB`` of the largest, -.

    |Z / Z_ref - 1| bounds both the relative amplitude error and the phase error (in radians, for
    small errors). Z, Z_ref : coefficients k = -K..K (the spectra may have different K; the common
    harmonics k <= min(K, K_ref) are compared).
    """
    K, Kr = (len(Z) - 1) // 2, (len(Z_ref) - 1) // 2
    n = min(K, Kr) if k_max is None else min(K, Kr, k_max)
    a = np.asarray(Z)[K + 1 : K + 1 + n]
    b = np.asarray(Z_ref)[Kr + 1 : Kr + 1 + n]
    sel = np.abs(b) >= np.abs(b).max() * 10 ** (-within_dB / 20)
    return float(np.max(np.abs(a[sel] / b[sel] - 1)))


def level_error_dB(Z, Z_ref, k_max: int | None = None, within_dB: float = WITHIN_DB) -> float:
    """Largest level difference (dB) over the harmonics k <= k_max whose reference level is within
    ``within_dB`` of the highest reference level."""
    K = (len(Z_ref) - 1) // 2
    k_max = K if k_max is None else min(k_max, K)
    ref = growth.levels_dB(Z_ref)[:k_max]
    lev = growth.levels_dB(Z)[:k_max]
    sel = ref >= ref.max() - within_dB
    return float(np.max(np.abs(lev[sel] - ref[sel])))


def pareto_front(times, errors) -> np.ndarray:
    """True for each point that no other point beats in both CPU time and error (ties allowed)."""
    t, e = np.asarray(times, float), np.asarray(errors, float)
    out = np.ones(len(t), dtype=bool)
    for i in range(len(t)):
        better = (t <= t[i]) & (e <= e[i]) & ((t < t[i]) | (e < e[i]))
        out[i] = not better.any()
    return out
