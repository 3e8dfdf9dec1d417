"""Convergence study: the error of what the figures show against a refined reference, with CPU time.

Three quantities, one per stage of the model:

* ``force``  : the normal force along the bay on a smooth rail (Fig. 22), at ``points`` positions.
  Error: max |P - P_ref| over the fluctuation max P_ref - min P_ref.
* ``wear``   : the wear spectrum of one passage over a 10 um harmonic roughness (Figs 13-19),
  Delta Z_k for k <= K. Error: max_k |Delta Z_k - Delta Z_k,ref| over the mean wear depth, the
  measure that decides growth (the bay variation is a few percent of the mean).
* ``growth`` : the roughness coefficients Z_k after the growth run from a smooth rail (Fig. 23).
  Errors: max_k |Z_k - Z_k,ref| over max_k |Z_k,ref| (the plotted one), and the largest level
  difference in dB over the harmonics within 20 dB of the highest level.

Each ``*_quantity`` function returns (values, cpu_seconds) and measures only its own stage (the
receptance table is timed for the track settings, not for the contact and growth settings).
"""

from __future__ import annotations

import io
import time

import numpy as np

from . import growth, interaction, moving, wear

__all__ = ["force_quantity", "wear_quantity", "growth_quantity", "force_error", "wear_error", "growth_error",
           "level_error_dB", "pareto_front"]


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


def wear_error(Z, Z_ref, mean_ref) -> float:
    """max_k |Delta Z_k - Delta Z_k,ref| over the mean wear depth, -. The spectra may have
    different K; the common harmonics are compared and the rest counted against zero."""
    K, Kr = (len(Z) - 1) // 2, (len(Z_ref) - 1) // 2
    n = max(K, Kr)
    a, b = np.zeros(2 * n + 1, complex), np.zeros(2 * n + 1, complex)
    a[n - K : n + K + 1], b[n - Kr : n + Kr + 1] = Z, Z_ref
    return float(np.max(np.abs(a - b)) / mean_ref)


def growth_error(Z, Z_ref) -> float:
    """max_k |Z_k - Z_k,ref| over max_k |Z_k,ref|, -."""
    return float(np.max(np.abs(np.asarray(Z) - Z_ref)) / np.max(np.abs(Z_ref)))


def level_error_dB(Z, Z_ref, k_max: int | None = None, within_dB: float = 20.0) -> float:
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
