"""The non-Hertzian normal contact in the model chain (issue 31): the report's regime untouched, the
contact filter on the force, the run that stops with its reason and keeps what it computed, and the
choice of model by configuration."""

import dataclasses
import io

import numpy as np
import pytest

from model import scenario

from rail import chain, halfspace, moving
from rail import contact as C
from rail import growth as G
from rail import interaction as I
from rail.contact import normal as N
from rail import track as T
from rail.app import api

K = 48
MATERIAL = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)
A0 = float(C.hertz_half_length(1e5, 0.575, MATERIAL))  # 6.3 mm: patch length 2a = 12.6 mm


def _track():
    return T.Track(T.Rail(2.1e11, 0.81e11, 7850.0, 7.69e-3, 30.55e-6, 0.4, 0.01), T.Pad(3.5e8, 0.25), T.Sleeper(162.0, 0.6),
                   T.Ballast(50e6, 1.0))


def _spring():
    om = 2 * np.pi * 1000
    return I.ContactSpring(1.4e9, halfspace.contact_loss_factor(om, 1.4e9, halfspace.ElasticMaterial(2.1e11, 0.3, 7850.0)) / om)


@pytest.fixture(scope="module")
def table():
    return moving.receptance_table(_track(), 40.0, K, offsets=[0.0])


def _scn(normal, **kw):
    s = scenario(_track(), MATERIAL, _spring(), K=K, **kw)
    return dataclasses.replace(s, contact_numerics=dataclasses.replace(s.contact_numerics, normal=normal))


@pytest.mark.parametrize("k", [1, 2, 3, 4, 6])
def test_force_from_roughness_is_scaled_by_the_contact_filter(table, k):
    # the force is linear in the roughness: the roughness's part of each force harmonic is scaled by
    # J0(beta a_0) exactly; at lambda >= 15 patch lengths (k <= 2) that is within 0.1 dB of the report's
    # point spring, at lambda = 10 patch lengths 0.22 dB below it: the contact filter, not an error
    rough = I.Roughness.harmonic(1e-5, 0.6 / k, 0.6, K)
    lam = 0.6 / k
    out = {}
    for model in ("report", "nonhertzian"):
        s = _scn(model)
        out[model] = chain.solve_forces(s, table, rough).P[0] - chain.solve_forces(s, table, I.Roughness.smooth(K)).P[0]
    H = float(N.approach_filter(2 * np.pi / lam, A0))
    big = np.abs(out["report"]) > 1e-3 * np.abs(out["report"]).max()
    np.testing.assert_allclose(out["nonhertzian"][big], H * out["report"][big], rtol=1e-9)
    if lam >= 15 * 2 * A0:
        assert abs(20 * np.log10(H)) < 0.1
    if lam <= 10 * 2 * A0:
        assert 20 * np.log10(H) < -0.2


def test_growth_at_long_wavelengths_equals_the_report_model(table):
    # 20,000 passages from a 10 um roughness at 0.3 m (24 patch lengths): every harmonic at a wavelength
    # of at least 15 patch lengths (k <= 3) ends within 0.1 dB of the report's model
    rough = I.Roughness.harmonic(1e-5, 0.3, 0.6, K)
    levels = {}
    for model in ("report", "nonhertzian"):
        h = chain.grow(_scn(model, nodes=41), table, rough, progress=io.StringIO())
        assert not h.stopped
        levels[model] = G.levels_dB(h.Z[-1])[:3]
    assert np.abs(levels["nonhertzian"] - levels["report"]).max() < 0.1


def test_a_growth_run_stops_with_the_reason_and_keeps_its_saved_states():
    # an integrator whose contact breaks at the third update: the history up to there, the reason,
    # the passage count and the wavelength that grew most
    Z0 = np.zeros(2 * 8 + 1, dtype=complex)
    Z0[8 + 5] = Z0[8 - 5] = 1e-7
    calls = []

    def wear(Z, phase):
        calls.append(1)
        if len(calls) == 3:
            raise C.ContactError("contact lost inside the patch: wheel 0 at x = 0.1 m.")
        return -Z / 10000, 0.0  # the roughness doubles every update of 10,000 passages

    out = io.StringIO()
    h = G.run_growth(wear, I.Roughness(Z0), 1, G.GrowthSettings(50000, 10000, 10000, False, 10.0), progress=out, period=0.6)
    assert list(h.passages) == [0, 10000, 20000]
    assert h.stopped.startswith("growth stopped at 20000 passages: contact lost inside the patch")
    assert "The most curved roughness is at wavelength 120 mm (now -4.9 dB re 1 µm, +12.0 dB since the start)" in h.stopped
    assert len(h.step_error) == len(h.full_slip) == 2  # one per update, the last one's error not estimated (NaN)
    assert "\n" not in h.stopped and h.stopped in out.getvalue()


