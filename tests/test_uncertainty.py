"""Uncertainty of the inputs as a seeded ensemble (rail.uncertainty, config/uncertainty.yaml): reproducible
bit for bit, zero spread gives zero width, the interval is the stated quantiles, bad input refused."""

import numpy as np
import pytest
import yaml

from rail import uncertainty as U


@pytest.fixture()
def study(root):
    return yaml.safe_load((root / "config/uncertainty.yaml").read_text())


def test_a_seeded_ensemble_is_reproducible_bit_for_bit_and_another_seed_differs(study):
    a = U.sample(study["parameters"], study["members"], study["seed"])
    b = U.sample(study["parameters"], study["members"], study["seed"])
    c = U.sample(study["parameters"], study["members"], study["seed"] + 1)
    assert list(a) == list(study["parameters"])
    for k in a:
        assert a[k].tobytes() == b[k].tobytes()
        assert not np.array_equal(a[k], c[k])
        assert np.unique(a[k]).size == study["members"]  # every parameter of the file has a spread


def test_the_draws_follow_their_distributions(study):
    # 20,000 draws: sample means within 4 standard errors of the distributions' (independent of the code)
    d = U.sample(study["parameters"], 20000, 1)
    n = 20000
    mu = d["contact.friction"]
    assert mu.min() >= 0.2 and mu.max() <= 0.4 and abs(mu.mean() - 0.3) < 4 * 0.2 / np.sqrt(12 * n)
    g = d["contact.creepage"]
    assert abs(g.mean() + 0.001) < 4 * 0.0002 / np.sqrt(n) and abs(g.std() / 0.0002 - 1) < 0.03
    lk = np.log(d["wear.coefficient"])
    assert abs(lk.mean() - np.log(2.5e-9)) < 4 * np.log(2.0) / np.sqrt(n) and abs(lk.std() / np.log(2.0) - 1) < 0.03


def test_a_parameter_with_zero_spread_gives_every_member_its_value_and_zero_width(study):
    params = dict(study["parameters"])
    params["contact.creepage"] = {"distribution": "normal", "mean": -0.001, "std": 0.0}
    params["track.pad.stiffness"] = {"distribution": "lognormal", "median": 3.5e8, "factor": 1.0}
    params["contact.friction"] = {"distribution": "uniform", "low": 0.3, "high": 0.3}
    d = U.sample(params, 16, 7)
    for k in ("contact.creepage", "track.pad.stiffness", "contact.friction"):
        assert np.all(d[k] == d[k][0])
    assert np.unique(d["wear.coefficient"]).size == 16  # the one with a spread still varies
    # members whose results are equal have an interval of zero width, exactly
    rows = np.tile(np.array([1.5, -2.0, np.nan]), (16, 1))
    med, lo, hi = U.band_statistics(rows, (0.1, 0.9))
    assert np.array_equal(hi[:2] - lo[:2], [0.0, 0.0]) and np.array_equal(med[:2], [1.5, -2.0]) and np.isnan(med[2])


def test_band_statistics_are_the_median_and_the_stated_quantiles():
    v = np.arange(1.0, 10.0)[:, None]  # 1..9: median 5; quantile q by linear interpolation: 1 + 8 q
    med, lo, hi = U.band_statistics(v, (0.1, 0.9))
    assert med[0] == 5.0 and lo[0] == pytest.approx(1.8, abs=1e-12) and hi[0] == pytest.approx(8.2, abs=1e-12)


def test_a_member_configuration_sets_the_keys_and_friction_sets_both(defaults):
    cfg = U.member_config(defaults, {"contact.friction": 0.25, "track.pad.stiffness": 2e8})
    assert cfg["contact"]["friction_static"] == cfg["contact"]["friction_dynamic"] == 0.25
    assert cfg["track"]["pad"]["stiffness"] == 2e8 and defaults["track"]["pad"]["stiffness"] == 3.5e8
    with pytest.raises(ValueError, match=r"uncertainty parameter contact\.frction: the configuration has no key contact\.frction"):
        U.member_config(defaults, {"contact.frction": 0.3})


@pytest.mark.parametrize("spec, message", [
    ({"distribution": "normal", "mean": 1.0, "std": -1.0}, r"std = -1\.0 is not allowed: it must be >= 0"),
    ({"distribution": "uniform", "low": 2.0, "high": 1.0}, r"low = 2\.0, high = 1\.0 are not allowed: low <= high"),
    ({"distribution": "lognormal", "median": 1.0, "factor": 0.5}, r"median = 1\.0, factor = 0\.5 are not allowed: median > 0 and factor >= 1"),
    ({"distribution": "beta", "a": 1.0}, r"distribution = 'beta' is not allowed: it must be one of uniform, normal"),
    ({"distribution": "normal", "mean": float("nan"), "std": 1.0}, r"mean = nan is not allowed: it must be a finite number"),
])
def test_a_bad_distribution_is_refused_naming_key_value_and_range(spec, message):
    with pytest.raises(ValueError, match=r"uncertainty parameter wear\.coefficient: " + message):
        U.sample({"wear.coefficient": spec}, 4, 0)


