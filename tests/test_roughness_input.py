"""Initial roughness at any wavelength: a measured profile and a one-third-octave spectrum over a
period of N bays (rail.roughness), with errors that name the file and the line."""

import re

import numpy as np
import pytest

from rail import roughness as R
from rail.interaction import Roughness
from rail.scenario import InitialRoughness

L = 0.6


def _write(path, text):
    path.write_text(text)
    return path


def test_profile_sinusoid_and_slope_give_the_exact_coefficient(tmp_path):
    # a 45 mm sinusoid does not fit one bay but fits 4 bays (2.4 m = 53.33 wavelengths: no) -
    # take 48 mm = 2.4 m / 50: harmonic j = 50 of the 4-bay period; 6 um amplitude plus a mean slope
    # of 5 um/m, sampled at 1 mm over 3 m. The slope is removed, the sinusoid is exact.
    x = np.arange(0.0, 3.0001, 0.001)
    z = 6e-6 * np.sin(2 * np.pi * x / 0.048) + 5e-6 * x
    p = _write(tmp_path / "p.csv", "position_m,height_m\n" + "".join(f"{a:.4f},{b:.6e}\n" for a, b in zip(x, z)))
    xr, zr = R.read_profile(p)
    J = 4 * 32
    Z = R.profile_coefficients(xr, zr, 4 * L, J)
    assert 2 * abs(Z[J + 50]) == pytest.approx(6e-6, rel=3e-3)  # linear resampling of 1 mm data
    assert np.angle(Z[J + 50]) == pytest.approx(-np.pi / 2, abs=3e-3)  # sin: Z = A / (2 i)
    others = np.delete(np.abs(Z), [J - 50, J + 50])
    assert others.max() < 2e-3 * 6e-6


def test_short_profile_warns_and_repeats(tmp_path):
    x = np.arange(0.0, 1.2001, 0.001)  # 1.2 m, shorter than 4 bays
    z = 3e-6 * np.cos(2 * np.pi * x / 0.04)
    p = _write(tmp_path / "p.csv", "position_m,height_m\n" + "".join(f"{a:.4f},{b:.6e}\n" for a, b in zip(x, z)))
    xr, zr = R.read_profile(p)
    with pytest.warns(R.RoughnessInputWarning, match=r"shorter than the roughness period N L = 2\.4 m; .* repeated 2 times"):
        Z = R.profile_coefficients(xr, zr, 4 * L, 4 * 32, source=str(p))
    J = 4 * 32
    assert 2 * abs(Z[J + 60]) == pytest.approx(3e-6, rel=3e-3)  # 0.04 m = 2.4 m / 60


@pytest.mark.parametrize(
    "text, message",
    [
        ("x,z\n0,1\n1,2\n", r"line 1: the header must be 'position_m,height_m' \(got x,z\)"),
        ("position_m,height_m\n0,1e-6\n0.001,abc\n", r"line 3: '0\.001,abc' is not two numbers"),
        ("position_m,height_m\n0,1e-6\n0.002,1e-6\n0.001,1e-6\n", r"line 4: position 0\.001 m does not increase"),
        ("position_m,height_m\n0,1e-6\n0.001,nan\n", r"line 3: '0\.001,nan' is not finite"),
        ("position_m,height_m\n0,1e-6\n", r"needs at least two data lines, has 1"),
    ],
)
def test_profile_reader_names_file_line_and_problem(tmp_path, text, message):
    p = _write(tmp_path / "bad.csv", text)
    with pytest.raises(ValueError, match=re_escape_path(p) + ".*" + message if "line" in message else message):
        R.read_profile(p)


def re_escape_path(p):
    import re

    return re.escape(str(p))


def test_spectrum_realisation_has_exactly_the_band_levels(tmp_path):
    # bands 0.5 m to 16 mm over 16 bays: every band's mean square (sum of 2 |Z_j|^2 over its
    # wavenumbers) is the level's, the profile's mean square is their sum (Parseval), and the
    # seed changes the phases only
    lam = np.array([0.5, 0.4, 0.315, 0.25, 0.2, 0.16, 0.125, 0.1, 0.08, 0.063, 0.05, 0.04, 0.0315, 0.025, 0.02, 0.016])
    lev = np.linspace(12.0, -6.0, lam.size)
    P, J = 16 * L, 16 * 64
    Z1 = R.spectrum_coefficients(lam, lev, P, J, seed=1)
    Z2 = R.spectrum_coefficients(lam, lev, P, J, seed=2)
    j = np.arange(1, J + 1)
    lo, hi = R.third_octave_edges(lam)  # the nominal centres name the exact bands 10^(-n/10) m (issue 45)
    np.testing.assert_allclose(hi[1:], lo[:-1], rtol=1e-14)  # the bands partition the wavelength axis
    assert hi[0] / 0.5012 == pytest.approx(10 ** (1 / 20), rel=1e-4) and 0.01585 / lo[-1] == pytest.approx(10 ** (1 / 20), rel=1e-3)
    for lc, lv, a, b in zip(lam, lev, lo, hi):
        inside = R.in_band(P / j, a, b)
        ms = 2 * np.sum(np.abs(Z1[J + j[inside]]) ** 2)
        assert 10 * np.log10(ms / 1e-12) == pytest.approx(lv, abs=1e-9)
    x = np.linspace(0.0, P, 8 * J, endpoint=False)
    z = Roughness(Z1, 16).profile(x, L)
    assert np.mean(z**2) == pytest.approx(np.sum((1e-6 * 10 ** (lev / 20)) ** 2), rel=1e-9)
    np.testing.assert_allclose(np.abs(Z1), np.abs(Z2), rtol=1e-12)
    assert np.abs(Z1 - Z2).max() > 0.1 * np.abs(Z1).max()
    np.testing.assert_array_equal(Z1, R.spectrum_coefficients(lam, lev, P, J, seed=1))
    np.testing.assert_allclose(Z1[:J], np.conj(Z1[J + 1 :][::-1]))


