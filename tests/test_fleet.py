"""Growth under a fleet (rail.fleet, rail.chain.fleet_wear / grow_fleet, rail.growth_spectrum.fleet_rate_spectrum):
the fleet reduces to the single train, its wear is the traffic-weighted sum of the classes' wear, its
spectrum the weighted sum of the classes' spectra and agrees with a growth run; bad fleets are refused
at start-up."""

import copy
import dataclasses
import io

import numpy as np
import pytest
from model import scenario
from test_growth import MATERIAL, contact_spring, track

from rail import chain
from rail import fleet as F
from rail import growth_spectrum as GS
from rail import interaction as I
from rail.setup import build, config

K = 24
BOGIE = (0.0, 3.3)


def base(positions=BOGIE, passages=20000, step=10000, bays=1):
    scn = scenario(track(), MATERIAL, contact_spring(), positions=positions, K=K, nodes=41, passages=passages, step=step)
    return dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=bays))


def vehicle(name="loco", positions=BOGIE, load=1e5, mass=1350.0, creepage=None, share=1.0):
    c = tuple([MATERIAL.creepage] * len(positions)) if creepage is None else tuple(creepage)
    return F.Vehicle(name, tuple(positions), load, mass, c, share)


def fleet(vehicles, speeds=(40.0,), weights=(1.0,)):
    return F.Fleet(tuple(vehicles), F.SpeedClasses(tuple(speeds), tuple(weights)), 20000.0)


def rough(bays=1, lines=(3, 7), amplitude=1e-7):
    J = bays * K
    Z = np.zeros(2 * J + 1, dtype=complex)
    for j in lines:
        Z[J + j] = Z[J - j] = amplitude / 2
    return I.Roughness(Z, bays)


# ---------------------------------------------------------------- reduction to the single train


def test_fleet_of_one_vehicle_at_one_speed_reproduces_the_single_train_growth_bitwise():
    scn = base()
    classes = fleet([vehicle()]).classes(scn)
    assert len(classes) == 1 and classes[0].weight == 1.0
    tables = chain.fleet_tables(classes)
    single = chain.grow(scn, chain.receptance_table(scn, 40.0), rough(), progress=io.StringIO())
    fl = chain.grow_fleet(classes, tables, rough(), progress=io.StringIO())
    np.testing.assert_array_equal(fl.passages, single.passages)
    np.testing.assert_array_equal(fl.Z, single.Z)  # bitwise: the same table, wear, step and update
    assert np.abs(fl.Z[-1] - fl.Z[0]).max() > 0  # the run did grow something


def test_two_identical_classes_at_half_shares_equal_one_class():
    scn = base()
    one = fleet([vehicle()]).classes(scn)
    two = fleet([vehicle("a", share=0.5), vehicle("b", share=0.5)]).classes(scn)
    tables = chain.fleet_tables(two)
    Z = rough().Z
    d1, _ = chain.fleet_wear(one, tables, Z, 0.3)
    d2, _ = chain.fleet_wear(two, tables, Z, 0.3)
    np.testing.assert_array_equal(d2, d1)  # 0.5 d + 0.5 d is d exactly in floating point


