"""A growth run with the rail's longitudinal flexibility on a track cell, end to end through rail.app.api (issue 55:
refused at start-up before rail.creepage.rail_flexibility_cell): the irregular_dampers case (two bays, a tuned rail damper at each
mid-span) with rail_flexibility.model = rod_and_bending, and a cell of two identical bays against the uniform
track over the same two-bay period (rail.creepage.rail_flexibility.RailHead). Coarse numerics (K = 18 per bay, 21 contact
nodes, two updates of 10,000 passages at 40 m/s). Slow: about 1-4 min per run on a shared machine."""

import io

import numpy as np
import pytest

from rail.app import api
from rail.creepage.rail_flexibility_cell import CellHead
from rail.creepage.rail_flexibility import RailHead
from rail.setup.config import deep_merge

pytestmark = pytest.mark.slow

K = 18
CHANGES = {"rail_flexibility": {"model": "rod_and_bending"}, "numerics": {"track": {"harmonics": K}, "contact": {"nodes": 21}},
           "growth": {"passages": 20000, "passages_per_update": 10000, "save_every": 10000}, "speeds": [40.0],
           "roughness": {"bays": 2},
           "figures": {"fig22": {"speeds": [40.0, 60.0]}, "growth": {"speeds": [40.0, 60.0, 80.0, 100.0]},
                       "rate_spectrum": {"speeds": [40.0], "shortest": 0.04, "bays": 2, "longest": 0.07, "per_octave": 12}}}


def _run(name, changes):
    study = api.load(name, changes=changes)
    return study.scenario.material.rail_flexibility, api.growth(study, speed=40.0, progress=io.StringIO())


def _Z(ds):
    return ds.Z_real.values[-1] + 1j * ds.Z_imag.values[-1]


def test_a_growth_run_with_the_rails_flexibility_on_a_cell_with_rail_dampers_runs_end_to_end():
    head, ds = _run("irregular_dampers", CHANGES)
    assert isinstance(head, CellHead) and len(head.cell.dampers) == 2
    assert "rail.creepage.rail_flexibility_cell" in ds.attrs["creepage_model"] and "2 rail dampers act vertically only" in ds.attrs["creepage_model"]
    Z = _Z(ds)
    assert np.all(np.isfinite(Z)) and np.abs(Z).max() > 0
    assert np.all(np.isfinite(ds.exponential_rate.values[1::2]))  # the bay harmonics (even lines of the 2-bay period)


def test_a_cell_of_identical_bays_grows_as_the_uniform_track_with_the_rails_flexibility():
    # The same two-bay period with the uniform track's head (its Bloch classes, rail.creepage.rail_flexibility) and with the cell's
    # (rail.creepage.rail_flexibility_cell): from a smooth rail the bay harmonics (even lines j = 2 k) grow; measured within 9.0e-7 of
    # themselves at every k <= K = 18 (6.8e-10 at k = 1). Before 2026-12-03 the uniform operator was handed the force
    # table's J = N K as its K per bay (N times the harmonics of the period, rail.creepage.coupling.rail_operator):
    # then 2.5e-4 for k <= 9, 2.5e-3 at k = 12 and 4.5e-2 at k = 17. The odd lines stay at rounding (9e-15 of the
    # even ones) on both.
    h_u, uni = _run("default", CHANGES)
    h_c, cel = _run("default", deep_merge(CHANGES, {"track": {"cell": {"bays": 2}}}))
    assert isinstance(h_u, RailHead) and isinstance(h_c, CellHead)
    J = 2 * K
    zu, zc = _Z(uni), _Z(cel)
    even = np.arange(2, J + 1, 2)
    assert np.all(np.abs(zc[J + even] - zu[J + even]) < 1e-5 * np.abs(zu[J + even])), np.abs(zc[J + even] / zu[J + even] - 1)
    odd = np.arange(1, J + 1, 2)
    assert np.abs(zc[J + odd]).max() < 1e-10 * np.abs(zc[J + even]).max()
