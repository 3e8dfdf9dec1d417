"""The mitigation study's summary (issue 55, rail.studies.mitigation): a fleet's mixture of one-wheel classes on the
same lines against its exact recursion, the band rows and verdicts, and the study file's wiring. The spectra
themselves are the workflow's (config/studies/track_mitigation.yaml; their linear method is checked against the probes in
tests/test_linear_creepage.py, the fleet's spectrum against its classes in tests/test_fleet_wheelsets.py)."""

import numpy as np
import pytest
import xarray as xr

from rail.growth_spectrum import source as src
from rail.noise.named import RoughnessSpectrum, named_spectrum
from rail.studies import mitigation as M

BAYS, L, FPP = 5, 0.6, 1069.0


def spectrum(V, g, drift=None, src_amp=None, scenario="s"):
    """A one-speed, one-wheel spectrum dataset on the lines j = 70..140 of a 5-bay period with growth rates g per
    passage (the names of rail.studies.rate_spectrum's)."""
    j = np.arange(70, 141)
    lam = BAYS * L / j
    g = np.broadcast_to(np.asarray(g, dtype=float), lam.shape)
    d = np.zeros_like(lam) if drift is None else np.broadcast_to(np.asarray(drift, dtype=float), lam.shape)
    s = np.zeros_like(lam) if src_amp is None else np.broadcast_to(np.asarray(src_amp, dtype=float), lam.shape)
    v = lambda x: (("speed", "wavelength"), np.asarray(x, dtype=float)[None, :])  # noqa: E731
    return xr.Dataset({"growth_rate": v(g), "drift": v(d), "source": v(s),
                       "growth_dB_per_1e5_axles": v(20 * np.log10(np.e) * g * 1e5),
                       "growth_dB_per_1e5_trains": v(20 * np.log10(np.e) * g * 1e5)},
                      coords={"speed": [float(V)], "wavelength": lam, "line": ("wavelength", j)},
                      attrs={"wheels": 1, "bays": BAYS, "sleeper_spacing_m": L, "pinned_pinned_Hz": FPP, "scenario": scenario})


def band_rates(V, peak, width=40.0, floor=-2e-6):
    """A growth band at ``peak`` Hz (V / wavelength), a Gaussian of ``width`` Hz of height 3e-6 per passage."""
    lam = BAYS * L / np.arange(70, 141)
    f = V / lam
    return floor + (3e-6 - floor) * np.exp(-0.5 * ((f - peak) / width) ** 2)


def test_a_mixture_is_the_weighted_sum_line_by_line_and_of_identical_parts_the_part():
    a, b = spectrum(39.0, band_rates(39.0, 1130.0), drift=1e-7), spectrum(39.0, -1e-6, drift=-2e-7)
    m = M.mixture([a, b], [0.3, 0.7])
    np.testing.assert_allclose(m.growth_rate.values, 0.3 * a.growth_rate.values + 0.7 * b.growth_rate.values, rtol=1e-15)
    np.testing.assert_allclose(m.drift.values, 0.3e-7 - 1.4e-7, rtol=1e-12)
    # Q = sum_c w_c abs(R_c)^2 P: the own rate's magnitude squared is the weighted mean of abs(R_c)^2
    np.testing.assert_allclose(m.own_rate_abs.values ** 2, 0.3 * (a.growth_rate ** 2 + a.drift ** 2).values
                               + 0.7 * (b.growth_rate ** 2 + b.drift ** 2).values, rtol=1e-12)
    same = M.mixture([a, a], [0.5, 0.5])
    np.testing.assert_allclose(same.growth_rate.values, a.growth_rate.values, rtol=1e-15)
    one = M.mixture([a, b], [1.0, 0.0])
    np.testing.assert_array_equal(one.growth_dB_per_1e5_axles.values, a.growth_dB_per_1e5_axles.values)


@pytest.mark.parametrize("weights", [[0.5, 0.6], [1.2, -0.2], [np.nan, 1.0], [1.0]])
def test_a_mixture_refuses_weights_that_are_not_shares(weights):
    a = spectrum(39.0, -1e-6)
    with pytest.raises(ValueError, match="weights"):
        M.mixture([a, a], weights)


def test_a_mixture_refuses_parts_on_other_lines_or_of_several_wheels():
    a = spectrum(39.0, -1e-6)
    other = a.assign_coords(wavelength=a.wavelength.values * 1.01)
    with pytest.raises(ValueError, match="same lines"):
        M.mixture([a, other], [0.5, 0.5])
    four = a.copy()
    four.attrs["wheels"] = 4
    with pytest.raises(ValueError, match="one-wheel"):
        M.mixture([a, four], [0.5, 0.5])