def test_two_classes_apply_the_share_weighted_wear_per_update():
    # a driven locomotive at 40 m/s (share w) and a lighter braked coach at 44 m/s (1 - w): each
    # class's wear computed on its own (its own table), summed with the shares by hand, equals
    # fleet_wear, and one growth update removes h sum_c w_c dZ_c with h = wheel passages per update
    # over the mean wheels per fleet passage
    w = 0.3
    scn = base(step=10000, passages=10000)
    loco = vehicle("loco", BOGIE, 1e5, 1350.0, (-0.001, -0.001), w)
    coach = vehicle("coach", (0.0, 2.5, 7.5), 6e4, 900.0, (0.0, 0.0008, 0.0008), 1 - w)
    fl = F.Fleet((loco, coach), F.SpeedClasses((40.0,), (1.0,)), 20000.0)
    classes = fl.classes(scn)
    c_loco = dataclasses.replace(scn, wheels=I.Wheels(1350.0, 0.575, 1e5, BOGIE, (-0.001, -0.001)))
    c_coach = dataclasses.replace(scn, wheels=I.Wheels(900.0, 0.575, 6e4, (0.0, 2.5, 7.5), (0.0, 0.0008, 0.0008)),
                                  spring=F.vehicle_spring(scn.spring, 1e5, 6e4))
    Z = rough().Z
    dA, _ = chain.train_wear(c_loco, chain.receptance_table(c_loco, 40.0), Z, 0.0)
    dB, _ = chain.train_wear(c_coach, chain.receptance_table(c_coach, 40.0), Z, 0.0)
    tables = chain.fleet_tables(classes)
    dF, _ = chain.fleet_wear(classes, tables, Z, 0.0)
    expect = w * dA + (1 - w) * dB
    # the shared table holds the offsets of both vehicles in one adaptive quadrature; at the offsets both
    # hold it equals each vehicle's own table to 1.6e-15 (measured), and the weighted wear to 4e-15 of
    # the largest harmonic (measured; the quadrature tolerance rtol 1e-4 would be the bound otherwise)
    err = np.abs(dF - expect)[K + 1:] / np.abs(expect[K + 1:]).max()
    assert err.max() < 1e-12, err.max()
    assert np.abs(dA - dB).max() > 0.1 * np.abs(dA).max()  # the two classes do differ
    # one update with the fleet's own wear
    h = 10000 / (w * 2 + (1 - w) * 3)
    assert chain.fleet_wheels(classes) == pytest.approx(w * 2 + (1 - w) * 3, rel=1e-15)
    hist = chain.grow_fleet(classes, tables, rough(), progress=io.StringIO(), stop_after_updates=1)
    np.testing.assert_allclose(hist.Z[1], Z - h * dF, rtol=0, atol=1e-15 * np.abs(Z).max())


def test_each_axle_wears_at_its_own_creepage():
    # a one-axle vehicle braked at +0.0008 wears as the scenario whose contact creepage is +0.0008
    scn = base(positions=(0.0,))
    braked = fleet([vehicle(positions=(0.0,), creepage=(0.0008,))]).classes(scn)[0].scenario
    same = dataclasses.replace(scn, material=dataclasses.replace(scn.material, creepage=0.0008))
    tab = chain.receptance_table(scn, 40.0)
    Z = rough().Z
    np.testing.assert_array_equal(chain.train_wear(braked, tab, Z)[0], chain.train_wear(same, tab, Z)[0])
    driven = chain.train_wear(scn, tab, Z)[0]
    assert np.abs(driven - chain.train_wear(braked, tab, Z)[0]).max() > 0


def test_tables_are_computed_once_per_speed_and_shared_between_vehicles(monkeypatch):
    calls = []
    real = chain.track_table
    monkeypatch.setattr(chain, "track_table", lambda *a, **k: calls.append(a[2]) or real(*a, **k))
    fl = fleet([vehicle("a", share=0.5), vehicle("b", (0.0, 2.5), 6e4, 900.0, share=0.5)], (38.0, 42.0), (0.5, 0.5))
    classes = fl.classes(base())
    tables = chain.fleet_tables(classes)
    assert len(classes) == 4 and sorted(calls) == [38.0, 42.0]
    for c in classes:  # every wheel pair of both vehicles is in the shared table
        assert set(chain.wheel_offsets(c.scenario)) <= {round(float(d), 9) for d in tables[c.speed].offsets}


# ---------------------------------------------------------------- definitions


def test_hertz_spring_scales_with_the_cube_root_of_the_load():
    s = I.ContactSpring(1.4e9, 2e-6, 0.0)
    eight = F.vehicle_spring(s, 1e5, 8e5)  # 8 x the load: twice the stiffness (Hertz k_H ~ P^(1/3))
    assert eight.hertz_stiffness == pytest.approx(2.8e9, rel=1e-14)
    assert eight.loss_slope == pytest.approx(4e-6, rel=1e-14)  # eta_H ~ k_H (the half-space's loss)
    assert F.vehicle_spring(s, 1e5, 1e5) is s


def test_normal_speed_classes_are_equal_probability_at_their_conditional_means():
    c = F.normal_classes(40.0, 4.0, 2)
    # two halves of N(40, 4): conditional means 40 -+ 4 sqrt(2 / pi)
    np.testing.assert_allclose(c.speeds, [40 - 4 * np.sqrt(2 / np.pi), 40 + 4 * np.sqrt(2 / np.pi)], rtol=1e-14)
    assert c.weights == (0.5, 0.5)
    for n in (1, 3, 7, 40):  # the mean is kept exactly, the variance rises towards std^2 from below
        c = F.normal_classes(40.0, 4.0, n)
        assert c.mean == pytest.approx(40.0, rel=1e-13)
    var = [np.dot(F.normal_classes(40.0, 4.0, n).weights, (np.array(F.normal_classes(40.0, 4.0, n).speeds) - 40) ** 2)
           for n in (2, 5, 20, 50)]
    assert all(a < b < 16.0 for a, b in zip(var, var[1:])) and var[-1] > 0.98 * 16
    u = F.uniform_classes(36.0, 44.0, 4)
    np.testing.assert_allclose(u.speeds, [37.0, 39.0, 41.0, 43.0], rtol=1e-15)


