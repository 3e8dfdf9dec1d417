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
LINES = [37, 87, 72]  # of the 4-bay period: 64.9 mm (free, grows at 40 m/s), 27.6 mm (free, decays) and 33.3 mm (on the one-bay
# comb: the supports' source, decays)


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


# ---------------------------------------------------------------- on the spectrum's lines


GROUND = ws.named_spectrum("E", "rail")
LIMIT = ws.RoughnessSpectrum(GROUND.centres, GROUND.levels + 3.0, "class E + 3 dB (the tests' limit: every band starts below it)")


@pytest.fixture(scope="module")
def two_classes():
    # a one-axle locomotive at 40 m/s and a one-axle coach at 44 m/s on a 4-bay period (K = 24, 41 nodes, one grid): their
    # class spectra on the fleet's shared tables (about 2 s), weights 0.6 and 0.4
    scn = base(bays=N, passages=100000, step=10000)
    loco = vehicle("loco", (0.0,), 1e5, 1350.0, (-0.001,), 0.6)
    coach = vehicle("coach", (0.0,), 6e4, 900.0, (0.0008,), 0.4)
    fl = F.Fleet((loco, coach), F.SpeedClasses((40.0, 44.0), (0.5, 0.5)), 20000.0)
    every = fl.classes(scn)
    classes = [dataclasses_replace(every[0], weight=0.6), dataclasses_replace(every[3], weight=0.4)]  # loco at 40, coach at 44
    assert [c.label for c in classes] == ["loco at 40 m/s", "coach at 44 m/s"]
    tables = chain.fleet_tables(classes)
    spectra = [GS.rate_spectrum(c.scenario, tables[c.speed], LINES, eps=1e-9, grid_phases=1, check_lines=1) for c in classes]
    return scn, fl, classes, tables, spectra


def dataclasses_replace(obj, **kw):
    import dataclasses

    return dataclasses.replace(obj, **kw)


def _fleet(scn, fl, classes, spectra, wheels):
    """The fleet's spectrum dataset with its source from the class spectra, each vehicle's wheel roughness ``wheels``."""
    fs = GS.fleet_spectrum_of(classes, spectra)
    ds = fleet_spectrum_dataset(fs, fl, classes)
    arrays = [ws.class_source_arrays(c.scenario, None, {}, sp, wheels[c.vehicle]) for c, sp in zip(classes, spectra)]
    return ws.fleet_source_dataset(ds, fs, fl, classes, N * scn.L, arrays, GROUND, LIMIT), arrays


def _one_train(c, sp, wheel):
    """The class alone as a one-train scenario (its one wheel: the spectrum's own rate is the wheel's), rail.studies's
    one-train path (source_dataset)."""
    ds = rate_spectrum.spectrum_dataset_of({c.speed: sp}, c.scenario)
    return ws.source_dataset(ds, wheel, ground=GROUND, limit=LIMIT)


def test_a_fleet_of_one_class_is_the_one_train_settled_spectrum(two_classes):
    # (a) the locomotive alone (weight 1): a = abs(1 - R)^2, Q and S_inf per line, the settled bands, the passages to
    # settle and to the limit (one axle: fleet passages are axle passages) as the one-train path gives them, to rounding
    scn, _, classes, _, spectra = two_classes
    c = dataclasses_replace(classes[0], weight=1.0)
    fl = F.Fleet((vehicle("loco", (0.0,), 1e5, 1350.0, (-0.001,), 1.0),), F.SpeedClasses((40.0,), (1.0,)), 20000.0)
    wheel = ws.named_spectrum("cast_iron")
    out, _ = _fleet(scn, fl, [c], spectra[:1], {"loco": wheel})
    one = _one_train(c, spectra[0], wheel)
    R = -(one.growth_rate.values[0] + 1j * one.drift.values[0])
    np.testing.assert_allclose(out.decay_factor.values, np.abs(1 - R) ** 2, rtol=1e-15, atol=0)
    for var in ("wheel_source_dB", "settled_level_dB", "settle_axles"):
        np.testing.assert_allclose(out[var].values, one[var].values[0], rtol=1e-13, atol=0, err_msg=var)
    for var in ("settled_band_level_dB", "settled_band_wheels_dB", "axles_to_limit"):
        np.testing.assert_allclose(out[var].values, one[var].values[0], rtol=1e-13, atol=0, err_msg=var)
    assert float(out.interval_axles) == pytest.approx(float(one.interval_axles[0]), rel=1e-13)
    # what was compared: a growing line (no settled level), a decaying free line and a decaying comb line, and an interval
    assert np.isposinf(out.settled_level_dB.values[0]) and np.isfinite(out.settled_level_dB.values[1:]).all()
    assert out.locked.values[2] == 1 and spectra[0].source[2] > 0
    assert np.isfinite(float(out.interval_axles))