def test_the_mixtures_time_to_the_limit_follows_the_exact_fleet_recursion():
    # The fleet's expected mean square per line S_{n+1} = sum_c w_c abs(1 - R_c)^2 S_n + sum_c w_c Q_c (each passage one
    # train drawn from the classes); the mixture takes a = abs(1 - sum_c w_c R_c)^2. With rates of 1e-6 per passage the
    # two differ by O(R^2) = 1e-12 in a: the time to the limit of a growing line agrees to 1e-5, computed here from the
    # exact recursion in closed form (S_n = a^n S_0 + Q (1 - a^n) / (1 - a)) line by line.
    V = 39.0
    a = spectrum(V, band_rates(V, 1130.0), drift=3e-7, scenario="motored")
    b = spectrum(V, -0.8e-6, drift=-1e-7, scenario="trailer")
    w = np.array([0.25, 0.75])
    m = M.mixture([a, b], w)
    wheel = named_spectrum("disc", "wheel")
    R = [-(p.growth_rate.values[0] + 1j * p.drift.values[0]) for p in (a, b)]
    P = src.wheel_line_power(a.wavelength.values, BAYS * L, wheel.centres, wheel.levels)
    a_exact = sum(wc * np.abs(1 - Rc) ** 2 for wc, Rc in zip(w, R))
    Q_exact = sum(wc * np.abs(Rc) ** 2 * P for wc, Rc in zip(w, R))
    R_mix = -(m.growth_rate.values[0] + 1j * m.drift.values[0])
    # a_exact - abs(1 - R_mix)^2 = sum_c w_c abs(R_c - R_mix)^2 (the classes' variance of R), about 1e-12 here
    spread_R = sum(wc * np.abs(Rc - R_mix) ** 2 for wc, Rc in zip(w, R))
    np.testing.assert_allclose(a_exact - np.abs(1 - R_mix) ** 2, spread_R, rtol=0, atol=1e-15)
    assert spread_R.max() < 1e-11
    np.testing.assert_allclose(m.own_rate_abs.values[0] ** 2 * P, Q_exact, rtol=1e-12)
    # one growing line from S_0 to 1000 S_0: the passages by the exact recursion and by the mixture's
    i = int(np.argmax(m.growth_rate.values[0]))
    S0 = 1e-14
    for aa in (a_exact[i], np.abs(1 - R_mix[i]) ** 2):
        assert aa > 1
    n_exact = np.log((1000 * S0 + Q_exact[i] / (a_exact[i] - 1)) / (S0 + Q_exact[i] / (a_exact[i] - 1))) / np.log(a_exact[i])
    a_mix = np.abs(1 - R_mix[i]) ** 2
    n_mix = np.log((1000 * S0 + Q_exact[i] / (a_mix - 1)) / (S0 + Q_exact[i] / (a_mix - 1))) / np.log(a_mix)
    assert abs(n_mix / n_exact - 1) < 1e-5, (n_mix, n_exact)


def test_the_rows_find_the_band_and_judge_each_mitigation_against_the_default():
    V = 39.0
    spread_speeds = [V * (1 - M.SPREAD), V, V * (1 + M.SPREAD)]
    # the default track's band at 1,130 Hz at every speed (a constant frequency: at the nominal speed's wavelengths the
    # other speeds' bands lie 8 % away, so the spread's peak is about half the default's)
    parts = [spectrum(v, band_rates(v, 1130.0), scenario="default") for v in spread_speeds]
    spread = xr.concat(parts, dim="speed")
    damped = spectrum(V, band_rates(V, 1130.0) - 3.5e-6, scenario="dampers")  # nothing grows
    soft = spectrum(V, band_rates(V, 1130.0) * 1.0, scenario="soft")          # the same
    stiff = spectrum(V, band_rates(V, 1130.0) * 1.5 + 1e-6, scenario="stiff")  # grows faster
    trailer = spectrum(V, -0.5e-6, scenario="trailer")
    rows = M.mitigation_rows({V: spread}, {(V, "rail dampers"): damped, (V, "soft pad"): soft, (V, "stiff pad"): stiff,
                                           (V, "trailer"): trailer})
    by = {r["case"]: r for r in rows}
    ref = by["default track, every train at V"]
    peak_dB = 20 * np.log10(np.e) * 3e-6 * 1e5
    assert ref["verdict"] == "reference" and abs(ref["peak_Hz"] - 1130.0) < 10.0 and abs(ref["peak_dB_per_1e5_axles"] - peak_dB) < 0.02
    assert by["rail dampers"]["verdict"] == "removes the band"
    assert by["soft pad"]["verdict"] == "no change" and by["soft pad"]["change_dB_per_1e5_axles"] == 0.0
    assert by["stiff pad"]["verdict"] == "increases"
    spread_row = by[f"speed spread +-{100 * M.SPREAD:g} %"]
    # the spread's peak: the largest over the nominal speed's lines of sum_i w_i g(V_i / wavelength), the band function
    # evaluated at each speed's own frequencies
    lam = BAYS * L / np.arange(70, 141)
    mixed = sum(w * band_rates(v, 1130.0) for w, v in zip(M.SPREAD_WEIGHTS, spread_speeds))
    assert spread_row["verdict"] == "reduces"
    assert spread_row["peak_dB_per_1e5_axles"] == pytest.approx(20 * np.log10(np.e) * 1e5 * mixed.max(), abs=1e-3)
    assert abs(spread_row["peak_Hz"] - V / lam[np.argmax(mixed)]) < 1e-6 + 0.05
    # the driven shares: 100 % is the default, 0 % the trailer, the peak linear in the share between
    shares = [by[f"driven axles {100 * s:g} %"]["peak_dB_per_1e5_axles"] for s in M.SHARES]
    assert shares[-1] == ref["peak_dB_per_1e5_axles"]
    assert shares[0] < 0
    assert np.all(np.diff(shares) > 0)


