"""The rail head's receptances on a track cell with uneven supports (rail.creepage.rail_flexibility_cell) against a direct solution
written without rail.creepage.rail_flexibility_cell or rail.cell (tests/independent/rail_head_direct.py: the free rail's Green's
functions by residues and a finite row of the cell's attachments solved for directly).

The cell: three bays of 0.55, 0.70 and 0.55 m, pads 1, 2.5 and 0.7 times the default, the second sleeper voided
(its ballast 1e-3 of the default), the third sleeper 1.3 times as heavy, and a tuned rail damper at every
mid-span (4 kg, 1,070 Hz, loss factor 0.35: the irregular_dampers case). The moving-load matrices at
V = 0.02 m/s (the stationary limit, as tests/test_head_positions.py) give the Fourier coefficients a_n over the
load's position x0 in the cell, and the receptance at x0 is their sum, alpha(x0) = sum_n a_n exp(i n beta_P x0),
abs(n) <= 12 N (12 per bay). Issue 55 asks for 1 % at the contact.
Measured at 900, 1,100 and 1,300 Hz against the direct value at x0: A_Q within
1.9e-4 at every position, psi/M within 9.7e-5, the rod within 2.3e-4, psi/F within 3.9e-4
between the attachments and 0.25-1.16 % of itself at them (below 4.7e-3 of the cell's largest psi/F). At an
attachment that is the summed series' truncation, not the model: psi/F jumps there (G_psiF is odd), and its
series converges as 1 / harmonics (at 900 Hz at the support at 0.55 m, 2.2 %, 1.5 % and 1.2 % with 6, 9 and 12
harmonics per bay; between the attachments 1.5e-3, 4.0e-4 and 1.6e-4). So each receptance is also compared with the
direct solution's own series to the same harmonics (its coefficients by the trapezoid rule over 1,152 points of
the cell; 2,304 change it by 2.5e-5 at most): the model's error alone. Measured at 1,100 Hz: psi/F within 3.5e-4
of itself at every position, the attachments included (1.0e-2 against the direct value at the support at
0.55 m, of which the series' truncation is 1.0e-2), the rod 1.5e-4, psi/M 1.2e-5, A_Q 1.2e-4. At 100 and 2,000 Hz (matrix): psi/F within
2.0e-3 and 6.2e-4 of the series, A_Q 2.5e-6 and 4.5e-6, the rod 8.4e-7 and 2.1e-6, psi/M 6.8e-5 and 6.8e-6.
The direct rows: 101 cells (303 supports and 303 dampers) for the beam and 281 cells for the rod.
Slow: about 6-8 min of CPU per frequency (the wavenumber rule at a vanishing speed: 0.4-0.7 and 1.2 million nodes).
"""

import sys
from pathlib import Path

import numpy as np
import pytest

from rail.cell import make_cell
from rail.creepage.rail_flexibility_cell import CellHead, cell_head_matrix
from rail.track import Ballast, Pad, Rail, Sleeper, Track

sys.path.insert(0, str(Path(__file__).parent / "independent"))
import rail_head_direct as direct  # noqa: E402

pytestmark = pytest.mark.slow

RAIL = Rail(2.1e11, 8.1e10, 7850.0, 7.69e-3, 3.055e-5, 0.4, 0.01, 1.6e-6)  # config/config.yaml
TRACK = Track(RAIL, Pad(3.5e8, 0.25, 2.8e4), Sleeper(162.0, 0.6), Ballast(5e7, 1.0, 8e4), "hysteretic")
CELL = make_cell(TRACK, 3, spacing=[0.55, 0.7, 0.55], pad=[1.0, 2.5, 0.7], ballast=[1.0, 1e-3, 1.0], sleeper_mass=[1.0, 1.0, 1.3],
                 damper={"mass": 4.0, "frequency": 1070.0, "loss_factor": 0.35, "viscous_damping": 0.0, "position": 0.5})
HEAD = CellHead(CELL)
PER_BAY = 12
GRID = 16 * 72  # the direct solution's sampling of the cell for its series: a multiple of 72 puts every attachment on it
# above each support, at quarter-spans and mid-spans (over a damper) of the bays
POSITIONS = [0.0, 0.1375, 0.275, 0.55, 0.725, 0.9, 1.25, 1.525, 1.6]
BETWEEN = (0.1375, 0.725, 1.6)  # the positions between the attachments (supports at 0, 0.55, 1.25 m; dampers at 0.275, 0.9, 1.525 m)