def test_bands_the_period_cannot_hold_are_named(tmp_path):
    with pytest.warns(R.RoughnessInputWarning, match=r"the bands 2 m, 0\.008 m hold no wavenumber"):
        R.spectrum_coefficients(np.array([2.0, 0.1, 0.008]), np.array([0.0, 0.0, 0.0]), 4 * L, 4 * 64, seed=0)


@pytest.mark.parametrize(
    "text, message",
    [
        ("lambda,L\n0.1,3\n0.2,4\n", r"line 1: the header must be 'wavelength_m,level_dB'"),
        ("wavelength_m,level_dB\n0.1,3\n-0.2,4\n", r"line 3: wavelength -0\.2 m is not allowed: it must be > 0"),
        ("wavelength_m,level_dB\n0.1,3\n0.1,4\n", r"line 3: wavelength 0\.1 m appears twice"),
        ("wavelength_m,level_dB\n0.1,3\n0.2\n", r"line 3: expected 2 values"),
    ],
)
def test_spectrum_reader_names_file_line_and_problem(tmp_path, text, message):
    p = _write(tmp_path / "bad.csv", text)
    with pytest.raises(ValueError, match=message):
        R.read_third_octave_spectrum(p)


def test_initial_roughness_kinds_realise_over_n_bays(tmp_path, root):
    spec = InitialRoughness("spectrum", 0.0, 1000.0, None, str(root / "config/roughness/example_spectrum.csv"), bays=16, seed=3)
    r = spec.realise(40.0, L, 64)
    assert r.bays == 16 and r.harmonics == 16 * 64
    prof = InitialRoughness("profile", 0.0, 1000.0, None, str(root / "config/roughness/synthetic_profile.csv"), bays=4)
    z = prof.realise(40.0, L, 64)
    # the synthetic profile's 45 mm corrugation (2.4 m / 53.3, between the lines j = 53 and 54)
    # and its 15 um, 0.3 m wave (j = 8) are there
    lev = 20 * np.log10(np.sqrt(2) * np.abs(z.Z[z.harmonics + 1 :]) / 1e-6)
    assert lev[7] == pytest.approx(20 * np.log10(15 / np.sqrt(2)), abs=0.5)
    assert max(lev[52], lev[53]) > 10.0
    with pytest.raises(ValueError, match=r"roughness\.kind = 'profile' needs roughness\.file, a CSV with header position_m,height_m"):
        InitialRoughness("profile", 0.0, 1000.0, None, None)


# issue 32, item 5: inputs in the wrong unit are refused when read, naming the likely unit


def test_profile_positions_in_millimetres_are_refused(tmp_path):
    # the synthetic 3 m record at 1 mm steps written in mm: 0 .. 3000 at steps of 1 "m"
    x = np.arange(0, 3001)
    p = _write(tmp_path / "mm.csv", "position_m,height_m\n" + "".join(f"{a},1e-6\n" for a in x))
    with pytest.raises(ValueError, match=re_escape_path(p) + r": the positions look like millimetres: the median sample "
                                         r"spacing is 1 m, .* \(at most 0\.05 m allowed\)"):
        R.read_profile(p)


def test_profile_record_longer_than_1000_m_is_refused_as_millimetres(tmp_path):
    # 1.2 m written in mm at 0.04 mm steps: the spacing passes, the 1200 "m" record does not
    x = np.arange(0, 30001) * 0.04
    p = _write(tmp_path / "mm.csv", "position_m,height_m\n" + "".join(f"{a:.2f},1e-6\n" for a in x))
    with pytest.raises(ValueError, match=re_escape_path(p) + r", line 30002: the positions look like millimetres: the record "
                                         r"is 1200 m long \(at most 1000 m allowed; in mm it would be 1\.2 m\)"):
        R.read_profile(p)


