"""The linearised wear feedback per wavenumber (rail.growth_spectrum) against full nonlinear growth
runs, for a growing and a decaying wavelength between the one-bay comb lines."""

import dataclasses
import io

import numpy as np
import pytest
from model import scenario
from test_growth import MATERIAL, contact_spring, track

from rail import chain, moving
from rail import growth_spectrum as GS
from rail import interaction as I

K, N = 24, 4


@pytest.fixture(scope="module")
def setup():
    tr = track()
    scn = scenario(tr, MATERIAL, contact_spring(), K=K, nodes=41, passages=100000, step=10000)
    scn = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=N))
    return scn, moving.bloch_tables(tr, 40.0, K, N)


def test_batches_hold_one_line_per_pair_of_classes():
    b = GS._batches([5, 9, 6, 3, 7, 8, 1], 4)
    for batch in b:
        keys = [min(j % 4, (4 - j % 4) % 4) for j in batch]
        assert len(keys) == len(set(keys))
    assert sorted(j for batch in b for j in batch) == [1, 3, 5, 6, 7, 8, 9]


def test_linear_rates_predict_full_growth_runs(setup):
    # lines between the comb lines of the 4-bay period at 40 m/s: j = 37 (64.9 mm, grows by about
    # 5 % per 1e5 passages) and j = 86 (27.9 mm, decays by about 18 %). The probe is in its linear
    # range (eps and 2 eps agree to 1e-4). A full growth run from 0.1 um sinusoids at both lines
    # (100,000 passages, 10 updates, varying contact grids, the parametric wear of the smooth rail
    # in class 0 beside them) ends where the growth loop's own explicit update (1 - h R_j)^10 says,
    # (measured 3e-4 and 1.1e-3), and within the update-step error of exp(-R_j n) (first order,
    # estimated 10 |h R|^2 / 2 = 0.07 % and 1.4 %; measured 0.09 % and 1.3 %).
    scn, tabs = setup
    lines = [37, 86]
    R = GS.wear_rates(scn, tabs, lines, eps=1e-8)
    R2 = GS.wear_rates(scn, tabs, lines, eps=2e-8)
    assert np.abs(R2 / R - 1).max() < 1e-4
    assert -R[0].real > 0 > -R[1].real  # one grows, one decays
    J = N * K
    Z = np.zeros(2 * J + 1, dtype=complex)
    for j in lines:
        Z[J + j] = Z[J - j] = 1e-7 / 2
    h = chain.grow(scn, tabs, I.Roughness(Z, N), progress=io.StringIO())
    g = scn.growth
    steps, hstep = g.passages // g.passages_per_update, g.passages_per_update  # one wheel: train = wheel passages
    for j, r in zip(lines, R):
        ratio = h.Z[-1][J + j] / h.Z[0][J + j]
        assert abs(abs(ratio) - 1) > 0.03  # changed measurably
        assert abs(ratio / (1 - hstep * r) ** steps - 1) < 2e-3
        assert abs(ratio / np.exp(-r * g.passages) - 1) < 1.5 * steps * abs(hstep * r) ** 2 / 2 + 1e-3