def test_two_classes_with_their_own_wheels_and_speeds_weigh_each_class_computed_alone(two_classes):
    # (b) disc-braked locomotive at 40 m/s, cast-iron block-braked coach at 44 m/s. Each class alone, as a one-train
    # scenario on its own receptance table with its own wheels (rate spectrum and source computed anew): per line
    # Q = sum_c w_c Q_c and a = sum_c w_c abs(1 - R_c)^2 from those. The one-axle classes' own tables equal the fleet's
    # shared ones, and the spectrum is deterministic (test_fleet: bitwise back to back), so to rounding
    scn, fl, classes, _, spectra = two_classes
    wheels = {"loco": ws.named_spectrum("disc"), "coach": ws.named_spectrum("cast_iron")}
    out, _ = _fleet(scn, fl, classes, spectra, wheels)
    alone = [_one_train(c, GS.rate_spectrum(c.scenario, chain.receptance_table(c.scenario, c.speed), LINES, eps=1e-9, grid_phases=1,
                                            check_lines=1), wheels[c.vehicle]) for c in classes]
    w = np.array([c.weight for c in classes])
    Qc = np.array([1e-12 * 10 ** (d.wheel_source_dB.values[0] / 10) for d in alone])
    Rc = np.array([-(d.growth_rate.values[0] + 1j * d.drift.values[0]) for d in alone])
    np.testing.assert_allclose(1e-12 * 10 ** (out.wheel_source_dB.values / 10), w @ Qc, rtol=1e-12, atol=0)
    a = w @ np.abs(1 - Rc) ** 2
    np.testing.assert_allclose(1 - out.decay_factor.values, 1 - a, rtol=1e-9, atol=0)  # 1 - a: a's rounding near 1 (1e-16 / 1e-5)
    np.testing.assert_allclose(out.class_wheel_source_dB.values, [d.wheel_source_dB.values[0] for d in alone], rtol=1e-12)
    # the classes differ where it shows: the wheels by the tables' difference, the rates by tens of percent
    assert np.all(np.abs(Qc[0] / Qc[1] - 1) > 0.1) and np.all(np.abs(Rc[0] / Rc[1] - 1) > 0.05)
    # and the fleet's a is not the mean train's: the draw's spread sum_c w_c abs(R_c - R)^2 adds to it
    R = w @ Rc
    # (to a's rounding: two ulps of a number near 1, 4.4e-16, against a spread of 2e-14 to 2e-12 here)
    np.testing.assert_allclose(out.decay_factor.values - np.abs(1 - R) ** 2, w @ np.abs(Rc - R) ** 2, rtol=0, atol=4.5e-16)
    assert np.all(w @ np.abs(Rc - R) ** 2 > 40 * 4.5e-16)
    # the CSV (units in every column) and the summary name the fleet's classes and its interval in axle passages
    text = ws.settled_csv_text(out)
    assert "loco at 40 m/s (weight 0.6); coach at 44 m/s (weight 0.4)" in text
    assert text.splitlines()[4] == ("band_nominal_m,wheel_dB_re_1um,settled_dB_re_1um,settled_wheels_only_dB_re_1um,ground_dB_re_1um,"
                                    "limit_dB_re_1um,axles_to_limit,years_to_limit")
    assert "under the fleet" in ws.settled_summary_markdown(out) and "loco: disc" in out.attrs["wheel_roughness"]


def test_twice_a_vehicles_wheel_roughness_amplitude_gives_its_class_four_times_the_source(two_classes, tmp_path):
    # (e) the coach's wheels read from a file at the cast-iron table's levels and at +20 log10(2) dB (twice the amplitude):
    # its class's Q_c per line four times (to the levels' rounding in the file, 1e-12), the locomotive's unchanged, the fleet's
    # Q the weighted sum; the wheels-only settled bands of the coach alone move by +6.02 dB
    from rail.setup import inputs

    scn, fl, classes, _, spectra = two_classes
    t = ws.named_spectrum("cast_iron")
    files = {}
    for name, gain in (("once", 0.0), ("twice", 20 * np.log10(2.0))):
        path = tmp_path / f"{name}.csv"
        path.write_text("wavelength_m,level_dB\n" + "".join(f"{float(c)!r},{float(v + gain)!r}\n" for c, v in zip(t.centres, t.levels) if c >= 1e-3))
        cfg = {"fleet": {"vehicles": [{"name": "loco", "wheel_source": {"roughness": "disc"}},
                                      {"name": "coach", "wheel_source": {"roughness": "file", "file": str(path)}}]},
               "wheel_source": {"roughness": "none"}, "figures": {"bands": {}}}
        files[name] = _fleet(scn, fl, classes, spectra, inputs.wheel_source_spectra(cfg)["vehicles"])[0]
    q1, q2 = (1e-12 * 10 ** (files[k].class_wheel_source_dB.values / 10) for k in ("once", "twice"))
    np.testing.assert_allclose(q2[1] / q1[1], 4.0, rtol=1e-12)
    np.testing.assert_array_equal(q2[0], q1[0])
    Q1, Q2 = (1e-12 * 10 ** (files[k].wheel_source_dB.values / 10) for k in ("once", "twice"))
    np.testing.assert_allclose(Q2 - Q1, 0.4 * 3 * q1[1], rtol=1e-9)