def test_the_report_model_at_the_same_roughness_stops_on_multiple_contact():
    # the report's local-curvature Hertz patch at 30 um, 10 mm: z'' = 12 1/m exceeds 1/R_w = 1.7 1/m
    st = api.load("default", changes={"numerics": {"contact": {"nodes": 41}},
                                      "roughness": {"kind": "harmonic", "amplitude": 3e-5, "wavelength": 0.010}})
    assert st.scenario.contact_numerics.normal.name == "report"
    ds = api.growth(st, speed=40.0, passages=20000, progress=io.StringIO())
    assert "multiple contact" in ds.attrs["stopped"]


def test_config_yaml_is_the_report_and_a_scenario_file_starts_from_the_nonhertzian_contact(tmp_path):
    assert api.load("default").scenario.contact_numerics.normal.name == "report"
    assert api.load("class87").scenario.contact_numerics.normal.name == "report"  # a report study pins it
    mine = tmp_path / "mine.yaml"
    mine.write_text("track:\n  pad:\n    stiffness: 1.5e+8\n")
    assert api.load(str(mine)).scenario.contact_numerics.normal.name == "nonhertzian"
    mine.write_text("contact:\n  normal: report\n")
    assert api.load(str(mine)).scenario.contact_numerics.normal.name == "report"


def test_the_command_line_writes_a_stopped_run_and_exits_3(tmp_path, capsys):
    from rail.app import cli

    mine = tmp_path / "rough.yaml"
    # the report's contact at 30 um, 10 mm: multiple contact at once (the non-Hertzian contact carries on at
    # 20 um with several zones, and reaches its limit only at about 60 um: test_multizone.py)
    mine.write_text("contact:\n  normal: report\nnumerics:\n  contact:\n    nodes: 41\nroughness:\n  kind: harmonic\n"
                    "  amplitude: 3.0e-5\n  wavelength: 0.01\n")
    out = tmp_path / "rough.nc"
    assert cli.main(["run", str(mine), "--speed", "40", "--passages", "20000", "--out", str(out)]) == 3
    assert out.exists()
    captured = capsys.readouterr()
    assert "(partial: growth stopped at 0 passages: " in captured.out


def test_a_patch_that_outgrows_its_estimate_gets_a_larger_grid_not_an_error(table, monkeypatch):
    # the grid is sized from the patch at 512 samples per bay; where the patch at the grid's own
    # points is larger (the broadband study died with "the patch half-length 0.01423 m exceeds the
    # grid's 0.01375 m"), the grid is rebuilt to hold it. Here the estimate is made too small on
    # purpose (half the curvature at the 512 samples): the wear is still computed, with the patch of
    # the undisturbed computation
    k = 41
    beta = 2 * np.pi * k / 0.6
    rough = I.Roughness.harmonic(0.95 / (MATERIAL.wheel_radius * beta**2), 0.6 / k, 0.6, K)  # trough: 0.95 / R_w
    s = _scn("report", nodes=41)
    forces = chain.solve_forces(s, table, rough)
    plain = chain.passage_wear(s, forces, rough)
    from rail.contact import models

    curvature = models.curvature_on_grid
    monkeypatch.setattr(models, "curvature_on_grid", lambda r, n, p: curvature(r, n, p) * (0.5 if n == 512 else 1.0))
    w = chain.passage_wear(s, forces, rough)
    assert np.all(np.isfinite(w.depth))
    assert w.a.max() == pytest.approx(plain.a.max(), rel=0.02)


def test_a_patch_whose_length_swings_beyond_the_grid_is_reported_as_near_multiple_contact(table):
    # the trough's curvature at 0.997 / R_w: the patch ranges from about 0.7 to 20 static half-lengths
    # along the bay; before, a ValueError of the basis ("must span more than two grid cells")
    k = 41
    beta = 2 * np.pi * k / 0.6
    rough = I.Roughness.harmonic(0.997 / (MATERIAL.wheel_radius * beta**2), 0.6 / k, 0.6, K)
    s = _scn("report", nodes=41)
    with pytest.raises(C.ContactError, match=r"multiple contact is near: the patch half-length of wheel 0 ranges from"):
        chain.passage_wear(s, chain.solve_forces(s, table, rough), rough)