def test_ensemble_dataset_gives_each_band_the_median_and_interval_of_its_members_band_means():
    import xarray as xr

    from rail.studies.ensemble import ensemble_dataset

    lam = np.array([0.105, 0.095, 0.079, 0.071])  # two lines in the 100 mm band, two in the 80 mm band
    members = [xr.Dataset({"growth_dB_per_1e5_axles": (("speed", "wavelength"), [[m, m + 2.0, -m, -m]])}, coords={"wavelength": lam})
               for m in range(5)]  # 100 mm band mean: m + 1; 80 mm band: -m
    ds = ensemble_dataset(members, {"wear.coefficient": np.arange(5.0)}, (0.25, 0.75))
    assert ds["band"].values.tolist() == [0.1, 0.08]
    assert np.array_equal(ds["band_growth_dB_per_1e5_axles"].values[:, 0], np.arange(5.0) + 1)
    assert ds["band_median_dB_per_1e5_axles"].values.tolist() == [3.0, -2.0]
    assert ds["band_lower_dB_per_1e5_axles"].values.tolist() == [2.0, -3.0] and ds["band_upper_dB_per_1e5_axles"].values.tolist() == [4.0, -1.0]
    assert ds["band_growth_dB_per_1e5_axles"].attrs["units"] == "dB per 100000 axle passages" and "draw_wear.coefficient" in ds.coords


def test_band_interval_figure_plots_the_per_axle_band_median_and_interval():
    # the figure's convention is the exports' (dB per 100,000 axle passages): the plotted median line and
    # the shaded interval are the dataset's band_*_dB_per_1e5_axles
    import xarray as xr

    from rail.plotting.ensemble import band_interval_figure
    from rail.studies.ensemble import ensemble_dataset

    lam = np.array([0.105, 0.095, 0.079, 0.071])
    members = [xr.Dataset({"growth_dB_per_1e5_axles": (("speed", "wavelength"), [[m, m + 2.0, -m, -m]])}, coords={"wavelength": lam})
               for m in range(5)]
    ds = ensemble_dataset(members, {"wear.coefficient": np.arange(5.0)}, (0.25, 0.75))
    ax = band_interval_figure(ds).axes[0]
    assert ax.get_ylabel() == "growth (dB per 100,000 axle passages)"
    median = [ln for ln in ax.get_lines() if ln.get_label() == "median"]
    assert len(median) == 1 and median[0].get_ydata().tolist() == [3.0, -2.0]
    path = ax.collections[0].get_paths()[0].vertices[:, 1]
    assert set(np.round(path, 12)) == {2.0, -3.0, 4.0, -1.0}


def test_the_ensemble_carries_the_head_height_and_the_pads_stiffnesses_with_their_stated_spreads(study):
    """Issue 54: e (track.rail.head_height), the pads' vertical, longitudinal and rotational stiffness are drawn
    with the file's spreads (20,000 draws against the distributions, independent of the code), within the
    schema's ranges, and every member holds the rail's flexibility (the file's changes), through which e and k_x act."""
    p = study["parameters"]
    for key in ("track.rail.head_height", "track.pad.stiffness", "track.pad.longitudinal_stiffness", "track.pad.rotational_stiffness"):
        assert key in p, key
    assert study["changes"]["rail_flexibility"]["model"] == "rod_and_bending"
    n = 20000
    d = U.sample(p, n, 3)
    e = d["track.rail.head_height"]
    assert 0.082 <= e.min() and e.max() <= 0.100 and abs(e.mean() - 0.091) < 4 * 0.018 / np.sqrt(12 * n)
    for key, median, factor in (("track.pad.longitudinal_stiffness", 1e7, 1.8), ("track.pad.rotational_stiffness", 9.45e5, 2.0)):
        lk = np.log(d[key])
        assert abs(lk.mean() - np.log(median)) < 4 * np.log(factor) / np.sqrt(n) and abs(lk.std() / np.log(factor) - 1) < 0.03, key
    # the file's 16 members stay inside the schema's ranges (k_x >= 1e6, k_theta <= 1e9)
    m = U.sample(p, study["members"], study["seed"])
    assert m["track.pad.longitudinal_stiffness"].min() >= 1e6 and m["track.pad.rotational_stiffness"].max() <= 1e9


def test_a_member_configuration_sets_an_optional_key_the_schema_declares(defaults, root):
    schema = yaml.safe_load((root / "config/schema/config.schema.yaml").read_text())
    assert "head_height" not in defaults["track"]["rail"]  # optional: absent from the resolved default
    cfg = U.member_config(defaults, {"track.rail.head_height": 0.085, "track.pad.rotational_stiffness": 5e5}, schema)
    assert cfg["track"]["rail"]["head_height"] == 0.085 and cfg["track"]["pad"]["rotational_stiffness"] == 5e5
    with pytest.raises(ValueError, match=r"the configuration has no key track\.rail\.head_hieght"):
        U.member_config(defaults, {"track.rail.head_hieght": 0.085}, schema)
    with pytest.raises(ValueError, match=r"the configuration has no key track\.rail\.head_height"):
        U.member_config(defaults, {"track.rail.head_height": 0.085})  # without the schema: refused as before
