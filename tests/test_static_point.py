"""The lattice sums and the moving-load tables near the static point (beta, omega -> 0 together: the column of a
constant load), where the m = 0 term of a lattice sum diverges.

Two losses of digits there, each found by tightening a rule's tolerance (issue 55): the closed form's denominator
1 + z^2 - 2 z cos(beta L) cancelled to an error of rounding 1 in (beta L)^2 (rail.track.lattice_factors now forms
it without), and the sum without its m = 0 term was the closed form minus that term, a difference of two numbers
of order 1 / (EI beta^4) (rail.track.beam_lattice_sums_excluding, rail.creepage.rail_flexibility.
rod_lattice_sum_excluding now form it without). The wavenumber integrals near beta = 0 magnified either as the
adaptive rule refined there: at rtol 1e-5 the vertical table with the pads' rotational stiffness gave -2.2 m/N for
a receptance of 6.6e-9 m/N, and the head's rod 28 m/N for 3.0e-9 m/N at rtol 1e-6. Each check below is against an
explicit sum or against the rule at another tolerance, with the old form's error shown beside it.
"""

import dataclasses

import numpy as np
import pytest

from rail import moving
from rail.creepage import rail_flexibility as lg
from rail.track import (Ballast, Pad, Rail, Sleeper, Track, beam_lattice_sums, beam_lattice_sums_excluding, free_beam_receptances,
                        free_receptance_poles, lattice_factors)

RAIL = Rail(2.1e11, 8.1e10, 7850.0, 7.69e-3, 3.055e-5, 0.4, 0.01, 1.6e-6)  # config/config.yaml
TRACK = Track(RAIL, Pad(3.5e8, 0.25, 2.8e4), Sleeper(162.0, 0.6), Ballast(5e7, 1.0, 8e4), "hysteretic")
ROTATIONAL = dataclasses.replace(TRACK, pad=dataclasses.replace(TRACK.pad, rotational_stiffness=9.45e5))  # docs/dynamic-creepage.md
V = 40.0
FRACTIONS = np.array([3e-1, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6])  # beta / beta0, each also negative


def _rod_pole(omega):
    EA = RAIL.youngs_modulus * RAIL.area * (1 + 1j * RAIL.loss_factor * np.sign(omega))
    p = np.sqrt(RAIL.density * RAIL.area * omega**2 / EA + 0j)
    return np.where(p.imag < 0, -p, p)


def _explicit_rest(f, beta, M=100_000):
    """sum over 0 < abs(m) <= M of f(beta + m beta0), plus the tail abs(m) > M of f ~ c / q^n by the midpoint rule
    (sum_{m > M} 1 / (m + a)^n ~ int from M + 1/2: an error O(M^-(n + 2))), c and n read off f at large q."""
    b0 = TRACK.beta0
    m = np.concatenate([np.arange(-M, 0), np.arange(1, M + 1)])
    total = f(beta[:, None] + m[None, :] * b0).sum(1)
    q = np.full((len(beta), 1), 1e3 * M * b0)  # far enough for the tail's leading power
    n = float(np.round(np.log(np.abs(f(q)[0, 0] / f(2 * q)[0, 0])) / np.log(2)))
    c = f(q)[:, 0] * q[:, 0] ** n
    a, X = beta / b0, M + 0.5
    if n == 1:  # an odd sum, summed symmetrically: int_X (1 / (x + a) - 1 / (x - a)) dx
        return total - c / b0 * np.log((X + a) / (X - a))
    return total + c / b0**n * ((X + a) ** (1 - n) + (-1) ** n * (X - a) ** (1 - n)) / (n - 1)


def test_the_closed_lattice_sum_keeps_its_digits_where_beta_and_the_pole_are_small():
    # sum_m 1 / ((beta + m b0)^2 - p^2) = (L / 2p) E (rail.track.lattice_factors), against its m = 0 term plus the
    # rest summed explicitly, on the rod's pole at omega = beta V (the static column): measured within 4.4e-16 of
    # itself at every beta; as 1 + z^2 - 2 z cos(beta L), 2.0e-8 at beta = 1e-5 beta0 and 2.0e-6 at 1e-6 beta0
    # (eps / (beta L)^2).
    L = TRACK.L
    beta = np.concatenate([FRACTIONS, -FRACTIONS]) * TRACK.beta0
    p = _rod_pole(beta * V)
    ref = 1.0 / (beta**2 - p**2) + _explicit_rest(lambda q: 1.0 / (q**2 - p[:, None] ** 2), beta)
    new = (L / (2 * p)) * lattice_factors(p, beta, L)[0]
    z = np.exp(1j * p * L)
    old = (L / (2 * p)) * (z * z - 1) / (1j * (1 + z * z - 2 * z * np.cos(beta * L)))
    assert np.all(np.abs(new / ref - 1) < 1e-13), np.abs(new / ref - 1)
    assert np.abs(old / ref - 1).max() > 1e-7  # the mechanism's error, shown with it off
    # the odd sum (symmetric in m), sum_m b / (b^2 - p^2) = L O, where it is not small: against the same sum
    odd = _explicit_rest(lambda q: q / (q**2 - p[:, None] ** 2), beta) + beta / (beta**2 - p**2)
    assert np.allclose(L * lattice_factors(p, beta, L)[1], odd, rtol=1e-9, atol=0)


