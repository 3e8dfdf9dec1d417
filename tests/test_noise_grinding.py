"""Grinding by noise (rail.noise.grinding) and the noise over traffic through every door (issue 56):
the criteria against hand calculations, the extrapolation rules, the schema's refusals, and the same
numbers from the API, the command line and the workflow script."""

import csv
import importlib.util
import io
import math

import numpy as np
import pytest
import xarray as xr
import yaml

from rail.app import api, cli
from rail.noise import cnossos as cn
from rail.noise import grinding as gr
from rail.setup.config import ConfigError

NEPER_DB = 20 / math.log(10)  # dB of amplitude per neper


def _energy_level(ms):
    """A level_of whose L_A is the total mean square in dB re 1 um: the rise is then 10 lg(ms / ms0) exactly."""
    total = float(np.nansum(ms))
    return 10 * math.log10(total / 1e-12), np.array([10 * math.log10(total / 1e-12)])


def _exponential(g=0.5, a0=2e-6, saves=4, bands=1):
    """Mean squares of one band growing as a0 exp(g n / 1e5) (g per 1e5 passages), saved every 1e5 passages."""
    n = np.arange(saves) * 1e5
    ms = (a0 * np.exp(g * n / 1e5)) ** 2
    return n, np.repeat(ms[:, None], bands, axis=1) / bands


def test_range_bands_hold_five_cnossos_bands_each_from_the_centre_rule():
    c = cn.cnossos_wavelength_bands()
    for lo, hi, _ in gr.GRASSIE_1999[:4]:
        inside = gr.range_bands(c.centre, lo, hi)
        assert inside.sum() == 5, (lo, hi)
    mm = {(lo, hi): sorted(1e3 * c.nominal[gr.range_bands(c.centre, lo, hi)]) for lo, hi, _ in gr.GRASSIE_1999}
    assert mm[(0.01, 0.03)] == [10, 12.5, 16, 20, 25] and mm[(0.03, 0.1)] == [31.5, 40, 50, 63, 80]
    assert mm[(1.0, 3.0)] == [1000, 1250, 1600, 2000]  # CNOSSOS-EU stops at 2000 mm
    # Grassie, Saxon & Smith (1999), abstract: 3, 7, 7, 45, 100 um
    assert [lim * 1e6 for *_, lim in gr.GRASSIE_1999] == pytest.approx([3, 7, 7, 45, 100])


def test_the_trend_is_the_saves_at_the_saves_and_geometric_between():
    n, ms = _exponential()
    t = gr.band_trend(n, ms)
    for k in range(len(n)):
        assert t.mean_square(n[k]) == pytest.approx(ms[k], rel=1e-12)
    # ln amplitude linear between saves: exact for an exponential
    assert t.mean_square(1.5e5)[0] == pytest.approx((2e-6 * math.exp(0.5 * 1.5)) ** 2, rel=1e-12)
    with pytest.raises(ValueError, match="before the first save"):
        t.mean_square(-1.0)


def test_the_rise_trips_where_the_exponential_reaches_it_within_the_run_and_beyond():
    g = 0.5  # per 1e5 passages: 4.34 dB of level per 1e5
    n, ms = _exponential(g)
    t = gr.band_trend(n, ms)
    assert t.law[0] == "exponential" and t.exp_rate[0] == pytest.approx(g, rel=1e-9)
    curve = gr.noise_curve(t, _energy_level, extrapolation_max=10)
    for rise in (5.0, 20.0):  # within the run (13.0 dB at the last save) and beyond it
        trip = gr.trip_rise(t, curve, _energy_level, rise)
        by_hand = rise / (NEPER_DB * g) * 1e5  # 20 lg(exp(g n)) = rise
        assert trip.passages == pytest.approx(by_hand, rel=1e-5)  # bisection to 1e-6 of the run
        assert trip.status == ("within the run" if rise == 5.0 else "extrapolated")
        if rise == 20.0:
            assert trip.extrapolation_factor == pytest.approx(by_hand / 3e5, rel=1e-5)
    # the save nearest the 5 dB trip (1.15e5) is below it before and above it after
    L = np.array([_energy_level(m)[0] for m in ms])
    assert L[1] - L[0] <= 5.0 < L[2] - L[0]