# 1,100 Hz in .ci/run; 100, 900, 1,300 and 2,000 Hz on demand (-m matrix): 5-8 min of CPU each (all five passed when written)
@pytest.mark.parametrize("f", [pytest.param(100.0, marks=pytest.mark.matrix), pytest.param(900.0, marks=pytest.mark.matrix), 1100.0,
                               pytest.param(1300.0, marks=pytest.mark.matrix), pytest.param(2000.0, marks=pytest.mark.matrix)])
def test_the_heads_receptances_on_uneven_supports_agree_with_the_direct_solution(f):
    om = 2 * np.pi * f
    J = PER_BAY * CELL.bays
    js = np.arange(-J, J + 1)
    m = cell_head_matrix(HEAD, 0.02, om, js, kinds=("rod", "psiM", "psiF"), rtol=1e-6)
    vx, vk, _, _ = direct.cell_row(CELL, om, 50)
    _, _, sx, sf = direct.cell_row(CELL, om, 140)
    kx = HEAD.longitudinal_stiffness * (1 + 1j * HEAD.longitudinal_loss_factor)
    e = HEAD.head_height
    psiF_scale = 0.0
    rows = []
    # the direct solution's own series to the same harmonics: its coefficients by the trapezoid rule on GRID points
    # over the cell (every attachment a grid point, where psi/F, which jumps there, takes its mean: the rule's error
    # O(1 / GRID^2)), so that the series' truncation at an attachment is the same on both sides
    xg = np.arange(GRID) * CELL.period / GRID
    Fg, Mg = direct.stationary_beam_rows(xg, om, TRACK, vx, vk)
    Rg = direct.stationary_rod_rows(xg, om, TRACK, sx, kx * sf)
    to_harmonics = np.exp(-1j * np.outer(js, CELL.beta_p * xg)) / GRID
    for x0 in POSITIONS:
        ph = np.exp(1j * js * CELL.beta_p * x0)
        ours = {k: complex(np.sum(m[k][:, J] * ph)) for k in ("rod", "psiM", "psiF")}
        series = {k: complex(ph @ (to_harmonics @ g)) for k, g in (("rod", Rg), ("psiM", Mg), ("psiF", Fg))}
        psiF, psiM = direct.stationary_beam_row(x0, om, TRACK, vx, vk)
        rod = direct.stationary_rod_row(x0, om, TRACK, sx, kx * sf)
        rows.append((x0, ours, psiF, psiM, rod, series))
        psiF_scale = max(psiF_scale, abs(psiF))
    for x0, ours, psiF, psiM, rod, series in rows:
        # issue 55's must-show, the model's error alone: each receptance against the direct solution's series to the
        # same harmonics, within 1 % of itself at every position, the attachments included
        for k in ("rod", "psiM", "psiF"):
            assert abs(ours[k] / series[k] - 1) < 1e-2, (f, x0, k, ours[k], series[k])
        A_Q_series = series["rod"] + HEAD.head_height**2 * series["psiM"]
        assert abs((ours["rod"] + HEAD.head_height**2 * ours["psiM"]) / A_Q_series - 1) < 1e-2, (f, x0)
        A_Q, A_Q_ref = ours["rod"] + e**2 * ours["psiM"], rod + e**2 * psiM
        assert abs(A_Q / A_Q_ref - 1) < 1e-2, (f, x0, A_Q, A_Q_ref)
        assert abs(ours["psiM"] / psiM - 1) < 1e-2, (f, x0, ours["psiM"], psiM)
        assert abs(ours["rod"] / rod - 1) < 1e-2, (f, x0, ours["rod"], rod)
        # psi per vertical force (A_P = e psi/F): between the attachments against itself; at an attachment (a support
        # or a damper) alpha(x0, x0) has a kink, where the series summed to 12 harmonics per bay converges slowest
        # (measured 0.25-1.16 % of itself there, falling as 1 / harmonics, 4.7e-3 of the cell's largest psi/F; A_Q's and
        # the rod's series within 2.3e-4 at the same points): judged there against the cell's largest
        scale = abs(psiF) if x0 in BETWEEN else psiF_scale
        assert abs(ours["psiF"] - psiF) < 1e-2 * scale, (f, x0, ours["psiF"], psiF)
