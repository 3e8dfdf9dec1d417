"""Rolling noise of a fleet's growth run (issue 56): each (vehicle, speed) class a CNOSSOS-EU traffic
class on the one rail roughness, the line's L'_W,eq,line the energy sum over the classes (Directive
2015/996 Annex II 2.3.2). Checked against the one-train noise (a fleet of one class is the one train),
splitting a class in two, doubling a class's flow by hand, each class against a one-train run of its
own vehicle and speed, the refusals, and the same numbers through the API, the command line and the
workflow script."""

import csv
import importlib.util
import io
import math

import numpy as np
import pytest
import xarray as xr
import yaml

from rail.app import api, cli
from rail.setup.config import ConfigError

GRAVITY = 9.80665


def _vehicle(name, axles=4, load=1.0e5, share=1.0, **extra):
    return {"name": name, "positions": [float(3 * i) for i in range(axles)], "static_load": load, "unsprung_mass": 1350.0,
            "creepage": [1.0e-4] * axles, "share": share, **extra}  # a trailer's drag: 0 is refused with the rail's flexibility


def _fleet(vehicles, speeds=(40.0,), weights=(1.0,), **noise):
    changes = {"fleet": {"vehicles": vehicles, "speeds": {"values": list(speeds), "weights": list(weights)}}}
    if noise:
        changes["figures"] = {"noise": noise}
    return api.load("default", changes=changes)


def _growth(study, V=40.0, fleet=True, J=64, j=12):
    """A one-bay growth dataset with the study's provenance: a 50 mm cosine (0.6 m / 12) growing as
    2 um x 1.5^k at the saves (as tests/test_noise_grinding.py), a fleet's attributes if ``fleet``."""
    n = np.arange(5) * 1e5
    Z = np.zeros((len(n), 2 * J + 1), complex)
    Z[:, J + j] = Z[:, J - j] = 2e-6 * 1.5 ** np.arange(5) / 2
    attrs = {"bays": 1, "speed_m_per_s": V, "scenario": study.name, "config": yaml.safe_dump(study.config, sort_keys=True)}
    if fleet:
        attrs.update(fleet_speeds=str(study.config["fleet"]["speeds"]), fleet_vehicles="as configured")
    return xr.Dataset({"Z_real": (("passage", "h"), Z.real), "Z_imag": (("passage", "h"), Z.imag)}, coords={"passage": n}, attrs=attrs)


def _rows(text):
    return list(csv.DictReader(io.StringIO("\n".join(x for x in text.splitlines() if not x.startswith("#")))))


def _energy(levels, axis=None):
    return 10 * np.log10(np.sum(10 ** (np.asarray(levels) / 10), axis=axis))