def test_a_decaying_band_is_held_never_decayed_and_a_rise_it_cannot_give_is_not_reached():
    n, ms = _exponential(g=-0.3)
    t = gr.band_trend(n, ms)
    assert t.mean_square(3e6)[0] == pytest.approx(ms[-1, 0], rel=1e-12)  # held at the last level
    curve = gr.noise_curve(t, _energy_level, extrapolation_max=10)
    trip = gr.trip_rise(t, curve, _energy_level, 1.0)
    assert trip.status == "not reached" and trip.passages == math.inf
    assert "within 10 x the run's passages (3,000,000 axle passages)" in trip.note and "held" in trip.note


def test_nothing_is_extrapolated_without_a_growth_law_and_the_run_only_with_factor_one():
    n, ms = _exponential(saves=2)  # two saves: no law (rail.growth.BAND_GROWTH_SAVES = 3)
    t = gr.band_trend(n, ms)
    curve = gr.noise_curve(t, _energy_level)
    assert curve.end == n[-1] and not curve.extrapolated.any()
    assert "nothing is extrapolated" in gr.trip_rise(t, curve, _energy_level, 20.0).note
    n, ms = _exponential()
    curve = gr.noise_curve(gr.band_trend(n, ms), _energy_level, extrapolation_max=1)
    assert curve.end == n[-1]
    with pytest.raises(ValueError, match="extrapolation_max = 0.5 is not allowed"):
        gr.noise_curve(gr.band_trend(n, ms), _energy_level, extrapolation_max=0.5)


def test_the_cycle_average_of_a_level_growing_linearly_matches_its_integral():
    # L = L0 + s n: the energy mean from 0 is L0 + 10 lg((exp(k n) - 1) / (k n)), k = s ln10 / 10
    g = 0.5
    n, ms = _exponential(g)
    t = gr.band_trend(n, ms)
    curve = gr.noise_curve(t, _energy_level, extrapolation_max=10)
    k = 2 * g / 1e5  # energy e-folding per passage
    L0 = 10 * math.log10(ms[0, 0] / 1e-12)
    x = curve.passages[1:]
    exact = L0 + 10 * np.log10(np.expm1(k * x) / (k * x))
    # trapezoid in energy on steps of 25,000 passages (k h = 0.25 inside the run, 0.29 beyond): relative
    # error of the integral at most (k h)^2 / 12 = 0.7 %, i.e. 0.03 dB
    np.testing.assert_allclose(curve.average[1:], exact, atol=0.04)
    assert curve.average[0] == pytest.approx(L0)
    target = L0 + 6.0
    trip = gr.trip_average(t, curve, target)
    from scipy.optimize import brentq
    by_hand = brentq(lambda y: L0 + 10 * math.log10(math.expm1(k * y) / (k * y)) - target, 1.0, 3e6)
    # the average rises about 3.9 dB per 1e5 passages there: 0.04 dB is about 1,000 passages
    assert trip.passages == pytest.approx(by_hand, abs=1500)
    assert trip.status == "within the run"


def test_band_rms_sums_the_mean_squares_of_its_range_and_names_the_band():
    c = cn.cnossos_wavelength_bands()
    B = len(c.centre)
    i40, i50 = list(c.nominal).index(0.04), list(c.nominal).index(0.05)
    n = np.arange(4) * 1e5
    ms = np.full((4, B), np.nan)
    rng = gr.range_bands(c.centre, 0.03, 0.1)
    ms[:, rng] = 0.0
    ms[:, i40] = (3e-6) ** 2  # steady
    ms[:, i50] = (2e-6 * np.exp(0.5 * n / 1e5)) ** 2  # growing
    t = gr.band_trend(n, ms)
    curve = gr.noise_curve(t, _energy_level, extrapolation_max=10)
    trip = gr.trip_band_rms(t, curve, c.centre)
    # 9 + 4 exp(n) = 49 (um^2): n = ln(10) 1e5 / 1 (the mean square's e-folding is 2 x 0.5 per 1e5)
    by_hand = math.log(10.0) * 1e5
    assert trip.passages == pytest.approx(by_hand, rel=1e-5)
    assert trip.range_index == 1 and trip.threshold == 7e-6 and trip.band_index == i50
    # the other ranges have no model band here (all NaN): each said not assessed
    for r in ("10-30", "100-300", "300-1000", "1000-3000"):
        assert f"{r} mm not assessed (no band of the range is the model's)" in trip.note