def test_without_a_wheel_source_a_fleets_class_files_keys_and_spectrum_are_as_before(two_classes, schema, defaults):
    # (c) no source (every vehicle none, or no section): the class files carry nothing more (class_source_arrays {}),
    # the fleet's dataset is handed back untouched, and the class keys are the keys without the source; a vehicle's
    # roughness 'none' written out changes no key and nothing that the jobs read (read_part)
    from rail.setup import build, config, inputs
    from rail.setup.study_files import class_key
    from rail.setup.targets import read_part
    from fleets import TWO_VEHICLES
    import yaml

    scn, fl, classes, tables, spectra = two_classes
    assert ws.class_source_arrays(classes[0].scenario, tables[40.0], {}, spectra[0], None) == {}
    fs = GS.fleet_spectrum_of(classes, spectra)
    ds = fleet_spectrum_dataset(fs, fl, classes)
    assert ws.with_fleet_source(ds, fs, fl, classes, tables, {}, None, N * scn.L) is ds
    plain = yaml.safe_load(TWO_VEHICLES)
    written = yaml.safe_load(TWO_VEHICLES)
    for v in written["fleet"]["vehicles"]:
        v["wheel_source"] = {"roughness": "none"}
    written["wheel_source"] = {"roughness": "none", "ground": "M"}
    cfgs = [config.resolve(defaults, schema, c, source="mix.yaml") for c in (plain, written)]
    for cfg in cfgs:
        assert inputs.wheel_source_spectra(cfg) is None and build.wheel_source_settings(cfg) is None
    keys = [[class_key(c, cfg["figures"]["rate_spectrum"]) for c in build.fleet_classes(cfg, build.spectrum_scenario(cfg, "mix"))]
            for cfg in cfgs]
    assert keys[0] == keys[1]
    assert read_part(cfgs[0], schema) == read_part(cfgs[1], schema)
    # with a source the classes of a rough vehicle take other keys, the others keep theirs
    rough = yaml.safe_load(TWO_VEHICLES)
    rough["fleet"]["vehicles"][0]["wheel_source"] = {"roughness": "disc"}
    cfg = config.resolve(defaults, schema, rough, source="mix.yaml")
    wheels = inputs.wheel_source_spectra(cfg)["vehicles"]
    assert wheels["coach"] is None and wheels["loco"].label.startswith("disc")
    new = [class_key(c, cfg["figures"]["rate_spectrum"], wheels[c.vehicle])
           for c in build.fleet_classes(cfg, build.spectrum_scenario(cfg, "mix"))]
    assert set(new[:3]).isdisjoint(keys[0]) and new[3:] == keys[0][3:]


@pytest.mark.parametrize("change, message", [
    ({"roughness": "drum"}, r"fleet\.vehicles\.0\.wheel_source\.roughness = 'drum' is not allowed: it must be one of \['none', "
                            r"'cast_iron', 'composite', 'disc', 'file'\]"),
    ({"roughness": "file"}, r"fleet\.vehicles\[0\] \(loco\)\.wheel_source\.roughness = 'file' needs fleet\.vehicles\[0\] \(loco\)"
                            r"\.wheel_source\.file"),
    ({"roughness": "file", "file": "nowhere.csv"}, r"fleet\.vehicles\[0\] \(loco\)\.wheel_source\.file: .*nowhere\.csv"),
    ({"roughness": "disc", "ground": "E"}, r"unknown key fleet\.vehicles\.0\.wheel_source\.ground = 'E'; the keys allowed under "
                                            r"fleet\.vehicles\.0\.wheel_source are: file, roughness"),  # the ground rail is the fleet's
])
def test_check_refuses_a_bad_vehicle_wheel_source_naming_the_key_before_computing(tmp_path, capsys, change, message):
    # (d) railgrowth check (the workflow and the API read the same: rail.setup.inputs.check_inputs)
    import yaml
    from fleets import TWO_VEHICLES

    from rail.app import cli

    cfg = yaml.safe_load(TWO_VEHICLES)
    cfg["fleet"]["vehicles"][0]["wheel_source"] = change
    scen = tmp_path / "mix.yaml"
    scen.write_text(yaml.safe_dump(cfg))
    assert cli.main(["check", str(scen)]) == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and re.search(message, err), err