def test_traffic_units_from_the_fleet_loads():
    # 60 % four-axle locomotives of wheel load 1e5 N (axle 20.394 t), 40 % two-axle
    # wagons of wheel load 5e4 N (axle 10.197 t): mean axles per train 0.6 * 4 + 0.4 * 2 = 3.2; mean
    # axle load (0.6 * 4 * 20.394 + 0.4 * 2 * 10.197) / 3.2 = 17.845 t; at 20,000 axles a day
    # 20000 * 365 * 17.845 / 1e6 = 130.27 MGT a year
    fl = F.Fleet((vehicle("loco", (0.0, 2.5, 10.0, 12.5), 1e5, share=0.6), vehicle("wagon", (0.0, 6.0), 5e4, share=0.4)),
                 F.SpeedClasses((40.0,), (1.0,)), 20000.0)
    axle = 2e5 / 9.80665 / 1000
    assert fl.axles_per_train == pytest.approx(3.2, rel=1e-15)
    assert fl.mean_axle_load == pytest.approx((0.6 * 4 * axle + 0.4 * 2 * axle / 2) / 3.2, rel=1e-14)
    assert fl.mgt_per_year == pytest.approx(20000 * 365 * 17.8448 / 1e6, rel=1e-4)
    assert fl.trains_per_day == pytest.approx(20000 / 3.2, rel=1e-15)


# ---------------------------------------------------------------- spectrum

N = 4
LINES = [37, 86]  # 64.9 mm (grows at 40 m/s) and 27.9 mm (decays), free lines of the 4-bay period


@pytest.fixture(scope="module")
def two_class_spectrum():
    scn = base(bays=N, passages=100000, step=10000)
    loco = vehicle("loco", (0.0,), 1e5, 1350.0, (-0.001,), 0.6)
    coach = vehicle("coach", (0.0,), 6e4, 900.0, (0.0008,), 0.4)
    fl = F.Fleet((loco, coach), F.SpeedClasses((40.0, 44.0), (0.5, 0.5)), 20000.0)
    classes = fl.classes(scn)
    tables = chain.fleet_tables(classes)
    return scn, classes, tables, GS.fleet_rate_spectrum(classes, tables, LINES, eps=1e-9, grid_phases=2, check_lines=1)


@pytest.mark.slow
def test_fleet_spectrum_is_the_share_weighted_sum_of_the_single_class_spectra(two_class_spectrum):
    # about 45 s CPU: four class spectra and four single-train spectra on a 4-bay period
    scn, classes, tables, fs = two_class_spectrum
    # each class alone, as a single-train spectrum on its own table (computed here, not shared)
    own = [GS.rate_spectrum(c.scenario, chain.receptance_table(c.scenario, c.speed), LINES, eps=1e-9, grid_phases=2,
                            check_lines=1) for c in classes]
    expect = sum(c.weight * s.rate for c, s in zip(classes, own))
    # one-wheel vehicles: the shared tables equal the own ones. The same spectrum computed again later in
    # one process differs by up to 2.6e-9 of the rate (measured; back-to-back repeats agree bitwise), so
    # 1e-8, against a spread of the classes' rates of tens of percent (below)
    np.testing.assert_allclose(fs.total.rate, expect, rtol=1e-8)
    assert np.allclose(fs.weights, [0.3, 0.3, 0.2, 0.2])
    g = np.array([-s.rate.real for s in fs.classes])
    assert np.ptp(g[:, 0]) > 0.1 * np.abs(g[:, 0]).max()  # the classes differ: the test would see a wrong weight


@pytest.fixture(scope="module")
def small_spectrum():
    # two one-wheel vehicles at 40 m/s on a 3-bay period: lines 2 and 4 free, 3 on the one-bay comb (locked)
    scn = base(bays=3)
    fl = fleet([vehicle("a", (0.0,), creepage=(-0.001,), share=0.6), vehicle("b", (0.0,), 6e4, 900.0, (0.0008,), 0.4)])
    classes = fl.classes(scn)
    tables = chain.fleet_tables(classes)
    return fl, classes, GS.fleet_rate_spectrum(classes, tables, [2, 3, 4], eps=1e-9, grid_phases=1, check_lines=1)