def test_spectrum_wavelengths_in_millimetres_are_refused(tmp_path):
    # EN 15610 centres 1 m .. 3.15 mm written in mm: before, every band was dropped (a smooth rail)
    # with a warning only
    lam = [1000, 800, 630, 500, 400, 315, 250, 200, 160, 125, 100, 80, 63, 50, 40, 31.5, 25, 20, 16, 12.5, 10, 8, 6.3, 5,
           4, 3.15]
    p = _write(tmp_path / "mm.csv", "wavelength_m,level_dB\n" + "".join(f"{v},0\n" for v in lam))
    with pytest.raises(ValueError, match=re_escape_path(p) + r", line 2: wavelength 1000 m is not allowed: it looks like "
                                         r"millimetres \(1 m\); rail roughness wavelengths lie between 1 mm and 10 m"):
        R.read_third_octave_spectrum(p)
    q = _write(tmp_path / "um.csv", "wavelength_m,level_dB\n0.01,0\n0.0005,0\n")
    with pytest.raises(ValueError, match=re_escape_path(q) + r", line 3: wavelength 0\.0005 m is not allowed: rail roughness "
                                         r"wavelengths lie between 1 mm and 10 m"):
        R.read_third_octave_spectrum(q)


def test_spectrum_no_band_of_which_the_period_holds_is_refused():
    # 2 m is longer than the 2.4 m period's line j = 1 band allows, 8 mm shorter than 2.4 m / 256:
    # the realisation would be a smooth rail
    with pytest.raises(ValueError, match=r"s\.csv: no band of the spectrum \(2 m \.\. 0\.008 m\) holds a wavenumber 2 pi j / \(N L\) "
                                         r"of the period N L = 2\.4 m with j <= 256 .*: the rail would be smooth"):
        R.spectrum_coefficients(np.array([2.0, 0.008]), np.array([0.0, 0.0]), 4 * L, 4 * 64, seed=0, source="s.csv")


def test_shipped_roughness_examples_pass_the_unit_checks(root):
    x, _ = R.read_profile(root / "config/roughness/synthetic_profile.csv")
    assert x[-1] == pytest.approx(3.0)
    assert len(R.read_third_octave_spectrum(root / "config/roughness/example_spectrum.csv")[0]) == 19
    for name in ("example_limit.csv", "example_limit_minus10.csv"):
        lam, _ = R.read_limit_spectrum(root / "config/roughness" / name)
        assert lam[0] == 1.0 and lam[-1] == 0.00315 and len(lam) == 26


# issue 36 (part B): units read from the header, the whole measured record, spike removal, the
# longest resolved band (docs/roughness-input.md)


def _profile_text(header, x, z):
    return header + "\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(x, z))


