"""The linear method with dynamic creepage on a track cell (rail.growth_spectrum.creepage.cell_closed_loop_wear, issue 55):
the tangent of the contact march over the cell with the loop of u_bar closed over the cell's harmonics, against the
cell's probes of the nonlinear march (rail.growth_spectrum.cell, method 'probe') with the Newton steps on u_bar
converged to 1e-9 of the creep velocity. Before it, a cell with the wheelset's modes, the rail's flexibility or falling
friction fell back to the probes (10-35 times the uniform track's cost, docs/performance.md), whose default tolerance
1e-5 leaves part of a probe's own change of u_bar unresolved.

The case: three bays with a voided sleeper (the ballast of support 1 a thousand times softer), the report's contact,
K = 12, 31 nodes, 40 m/s, lines 1.8 m (the cell's fundamental, with the supports' coupling), 360 mm, 150 mm and 60 mm.
The mechanisms are the scenario files' (rail.setup.config.MOTORED_WHEELSET, TRAILER_WHEELSET, rod_and_bending) and a
falling friction (mu_s 0.4 to mu_d 0.3 over 1.67 m/s of slip).
"""

import dataclasses
import functools

import numpy as np
import pytest

from rail import chain
from rail import growth_spectrum as gs
from rail.creepage import coupling
from rail.setup import build, config

V = 40.0
LINES = np.array([3, 5, 12, 30])
MECHANISMS = {"motored": {"wheelset": config.MOTORED_WHEELSET}, "trailer": {"wheelset": config.TRAILER_WHEELSET},
              "rail": {"rail_flexibility": {"model": "rod_and_bending"}},
              "falling": {"contact": {"friction_static": 0.4, "friction_dynamic": 0.3, "friction_decay": 1.67}},
              "together": {"wheelset": config.MOTORED_WHEELSET, "rail_flexibility": {"model": "rod_and_bending"}}}


@functools.lru_cache(maxsize=None)
def _case(mechanism: str, normal: str = "report", path: str = "wheel"):
    """(scenario, table) of the voided three-bay cell with one mechanism ('none': the report's fixed creepage)."""
    cfg = config.load_yaml("config/config.yaml")
    over = {"track": {"cell": {"bays": 3, "ballast": [1.0, 1e-3, 1.0]}}, "roughness": {"bays": 3},
            "figures": {"rate_spectrum": {"bays": 3}}, "contact": {"normal": normal, "wear_path": path}}
    over = config.deep_merge(over, MECHANISMS.get(mechanism, {}))
    scn = build.spectrum_scenario(config.deep_merge(cfg, over), "cell")
    scn = dataclasses.replace(scn, track_numerics=dataclasses.replace(scn.track_numerics, harmonics=12),
                              contact_numerics=dataclasses.replace(scn.contact_numerics, nodes=31))
    return scn, chain.receptance_table(scn, V)


@pytest.mark.parametrize("mechanism,normal,path", [("motored", "report", "wheel")] + [
    pytest.param(m, n, p, marks=pytest.mark.slow) for m, n, p in (("trailer", "report", "wheel"), ("rail", "report", "wheel"),
                                                                  ("falling", "report", "wheel"), ("together", "report", "wheel"),
                                                                  ("together", "nonhertzian", "patch"))])
def test_the_cells_linear_method_with_dynamic_creepage_matches_its_converged_probes(mechanism, normal, path, monkeypatch):
    """Every line's two eigenvalues (complex: the drift too) against themselves. Measured: 1.2e-5 to 6.2e-5 (motored),
    8.7e-6 to 7.5e-5 (trailer), 3.5e-8 to 4.9e-6 (rail), 2.5e-5 to 6.5e-4 (falling: the probes' O(eps) nonlinearity
    of the slip-rate law) and 5.9e-6 to 2.2e-4 (together; 6.3e-6 to 2.6e-5 with the non-Hertzian contact on the patch's
    true path, the scenario files' default, whose step times and pressure shape the probes change too); the smooth
    rail's source within 1e-7 of itself (the tangent's
    reference is march_with_creepage's periodic state). The mechanism must move the rate (else the check would pass
    without it): against the fixed creepage's rates by more than ten times the agreement."""
    scn, tab = _case(mechanism, normal, path)
    fast = gs.rate_spectrum(scn, tab, LINES, grid_phases=1, check_lines=1)
    assert fast.method == "cell of 3 bays: the tangent of the contact march over the cell at every line"
    with monkeypatch.context() as mp:
        mp.setattr(coupling, "march_with_creepage", functools.partial(coupling.march_with_creepage, tol=1e-9, max_iter=200))
        ref = gs.rate_spectrum(scn, tab, LINES, grid_phases=1, check_lines=None, method="probe")
    err = np.maximum(np.abs(fast.rate - ref.rate) / np.abs(ref.rate), np.abs(fast.rate_other - ref.rate_other) / np.abs(ref.rate_other))
    assert err.max() < 2e-3, dict(zip(LINES, err))
    assert np.allclose(fast.source, ref.source, rtol=1e-6, atol=0)
    fixed = gs.rate_spectrum(*_case("none", normal, path), LINES, grid_phases=1, check_lines=None)
    moved = np.abs(fixed.rate - ref.rate) / np.abs(ref.rate)
    assert moved.max() > 10 * err.max(), (moved, err)
    # the linearity check (probes of 2 eps by the nonlinear march, u_bar from the smooth rail's to 1e-10)
    assert 0 < fast.linearity < 1e-3
    if mechanism == "motored":  # the probes' columns handed over in chunks (the loop's basis held per wheel): the same rates
        # (an 8-bay cell's 170 columns at once peaked at 4.6 GB: cell_linear_operators chunks them as without u_bar)
        chunked = gs.cell_rate_spectrum(scn, tab, LINES, 1e-9, 1, max_columns=3)
        assert np.allclose(chunked.rate, fast.rate, rtol=1e-9, atol=0) and np.allclose(chunked.rate_other, fast.rate_other, rtol=1e-9, atol=0)


def test_the_cell_heads_table_is_built_before_the_first_passage_and_said():
    """The cell head's table, most of an hour of CPU for eight bays at K = 36, was built silently inside the first march of a
    growth run or a spectrum: rail.chain.cell_head_ready builds it first and says what and how long; nothing on the uniform
    track or without the rail's flexibility."""
    from rail.creepage.rail_flexibility_cell import cell_head_table
    scn, _ = _case("rail")
    small = dataclasses.replace(scn, track_numerics=dataclasses.replace(scn.track_numerics, harmonics=2))
    told = []
    assert chain.cell_head_ready(small, V, told.append) >= 0.0
    assert told[0] == "the rail head's moving receptances over the cell of 3 bays at 40 m/s: 13 harmonics, 3 attachments (built once for the run)"
    assert told[1].startswith("the rail head's table over the cell built in ") and len(told) == 2
    hits = cell_head_table.cache_info().hits
    chain.cell_head_ready(small, V)
    assert cell_head_table.cache_info().hits == hits + 1  # built once: the march's own call finds it
    for other in (_case("motored")[0], dataclasses.replace(small, cell=None, material=_case("none")[0].material)):
        said = []
        assert chain.cell_head_ready(other, V, said.append) == 0.0 and said == []