def test_fleet_spectrum_is_the_weighted_sum_of_single_train_spectra_at_free_lines(small_spectrum):
    fl, classes, fs = small_spectrum
    own = [GS.rate_spectrum(c.scenario, chain.receptance_table(c.scenario, c.speed), [2, 3, 4], eps=1e-9, grid_phases=1,
                            check_lines=1) for c in classes]
    free = [0, 2]
    expect = 0.6 * own[0].rate[free] + 0.4 * own[1].rate[free]
    np.testing.assert_allclose(fs.total.rate[free], expect, rtol=1e-8)  # see the 4-bay test for the 1e-8
    assert abs(own[0].rate[0] - own[1].rate[0]) > 0.1 * abs(own[0].rate[0])  # the classes differ


def test_fleet_spectrum_at_a_locked_line_is_the_eigenvalue_of_the_weighted_operator(small_spectrum):
    fl, classes, fs = small_spectrum
    assert list(fs.total.locked) == [0, 1, 0]
    M = 0.6 * fs.classes[0].operator[1] + 0.4 * fs.classes[1].operator[1]
    ev = np.linalg.eigvals(M)
    ev = ev[np.argsort(ev.real)]
    np.testing.assert_allclose([fs.total.rate[1], fs.total.rate_other[1]], ev, rtol=1e-12)
    # here it is close to the weighted sum of the classes' eigenvalues (the same to 6 digits, measured):
    # one-wheel trains at one speed give nearly commuting operators; in general the two differ


@pytest.mark.slow
def test_fleet_spectrum_agrees_with_a_short_fleet_growth_run(two_class_spectrum):
    # about 60 s CPU. 100,000 axle passages (10 updates) from 0.1 um sinusoids at the two lines under the fleet: each
    # line's amplitude ends where the explicit update (1 - h R)^10 of the fleet's rate says, and within
    # the update-step error of exp(-R n) (first order: about n h |R|^2 / 2)
    scn, classes, tables, fs = two_class_spectrum
    hist = chain.grow_fleet(classes, tables, rough(N, LINES), progress=io.StringIO())
    J = N * K
    nbar = chain.fleet_wheels(classes)
    h = scn.growth.passages_per_update / nbar  # fleet passages per update
    n = scn.growth.passages / nbar
    for i, j in enumerate(LINES):
        R = fs.total.rate[i]
        got = abs(hist.Z[-1, J + j] / hist.Z[0, J + j])
        explicit = abs((1 - h * R) ** 10)
        exact = abs(np.exp(-R * n))
        step_error = n * h * abs(R) ** 2 / 2
        print(f"line {j}: growth over the run {got:.6f}, explicit {explicit:.6f} ({got / explicit - 1:+.2e}), "
              f"exp(-R n) {exact:.6f} ({got / exact - 1:+.2e}), estimated step error {step_error:.2e}")
        assert abs(got / explicit - 1) < 3e-3, (j, got, explicit)
        assert abs(got / exact - 1) < 1.5 * step_error + 3e-3, (j, got, exact, step_error)
        assert abs(np.log(got)) > 10 * abs(got / explicit - 1)  # the line did change, more than the error


# ---------------------------------------------------------------- bad input at start-up

FLEET = {"vehicles": [{"name": "loco", "positions": [0.0, 3.3], "static_load": 1.0e5, "unsprung_mass": 1350.0,
                       "creepage": [-0.001, -0.001], "share": 0.3},
                      {"name": "coach", "positions": [0.0, 2.5], "static_load": 6.0e4, "unsprung_mass": 900.0,
                       "creepage": [0.0, 0.0005], "share": 0.7}],
         "speeds": {"values": [36.0, 40.0, 44.0], "weights": [0.25, 0.5, 0.25]}}


def _with(path, value):
    f = copy.deepcopy(FLEET)
    node = f
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return {"fleet": f}


