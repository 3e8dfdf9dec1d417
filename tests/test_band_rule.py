"""One-third-octave bands have one home and one rule (rail.bands, issue 46): IEC 61260-1 base-ten
edges in frequency and wavelength, the same bands under lambda = V / f, a partition of the axis,
nominal labels inside their bands, and the rule's source stated."""

import numpy as np
import pytest

from rail import bands, decay, roughness
from rail.studies import bands as band_view
from rail.studies import exports

# rounding: a centre or edge is one power of ten (correctly rounded, 0.5 ulp) times at most one
# product or quotient; two such numbers agree to a few ulp, 1e-15 relative; 1e-14 leaves margin
RTOL_ROUNDING = 1e-14


def test_exact_edges_are_the_iec_61260_base_ten_values():
    # IEC 61260-1's exact base-ten mid-band and band-edge frequencies, to the 6 figures the
    # standard's tables print: 1000 Hz (891.251, 1122.02 Hz) and 100 Hz (89.1251, 112.202 Hz)
    f = bands.frequency_bands(100, 1000)
    assert f.unit == "Hz" and f.nominal[0] == 100 and f.nominal[-1] == 1000
    np.testing.assert_allclose([f.lower[0], f.centre[0], f.upper[0]], [89.1251, 100.0, 112.202], rtol=5e-6)
    np.testing.assert_allclose([f.lower[-1], f.centre[-1], f.upper[-1]], [891.251, 1000.0, 1122.02], rtol=5e-6)
    # in wavelength, the EN 15610 band 0.315 m: exact centre 10^(-1/2) m = 0.316228 m, edges
    # 10^(-0.55) m = 0.281838 m and 10^(-0.45) m = 0.354813 m
    w = bands.wavelength_bands(0.315, 0.315)
    assert w.unit == "m" and w.nominal[0] == 0.315
    np.testing.assert_allclose([w.lower[0], w.centre[0], w.upper[0]], [0.281838, 0.316228, 0.354813], rtol=5e-6)


def test_a_frequency_band_at_speed_v_is_the_wavelength_band_v_over_f():
    # at V = 100 m/s the frequency bands 100 Hz .. 5 kHz are the wavelength bands 1 m .. 20 mm, band
    # for band: centre_lambda = V / centre_f, lower_lambda = V / upper_f, upper_lambda = V / lower_f
    V = 100.0
    f = bands.frequency_bands(100, 5000)
    w = bands.wavelength_bands(1.0, 0.02)
    assert len(f.centre) == len(w.centre) == 18
    np.testing.assert_allclose(w.centre, V / f.centre, rtol=RTOL_ROUNDING)
    np.testing.assert_allclose(w.lower, V / f.upper, rtol=RTOL_ROUNDING)
    np.testing.assert_allclose(w.upper, V / f.lower, rtol=RTOL_ROUNDING)
    # the nominal labels name the same band both ways (100 / 160 Hz = 0.625 m is the 0.63 m band)
    assert [bands.nominal_band(V / x) for x in f.nominal] == [bands.nominal_band(x) for x in w.nominal]
    # at any speed the rule maps onto itself: the band at f Hz seen at 40 m/s has the edges
    # (V / f) 10^(-+1/20) of a wavelength band centred on V / f
    V = 40.0
    np.testing.assert_allclose(V / f.upper, V / f.centre * 10 ** (-1 / 20), rtol=RTOL_ROUNDING)
    np.testing.assert_allclose(V / f.lower, V / f.centre * 10 ** (1 / 20), rtol=RTOL_ROUNDING)
    # and a spectrum written at the centres V / f with V = 100 m/s gets these edges (third_octave_edges)
    lo, hi = bands.third_octave_edges(100.0 / f.centre)
    np.testing.assert_allclose(lo, 100.0 / f.upper, rtol=RTOL_ROUNDING)
    np.testing.assert_allclose(hi, 100.0 / f.lower, rtol=RTOL_ROUNDING)