def test_figures_noise_keys_are_refused_at_start_up_naming_key_value_and_range():
    with pytest.raises(ConfigError, match=r"figures\.noise\.rise_dB = -1(\.0)? .*0"):
        api.load("default", changes={"figures": {"noise": {"rise_dB": -1.0}}})
    with pytest.raises(ConfigError, match=r"figures\.noise\.extrapolation_max = 0\.5"):
        api.load("default", changes={"figures": {"noise": {"extrapolation_max": 0.5}}})
    with pytest.raises(ConfigError, match=r"figures\.noise\.wheel = 'steel'"):
        api.load("default", changes={"figures": {"noise": {"wheel": "steel"}}})
    with pytest.raises(ConfigError, match=r"figures\.noise\.average_target_dBA = nan is not allowed: it must be a finite number"):
        api.load("default", changes={"figures": {"noise": {"average_target_dBA": float("nan")}}})
    with pytest.raises(ConfigError, match=r"figures\.noise\.pad_class = 'soft' is not allowed with figures\.noise\.sleeper = 'wooden'"):
        api.load("default", changes={"figures": {"noise": {"pad_class": "soft", "sleeper": "wooden"}}})


# --- every door --------------------------------------------------------------------------------------

def _script(root, name):
    spec = importlib.util.spec_from_file_location(name, root / f"workflow/scripts/{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _growth(study, V=40.0, J=64, j=12):
    """A one-bay growth dataset as a growth run writes it: a 50 mm cosine (0.6 m / 12) growing as
    2 um x 1.5^k at the saves, with the run's provenance."""
    n = np.arange(5) * 1e5
    Z = np.zeros((len(n), 2 * J + 1), complex)
    Z[:, J + j] = Z[:, J - j] = 2e-6 * 1.5 ** np.arange(5) / 2
    return xr.Dataset({"Z_real": (("passage", "h"), Z.real), "Z_imag": (("passage", "h"), Z.imag)}, coords={"passage": n},
                      attrs={"bays": 1, "speed_m_per_s": V, "scenario": study.name,
                             "config": yaml.safe_dump(study.config, sort_keys=True)})


def _rows(text):
    return list(csv.DictReader(io.StringIO("\n".join(x for x in text.splitlines() if not x.startswith("#")))))


def test_the_noise_comes_alike_through_the_api_the_command_line_and_the_workflow_script(root, tmp_path, capsys):
    study = api.load("default")
    growth = _growth(study)
    gpath = tmp_path / "growth.nc"
    growth.to_netcdf(gpath)
    o = api.noise(study, growth)
    assert cli.main(["noise", "default", str(gpath), "--out", str(tmp_path / "cli_noise.nc")]) == 0
    out = capsys.readouterr().out
    assert "change +" in out and "grinding by noise: rise of the A-weighted line sound power over the start 3 dB: tripped" in out
    wf = {"data": tmp_path / "wf.nc", "csv": tmp_path / "wf.csv", "figure": tmp_path / "wf.png"}
    log = io.StringIO()
    _script(root, "noise").main(study.config, study.name, str(gpath), wf, log=log)
    assert (tmp_path / "cli_noise.csv").read_text() == wf["csv"].read_text() == o.csv
    assert (tmp_path / "cli_noise.png").stat().st_size > 0 and wf["figure"].stat().st_size > 0
    with xr.open_dataset(tmp_path / "cli_noise.nc") as c, xr.open_dataset(wf["data"]) as w:
        for name in ("line_sound_power", "line_sound_power_A", "line_sound_power_A_cycle_average", "band_rms"):
            np.testing.assert_array_equal(c[name].values, o.data[name].values)
            np.testing.assert_array_equal(w[name].values, o.data[name].values)
            assert c[name].attrs["units"] and w[name].attrs["long_name"]
        for c_ in ("rise", "band_rms"):
            assert c.attrs[f"grinding_noise_{c_}_passages"] == w.attrs[f"grinding_noise_{c_}_passages"]
        assert "config" in c.attrs and "config" in w.attrs
    assert log.getvalue().startswith("noise (CNOSSOS-EU, 40 m/s): L'_W,A")

    # the numbers: the change is the A-weighted line power's, the rise trips between the saves around it,
    # and the years and MGT are the traffic's (20,000 axles/day, 2 x 100 kN / g)
    d, a = o.data, o.data.attrs
    L = d["line_sound_power_A"].values
    np.testing.assert_allclose(d["line_sound_power_A_change"].values, L - L[0], atol=1e-12)
    p = a["grinding_noise_rise_passages"]
    k = int(np.searchsorted(d["passage"].values, p))
    assert L[k - 1] - L[0] <= 3.0 < L[k] - L[0]
    assert a["grinding_noise_rise_years"] == pytest.approx(p / 20000 / 365, rel=1e-12)
    assert a["grinding_noise_rise_MGT"] == pytest.approx(p * 2 * 1e5 / 9.80665 / 1e9, rel=1e-12)
    # band rms 30-100 mm: the cosine's rms (amplitude / sqrt 2) from the model's 50 mm band, and the
    # 7 um limit crossed between the saves around it
    rms = d["band_rms"].values[:, 1]
    np.testing.assert_allclose(rms, 2 * 1.5 ** np.arange(5) / math.sqrt(2), rtol=1e-12)
    pr = a["grinding_noise_band_rms_passages"]
    kr = int(np.searchsorted(d["passage"].values, pr))
    assert rms[kr - 1] <= 7 < rms[kr] and "30-100 mm range" in a["grinding_noise_band_rms_driver"]
    rows = _rows(o.csv)
    assert [float(r["line_sound_power_A_dBA_re_1pW_per_m"]) for r in rows] == pytest.approx(L, abs=5e-4)
    units = ("_dBA_re_1pW_per_m", "_dB", "_dBA_re_1pW", "_um", "_dB_re_1pW_per_m")
    assert all(c in ("axle_passages", "years", "MGT") or c.endswith(units) for c in rows[0]), list(rows[0])
    assert "years" in rows[0] and "MGT" in rows[0] and "band_rms_30_100mm_um" in rows[0]


def test_the_noise_of_another_scenarios_growth_file_is_refused_naming_what_differs(tmp_path, capsys):
    other = api.load("default", changes={"track": {"pad": {"stiffness": 5.0e8}}})
    gpath = tmp_path / "growth.nc"
    _growth(other).to_netcdf(gpath)
    assert cli.main(["noise", "default", str(gpath)]) == cli.EXIT_INPUT
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "track.pad.stiffness: 500000000.0 / 350000000.0" in err, err
    assert list(tmp_path.glob("growth_noise*")) == []


def test_a_fleet_growth_without_its_fleet_and_a_speed_outside_cnossos_are_refused_before_computing():
    study = api.load("default")
    g = _growth(study)
    g.attrs["fleet_speeds"] = "[40.0] m/s"
    with pytest.raises(ConfigError, match="the growth result is a fleet's run and default has no fleet"):
        api.noise(study, g)
    from rail.setup.inputs import noise_problem
    assert "growth speed = 120.0 m/s is not allowed" in noise_problem(study.config, 120.0)
    soft = api.load("default", changes={"track": {"pad": {"stiffness": 7.0e7}}})
    assert "has no CNOSSOS-EU pad class" in noise_problem(soft.config, 40.0)
    named = api.load("default", changes={"track": {"pad": {"stiffness": 7.0e7}}, "figures": {"noise": {"pad_class": "soft"}}})
    assert noise_problem(named.config, 40.0) is None


def test_run_of_one_train_ends_with_the_noise_change_in_one_line(tmp_path, monkeypatch, capsys):
    study = api.load("default")
    grown = _growth(study)
    monkeypatch.setattr(api, "growth", lambda *a, **k: grown)  # the run itself is tested elsewhere (tests/test_app.py)
    out = tmp_path / "x.nc"
    assert cli.main(["run", "default", "--speed", "40", "--out", str(out)]) == 0
    lines = [x for x in capsys.readouterr().out.splitlines() if x.startswith("noise")]
    L = api.noise(study, grown).data["line_sound_power_A"].values
    assert len(lines) == 1 and f"change {L[-1] - L[0]:+.2f} dB" in lines[0], lines
    assert "first to trip: rise of the A-weighted line sound power over the start 3 dB: tripped after" in lines[0]
    grown.attrs["speed_m_per_s"] = 120.0  # outside CNOSSOS-EU: the line says why
    assert cli.main(["run", "default", "--speed", "40", "--out", str(out)]) == 0
    assert "noise: not computed: growth speed = 120.0 m/s is not allowed" in capsys.readouterr().out