@pytest.mark.parametrize("change, message", [
    ((("vehicles", 0, "share"), 0.5), r"fleet\.vehicles\[\*\]\.share = \[0\.5, 0\.7\] sums to 1\.2: it must sum to 1 "
                                      r"\(each value in \[0, 1\]"),
    ((("speeds", "weights"), [0.25, 0.5, 0.5]), r"fleet\.speeds\.weights = \[0\.25, 0\.5, 0\.5\] sums to 1\.25: it must sum to 1"),
    ((("speeds", "weights"), [0.75, 0.5, -0.25]), r"fleet\.speeds\.weights\.2 = -0\.25 is not allowed: it must be >= 0 "
                                                  r"\(valid range \[0, 1\]\)"),
    ((("vehicles", 1, "share"), -0.3), r"fleet\.vehicles\.1\.share = -0\.3 is not allowed: it must be >= 0"),
    ((("speeds", "weights"), [0.25, float("nan"), 0.25]), r"fleet\.speeds\.weights\[1\] = nan is not allowed: it must be a finite number"),
    ((("vehicles", 0, "static_load"), float("nan")), r"fleet\.vehicles\[0\]\.static_load = nan is not allowed"),
    ((("vehicles", 0, "creepage"), [-0.001]), r"fleet\.vehicles\[0\] \(loco\)\.creepage has 1 values: it needs one per axle"),
    ((("speeds",), {"distribution": "normal", "mean": 10.0, "std": 10.0, "classes": 9}),
     r"slowest class at -7\.05 m/s: every class must be > 0"),
    ((("speeds",), {"distribution": "uniform", "low": 44.0, "high": 36.0, "classes": 4}),
     r"fleet\.speeds\.low = 44\.0 m/s is not allowed: it must be <= fleet\.speeds\.high = 36\.0 m/s"),
    ((("speeds",), {"values": [40.0], "weights": [1.0], "distribution": "normal"}), r"give either values and weights, or distribution"),
    # a line break in a name split `railgrowth check`'s one line per vehicle (found by tests/test_doors.py's fuzzing)
    ((("vehicles", 0, "name"), "lo\nco"), r"fleet\.vehicles\[0\]\.name = 'lo\\nco' is not allowed: a vehicle type's name must be one line"),
    ((("vehicles", 1, "name"), "\x85"), r"fleet\.vehicles\[1\]\.name = '\\x85' is not allowed"),
])
def test_bad_fleet_is_refused_at_start_up_naming_key_value_and_range(schema, defaults, change, message):
    with pytest.raises(config.ConfigError, match=message):
        config.resolve(defaults, schema, _with(*change), source="fleet.yaml")


def test_a_configuration_without_fleet_has_no_classes_and_a_good_fleet_builds(schema, defaults):
    cfg = config.resolve(defaults, schema, {}, source="config")
    assert build.fleet(cfg) is None and build.fleet_classes(cfg, build.scenario(cfg)) == ()
    cfg = config.resolve(defaults, schema, {"fleet": FLEET}, source="fleet.yaml")
    classes = build.fleet_classes(cfg, build.scenario(cfg))
    assert [c.label for c in classes][:2] == ["loco at 36 m/s", "loco at 40 m/s"]
    np.testing.assert_allclose([c.weight for c in classes], [0.075, 0.15, 0.075, 0.175, 0.35, 0.175], rtol=1e-15)
    assert sum(c.weight for c in classes) == pytest.approx(1.0, abs=1e-15)
    assert classes[3].scenario.wheels.creepage == (0.0, 0.0005) and classes[3].scenario.wheels.static_load == 6e4


def test_fleet_spectrum_dataset_keeps_each_class_and_states_rates_per_year(small_spectrum, defaults):
    from rail.setup import io as rio
    from rail.studies.fleet import fleet_spectrum_dataset

    fl, classes, fs = small_spectrum
    ds = rio.finalize(fleet_spectrum_dataset(fs, fl), defaults, title="fleet spectrum", source="test", scenario="test")
    assert ds["class_contribution"].dims == ("class", "wavelength") and ds.sizes["class"] == 2
    free = ds["locked"].values == 0
    np.testing.assert_allclose(ds["class_contribution"].sum("class").values[free], ds["growth_rate"].values[free], rtol=1e-12)
    # one-wheel trains: 20,000 axles a day are 20,000 trains a day, 7.3e6 a year
    np.testing.assert_allclose(ds["growth_rate_per_year"], ds["growth_rate"] * 20000 * 365, rtol=1e-14)
    axle = 2 / 9.80665 / 1000  # t per N of wheel load
    assert ds.attrs["mgt_per_year"] == pytest.approx(20000 * 365 * (0.6 * 1e5 + 0.4 * 6e4) * axle / 1e6, rel=1e-14)


