"""rail.growth_spectrum.band: band_edges on synthetic spectra whose band's edges are known, and class_pair_spectrum
against rate_spectrum on every line at once (issue 54)."""

import numpy as np
import pytest

from test_linear_creepage import case

from rail import growth_spectrum as GS
from rail.growth_spectrum.band import band_edges, class_pair_spectrum


def tent(f, f0, peak, half_base):
    """A band whose rate is linear in f on either side of f0 (so linear interpolation between lines is exact) on a floor of -1."""
    return np.maximum(peak * (1 - np.abs(f - f0) / half_base), -1.0)


def test_edges_of_a_piecewise_linear_band_are_exact_between_any_lines():
    # lines 7 Hz apart, one on the peak; the rate crosses 0 at 1,080 and 1,160 Hz and half its peak at 1,100 and 1,140 Hz
    f = 1120.0 + 7.0 * np.arange(-20, 21)
    b = band_edges(f, tent(f, 1120.0, 2.0, 40.0))
    assert (b.peak_frequency, b.peak_rate) == (1120.0, 2.0)
    assert b.low == pytest.approx(1080.0, abs=1e-9) and b.high == pytest.approx(1160.0, abs=1e-9)
    assert b.half_low == pytest.approx(1100.0, abs=1e-9) and b.half_high == pytest.approx(1140.0, abs=1e-9)
    assert b.width == pytest.approx(80.0, abs=1e-9) and b.half_width == pytest.approx(40.0, abs=1e-9)
    assert b.lines_growing == 11  # 1,085 ... 1,155 Hz
    assert b.spacing == pytest.approx(7.0)


def test_edges_of_a_smooth_band_fall_within_a_small_part_of_the_spacing_and_converge():
    # g = 2 - ((f - 1118) / 25)^2: zero edges at 1118 -+ 25 sqrt(2) Hz, half-peak edges at 1118 -+ 25 Hz
    exact = np.array([1118 - 25 * np.sqrt(2), 1118 + 25 * np.sqrt(2), 1093.0, 1143.0])
    errs = []
    for df in (15.0, 7.5, 3.75):
        f = np.arange(900.0, 1400.0, df) + 0.37 * df
        b = band_edges(f, 2 - ((f - 1118.0) / 25.0) ** 2)
        err = np.abs(np.array([b.low, b.high, b.half_low, b.half_high]) - exact)
        assert np.all(err < 0.25 * df), (df, err)
        errs.append(err.max())
    assert errs[2] < errs[0] / 8  # linear interpolation of a smooth rate: error O(df^2)


def test_a_spectrum_that_does_not_grow_has_no_edges():
    f = np.linspace(1000.0, 1300.0, 21)
    b = band_edges(f, -1.0 - ((f - 1150.0) / 100.0) ** 2)
    assert b.peak_frequency == 1150.0 and b.peak_rate == -1.0
    assert np.isnan([b.low, b.high, b.half_low, b.half_high, b.width]).all() and b.lines_growing == 0


def test_an_edge_beyond_the_last_line_is_not_known_and_the_other_is():
    f = np.linspace(1000.0, 1200.0, 21)  # 10 Hz apart; the band runs on above 1,200 Hz
    b = band_edges(f, (f - 1100.0) / 50.0)
    assert b.peak_frequency == 1200.0 and np.isnan(b.high) and np.isnan(b.half_high)
    assert b.low == pytest.approx(1100.0) and b.half_low == pytest.approx(1150.0)


def test_the_window_picks_one_of_two_bands_and_the_order_of_the_lines_does_not_matter():
    f = np.arange(200.0, 1400.0, 10.0)
    g = tent(f, 300.0, 5.0, 30.0) + 1.0 + tent(f, 1120.0, 2.0, 40.0)  # a faster band at 300 Hz
    assert band_edges(f, g).peak_frequency == 300.0
    rng = np.random.default_rng(1)
    p = rng.permutation(f.size)
    b = band_edges(f[p], g[p], low=900.0, high=1400.0)
    assert b.peak_frequency == 1120.0 and b.low == pytest.approx(1080.0) and b.high == pytest.approx(1160.0)