@pytest.mark.parametrize("header, fx, fz", [
    ("position_cm,height_mm", 100.0, 1e3),
    ("position [mm],roughness [µm]", 1e3, 1e6),
    ("distance (mm), height [um]", 1e3, 1e6),
    ("Position_MM,displacement_\u03bcm", 1e3, 1e6),
    (" position [cm] , height [m] ", 100.0, 1.0),
])
def test_profile_in_cm_mm_and_um_gives_the_roughness_of_the_si_file(tmp_path, header, fx, fz):
    # the same 3 m record written in metres and in the units practice writes: the positions,
    # heights and the coefficients over 4 bays agree to rounding, and the units are stated back
    rng = np.random.default_rng(36)
    x = np.arange(0.0, 3.0005, 0.001)
    z = 6e-6 * np.sin(2 * np.pi * x / 0.048) + 1e-6 * rng.standard_normal(x.size)
    si = _write(tmp_path / "si.csv", _profile_text("position_m,height_m", x, z))
    other = _write(tmp_path / "other.csv", _profile_text(header, x * fx, z * fz))
    a, b = R.read_profile_record(si), R.read_profile_record(other)
    np.testing.assert_allclose(b.x, a.x, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(b.z, a.z, rtol=1e-12, atol=1e-21)
    J = 4 * 32
    Za, Zb = R.profile_coefficients(a.x, a.z, 4 * L, J), R.profile_coefficients(b.x, b.z, 4 * L, J)
    np.testing.assert_allclose(Zb, Za, rtol=0, atol=1e-12 * np.abs(Za).max())
    ux, uz = (split.strip() for split in header.split(","))
    unit_x = {100.0: "cm", 1e3: "mm"}[fx]
    unit_z = {1e3: "mm", 1e6: "µm", 1.0: "m"}[fz]
    assert b.units == (unit_x, unit_z)
    said = b.describe()
    assert f"position in {unit_x}, height in {unit_z}, {x.size} rows" in said and "record 3 m" in said


@pytest.mark.parametrize("header, fl, to_level", [
    ("wavelength_cm,level_dB", 100.0, lambda d: d),
    ("wavelength [mm],level [dB re 1 µm]", 1e3, lambda d: d),
    ("wavelength_m,level_um", 1.0, lambda d: 10 ** (d / 20)),
    ("wavelength (cm), level [µm]", 100.0, lambda d: 10 ** (d / 20)),
])
def test_spectrum_in_cm_mm_and_um_gives_the_roughness_of_the_si_file(tmp_path, header, fl, to_level):
    # EN 15610 / ISO 3095 tables in cm and µm: the same band levels as the file in m and dB (a level
    # in µm is the band's rms roughness, 20 log10(level / 1 µm) dB), so the same realisation
    lam = np.array([0.5, 0.4, 0.315, 0.25, 0.2, 0.16, 0.125, 0.1, 0.08, 0.063, 0.05, 0.04, 0.0315, 0.025, 0.02, 0.016])
    lev = np.linspace(12.0, -6.0, lam.size)
    si = _write(tmp_path / "si.csv", "wavelength_m,level_dB\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(lam, lev)))
    other = _write(tmp_path / "other.csv", header + "\n" + "".join(f"{float(a * fl)!r},{float(to_level(b))!r}\n" for a, b in zip(lam, lev)))
    a, b = R.read_spectrum_table(si), R.read_spectrum_table(other)
    np.testing.assert_allclose(b.wavelength, a.wavelength, rtol=1e-12)
    np.testing.assert_allclose(b.level_dB, a.level_dB, rtol=0, atol=1e-9)
    P, J = 16 * L, 16 * 64
    np.testing.assert_allclose(R.spectrum_coefficients(b.wavelength, b.level_dB, P, J, seed=1),
                               R.spectrum_coefficients(a.wavelength, a.level_dB, P, J, seed=1), rtol=0, atol=1e-15)
    assert f"{lam.size} rows" in b.describe() and f"wavelength in {b.units[0]}" in b.describe()


@pytest.mark.parametrize("reader, text, message", [
    ("profile", "position_in,height_m\n0,0\n1,0\n",
     r"line 1, column 1 \('position_in'\): the unit 'in' is not accepted for position: it must be one of m, cm, mm"),
    ("profile", "position,height_m\n0,0\n1,0\n",
     r"line 1, column 1 \('position'\): no unit: write position_<unit> or 'position \[<unit>\]' with <unit> one of m, cm, mm"),
    ("profile", "position_mm,height_cm\n0,0\n1,0\n",
     r"line 1, column 2 \('height_cm'\): the unit 'cm' is not accepted for height: it must be one of m, mm, µm \(or um\)"),
    ("spectrum", "wavelength_m,level\n0.1,0\n0.05,0\n",
     r"line 1, column 2 \('level'\): no unit: .* one of dB \(re 1 µm\), µm \(or um\)"),
    ("spectrum", "wavelength [ft],level_dB\n0.1,0\n0.05,0\n",
     r"line 1, column 1 \('wavelength \[ft\]'\): the unit 'ft' is not accepted for wavelength: it must be one of m, cm, mm"),
    ("spectrum", "wavelength_m,level [dB re 20 µPa]\n0.1,0\n0.05,0\n",
     r"line 1, column 2 \('level \[dB re 20 µPa\]'\): the unit 'dB re 20 µPa' is not accepted for level"),
])
def test_a_missing_or_unknown_unit_names_the_file_the_column_and_the_accepted_units(tmp_path, reader, text, message):
    p = _write(tmp_path / "bad.csv", text)
    read = R.read_profile if reader == "profile" else R.read_third_octave_spectrum
    with pytest.raises(ValueError, match=re_escape_path(p) + ", " + message):
        read(p)


def test_a_level_in_um_that_is_not_positive_is_refused(tmp_path):
    p = _write(tmp_path / "bad.csv", "wavelength_cm,level_um\n10,1.5\n5,0\n")
    with pytest.raises(ValueError, match=re_escape_path(p) + r", line 3: level 0 µm is not allowed: an rms level in µm must be > 0"):
        R.read_third_octave_spectrum(p)


def test_a_bad_unit_stops_the_scenario_at_load_before_any_job(tmp_path):
    # the start-up path the workflow, railgrowth and the API share (rail.setup.inputs.check_inputs)
    from rail.app import api
    from rail.setup.config import ConfigError

    bad = _write(tmp_path / "bad.csv", "position [in],height [µm]\n0,0\n0.04,1\n")
    with pytest.raises(ConfigError, match=r"scenario profile_example \(.*\): roughness: " + re_escape_path(bad)
                                          + r", line 1, column 1 \('position \[in\]'\): the unit 'in' is not accepted"):
        api.load("profile_example", changes={"roughness": {"file": str(bad)}})


def _band_levels(Z, J, period):
    """Band levels [dB re 1 µm] of coefficients over exact one-third-octave bands 10^(-n/10) m,
    edges 10^(-(n -+ 1/2)/10) m (written here, not taken from rail.roughness)."""
    j = np.arange(1, J + 1)
    lam_j = period / j
    ms = 2 * np.abs(Z[J + 1:]) ** 2
    out = {}
    for n in range(2, 22):  # 0.63 m .. 6.3 mm
        inside = (lam_j < 10 ** (-(n - 0.5) / 10)) & (lam_j >= 10 ** (-(n + 0.5) / 10))
        if inside.any():
            out[n] = 10 * np.log10(ms[inside].sum() / 1e-12)
    return out


def test_a_record_twice_the_period_gives_band_levels_from_the_whole_record(tmp_path):
    # a 4.8 m record over a 2.4 m period (4 bays): its two halves differ (a 48 mm wave of 2 then
    # 6 µm, independent random roughness). The band levels must be the mean of the two halves'
    # spectra, computed here directly: numpy's FFT of each half (sampled on the transform's own
    # grid, so no resampling) with the end-to-end line removed, power averaged.
    N, K = 4, 32
    P, J = N * L, N * K
    n = 8 * J
    x = np.arange(2 * n + 1) * (P / n)
    rng = np.random.default_rng(3601)
    amp = np.where(x < P, 2e-6, 6e-6)
    z = amp * np.sin(2 * np.pi * x / 0.048) + np.where(x < P, 0.5e-6, 1.5e-6) * rng.standard_normal(x.size)
    path = _write(tmp_path / "long.csv", _profile_text("position [mm],height [µm]", x * 1e3, z * 1e6))
    rough = InitialRoughness("profile", 0.0, 1000.0, None, str(path), bays=N)
    Z = rough.realise(40.0, L, K).Z
    power = np.zeros(J)  # |F_j|^2 summed over the two halves, j = 1..J
    for s in range(2):
        seg = z[s * n: (s + 1) * n + 1]
        seg = seg - (seg[0] + (seg[-1] - seg[0]) * np.linspace(0.0, 1.0, n + 1))
        power += np.abs(np.fft.rfft(seg[:n])[1: J + 1] / n) ** 2
    direct = np.zeros(2 * J + 1, dtype=complex)
    direct[J + 1:] = np.sqrt(power / 2)  # the mean over the halves
    got, want = _band_levels(Z, J, P), _band_levels(direct, J, P)
    assert got.keys() == want.keys() and len(got) >= 15
    for k in want:
        assert got[k] == pytest.approx(want[k], abs=1e-6), f"band 10^(-{k}/10) m"
    # the first half alone (what was used before) is 3 dB and more below in the 48 mm band (n = 13)
    first = np.zeros(2 * J + 1, dtype=complex)
    seg = z[: n + 1] - (z[0] + (z[n] - z[0]) * np.linspace(0.0, 1.0, n + 1))
    first[J + 1:] = np.fft.rfft(seg[:n])[1: J + 1] / n
    assert want[13] - _band_levels(first, J, P)[13] > 3.0
    # and it is stated: two segments, nothing left over, the longest band a 2.4 m segment resolves
    said = rough.statement(L, K)
    assert said["roughness_segments"] == 2 and said["roughness_remainder_m"] == pytest.approx(0.0, abs=1e-9)
    assert "2 segment(s) of N L = 2.4 m" in said["roughness_processing"]
    assert "position in mm, height in µm" in said["roughness_input"]


def test_the_remainder_after_the_last_whole_period_is_stated():
    assert R.record_segments(5.1, 2.4) == (2, pytest.approx(0.3))
    assert R.record_segments(2.4, 2.4) == (1, 0.0)
    assert R.record_segments(1.2, 2.4) == (0, pytest.approx(1.2))


def test_the_period_from_the_record_takes_the_bays_it_holds(root):
    from rail.app import api
    from rail.setup.config import ConfigError

    # the shipped synthetic record is 3.0 m: 5 bays of 0.6 m (profile_example.yaml asks 4)
    study = api.load("profile_example", changes={"roughness": {"record": "period"}})
    assert study.scenario.roughness.bays == 5
    said = study.scenario.roughness.statement(study.scenario.L, 8)
    assert "the period N L taken from the record" in said["roughness_processing"] and said["roughness_segments"] == 1
    with pytest.raises(ConfigError, match=r"spectrum_n16\.yaml: roughness\.record = 'period' is not allowed with roughness\.kind = "
                                          r"'spectrum'"):
        api.load("spectrum_n16", changes={"roughness": {"record": "period"}})


def _spiky_sinusoid():
    # 6 µm at 48 mm over 3 m at 1 mm steps, with 20 spikes and pits of 20-50 µm, one or two samples wide
    x = np.arange(3001) * 1e-3
    true = 6e-6 * np.sin(2 * np.pi * x / 0.048)
    rng = np.random.default_rng(15610)
    z = true.copy()
    where = rng.choice(np.arange(10, 2990), 20, replace=False)
    for k, i in enumerate(where):
        h = rng.uniform(20e-6, 50e-6) * (1 if k % 2 else -1)
        z[i] += h
        if k % 3 == 0:
            z[i + 1] += h
    return x, true, z


def test_spike_removal_restores_a_sinusoid_and_is_visibly_off_without_it():
    x, true, z = _spiky_sinusoid()
    # off: the spikes are there (20 µm and more)
    assert np.abs(z - true).max() > 20e-6
    cleaned, removed = R.remove_spikes(x, z)
    # on: each spike of one (two) samples and its two neighbours, whose curvature it raises, are
    # flagged; the run is replaced by the chord over w = 4 (5) steps, which differs from the
    # sinusoid by at most A k^2 (w dx)^2 / 8
    k = 2 * np.pi / 0.048
    bound = 6e-6 * k**2 * (5 * 1e-3) ** 2 / 8  # 0.32 µm
    assert np.abs(cleaned - true).max() < bound
    assert 60 <= removed.sum() <= 80  # 20 spikes, 7 of two samples: 20 x 3 + 7 = 67 samples
    # the clean sinusoid is left alone
    same, none = R.remove_spikes(x, true)
    assert not none.any() and np.array_equal(same, true)
    # in the coefficients over 4 bays (the option of a scenario): the lines away from the 48 mm
    # wave hold the spikes' energy with it off (above 2 % of the wave's amplitude; measured 3.6 %),
    # and the chords' error only with it on (below 0.1 %; measured 0.04 %)
    J = 4 * 64
    off = R.process_profile(x, z, 4 * L, J).Z
    on = R.process_profile(x, z, 4 * L, J, spikes=True)
    ref = R.process_profile(x, true, 4 * L, J).Z
    away = np.ones(2 * J + 1, dtype=bool)
    away[[J - 50, J + 50]] = False
    assert np.abs(off - ref)[away].max() > 2e-2 * 6e-6
    assert np.abs(on.Z - ref)[away].max() < 1e-3 * 6e-6
    # the wave itself within 0.3 % (measured 0.10 %: the 67 chords each cut a little off the wave's
    # crests; ref is the clean record through the same resampling)
    assert abs(on.Z[J + 50] - ref[J + 50]) < 3e-3 * abs(ref[J + 50])
    assert on.spikes_removed == removed.sum()


def test_spike_removal_is_a_scenario_option_stated_in_the_attributes(tmp_path):
    x, _, z = _spiky_sinusoid()
    path = _write(tmp_path / "spiky.csv", _profile_text("position_m,height_m", x, z))
    off = InitialRoughness("profile", 0.0, 1000.0, None, str(path), bays=4).statement(L, 64)
    on = InitialRoughness("profile", 0.0, 1000.0, None, str(path), bays=4, spike_removal=True).statement(L, 64)
    assert off["roughness_spikes_removed"] == -1 and "spike removal off" in off["roughness_processing"]
    assert 60 <= on["roughness_spikes_removed"] <= 80 and "spike removal on" in on["roughness_processing"]
    with pytest.raises(ValueError, match=r"roughness\.spike_removal = true is not allowed with roughness\.kind = 'spectrum'"):
        InitialRoughness("spectrum", 0.0, 1000.0, None, str(path), spike_removal=True)


def test_the_longest_resolved_band_of_a_known_record_length():
    # a band is resolved when the record holds 3 wavelengths of its upper edge, the exact edge of the one
    # band rule 10^(1/20) lambda_c (rail.bands.exact_edges): 3 m / 3 = 1 m, so the 0.8 m band (exact
    # 10^(-0.1) = 0.794 m, edge 0.891 m) is the longest and 1 m (edge 1.122 m) is not; 2.4 m: 0.8 m ->
    # 0.63 m (0.8 m's edge 0.891 m is longer); 10 m: 3.33 m -> 3.15 m (edge 3.548 m > 3.33: not) -> 2.5 m
    from rail.bands import exact_edges

    assert R.longest_resolved_band(3.0) == pytest.approx(10 ** -0.1)
    assert R.longest_resolved_band(2.4) == pytest.approx(10 ** -0.2)
    assert R.longest_resolved_band(10.0) == pytest.approx(10 ** 0.4)
    for n in (-4, 1, 2, 5, 10):  # exactly at a band's upper edge: resolved; a part in 1e6 short: the next band down
        lo, hi = exact_edges(np.array([n]), "m")
        upper = float(max(lo[0], hi[0]))
        assert R.longest_resolved_band(3 * upper) == pytest.approx(10 ** (-n / 10))
        assert R.longest_resolved_band(3 * upper * (1 - 1e-6)) == pytest.approx(10 ** (-(n + 1) / 10))
    # the band whose 2^(1/6) edge (the rule before) and 10^(1/20) edge lie on either side of the length
    # (the 0.63 m band: exact upper edge 10^(-0.15) = 0.70795 m, 2^(1/6) x 10^(-0.2) = 0.70822 m)
    assert R.longest_resolved_band(3 * 0.7080) == pytest.approx(10 ** -0.2)
    np.testing.assert_array_equal(R.resolved_bands([1.0, 0.8, 0.63, 0.1], 3.0), [False, True, True, True])



def test_the_shipped_profile_states_its_record_segments_and_longest_band(root):
    # config/roughness/synthetic_profile.csv: 3 m at 1 mm; over 4 bays (2.4 m) one segment, 0.6 m
    # not used; the 2.4 m segment resolves down to 0.63 m, the 3 m record to 0.8 m
    said = InitialRoughness("profile", 0.0, 1000.0, None, str(root / "config/roughness/synthetic_profile.csv"), bays=4).statement(L, 64)
    assert said["roughness_segments"] == 1 and said["roughness_remainder_m"] == pytest.approx(0.6)
    assert said["roughness_record_length_m"] == pytest.approx(3.0)
    assert said["roughness_longest_resolved_band_m"] == pytest.approx(10 ** -0.2)
    assert said["roughness_record_longest_band_m"] == pytest.approx(10 ** -0.1)
    assert "position in m, height in m, 3001 rows" in said["roughness_input"]
    assert "0.6 m at the end of the 3 m record not used" in said["roughness_processing"]
    assert "longest resolved one-third-octave band 0.631 m" in said["roughness_processing"]


def test_the_growth_result_and_its_log_state_the_measured_profile(root):
    # one update of 10,000 passages from the shipped profile (1 bay): the result's attributes and the
    # log lines say what was read and how it was processed
    import dataclasses
    import io

    from test_contact_shift import K as K_CS
    from test_contact_shift import _scn, _track

    from rail import chain, moving
    from rail.studies import runs

    table = moving.receptance_table(_track(), 40.0, K_CS, offsets=[0.0])
    scn = _scn("report", passages=10000, step=10000)
    prof = InitialRoughness("profile", 0.0, 1000.0, None, str(root / "config/roughness/synthetic_profile.csv"), bays=1,
                            spike_removal=True)
    scn = dataclasses.replace(scn, roughness=prof)
    h = chain.grow(scn, table, progress=io.StringIO())
    log = io.StringIO()
    ds = runs.growth_dataset(scn, table, h, 40.0, warn=log)
    assert ds.attrs["roughness_kind"] == "profile"
    assert ds.attrs["roughness_segments"] == 5 and ds.attrs["roughness_remainder_m"] == pytest.approx(0.0, abs=1e-9)
    assert ds.attrs["roughness_spikes_removed"] == 0
    # a 0.6 m segment: 0.6 / (3 x 1.1225) = 0.178 m, so the 0.16 m band (exact 10^(-0.8) = 0.158 m)
    assert ds.attrs["roughness_longest_resolved_band_m"] == pytest.approx(10 ** -0.8)
    lines = [a for a in log.getvalue().splitlines() if a.startswith("initial roughness: ")]
    assert len(lines) == 2 and "synthetic_profile.csv: measured profile, position in m" in lines[0]
    assert "5 segment(s) of N L = 0.6 m" in lines[1] and "spike removal on" in lines[1]


@pytest.mark.parametrize("bays", [1, 4, 16])
def test_a_spectrum_start_is_analysed_back_to_its_input_levels(root, bays):
    # issue 45, item 3: the band view of a spectrum start at 0 passages gave 31.5 mm -3.322 dB against
    # -3.2 input and 25 mm -4.821 against -5.0. The synthesis split the bands at the geometric mean of
    # the nominal centres (0.0315 and 0.025 m: 28.06 mm) with a line on an edge in the longer band, the
    # analysis at the exact edges 10^((-n -+ 1/2)/10) m with a line on an edge in the shorter band:
    # lines near 28.1 mm fell in one band when written and in the other when read. One rule now.
    from rail.studies import bands as B

    t = R.read_spectrum_table(root / "config/roughness/example_spectrum.csv")
    K = 64
    P, J = bays * L, bays * K
    Z = R.spectrum_coefficients(t.wavelength, t.level_dB, P, J, seed=1) if bays > 1 else None
    if bays == 1:
        with pytest.warns(R.RoughnessInputWarning):  # the bands longer than 0.6 m hold no line
            Z = R.spectrum_coefficients(t.wavelength, t.level_dB, P, J, seed=1)
    tob = B.third_octave_bands()
    level, resolved = B.band_levels(Z, P, tob)
    checked = 0
    for lam, lev in zip(t.wavelength, t.level_dB):
        b = int(np.argmin(np.abs(np.log(tob.nominal / lam))))
        if resolved[b]:
            assert level[b] == pytest.approx(lev, abs=1e-9), (lam, level[b], lev)
            checked += 1
    assert checked >= 10


# Issue 57, item 3: a record of N samples at spacing d covers N d. A 2,400-sample record at 1 mm is
# one whole period of 2.4 m (it was called 1 mm short, repeated and cut with a 1 mm seam that put
# lines at 2.4 and 1.2 m); a 300-sample record of a 50 mm sine put 8.3 % of its energy on the lines
# 48.98 and 51.06 mm of the period (repeated 9 times and cut), while the warning said only its own
# wavenumbers were present.
def _line_powers(Z, J):
    """2 |Z_j|^2, j = 1..J: the mean square on each line [m^2]."""
    return 2 * np.abs(Z[J + 1:]) ** 2


def test_a_record_of_one_sampled_period_is_that_period_without_a_seam(recwarn):
    P, J = 4 * L, 4 * 32
    x = np.arange(2400) * 1e-3  # 0 .. 2.399 m: 2,400 samples at 1 mm cover 2.4 m
    z = 6e-6 * np.sin(2 * np.pi * x / 0.05) + 2e-6 * np.cos(2 * np.pi * x / 2.4)  # 48 and 1 cycles in 2.4 m
    p = R.process_profile(x, z, P, J, source="one_period.csv")
    power = _line_powers(p.Z, J)
    assert power[48 - 1] == pytest.approx(6e-6 ** 2 / 2, rel=1e-6)  # 50 mm = 2.4 m / 48: the sine, whole
    assert power[1 - 1] == pytest.approx(2e-6 ** 2 / 2, rel=1e-6)  # the 2.4 m wave, no seam added to it
    others = np.delete(power, [0, 47])
    # the seam put 1.6e-3 of the sine's power on 2.4 m and 4e-4 on 1.2 m; the linear resampling of 1 mm
    # data onto 1,024 points leaves images of about 2e-9 (measured): 1e-7 lies between
    assert others.max() < 1e-7 * power[47], 1e3 * P / (np.argmax(others) + 2)  # the 1.2 m line (j = 2) among them
    assert not [w for w in recwarn if issubclass(w.category, R.RoughnessInputWarning)]  # nothing is short
    assert p.segments == 1 and p.sampled_period and p.analysed == P and p.remainder == 0.0
    said = R.profile_statement(R.ProfileRecord(x, z, "one_period.csv", ("m", "m")), p)
    assert "1 segment(s) of N L = 2.4 m (its last sample 1 mm, one sample spacing, short of the end: its samples cover 2.4 m" in \
        said["roughness_processing"]
    # two sampled periods are two segments, and the period taken from the record holds all 4 bays
    x2 = np.arange(4800) * 1e-3
    two = R.process_profile(x2, 6e-6 * np.sin(2 * np.pi * x2 / 0.05), P, J)
    assert two.segments == 2 and two.remainder == 0.0
    assert R.record_bays(2.399, L, 1e-3) == 4 and R.record_bays(2.399, L) == 3  # without the spacing: the bays up to the last sample
    assert R.record_bays(2.3985, L, 1e-3) == 3  # 1.5 mm short of the fourth bay: not a sampled period


def test_a_short_record_that_is_a_whole_fraction_of_the_period_is_repeated_with_nothing_else():
    P, J = 4 * L, 4 * 32
    x = np.arange(300) * 1e-3  # 0 .. 0.299 m: 300 samples at 1 mm cover 0.3 m = 2.4 m / 8
    z = 6e-6 * np.sin(2 * np.pi * x / 0.05)
    with pytest.warns(R.RoughnessInputWarning) as said:
        p = R.process_profile(x, z, P, J, source="short.csv")
    power = _line_powers(p.Z, J)
    assert power[47 - 1] < 1e-12 * power[47] and power[49 - 1] < 1e-12 * power[47]  # 51.06 and 48.98 mm: nothing
    assert power[48 - 1] == pytest.approx(6e-6 ** 2 / 2, rel=1e-6)
    assert np.all(power[np.arange(1, J + 1) % 8 != 0] == 0)  # only the record's own lines j = 8 k
    assert p.repeats == 8 and p.analysed == pytest.approx(0.3, rel=1e-12)
    assert ("the profile is 0.3 m long, shorter than the roughness period N L = 2.4 m; it is made periodic over its own length "
            "(its samples cover 0.3 m) and repeated 8 times: its wavenumbers 2 pi k / 0.3 m are the lines j = 8 k of the period, "
            "no other line is present") in str(said[0].message)


def test_a_short_record_of_any_length_has_only_its_own_lines_placed_on_the_nearest_lines_of_the_period():
    # 310 samples (0.309 m): 2.4 m / 0.309 m = 7.77 is no whole number. Each line k of the record's
    # own transform (an independent numpy FFT of the record, made periodic over 0.309 m by the line
    # through its ends, on its own 1 mm samples) is the line j = round(7.77 k) of the period, with
    # its power; no other line is present; the move of a wavelength is at most half a line
    P, J = 4 * L, 4 * 32
    x = np.arange(310) * 1e-3
    rng = np.random.default_rng(57)
    z = 6e-6 * np.sin(2 * np.pi * x / 0.05) + 1e-6 * rng.standard_normal(x.size)
    with pytest.warns(R.RoughnessInputWarning) as said:
        p = R.process_profile(x, z, P, J, source="short.csv")
    T = x[-1]
    t = x / T
    own = z - (z[0] + (z[-1] - z[0]) * t)  # made periodic over T: the last sample is the first
    F = np.fft.rfft(own[:-1]) / (x.size - 1)  # lines k / T, k = 0 .. 154
    k = np.arange(1, F.size)
    j = np.floor(k * P / T + 0.5).astype(int)
    keep = j <= J
    power = _line_powers(p.Z, J)
    placed = np.zeros(J)
    placed[j[keep] - 1] = 2 * np.abs(F[k[keep]]) ** 2
    assert set(np.nonzero(power)[0]) <= set(j[keep] - 1)
    np.testing.assert_allclose(power[j[keep] - 1], placed[j[keep] - 1], rtol=0.02, atol=1e-3 * placed.max())  # linear resampling of 1 mm data
    move = np.abs((k * P / T) / j - 1)
    assert np.all(move <= (T / k) / (2 * P) * (1 + 1e-12))  # half a line of the period: lambda / (2 P) relative
    assert p.wavelength_shift == pytest.approx(0.0085, abs=5e-5) and p.repeats == 0
    assert re.search(r"no whole fraction of N L, so it is not repeated: .* placed on the nearest line 2 pi j / \(N L\) .* no other "
                     r"line is present; the lines it resolves move by at most 0\.85 % in wavelength", str(said[0].message))