@pytest.mark.slow
def test_api_growth_runs_a_study_with_a_fleet_and_refuses_a_speed():
    # about 60 s CPU: two speeds' tables at K = 48 and two updates of two classes
    from rail.app import api

    changes = {"fleet": {"vehicles": [{"name": "loco", "positions": [0.0], "static_load": 1.0e5, "unsprung_mass": 1350.0,
                                       "creepage": [-0.001], "share": 1.0}],
                         "speeds": {"distribution": "uniform", "low": 38.0, "high": 42.0, "classes": 2}},
               "numerics": {"track": {"harmonics": 48}, "contact": {"nodes": 41}},
               "growth": {"passages": 20000, "passages_per_update": 10000, "save_every": 10000}}
    study = api.load("default", changes=changes)
    with pytest.raises(config.ConfigError, match=r"speed = 40\.0 is not allowed for default: its fleet sets the speeds"):
        api.growth(study, speed=40.0)
    ds = api.growth(study, progress=io.StringIO())
    np.testing.assert_allclose(ds["years"], np.array([0, 10000, 20000]) / 20000 / 365, rtol=1e-15)
    assert ds.attrs["fleet_speeds"].startswith("[39.0, 41.0] m/s with weights [0.5, 0.5]")
    assert np.isfinite(ds["level"].values[-1]).any()


@pytest.mark.slow
def test_api_fleet_spectrum_gives_the_weighted_rates_with_each_class():
    # about 40 s CPU: two speeds' Bloch tables of a 4-bay period at K = 48, a few lines
    from rail.app import api

    changes = {"fleet": {"vehicles": [{"name": "loco", "positions": [0.0], "static_load": 1.0e5, "unsprung_mass": 1350.0,
                                       "creepage": [-0.001], "share": 0.5},
                                      {"name": "coach", "positions": [0.0], "static_load": 6.0e4, "unsprung_mass": 900.0,
                                       "creepage": [0.0008], "share": 0.5}],
                         "speeds": {"values": [40.0], "weights": [1.0]}},
               "numerics": {"track": {"harmonics": 48}, "contact": {"nodes": 41}}}
    study = api.load("default", changes=changes)
    with pytest.raises(config.ConfigError, match="default has no fleet"):
        api.fleet_spectrum(api.load("default"))
    ds = api.fleet_spectrum(study, bays=4, shortest=0.06, longest=0.07, per_octave=1, grid_phases=1)
    assert ds.sizes["class"] == 2 and list(ds["class_weight"].values) == [0.5, 0.5]
    free = ds["locked"].values == 0
    np.testing.assert_allclose(ds["class_contribution"].sum("class").values[free], ds["growth_rate"].values[free], rtol=1e-12)
    assert ds["growth_dB_per_year"].attrs["level_unit"] == "dB"


def test_a_train_over_an_n_bay_period_wears_a_bay_periodic_roughness_as_over_one_bay():
    # found by the traffic study: the second wheel of a train over an N-bay period was handed a 1-bay
    # roughness (rail.wear.apply_wear drops the period) and the run stopped. A bay-periodic roughness
    # (lines j = k N only) on a 2-bay period must wear exactly as on one bay, wheel after wheel.
    s1, s2 = base(), base(bays=2)
    t1 = chain.receptance_table(s1, 40.0)
    t2 = chain.receptance_table(s2, 40.0)
    Z1 = rough(1, lines=(3, 7)).Z
    Z2 = np.zeros(2 * 2 * K + 1, dtype=complex)
    Z2[2 * K + 2 * np.arange(-K, K + 1)] = Z1
    d1, _ = chain.train_wear(s1, t1, Z1)
    d2, _ = chain.train_wear(s2, t2, Z2)
    on_comb = 2 * K + 2 * np.arange(-K, K + 1)
    np.testing.assert_allclose(d2[on_comb], d1, rtol=0, atol=1e-6 * np.abs(d1).max())
    off = np.setdiff1d(np.arange(d2.size), on_comb)
    assert np.abs(d2[off]).max() <= 1e-6 * np.abs(d1).max()


def test_linear_spectrum_of_a_train_whose_wheels_have_grids_of_different_size_matches_the_probes():
    # found by the traffic study: the wheels of a coach (axles at 0, 2.6, 16, 18.6 m) roll on contact
    # grids of 1844 and 1845 points per bay (their forces differ), and the tangent method summed their
    # derivatives on one array (a broadcast error). Against the independent probes of the nonlinear
    # march, with the bound of tests/test_growth_spectrum.py (2e-3 of |R|; measured there 3e-4).
    from rail import wear

    pos = (0.0, 2.6, 16.0, 18.6)
    s1 = base(positions=pos)
    t1 = chain.receptance_table(s1, 40.0)
    Z0 = I.Roughness(np.zeros(2 * K + 1, dtype=complex), 1)
    f1 = chain.solve_forces(s1, t1, Z0)
    nx = {wear.march_inputs(f1, l, Z0, chain.wheel_material(s1, l), s1.contact_numerics, 0.0).Nx for l in range(len(pos))}
    assert len(nx) > 1, nx  # the case this test is about
    scn = base(positions=pos, bays=4)
    scn = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, kind="smooth"))
    tabs = chain.receptance_table(scn, 40.0)
    lines = [37, 86, 4, 30]  # two free lines, the comb (j = N) and a half-comb line (j = 30 = 7.5 N)
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    ref = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="probe")
    assert fast.method == "linear"
    err = np.abs(fast.rate - ref.rate) / np.abs(ref.rate)
    assert err.max() < 2e-3, dict(zip(lines, err))