@pytest.mark.parametrize("entry", [0, 1, 3])
def test_the_beams_lattice_sums_without_their_m0_term_equal_the_explicit_sum(entry):
    # S - H_0 of H_ww, H_wM and H_psiM (H_psiF = -H_wM) at omega = beta V, against 0 < |m| <= 1e5 summed with a
    # midpoint tail (itself within 1e-14): measured within 6.2e-11, 5.2e-11 and 1.4e-11 of itself, at beta = 0.3 beta0
    # (the static form beyond |m| = 40 leaves out the rho A omega^2 terms); the closed form minus H_0 as it was formed,
    # 0.14 of itself at 1e-4 beta0 and 210 at 1e-5 (its digits lost to the cancellation of two terms of order
    # 1 / (EI beta^4)); even with the closed form's new denominator, 200 (H_ww) and 350 (H_wM) at 1e-5 beta0.
    beta = np.concatenate([FRACTIONS, -FRACTIONS]) * TRACK.beta0
    om = beta * V
    ref = _explicit_rest(lambda q: free_beam_receptances(q, om[:, None], TRACK)[entry], beta)
    new = beam_lattice_sums_excluding(beta, om, TRACK)[entry]
    assert np.all(np.abs(new / ref - 1) < 2e-10), np.abs(new / ref - 1)
    if entry == 0:  # as it was formed: the closed form of periodic_sum (1 + z^2 - 2 z cos(beta L)) minus H_0
        c, p = free_receptance_poles(om, TRACK)
        z = np.exp(1j * p * TRACK.L)
        S = sum(cj * (TRACK.L / (2 * pj)) * (zj * zj - 1) / (1j * (1 + zj * zj - 2 * zj * np.cos(beta * TRACK.L))) for cj, pj, zj in zip(c, p, z))
        old = S - free_beam_receptances(beta, om, TRACK)[0]
        assert np.abs(old / ref - 1).max() > 1e-2, np.abs(old / ref - 1)
        assert np.abs((beam_lattice_sums(beta, om, TRACK)[0] - free_beam_receptances(beta, om, TRACK)[0]) / ref - 1).max() > 1.0
    assert np.allclose(beam_lattice_sums_excluding(beta, om, TRACK)[2], -new if entry == 1 else -beam_lattice_sums_excluding(beta, om, TRACK)[1])


def test_the_rods_lattice_sum_without_its_m0_term_equals_the_explicit_sum():
    # measured within 1.4e-11 of itself (at 0.3 beta0: the static form beyond |m| = 40)
    beta = np.concatenate([FRACTIONS, -FRACTIONS]) * TRACK.beta0
    om = beta * V
    ref = _explicit_rest(lambda q: lg.rod_receptance(q, om[:, None], TRACK), beta)
    assert np.allclose(lg.rod_lattice_sum_excluding(beta, om, TRACK), ref, rtol=1e-10, atol=0)


def test_the_static_columns_receptance_is_the_same_at_every_tolerance_of_the_rule():
    # the diagonal of the static column (a constant load) at rtol 1e-4, 1e-5 and 1e-8: measured within 1.3e-11 of
    # the finest for the vertical table with the pads' rotational stiffness (before: -2.2 m/N at 1e-5 for 6.58e-9
    # m/N) and 1.1e-9 for the head's rod (before: 3.4e-8 at 1e-5, 28 m/N at 1e-6)
    vert = [moving.receptance_table(ROTATIONAL, V, 2, rtol=r).A[0, 2, 2] for r in (1e-4, 1e-5, 1e-8)]
    rod = [lg.moving_head_matrix(lg.RailHead(TRACK), V, 0.0, np.arange(-2, 3), ("rod",), r)["rod"][2, 2] for r in (1e-4, 1e-5, 1e-8)]
    for vals in (vert, rod):
        assert np.allclose(vals[:2], vals[2], rtol=1e-8, atol=0), vals
        assert abs(vals[2].imag) < 1e-12 * abs(vals[2])  # a static load's response is in phase with it