@pytest.mark.parametrize("which", ["wavelength", "frequency", "rolling noise"])
def test_adjacent_bands_share_their_edges_exactly(which):
    b = {"wavelength": bands.wavelength_bands(), "frequency": bands.frequency_bands(1, 1e6),
         "rolling noise": exports.rolling_noise_bands()}[which]
    if b.unit == "m":  # longest first
        assert np.array_equal(b.upper[1:], b.lower[:-1])
    else:  # lowest first
        assert np.array_equal(b.lower[1:], b.upper[:-1])
    assert np.all(b.lower < b.centre) and np.all(b.centre < b.upper)


def test_every_wavelength_lies_in_exactly_one_band_and_an_edge_in_the_shorter():
    b = bands.wavelength_bands()
    lam = np.concatenate([np.geomspace(b.lower.min() * 1.0001, b.upper.max(), 5001), b.lower[:-1]])
    count = sum(bands.in_band(lam, lo, hi).astype(int) for lo, hi in zip(b.lower, b.upper))
    assert np.all(count == 1)
    # the edge between the 0.1 m and 0.08 m bands belongs to the 0.08 m band
    k = int(np.flatnonzero(b.nominal == 0.1)[0])
    edge = b.lower[k]
    assert not bands.in_band(edge, b.lower[k], b.upper[k]) and bands.in_band(edge, b.lower[k + 1], b.upper[k + 1])
    # the edges of the nominal labels are the bands' (synthesis and analysis use the same edges)
    lo, hi = bands.third_octave_edges(bands.NOMINAL_WAVELENGTHS_M)
    assert np.array_equal(lo, b.lower) and np.array_equal(hi, b.upper)


@pytest.mark.parametrize("which", ["wavelength", "frequency", "rolling noise"])
def test_every_nominal_label_lies_in_its_band_within_the_tolerance_of_its_exact_centre(which):
    b = {"wavelength": bands.wavelength_bands(), "frequency": bands.frequency_bands(1, 1e6),
         "rolling noise": exports.rolling_noise_bands()}[which]
    assert np.all((b.lower < b.nominal) & (b.nominal <= b.upper))
    off = np.abs(b.nominal / b.centre - 1)
    assert off.max() <= bands.NOMINAL_TOLERANCE
    # the labels are at most 0.95 % from their exact centres (160 Hz against 158.49 Hz; 0.63 m
    # against 0.631 m is 0.2 %): the tolerance 1.5 % holds them, and the neighbours 26 % away do not
    assert off.max() < 0.0096
    if which == "wavelength":
        assert [bands.nominal_band(x) for x in b.nominal] == list(range(len(b.nominal)))


def test_the_edge_rule_states_its_source():
    for ref in ("IEC 61260-1", "EN 15610", "EN ISO 3095", "10^(-+1/20)", "lower < lam <= upper"):
        assert ref in bands.__doc__, ref
    assert "IEC 61260-1" in bands.exact_edges.__doc__


def test_the_old_names_are_the_one_home():
    assert decay.ThirdOctaveBands is band_view.ThirdOctaveBands is bands.ThirdOctaveBands
    assert decay.third_octave_bands is bands.frequency_bands and band_view.third_octave_bands is bands.wavelength_bands
    assert decay.NOMINAL_THIRD_OCTAVE_CENTRES is bands.NOMINAL_THIRD_OCTAVE_CENTRES
    for name in ("NOMINAL_WAVELENGTHS_M", "NOMINAL_TOLERANCE", "nominal_band", "band_edges", "third_octave_edges", "in_band"):
        assert getattr(roughness, name) is getattr(bands, name), name


def test_bands_are_built_by_keyword_and_say_their_unit():
    c = np.array([1.0])
    with pytest.raises(TypeError):
        bands.ThirdOctaveBands(c, c, c, c, "m")
    with pytest.raises(ValueError, match=r"unit = 'mm' is not allowed: it must be 'Hz' \(frequency bands\) or 'm'"):
        bands.ThirdOctaveBands(centre=c, nominal=c, lower=c, upper=c, unit="mm")
    with pytest.raises(ValueError, match=r"unit = 'rad/m' is not allowed"):
        bands.exact_edges([0], "rad/m")
    sub = bands.wavelength_bands().select(slice(2, 4))
    assert sub.unit == "m" and list(sub.nominal) == [0.63, 0.5]