def test_each_axle_of_a_vehicle_takes_its_own_rate_alone_on_the_track():
    # a two-axle vehicle, its leading axle driven (-0.001) and its trailing one braked (+0.0008): class_source_arrays's
    # rows are each axle's own rate, against a one-wheel train built apart at that creepage on its own table, and the
    # class's Q_c is the sum over the axles of abs(R_own)^2 P (two axle groups: two single-axle spectra)
    import dataclasses

    from test_growth import MATERIAL

    settings = {"shortest": 0.027, "longest": 0.066, "per_octave": 1, "eps": 1e-9, "grid_phases": 1}
    scn = base(bays=N, passages=100000, step=10000)
    v = vehicle("loco", (0.0, 3.3), 1e5, 1350.0, (-0.001, 0.0008), 1.0)
    fl = F.Fleet((v,), F.SpeedClasses((40.0,), (1.0,)), 20000.0)
    c = fl.classes(scn)[0]
    tables = chain.fleet_tables([c])
    sp = rate_spectrum.spectrum_with_settings(c.scenario, tables[40.0], settings)
    assert ws.axle_groups(c.scenario) == [[0], [1]]
    arr = ws.class_source_arrays(c.scenario, tables[40.0], settings, sp, ws.named_spectrum("disc"))
    for l, creep in enumerate(v.creepage):
        one = base(positions=(0.0,), bays=N, passages=100000, step=10000)
        one = dataclasses.replace(one, material=dataclasses.replace(MATERIAL, creepage=creep))
        alone = rate_spectrum.spectrum_with_settings(one, chain.receptance_table(one, 40.0), settings)
        # the fleet's table holds the vehicle's axle offsets, the wheel's own table only 0: 4.3e-10 apart here (measured),
        # 1e-8 as test_fleet allows between shared and own tables, against the axles' 5 % and more apart (below)
        np.testing.assert_allclose(arr["wheel_rate_own"][l], alone.rate, rtol=1e-8)
    R0, R1 = arr["wheel_rate_own"]
    assert np.all(np.abs(R0 / R1 - 1) > 0.05)  # the driven and the braked axle differ
    np.testing.assert_allclose(src.axle_source_power(arr["wheel_rate_own"], arr["wheel_power"]),
                               (np.abs(R0) ** 2 + np.abs(R1) ** 2) * arr["wheel_power"], rtol=1e-15)


def test_the_workflows_class_files_carry_the_source_and_the_settled_rule_draws_the_fleets(two_classes, defaults, root, tmp_path):
    # rules fleet_class_spectrum -> fleet_rate_spectrum -> fleet_settled_spectrum: the class files (.npz) carry the
    # source's arrays and read back bitwise; the fleet's dataset from them equals the one from memory; written as the
    # results are (io.finalize: units on every variable) the settled script draws it, its CSV with units in every column
    import importlib.util

    from rail.setup import io as rio
    from rail.studies import fleet as FS

    scn, fl, classes, _, spectra = two_classes
    wheels = {"loco": ws.named_spectrum("disc"), "coach": ws.named_spectrum("cast_iron")}
    want, arrays = _fleet(scn, fl, classes, spectra, wheels)
    back, sources = [], []
    for k, (sp, arr) in enumerate(zip(spectra, arrays)):
        np.savez(tmp_path / f"c{k}.npz", **FS.spectrum_arrays(sp), **arr)
        with np.load(tmp_path / f"c{k}.npz") as a:
            back.append(FS.spectrum_from_arrays(a))
            sources.append(ws.source_arrays_of(a))
    fs = GS.fleet_spectrum_of(classes, back)
    got = ws.fleet_source_dataset(fleet_spectrum_dataset(fs, fl, classes), fs, fl, classes, N * scn.L, sources, GROUND, LIMIT)
    for v in ("wheel_source_dB", "decay_factor", "settled_level_dB", "settled_band_level_dB", "axles_to_limit", "interval_axles"):
        np.testing.assert_array_equal(got[v].values, want[v].values, err_msg=v)
    path = tmp_path / "rate_spectrum.nc"
    rio.write_netcdf(rio.finalize(got, defaults, title="fleet", source="test", scenario="mix"), path)
    spec = importlib.util.spec_from_file_location("settled_spectrum", root / "workflow/scripts/settled_spectrum.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = {k: tmp_path / f"settled.{k}" for k in ("png", "csv", "md")}
    mod.main(path, out["png"], out["csv"], out["md"], "mix")
    assert out["png"].stat().st_size > 5000
    header = [x for x in out["csv"].read_text().splitlines() if not x.startswith("#")][0].split(",")
    assert all(re.search(r"_(m|dB_re_1um)$|^axles_to_limit$|^years_to_limit$", h) for h in header), header
    assert "under the fleet" in out["md"].read_text()