def test_a_fleet_of_one_vehicle_at_one_speed_is_the_one_train_noise_of_the_scenario():
    # (a) the scenario's wheel (100 kN), 4 axles (figures.noise.axles_per_vehicle's default), disc wheels, 40 m/s:
    # the same traffic class, Q = 20,000 axles/day / 24 h / 4 either way
    one = api.noise(api.load("default"), _growth(api.load("default"), fleet=False))
    study = _fleet([_vehicle("train")])
    fl = api.noise(study, _growth(study))
    d1, df = one.data, fl.data
    assert df.sizes["traffic_class"] == 1 and df["class_name"].values[0] == "train at 40 m/s"
    assert df.attrs["vehicles_per_hour"] == pytest.approx(d1.attrs["vehicles_per_hour"], rel=1e-14)
    for name in ("line_sound_power", "line_sound_power_A", "line_sound_power_A_cycle_average", "band_rms", "rail_roughness"):
        np.testing.assert_allclose(df[name].values, d1[name].values, rtol=0, atol=1e-9, err_msg=name)
    for name in ("total_effective_roughness", "sound_power", "sound_power_A"):
        np.testing.assert_allclose(df[name].values[:, 0], d1[name].values, rtol=0, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(df["line_sound_power_class"].values[:, 0], d1["line_sound_power"].values, atol=1e-9)
    for c in ("rise", "band_rms"):
        assert df.attrs[f"grinding_noise_{c}_passages"] == pytest.approx(d1.attrs[f"grinding_noise_{c}_passages"], rel=1e-12)
        assert df.attrs[f"grinding_noise_{c}_status"] == d1.attrs[f"grinding_noise_{c}_status"]
    np.testing.assert_allclose(df["years"].values, d1["years"].values, rtol=1e-14)
    np.testing.assert_allclose(df["mgt"].values, d1["mgt"].values, rtol=1e-14)
    r1, rf = _rows(one.csv), _rows(fl.csv)
    for key in ("line_sound_power_A_dBA_re_1pW_per_m", "line_sound_power_1000Hz_dB_re_1pW_per_m", "band_rms_30_100mm_um"):
        assert [r[key] for r in rf] == [r[key] for r in r1], key
    assert [r["line_sound_power_A_class0_dBA_re_1pW_per_m"] for r in rf] == [r["line_sound_power_A_dBA_re_1pW_per_m"] for r in r1]


def test_two_identical_classes_with_half_the_traffic_each_give_the_one_class_result():
    # (b) by vehicle types (two equal vehicles of share 0.5) and by speed classes (one vehicle, two speed
    # classes of weight 0.5 at the same speed is refused by nothing: both are the class at 40 m/s)
    ref = api.noise(_fleet([_vehicle("a")]), _growth(_fleet([_vehicle("a")]))).data
    split = _fleet([_vehicle("a", share=0.5), _vehicle("b", share=0.5)])
    d = api.noise(split, _growth(split)).data
    assert d.sizes["traffic_class"] == 2
    np.testing.assert_allclose(d["class_vehicles_per_hour"].values, ref["class_vehicles_per_hour"].values[0] / 2, rtol=1e-14)
    # each half is 10 lg 2 below the whole, per band; their energy sum is the whole
    np.testing.assert_allclose(d["line_sound_power_class"].values,
                               np.repeat(ref["line_sound_power_class"].values - 10 * math.log10(2), 2, axis=1), atol=1e-9)
    for name in ("line_sound_power", "line_sound_power_A", "line_sound_power_A_cycle_average"):
        np.testing.assert_allclose(d[name].values, ref[name].values, atol=1e-9, err_msg=name)
    for c in ("rise", "band_rms"):
        assert d.attrs[f"grinding_noise_{c}_passages"] == pytest.approx(ref.attrs[f"grinding_noise_{c}_passages"], rel=1e-9)


def test_doubling_one_classs_vehicles_per_hour_adds_10_lg_of_its_share_by_hand():
    # (c) 400 trains/h, loco 0.25 (100/h, cast-iron blocks, 4 axles, 100 kN) and coach 0.75 (300/h, disc, 2 axles,
    # 60 kN) at 30 and 40 m/s; then 500 trains/h, loco 0.4 (200/h), coach 0.6 (300/h): the loco classes' flows doubled
    def study(q, loco):
        return _fleet([_vehicle("loco", 4, 1.0e5, loco, brake="cast_iron"), _vehicle("coach", 2, 6.0e4, 1 - loco)],
                      speeds=(30.0, 40.0), weights=(0.5, 0.5), vehicles_per_hour=q)
    s1, s2 = study(400.0, 0.25), study(500.0, 0.4)
    d1, d2 = api.noise(s1, _growth(s1)).data, api.noise(s2, _growth(s2)).data
    assert list(d1["class_vehicles_per_hour"].values) == pytest.approx([50, 50, 150, 150], rel=1e-12)
    assert list(d2["class_vehicles_per_hour"].values) == pytest.approx([100, 100, 150, 150], rel=1e-12)
    assert list(d1["class_wheel_roughness"].values) == ["cast_iron", "cast_iron", "disc", "disc"]
    loco = [0, 1]
    L1, L2 = d1["line_sound_power_A"].values, d2["line_sound_power_A"].values
    share = np.sum(10 ** (d1["line_sound_power_A_class"].values[:, loco] / 10), axis=1) / 10 ** (L1 / 10)  # the loco's share of the energy
    np.testing.assert_allclose(L2 - L1, 10 * np.log10(1 + share), atol=1e-9)
    assert np.all(share > 0.05) and np.all(share < 0.95)  # a case where the share matters
    # per class: the loco classes 10 lg 2 up, the coach classes unchanged
    up = d2["line_sound_power_class"].values - d1["line_sound_power_class"].values
    np.testing.assert_allclose(up[:, loco], 10 * math.log10(2), atol=1e-9)
    np.testing.assert_allclose(up[:, 2:], 0.0, atol=1e-9)
    # the total per band is the energy sum over the classes (Annex II 2.3.2), and the A-weighted total that of the bands
    np.testing.assert_allclose(d1["line_sound_power"].values, _energy(d1["line_sound_power_class"].values, axis=1), atol=1e-9)
    np.testing.assert_allclose(L1, _energy(d1["line_sound_power"].values + d1["a_weighting"].values, axis=1), atol=1e-9)


def test_each_class_is_the_one_train_noise_of_its_vehicle_at_its_speed():
    # the default traffic: 20,000 axles/day of 0.4 x 4-axle locos and 0.6 x 2-axle coaches, 2.8 axles a train;
    # each class against a one-train run of that vehicle (its load, axles, brake) at that speed on the same roughness
    st = _fleet([_vehicle("loco", 4, 1.0e5, 0.4, brake="cast_iron"), _vehicle("coach", 2, 6.0e4, 0.6)],
                speeds=(30.0, 40.0), weights=(0.25, 0.75))
    d = api.noise(st, _growth(st, V=37.5)).data
    trains_per_hour = 20000 / (0.4 * 4 + 0.6 * 2) / 24
    assert d.attrs["vehicles_per_hour"] == pytest.approx(trains_per_hour, rel=1e-12)
    for k, (load, axles, brake, v, w) in enumerate([(1e5, 4, "cast_iron", 30.0, 0.1), (1e5, 4, "cast_iron", 40.0, 0.3),
                                                    (6e4, 2, "disc", 30.0, 0.15), (6e4, 2, "disc", 40.0, 0.45)]):
        one = api.load("default", changes={"wheels": {"static_load": load},
                                           "figures": {"noise": {"axles_per_vehicle": axles, "wheel": brake,
                                                                 "vehicles_per_hour": w * trains_per_hour}}})
        o = api.noise(one, _growth(one, V=v, fleet=False)).data
        assert float(d["class_share"].values[k]) == pytest.approx(w, rel=1e-12)
        np.testing.assert_allclose(d["sound_power"].values[:, k], o["sound_power"].values, atol=1e-9)
        np.testing.assert_allclose(d["line_sound_power_class"].values[:, k], o["line_sound_power"].values, atol=1e-9)
        np.testing.assert_allclose(d["line_sound_power_A_class"].values[:, k], o["line_sound_power_A"].values, atol=1e-9)
    # the axles per hour of the classes are the traffic's
    assert float(np.sum(d["class_vehicles_per_hour"].values * d["class_axles"].values)) == pytest.approx(20000 / 24, rel=1e-12)
    # the years and MGT are the fleet's traffic (mean axle load of the axles that pass)
    axle_t = 2 * (0.4 * 4 * 1e5 + 0.6 * 2 * 6e4) / (0.4 * 4 + 0.6 * 2) / GRAVITY / 1000
    np.testing.assert_allclose(d["mgt"].values, d["passage"].values * axle_t / 1e6, rtol=1e-12)


def test_bad_fleet_inputs_for_noise_are_refused_before_computing_naming_key_value_and_range():
    from rail.setup.inputs import noise_problem

    with pytest.raises(ConfigError, match=r"fleet\.vehicles\.0\.brake = 'steel'.*(disc|composite|cast_iron)"):
        _fleet([_vehicle("loco", brake="steel")])
    with pytest.raises(ConfigError, match=r"figures\.noise\.axles_per_vehicle = 2 is not used by a fleet: each vehicle's axles"):
        _fleet([_vehicle("loco")], axles_per_vehicle=2)  # it would be silently unused
    fast = _fleet([_vehicle("loco")], speeds=(40.0, 120.0), weights=(0.5, 0.5))
    why = noise_problem(fast.config)
    assert why.startswith("fleet.speeds: the class speed of loco = 120.0 m/s is not allowed") and "7.94 .. 100 m/s" in why, why
    with pytest.raises(ValueError, match=r"fleet\.speeds: the class speed of loco = 120\.0 m/s is not allowed"):
        api.noise(fast, _growth(fast))
    ok = _fleet([_vehicle("loco")])
    assert noise_problem(ok.config) is None
    with pytest.raises(ConfigError, match=r"argument axles_per_vehicle = 2 is not used by a fleet"):
        api.noise(ok, _growth(ok), axles=2)
    with pytest.raises(ConfigError, match=r"the growth result is a one-train run and default has a fleet"):
        api.noise(ok, _growth(ok, fleet=False))
    with pytest.raises(ConfigError, match=r"argument wheel = 'steel'"):
        api.noise(ok, _growth(ok), brake="steel")


def _script(root, name):
    spec = importlib.util.spec_from_file_location(name, root / f"workflow/scripts/{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_a_fleets_noise_comes_alike_through_the_api_the_command_line_and_the_workflow_script(root, tmp_path, capsys):
    fleet = {"fleet": {"vehicles": [_vehicle("loco", 4, 1.0e5, 0.4, brake="cast_iron"), _vehicle("coach", 2, 6.0e4, 0.6)],
                       "speeds": {"values": [30.0, 40.0], "weights": [0.25, 0.75]}}}
    scen = tmp_path / "mix.yaml"
    scen.write_text(yaml.safe_dump(fleet))
    study = api.load(scen)
    gpath = tmp_path / "growth.nc"
    _growth(study, V=37.5).to_netcdf(gpath)
    o = api.noise(study, xr.open_dataset(gpath).load())
    assert cli.main(["noise", str(scen), str(gpath)]) == 0
    out = capsys.readouterr().out
    assert "noise (CNOSSOS-EU, fleet of 4 classes at 30-40 m/s): L'_W,A" in out and "grinding by noise: rise" in out
    wf = {"data": tmp_path / "wf.nc", "csv": tmp_path / "wf.csv", "figure": tmp_path / "wf.png"}
    log = io.StringIO()
    _script(root, "noise").main(study.config, study.name, str(gpath), wf, log=log)
    assert (tmp_path / "growth_noise.csv").read_text() == wf["csv"].read_text() == o.csv
    assert (tmp_path / "growth_noise.png").stat().st_size > 0 and wf["figure"].stat().st_size > 0
    with xr.open_dataset(tmp_path / "growth_noise.nc") as c, xr.open_dataset(wf["data"]) as w:
        for name in ("line_sound_power", "line_sound_power_A", "line_sound_power_class", "line_sound_power_A_class", "sound_power_A"):
            np.testing.assert_array_equal(c[name].values, o.data[name].values)
            np.testing.assert_array_equal(w[name].values, o.data[name].values)
            assert c[name].attrs["units"] and w[name].attrs["long_name"]
        for c_ in ("rise", "band_rms"):
            assert c.attrs[f"grinding_noise_{c_}_passages"] == w.attrs[f"grinding_noise_{c_}_passages"] == o.data.attrs[
                f"grinding_noise_{c_}_passages"]
        assert list(c["class_name"].values) == ["loco at 30 m/s", "loco at 40 m/s", "coach at 30 m/s", "coach at 40 m/s"]
    assert log.getvalue().startswith("noise (CNOSSOS-EU, fleet of 4 classes at 30-40 m/s)")
    # the CSV: per class and total, units in every column, each class named in the header
    rows = _rows(o.csv)
    assert [float(r["line_sound_power_A_dBA_re_1pW_per_m"]) for r in rows] == pytest.approx(o.data["line_sound_power_A"].values, abs=5e-4)
    assert [float(r["line_sound_power_A_class2_dBA_re_1pW_per_m"]) for r in rows] == pytest.approx(
        o.data["line_sound_power_A_class"].values[:, 2], abs=5e-4)
    units = ("_dBA_re_1pW_per_m", "_dB", "_dBA_re_1pW", "_um", "_dB_re_1pW_per_m")
    assert all(c in ("axle_passages", "years", "MGT") or c.endswith(units) for c in rows[0]), list(rows[0])
    assert "# class 2: coach at 30 m/s, share 0.15" in o.csv and "wheel roughness cast_iron" in o.csv
    # the fleet's grown for another scenario is refused, naming what differs
    assert cli.main(["noise", "default", str(gpath)]) == cli.EXIT_INPUT
    assert "fleet: given / not given" in capsys.readouterr().err


def test_run_of_a_fleet_ends_with_the_noise_change_of_the_line_in_one_line(tmp_path, monkeypatch, capsys):
    scen = tmp_path / "mix.yaml"
    scen.write_text(yaml.safe_dump({"fleet": {"vehicles": [_vehicle("loco", 4, 1.0e5, 0.4), _vehicle("coach", 2, 6.0e4, 0.6)],
                                              "speeds": {"values": [40.0], "weights": [1.0]}}}))
    study = api.load(scen)
    grown = _growth(study)
    monkeypatch.setattr(api, "growth", lambda *a, **k: grown)  # the fleet's run itself is tested elsewhere (tests/test_fleet.py)
    assert cli.main(["run", str(scen), "--out", str(tmp_path / "x.nc")]) == 0
    lines = [x for x in capsys.readouterr().out.splitlines() if x.startswith("noise")]
    L = api.noise(study, grown).data["line_sound_power_A"].values
    assert len(lines) == 1 and lines[0].startswith("noise (CNOSSOS-EU, fleet of 2 classes at 40 m/s)"), lines
    assert f"change {L[-1] - L[0]:+.2f} dB" in lines[0]