def test_the_rows_refuse_a_spread_without_its_three_speeds():
    V = 60.0
    spread = xr.concat([spectrum(v, -1e-6) for v in (55.0, 60.0)], dim="speed")
    with pytest.raises(ValueError, match="speed spread at 60 m/s"):
        M.mitigation_rows({V: spread}, {})


def test_verdicts_are_signs_of_the_change_beyond_the_grids_spread():
    assert M.verdict(-0.1, 2.0) == "removes the band"
    assert M.verdict(1.0, 2.0) == "reduces"
    assert M.verdict(2.03, 2.0) == "no change"
    assert M.verdict(2.5, 2.0) == "increases"
    assert M.verdict(-1.0, -0.5) == "reduces"  # nothing grew before: a faster decay


def test_the_interval_of_a_growing_band_is_finite_and_of_a_decaying_one_set_by_the_source():
    # from the ground rail (class E) to a limit 10 dB above it: a band growing 2.6 dB per 100,000 axles crosses it;
    # a line decaying at 1e-6 per passage under disc-braked wheels settles far below it (never)
    V = 39.0
    ground = named_spectrum("E", "rail")
    limit = RoughnessSpectrum(ground.centres, ground.levels + 10.0, "E + 10 dB")
    spectra = {"wheel": named_spectrum("disc", "wheel"), "ground": ground, "limit": limit}
    grow = M.interval(spectrum(V, band_rates(V, 1130.0)), spectra, axles_per_day=20000.0)
    decay = M.interval(spectrum(V, -1e-6), spectra, axles_per_day=20000.0)
    # the fastest line grows at 3e-6 per passage: its band (of several lines) needs at least the line's own time,
    # 10 dB / (20 log10(e) 3e-6) passages
    assert np.isfinite(grow["interval_axles"]) and grow["interval_axles"] >= 10 / (20 * np.log10(np.e) * 3e-6) * 0.999
    assert grow["interval_years"] == pytest.approx(grow["interval_axles"] / (365 * 20000.0), rel=1e-12)
    assert np.isinf(decay["interval_axles"]) and np.isnan(decay["interval_band_mm"])
    assert np.isinf(grow["settled_peak_band_dB"]) and np.isfinite(decay["settled_peak_band_dB"])


def test_a_spread_cases_union_of_lines_and_a_one_speed_case_mix_on_their_common_lines():
    # the spread case's spectrum holds the lines of three speeds' bands (a union); a one-speed case of the same period
    # holds the nominal speed's alone, a subset: the driven share mixes them there, line by line
    wide = spectrum(39.0, band_rates(39.0, 1130.0))
    narrow = wide.isel(wavelength=slice(10, 40))
    a, b = M.on_common_lines(wide, narrow)
    np.testing.assert_array_equal(a.line.values, narrow.line.values)
    np.testing.assert_array_equal(a.growth_rate.values, narrow.growth_rate.values)
    with pytest.raises(ValueError, match="same lines"):
        M.mixture([wide, narrow], [0.5, 0.5])
    other = narrow.copy()
    other.attrs["bays"] = 8
    with pytest.raises(ValueError, match="different periods"):
        M.on_common_lines(wide, other)


def test_the_rows_dataset_carries_units_and_long_names_on_every_variable():
    V = 39.0
    spread = xr.concat([spectrum(v, band_rates(v, 1130.0)) for v in (V * (1 - M.SPREAD), V, V * (1 + M.SPREAD))], dim="speed")
    ds = M.rows_dataset(M.mitigation_rows({V: spread}, {}))
    for name in list(ds.data_vars) + list(ds.coords):
        assert ds[name].attrs.get("units") and ds[name].attrs.get("long_name"), name