def test_fleet_spectrum_per_axle_figure_and_the_traffic_study_summary_from_class_spectra(small_spectrum, defaults, tmp_path):
    # the workflow's path: class spectra saved and read back (bitwise), combined by fleet_spectrum_of into
    # the same spectrum as fleet_rate_spectrum; per axle = per fleet passage / axles per train; the
    # study's band means and summary of two cases whose rates differ by a known factor
    import xarray as xr

    from rail.plotting import studies as plots
    from rail.studies import fleet as FS
    from rail.studies.bands import third_octave_bands

    fl, classes, fs = small_spectrum
    back = []
    for k, sp in enumerate(fs.classes):
        np.savez(tmp_path / f"c{k}.npz", **FS.spectrum_arrays(sp))
        with np.load(tmp_path / f"c{k}.npz") as a:
            back.append(FS.spectrum_from_arrays(a))
    again = GS.fleet_spectrum_of(classes, back)
    assert np.array_equal(again.total.rate, fs.total.rate) and np.array_equal(again.total.rate_other, fs.total.rate_other)
    ds = FS.fleet_spectrum_dataset(again, fl)
    np.testing.assert_allclose(ds["growth_dB_per_1e5_axles"].values, ds["growth_dB_per_1e5_trains"].values / fl.axles_per_train, rtol=1e-15)
    # per MGT: the traffic's mean axle load worked out here from the vehicles (2 P / g per axle, weighted by share x axles)
    w = [v.share * len(v.positions) for v in fl.vehicles]
    load_t = sum(wi * 2 * v.static_load / 9.80665 / 1000 for wi, v in zip(w, fl.vehicles)) / sum(w)
    np.testing.assert_allclose(ds["growth_dB_per_MGT"].values, ds["growth_dB_per_1e5_axles"].values / 1e5 * 1e6 / load_t, rtol=1e-12)
    ds.attrs.update({"pinned_pinned_frequency_Hz": 1000.0, "mean_speed_m_per_s": 40.0,
                     "pinned_pinned_wavelength_m": float(ds["wavelength"].values.mean())})
    fig = plots.fleet_spectrum_figure(ds)
    fig.savefig(tmp_path / "f.png")
    # issue 45: long wavelengths on the left as every study figure, the frequency at the mean speed on top,
    # dB per MGT at the traffic's mean axle load on the right
    ax = fig.axes[0]
    assert ax.get_xlim()[0] > ax.get_xlim()[1]
    assert [a.get_xlabel() for a in ax.child_axes if a.get_xlabel()] == ["frequency at mean V = 40 m/s (Hz)"]
    assert [a.get_ylabel() for a in ax.child_axes if a.get_ylabel()] == [f"dB per MGT (axle load {load_t:.3g} t)"]
    twice = ds.copy(deep=True)
    twice["growth_dB_per_1e5_axles"] = 2 * ds["growth_dB_per_1e5_axles"]
    st = FS.traffic_study_dataset([ds, twice], [("driven", 0.0), ("driven", 0.1)])
    lam, g = ds["wavelength"].values, ds["growth_dB_per_1e5_axles"].values
    bands = third_octave_bands(float(lam.max()), float(lam.min()))
    for b, (lo, hi) in enumerate(zip(bands.lower, bands.upper)):
        sel = (lam >= lo) & (lam < hi)
        got = st["band_growth_dB_per_1e5_axles"].sel(drive="driven", spread=0.1, band=bands.nominal[b]).item()
        assert (np.isnan(got) and not sel.any()) or got == pytest.approx(2 * g[sel].mean(), rel=1e-14)
    text = FS.traffic_summary_markdown(st)
    assert "| driven | ±0 % |" in text and "| driven | ±10 % |" in text
    fig = plots.traffic_study_figure(st)
    fig.savefig(tmp_path / "t.png")
    assert all(a.get_xlim()[0] > a.get_xlim()[1] for a in fig.axes if a.get_xlabel() == "wavelength (mm)")
    assert isinstance(st, xr.Dataset) and (tmp_path / "t.png").stat().st_size > 5000