@pytest.mark.parametrize("f, g, kw, words", [
    ([1000.0, np.nan], [1.0, 2.0], {}, "frequency"),
    ([1000.0, -5.0], [1.0, 2.0], {}, "frequency"),
    ([1000.0, 1000.0], [1.0, 2.0], {}, "repeated"),
    ([1000.0, 1010.0], [1.0], {}, "rate"),
    ([1000.0, 1010.0], [1.0, np.inf], {}, "rate"),
    ([1000.0, 1010.0], [1.0, 2.0], {"low": 1200.0, "high": 1100.0}, "low"),
    ([1000.0, 1010.0], [1.0, 2.0], {"low": 1100.0, "high": 1200.0}, "holds no line"),
])
def test_bad_input_is_refused_naming_it(f, g, kw, words):
    with pytest.raises(ValueError, match=words):
        band_edges(f, g, **kw)


def test_a_spectrum_one_class_pair_at_a_time_is_the_spectrum_of_every_line_at_once():
    """The motored wheelset on a 4-bay period (the tests' track, K = 24, 31 nodes): free lines of classes 1 and 3
    (one pair) and the comb (class 0, with the wheelset's torque balance); the classes do not couple, so each line's
    rate is the same whichever lines share its call, to the probes' march inputs' own nonlinearity: those are
    differenced with and without 1 nm probes, one line of each class pair per batch, so the lines sharing a batch
    change with the call, by O(eps / roughness scale) (measured 7e-9 of the largest rate; allowed 1e-7)."""
    scn, tabs = case("motored", bays=4)
    lines = [21, 23, 24]
    every = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1)
    told = []
    pairs = class_pair_spectrum(scn, tabs, lines[::-1], grid_phases=1, check_lines=1, progress=told.append)
    assert [t.split(":")[0] for t in told if t.startswith("class pair")] == ["class pair (0, 0) of 4 bays", "class pair (1, 3) of 4 bays"]
    assert np.array_equal(pairs.line, every.line) and np.array_equal(pairs.locked, every.locked)
    big = np.abs(every.rate).max()
    for name in ("rate", "rate_other"):
        assert np.abs(getattr(pairs, name) - getattr(every, name)).max() < 1e-7 * big, name
    assert np.allclose(pairs.wavelength, every.wavelength, rtol=0, atol=0) and np.allclose(pairs.source, every.source, rtol=1e-7, atol=0)
    assert np.abs(pairs.operator - every.operator).max() < 1e-7 * big
    # the linearity check, with dynamic creepage on more than 2 bays made on the 2-bay period (the march over N bays
    # needs the rail head's tables of every class): the same order as the N-bay check's, both far inside the linear range
    print(f"linearity: {every.linearity:.2e} on the 4-bay check, {pairs.linearity:.2e} on the 2-bay period")
    assert "2-bay period" in pairs.method and "2-bay period" not in every.method
    assert 0 < pairs.linearity < 1e-2 and 0 < every.linearity < 1e-2


def test_a_studys_spectrum_with_dynamic_creepage_on_more_than_two_bays_runs_one_class_pair_at_a_time(monkeypatch):
    """rail.studies.rate_spectrum.spectrum_with_settings (the workflow's, the command line's and the API's spectrum)
    takes class_pair_spectrum where the linear method with dynamic creepage would march every class's u_bar basis at
    once (measured over 10 GB on 8 bays at 40 m/s); on 2 bays, and with fixed creepage, rate_spectrum as before."""
    import dataclasses

    from rail.studies import rate_spectrum as RS

    calls = []
    monkeypatch.setattr(RS, "class_pair_spectrum", lambda *a, **k: calls.append("pairs"))
    monkeypatch.setattr(RS, "rate_spectrum", lambda *a, **k: calls.append("all"))
    s = {"shortest": 0.03, "longest": 0.06, "per_octave": 3, "eps": 1e-9, "grid_phases": 1}
    scn, tabs = case("motored", bays=4)
    RS.spectrum_with_settings(scn, tabs, s)
    RS.spectrum_with_settings(dataclasses.replace(scn, material=dataclasses.replace(scn.material, longitudinal=None)), tabs, s)
    scn2, tabs2 = case("motored", bays=2)
    RS.spectrum_with_settings(scn2, tabs2, s)
    assert calls == ["pairs", "all", "all"]
