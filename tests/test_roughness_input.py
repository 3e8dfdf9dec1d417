"""Initial roughness at any wavelength: a measured profile and a one-third-octave spectrum over a
period of N bays (rail.roughness), with errors that name the file and the line."""

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
    lo, hi = R.band_edges(lam)
    assert np.all(hi[1:] == lo[:-1])  # the bands partition the wavelength axis
    assert hi[0] / lam[0] == pytest.approx(2 ** (1 / 6)) and lam[-1] / lo[-1] == pytest.approx(2 ** (1 / 6))
    for lc, lv, a, b in zip(lam, lev, lo, hi):
        inside = (P / j >= a) & (P / j < b)
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