def test_a_fleets_class_keys_hash_only_what_a_class_spectrum_reads(schema, defaults):
    # issue 57, item 8: changing only growth.passages of a fleet reran all 8 class spectra (the key hashed
    # the whole scenario); the growth settings, the initial roughness and the traffic are not read by a
    # class spectrum (taken about the smooth rail), the track and the contact are

    from rail.setup.study_files import class_key

    def keys(change):
        cfg = config.resolve(defaults, schema, {**change, "fleet": {**FLEET, **change.get("fleet", {})}}, source="fleet.yaml")
        return [class_key(c, cfg["figures"]["rate_spectrum"]) for c in build.fleet_classes(cfg, build.spectrum_scenario(cfg, "mix"))]

    first = keys({})
    assert len(set(first)) == len(first) == 6
    unread = [{"growth": {"passages": 300000, "save_every": 50000}}, {"traffic": {"axles_per_day": 55000.0}},
              {"roughness": {"kind": "harmonic", "amplitude": 3e-6, "frequency": 800.0}}]
    for change in unread:
        assert keys(change) == first, change
    read = [{"track": {"pad": {"stiffness": 1.0e9}}}, {"contact": {"friction_dynamic": 0.25}},
            {"fleet": {"spectrum": {"bays": 4}}}]
    for change in read:
        assert set(keys(change)).isdisjoint(first), change


def test_every_scenario_field_is_hashed_by_the_class_key_or_named_as_unread():
    # a field added to Scenario must be decided on: read by a class spectrum (hashed) or not
    import dataclasses as dc

    from rail.scenario import Scenario
    from rail.setup.study_files import CLASS_SPECTRUM_READS

    # every field of a Scenario is either hashed or named here as unread: a new field must be decided on
    assert set(CLASS_SPECTRUM_READS) | {"name", "growth", "roughness", "axles_per_day"} == {f.name for f in dc.fields(Scenario)}


def test_a_fleets_band_is_resolved_at_every_class_speed_and_a_period_too_coarse_for_it_stops_at_start_up():
    # fleet.spectrum.band (issue 55): the band just above pinned-pinned is about 50 Hz wide; a fleet's log-spaced lines
    # (6 per octave, 12 % apart) lie 90-110 Hz apart there. Every class takes the same lines, each class's neighbours
    # inside the band at most `spacing` apart at its own speed (judged here by the lines' frequencies j V / (N L)).
    from rail.app import api
    from rail.growth_spectrum import settings_lines

    L = 0.6
    fleet = {"vehicles": [{"name": "loco", "positions": [0.0], "static_load": 1.0e5, "unsprung_mass": 1350.0, "creepage": [-0.001],
                           "share": 1.0}],
             "speeds": {"distribution": "uniform", "low": 36.0, "high": 44.0, "classes": 3},
             "spectrum": {"bays": 5, "band": {"low": 1000.0, "high": 1300.0, "spacing": 16.0}}}
    study = api.load("default", changes={"fleet": fleet})
    s = study.config["figures"]["rate_spectrum"]
    assert s["speeds"] == pytest.approx([36.0 + 8.0 / 6, 40.0, 44.0 - 8.0 / 6])
    lines = settings_lines(L, 5, study.scenario.harmonics, s)
    plain = settings_lines(L, 5, study.scenario.harmonics, {**s, "band": None})
    for V in s["speeds"]:
        f = lines * V / (5 * L)
        inside = f[(f >= 1000.0) & (f <= 1300.0)]
        assert np.diff(inside).max() <= 16.0 * (1 + 1e-12) and inside.min() - 1000.0 < 16.0 and 1300.0 - inside.max() < 16.0, V
        fp = plain * V / (5 * L)
        assert np.diff(fp[(fp >= 1000.0) & (fp <= 1300.0)]).min() > 50.0  # without it: lines wider apart than the band
    coarse = {**fleet, "spectrum": {**fleet["spectrum"], "band": {"low": 1000.0, "high": 1300.0, "spacing": 12.0}}}
    coarse_text = r"fleet\.spectrum: a roughness period of 5 bays spaces the lines 14\.2 Hz apart at 42\.6667 m/s.* at least 6 bays"
    with pytest.raises(config.ConfigError, match=coarse_text):
        api.load("default", changes={"fleet": coarse})
