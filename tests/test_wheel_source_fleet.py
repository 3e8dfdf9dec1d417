"""The wheels' roughness as a source under a fleet (issue 58 for fleets; rail.growth_spectrum.source, rail.studies.wheel_source,
docs/wheel-source.md): per fleet passage S_{n+1} = a S_n + Q with a = sum_c w_c abs(1 - R_c)^2 and Q = sum_c w_c Q_c.
Checked against an ensemble of random class draws and wheel phases (the derivation), against the hand recursion of the
comb's moments, against each class computed alone as a one-train scenario, and for the inputs and the no-source case."""

import re

import numpy as np
import pytest
from test_fleet import base, vehicle

from rail import chain
from rail import fleet as F
from rail import growth_spectrum as GS
from rail.growth_spectrum import source as src
from rail.studies import rate_spectrum
from rail.studies import wheel_source as ws
from rail.studies.fleet import fleet_spectrum_dataset

N = 4
LINES = [37, 86, 48]  # 64.9 mm (a free line), 27.9 mm (on the half-comb) and 50 mm (on the one-bay comb: the supports' source)


# ---------------------------------------------------------------- the equation, by itself


def test_the_fleets_expected_mean_square_follows_an_ensemble_of_random_class_draws_and_wheel_phases():
    # the derivation as a Monte Carlo of one line's cosine amplitude A (mean square abs(A)^2 / 2, no spectrum): each
    # passage a class drawn with probability w_c, A -> (1 - R_c) A - sum over its wheels of R_own W e^{i phi} (each wheel
    # its own random phase, mean square P_c = W^2 / 2) + s_c (the comb, the classes in phase), from a ground rail of random
    # phase. Rates of a few percent so that the draw's spread and the settling show within 120 passages. The ensemble's
    # mean square against S_n (fleet_decay_factor, fleet_source_power) plus fleet_comb_mean_square, within three standard
    # errors at every passage (the ensemble's own sampling error)
    rng = np.random.default_rng(58)
    w = np.array([0.5, 0.3, 0.2])
    Rc = np.array([0.04 + 0.03j, 0.01 - 0.02j, 0.09 + 0.01j])
    own = np.array([[0.03 + 0.01j, 0.02 + 0.0j], [0.01 + 0.0j, 0.0 + 0.0j], [0.05 - 0.02j, 0.04 - 0.01j]])  # two wheels each
    Wamp = np.array([1.0, 3.0, 0.5])  # each class's wheel amplitude [arbitrary units]
    sc = np.array([0.02, 0.05, 0.0])
    A0 = 2.0
    members, passages = 40000, 120
    A = A0 * np.exp(1j * rng.uniform(0, 2 * np.pi, members))
    ms = [np.abs(A) ** 2 / 2]
    for _ in range(passages):
        c = rng.choice(3, size=members, p=w)
        phases = np.exp(1j * rng.uniform(0, 2 * np.pi, (2, members)))
        A = (1 - Rc[c]) * A - (own[c].T * Wamp[c] * phases).sum(axis=0) + sc[c]
        ms.append(np.abs(A) ** 2 / 2)
    ms = np.array(ms)
    Qc = src.axle_source_power(own.T, Wamp**2 / 2)
    a, Q = src.fleet_decay_factor(Rc, w), src.fleet_source_power(Qc, w)
    n = np.arange(passages + 1)[:, None]
    want = (src.expected_mean_square(n, A0**2 / 2, Rc @ w, Q, decay=a)
            + src.fleet_comb_mean_square(n, Rc[:, None], sc[:, None], w))[:, 0]
    mean, se = ms.mean(axis=1), ms.std(axis=1, ddof=1) / np.sqrt(members)
    assert np.all(np.abs(mean[1:] - want[1:]) <= 3 * se[1:]), np.round((mean - want) / se, 1)
    assert want[-1] > 10 ** (-1 / 10) * (src.settled_mean_square(Rc @ w, Q, decay=a) + src.fleet_settled_comb(Rc[:, None], sc[:, None], w))
    # the draw's spread matters here: a train of the fleet's mean rate and source (a = abs(1 - R)^2) misses the ensemble
    wrong = src.expected_mean_square(n[:, 0], A0**2 / 2, Rc @ w, Q, comb=sc @ w)
    assert np.max(np.abs(mean - wrong) / se) > 10


def test_the_fleets_comb_is_the_hand_recursion_of_its_first_two_moments_and_one_class_the_one_trains():
    # E c_{n+1} = (1 - R) E c_n + s and E abs(c_{n+1})^2 = a E abs(c_n)^2 + 2 Re[sum_c w_c (1 - R_c) s_c E c_n] + sum_c w_c s_c^2
    # iterated by hand over 400 passages (decaying and slowly decaying lines, a line where one class grows and the fleet
    # decays, a line with R_c = 0), the classes' sources in phase; the closed form (geometric sums by expm1 and log1p) to
    # 1e-9 of the hand value, and its limit the settled comb
    Rc = np.array([[0.02 + 0.01j, 1e-5 - 2e-5j, -0.01 + 0.005j, 0.0], [0.05 - 0.02j, 3e-5 + 1e-5j, 0.005 + 0.01j, 0.0]])
    sc = np.array([[1e-9, 2e-9, 1e-9, 0.0], [3e-9, 1e-9, 0.5e-9, 1e-9]])
    w = np.array([0.3, 0.7])
    a = src.fleet_decay_factor(Rc, w)
    R, s = w @ Rc, w @ sc
    m, M = np.zeros(4, complex), np.zeros(4)
    for n in range(400):
        assert np.allclose(src.fleet_comb_mean_square(n, Rc, sc, w), M / 2, rtol=1e-9, atol=0), n
        M = a * M + 2 * np.real((w[:, None] * (1 - Rc) * sc).sum(0) * m) + w @ sc**2
        m = (1 - R) * m + s
    S = src.fleet_settled_comb(Rc, sc, w)
    assert np.isinf(S[3]) and np.all(np.isfinite(S[:3]))  # the line that holds (R_c = 0) has no settled comb
    assert a[2] < 1 and Rc[0, 2].real < 0  # one class grows there, the fleet decays
    assert np.allclose(src.fleet_comb_mean_square(1e9, Rc, sc, w)[:3], S[:3], rtol=1e-9)
    # one class of weight 1: the one train's comb exactly (the spread is 0; the mean comb is the train's)
    for n in (0, 1, 7, 1e3, 1e6):
        got, one = src.fleet_comb_mean_square(n, Rc[:1], sc[:1], [1.0]), src.expected_mean_square(n, 0.0, Rc[0], 0.0, sc[0])
        assert np.array_equal(got, one, equal_nan=True), n
    assert np.array_equal(src.settled_mean_square(Rc[0], 0.0) + src.fleet_settled_comb(Rc[:1], sc[:1], [1.0]),
                          src.settled_mean_square(Rc[0], 0.0, sc[0]))
    assert np.array_equal(src.fleet_decay_factor(Rc[:1], [1.0]), np.abs(1 - Rc[0]) ** 2)
