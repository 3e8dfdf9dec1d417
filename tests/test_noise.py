"""Rolling noise by CNOSSOS-EU (rail.noise, docs/noise.md): the Appendix G tables pinned to a second
transcription, the A-weighting against IEC 61672-1's poles, the energy sum and both
wavelength-to-frequency rules against hand calculations, the sound power per vehicle and per metre
of line written out from the Directive's equations, and the input checks.

How the tables are pinned. Every value of rail.noise.tables is compared with a copy written a
second time here, row by row as the Official Journal prints them (one row per band, the columns
side by side), not column by column as the module holds them:

* Table G-1a (wheel roughness): typed from the official text of Directive (EU) 2015/996, Annex,
  Appendix G, Table G-1 (legislation.gov.uk/eudr/2015/996/annex/appendix/G), with its printed labels
  120, 12, 3.2 and 1.2 mm;
* Tables G-1b, G-2, G-3a, G-3b, G-3c (as replaced or re-issued by 2021/1226): the Official Journal text
  of 2021/1226 was not in any stored source, so the rows below are NoiseModelling's transcription
  (RailwayEmissionCnossos.json at commit 35d2da1b, entries EU3..EU10) laid out row-wise, while the
  module was typed from phonometry's (cnossos_rail.py at 0bdfbf9). Two independent public
  transcriptions must agree to the printed 0.1 dB; a typing slip in either fails the test.
"""

import math

import numpy as np
import pytest

from rail.noise import cnossos as C
from rail.noise import rolling as R
from rail.noise import tables as T
from rail.noise import weighting as W

# Table G-1 of 2015/996 (wheel roughness L_r,VEH [dB re 1 um]), as printed: wavelength [mm],
# cast-iron tread brake, composite brake, disk brake (the Min and Max columns, -15.0 and 25.0, left out)
G1A_ROWS = """
1000  2.2 -4.0 -5.9
800   2.2 -4.0 -5.9
630   2.2 -4.0 -5.9
500   2.2 -4.0 -5.9
400   2.2 -4.0 -5.9
315   2.2 -4.0 -5.9
250   2.2 -4.0  2.3
200   2.2 -4.0  2.8
160   2.4 -4.0  2.6
120   0.6 -4.0  1.2
100   2.6 -4.0  2.1
80    5.8 -4.3  0.9
63    8.8 -4.6 -0.3
50   11.1 -4.9 -1.6
40   11.0 -5.2 -2.9
31.5  9.8 -6.3 -4.9
25    7.5 -6.8 -7.0
20    5.1 -7.2 -8.6
16    3.0 -7.3 -9.3
12    1.3 -7.3 -9.5
10    0.2 -7.1 -10.1
8    -0.7 -6.9 -10.3
6.3  -1.2 -6.7 -10.3
5    -1.0 -6.0 -10.8
4     0.3 -3.7 -10.9
3.2   0.2 -2.4 -9.5
2.5   1.3 -2.6 -9.5
2     3.1 -2.5 -9.5
1.6   3.1 -2.5 -9.5
1.2   3.1 -2.5 -9.5
1     3.1 -2.5 -9.5
0.8   3.1 -2.5 -9.5
"""

# Tables G-1b (rail roughness: E, M) and G-2 (contact filter A_3: (wheel load kN, wheel diameter mm) =
# (50, 360), (50, 680), (50, 920), (25, 920), (100, 920)) [dB], rows by wavelength [mm]
G1B_G2_ROWS = """
2000    17.1   35.0    0.0    0.0    0.0    0.0    0.0
1600    17.1   31.0    0.0    0.0    0.0    0.0    0.0
1250    17.1   28.0    0.0    0.0    0.0    0.0    0.0
1000    17.1   25.0    0.0    0.0    0.0    0.0    0.0
800     17.1   23.0    0.0    0.0    0.0    0.0    0.0
630     17.1   20.0    0.0    0.0    0.0    0.0    0.0
500     17.1   17.0    0.0    0.0    0.0    0.0    0.0
400     17.1   13.5    0.0    0.0    0.0    0.0    0.0
315     15.0   10.5    0.0    0.0    0.0    0.0    0.0
250     13.0    9.0    0.0    0.0    0.0    0.0    0.0
200     11.0    6.5    0.0    0.0    0.0    0.0    0.0
160      9.0    5.5    0.0    0.0    0.0    0.0   -0.1
125      7.0    5.0    0.0    0.0   -0.1    0.0   -0.2
100      4.9    3.5    0.0   -0.1   -0.1    0.0   -0.3
80       2.9    2.0   -0.1   -0.2   -0.3   -0.1   -0.6
63       0.9    0.1   -0.2   -0.3   -0.6   -0.3   -1.0
50      -1.1   -0.2   -0.3   -0.7   -1.1   -0.5   -1.8
40      -3.2   -0.3   -0.6   -1.2   -1.3   -1.1   -3.2
31.5    -5.0   -0.8   -1.0   -2.0   -3.5   -1.8   -5.4
25      -5.6   -3.0   -1.8   -4.1   -5.3   -3.3   -8.7
20      -6.2   -5.0   -3.2   -6.0   -8.0   -5.3  -12.2
16      -6.8   -7.0   -5.4   -9.2  -12.0   -7.9  -16.7
12.5    -7.4   -8.0   -8.7  -13.8  -16.8  -12.8  -17.7
10      -8.0   -9.0  -12.2  -17.2  -17.7  -16.8  -17.8
8       -8.6  -10.0  -16.7  -17.7  -18.0  -17.7  -20.7
6.3     -9.2  -12.0  -17.7  -18.6  -21.5  -18.2  -22.1
5       -9.8  -13.0  -17.8  -21.5  -21.8  -20.5  -22.8
4      -10.4  -14.0  -20.7  -22.3  -22.8  -22.0  -24.0
3.15   -11.0  -15.0  -22.1  -23.1  -24.0  -22.8  -24.5
2.5    -11.6  -16.0  -22.8  -24.4  -24.5  -24.2  -24.7
2      -12.2  -17.0  -24.0  -24.5  -25.0  -24.5  -27.0
1.6    -12.8  -18.0  -24.5  -25.0  -27.3  -25.0  -27.8
1.25   -13.4  -19.0  -24.7  -28.0  -28.1  -27.4  -28.6
1      -14.0  -19.0  -27.0  -28.8  -28.9  -28.2  -29.4
0.8    -14.0  -19.0  -27.8  -29.6  -29.7  -29.0  -30.2
"""
# Tables G-3a (L_H,TR: mono-block soft, medium, hard; bi-block soft, medium, hard; wooden; direct
# fastening), G-3b (L_H,VEH: 920, 840, 680, 1200 mm) and G-3c (superstructure) [dB per axle], rows by
# frequency [Hz]
G3_ROWS = """
50      53.3   50.9   50.1   50.9   50.0   49.8   44.0   75.4   75.4   75.4   75.4   75.4    0.0
63      59.3   57.8   57.2   56.6   56.1   55.9   51.0   77.4   77.3   77.3   77.3   77.3    0.0
80      67.2   66.5   66.3   64.3   64.1   64.0   59.9   81.4   81.1   81.1   81.1   81.1    0.0
100     75.9   76.8   77.2   72.3   72.5   72.5   70.8   87.1   84.1   84.1   84.1   84.1    0.0
125     79.2   80.9   81.6   75.4   75.8   75.9   75.1   88.0   83.3   82.8   82.8   82.8    0.0
160     81.8   83.3   84.0   78.5   79.1   79.4   76.9   89.7   84.3   83.3   83.3   83.3    0.0
200     84.2   85.8   86.5   81.8   83.6   84.4   77.2   83.4   86.0   84.1   83.9   84.5    0.0
250     88.6   90.0   90.7   86.6   88.7   89.7   80.9   87.7   90.1   86.9   86.3   90.4    0.0
315     91.0   91.6   92.1   89.1   89.6   90.2   85.3   89.8   89.8   87.9   88.0   90.4    0.0
400     94.5   93.9   94.3   91.9   89.7   90.2   92.5   97.5   89.0   89.9   92.2   89.9    0.0
500     97.0   95.6   95.8   94.5   90.6   90.8   97.0   99.0   88.8   90.9   93.9   90.1    0.0
630     99.2   97.4   97.0   97.5   93.8   93.1   98.7  100.8   90.4   91.5   92.5   91.3    0.0
800    104.0  101.7  100.3  104.0  100.6   97.9  102.8  104.9   92.4   91.5   90.9   91.5    0.0
1000   107.1  104.4  102.5  107.9  104.7  101.1  105.4  111.8   94.9   93.0   90.4   93.6    0.0
1250   108.3  106.0  104.2  108.9  106.3  103.4  106.5  113.9  100.4   98.7   93.2  100.5    0.0
1600   108.5  106.8  105.4  108.8  107.1  105.4  106.4  115.5  104.6  101.6   93.5  104.6    0.0
2000   109.7  108.3  107.1  109.8  108.8  107.7  107.5  114.9  109.6  107.6   99.6  115.6    0.0
2500   110.0  108.9  107.9  110.2  109.3  108.5  108.1  118.2  114.9  111.9  104.9  115.9    0.0
3150   110.0  109.1  108.2  110.1  109.4  108.7  108.4  118.3  115.0  114.5  108.0  116.0    0.0
4000   110.0  109.4  108.7  110.1  109.7  109.1  108.7  118.4  115.0  114.5  111.0  116.0    0.0
5000   110.3  109.9  109.4  110.3  110.0  109.6  109.1  118.9  115.5  115.0  111.5  116.5    0.0
6300   110.0  109.9  109.7  109.9  109.8  109.6  109.1  117.5  115.6  115.1  111.6  116.6    0.0
8000   110.1  110.3  110.4  110.0  110.0  109.9  109.5  117.9  116.0  115.5  112.0  117.0    0.0
10000  110.6  111.0  111.4  110.4  110.5  110.6  110.2  118.6  116.7  116.2  112.7  117.7    0.0
"""


def _rows(text):
    return np.array([[float(x) for x in line.split()] for line in text.strip().splitlines()])


# --- the tables ---------------------------------------------------------------------------------------

def test_wheel_roughness_table_g1a_equals_the_official_text_row_by_row():
    rows = _rows(G1A_ROWS)
    assert rows.shape == (32, 4)
    np.testing.assert_array_equal(rows[:, 0], T.WHEEL_WAVELENGTH_LABELS_MM)
    for j, brake in enumerate(("cast_iron", "composite", "disc"), start=1):
        np.testing.assert_array_equal(T.WHEEL_ROUGHNESS[brake], rows[:, j], err_msg=f"Table G-1a, {brake}")


def test_rail_roughness_g1b_and_contact_filter_g2_equal_the_second_transcription_row_by_row():
    rows = _rows(G1B_G2_ROWS)
    assert rows.shape == (35, 8)
    np.testing.assert_array_equal(rows[:, 0], T.WAVELENGTH_LABELS_MM)
    np.testing.assert_array_equal(T.RAIL_ROUGHNESS["E"], rows[:, 1], err_msg="Table G-1b, E")
    np.testing.assert_array_equal(T.RAIL_ROUGHNESS["M"], rows[:, 2], err_msg="Table G-1b, M")
    assert list(T.RAIL_ROUGHNESS) == ["E", "M"]
    columns = [(50.0, 360.0), (50.0, 680.0), (50.0, 920.0), (25.0, 920.0), (100.0, 920.0)]
    assert sorted(T.CONTACT_FILTER) == sorted(columns)
    for j, key in enumerate(columns, start=3):
        np.testing.assert_array_equal(T.CONTACT_FILTER[key], rows[:, j], err_msg=f"Table G-2, {key}")


def test_transfer_functions_g3a_g3b_g3c_equal_the_second_transcription_row_by_row():
    rows = _rows(G3_ROWS)
    assert rows.shape == (24, 14)
    np.testing.assert_array_equal(rows[:, 0], T.FREQUENCY_LABELS_HZ)
    track = [("monoblock", "soft"), ("monoblock", "medium"), ("monoblock", "hard"), ("biblock", "soft"),
             ("biblock", "medium"), ("biblock", "hard"), ("wooden", None), ("direct", None)]
    assert sorted(T.TRACK_TRANSFER, key=str) == sorted(track, key=str)
    for j, key in enumerate(track, start=1):
        np.testing.assert_array_equal(T.TRACK_TRANSFER[key], rows[:, j], err_msg=f"Table G-3a, {key}")
    assert list(T.VEHICLE_TRANSFER) == [920.0, 840.0, 680.0, 1200.0]
    for j, d in enumerate(T.VEHICLE_TRANSFER, start=9):
        np.testing.assert_array_equal(T.VEHICLE_TRANSFER[d], rows[:, j], err_msg=f"Table G-3b, {d} mm")
    np.testing.assert_array_equal(T.SUPERSTRUCTURE_TRANSFER, rows[:, 13], err_msg="Table G-3c")


def test_every_table_names_its_source_and_the_pad_classes_are_those_of_2021():
    for name in ("WHEEL_ROUGHNESS", "RAIL_ROUGHNESS", "CONTACT_FILTER", "TRACK_TRANSFER", "VEHICLE_TRANSFER",
                 "SUPERSTRUCTURE_TRANSFER", "PAD_CLASSES_MN_PER_M", "A_WEIGHTING"):
        assert name in T.SOURCES and len(T.SOURCES[name]) > 40
    assert T.PAD_CLASSES_MN_PER_M == {"soft": (150.0, 250.0), "medium": (250.0, 800.0), "hard": (800.0, 1000.0)}


def test_the_wavelength_bands_are_the_rolling_noise_exports_bands():
    # one set of 35 bands: the export railgrowth writes for rolling-noise tools is the CNOSSOS grid
    from rail.studies.exports import ROLLING_NOISE_WAVELENGTHS_M, rolling_noise_bands
    b, e = C.cnossos_wavelength_bands(), rolling_noise_bands()
    np.testing.assert_allclose(b.nominal, ROLLING_NOISE_WAVELENGTHS_M, rtol=1e-12)
    np.testing.assert_allclose(b.centre, e.centre, rtol=1e-12)
    np.testing.assert_allclose(b.lower, e.lower, rtol=1e-12)
    f = C.cnossos_frequency_bands()
    np.testing.assert_allclose(f.nominal, T.FREQUENCY_LABELS_HZ, rtol=1e-12)
    np.testing.assert_allclose(f.centre, 1000 * 10 ** (np.arange(-13, 11) / 10), rtol=1e-12)


# --- A-weighting and energy sums ---------------------------------------------------------------------

def _iec_poles():
    """The A-weighting's poles from IEC 61672-1:2013 Annex E's defining constants: f_r = 1 kHz,
    f_L = 10^1.5 Hz, f_H = 10^3.9 Hz, D = 1/sqrt(2) (D^2 = 1/2), f_A = 10^2.45 Hz."""
    fr, fl, fh, d = 1000.0, 10 ** 1.5, 10 ** 3.9, math.sqrt(0.5)
    c = fl ** 2 * fh ** 2
    b = (fr ** 2 + fl ** 2 * fh ** 2 / fr ** 2 - d * (fl ** 2 + fh ** 2)) / (1 - d)
    f1 = math.sqrt((-b - math.sqrt(b * b - 4 * c)) / 2)
    f4 = math.sqrt((-b + math.sqrt(b * b - 4 * c)) / 2)
    fa = 10 ** 2.45
    return f1, (3 - math.sqrt(5)) / 2 * fa, (3 + math.sqrt(5)) / 2 * fa, f4


def test_a_weighting_poles_follow_from_iec_61672_constants():
    p = _iec_poles()
    np.testing.assert_allclose(p, W.IEC_61672_POLES_HZ, rtol=1e-6)
    # the rounded values IEC 61672-1 prints: 20.60, 107.7, 737.9, 12194 Hz
    assert [round(p[0], 2), round(p[1], 1), round(p[2], 1), round(p[3])] == [20.60, 107.7, 737.9, 12194]
    assert abs(float(W.a_weighting_analytic(1000.0))) < 2e-3  # A_1000 = -2.000 dB normalises it


def test_a_weighting_table_values_are_iec_61672_rounded_at_the_exact_frequencies():
    # Table 3's values are the analytic weighting at the exact base-ten frequencies rounded to 0.1 dB:
    # computed here from the poles (not from the module's constants), each table value within 0.05 dB
    # (normalised to 0 dB at 1 kHz exactly: A_1000 = -2.000 dB is that constant rounded, -1.9997 dB)
    f1, f2, f3, f4 = _iec_poles()

    def a_of(f):
        f = np.asarray(f, dtype=float)
        return 20 * np.log10(f4 ** 2 * f ** 4 / ((f ** 2 + f1 ** 2) * np.sqrt(f ** 2 + f2 ** 2)
                                                  * np.sqrt(f ** 2 + f3 ** 2) * (f ** 2 + f4 ** 2)))

    a = a_of(1000 * 10 ** (np.arange(-13, 11) / 10)) - a_of(1000.0)
    assert np.all(np.abs(np.array(T.A_WEIGHTING) - a) <= 0.05 + 1e-9), np.round(np.array(T.A_WEIGHTING) - a, 3)
    np.testing.assert_array_equal(W.a_weighting([50, 1000, 10000]), [-30.2, 0.0, -2.5])
    with pytest.raises(ValueError, match="frequency = 55 Hz is not a nominal"):
        W.a_weighting([55.0])


def test_energy_sum_of_equal_levels_is_3_01_db_up_and_refuses_an_empty_band():
    assert W.energy_sum([60.0, 60.0]) == pytest.approx(60 + 10 * math.log10(2), abs=1e-12)
    assert W.energy_sum([60.0, 50.0]) == pytest.approx(60 + 10 * math.log10(1.1), abs=1e-12)  # +0.41 dB
    assert W.energy_sum([70.0, -np.inf]) == pytest.approx(70.0, abs=1e-12)
    assert W.energy_sum([-np.inf, -np.inf]) == -np.inf
    with pytest.raises(ValueError, match="NaN"):
        W.energy_sum([60.0, np.nan])


def test_overall_a_weighted_level_of_a_flat_spectrum_by_hand():
    levels = np.full(24, 80.0)
    expected = 10 * math.log10(sum(10 ** ((80.0 + a) / 10) for a in T.A_WEIGHTING))
    assert W.overall_level(levels, T.FREQUENCY_LABELS_HZ) == pytest.approx(expected, abs=1e-10)
    assert W.overall_level(levels, T.FREQUENCY_LABELS_HZ, "Z") == pytest.approx(80 + 10 * math.log10(24), abs=1e-10)


# --- wavelength to frequency ----------------------------------------------------------------------------

def test_a_flat_spectrum_gives_the_same_level_by_both_rules_at_any_speed():
    for v in (8.0, 23.7, 33.3, 61.0, 100.0):
        for rule in C.RULES:
            np.testing.assert_allclose(C.wavelength_to_frequency(np.full(35, 7.5), v, rule), 7.5, atol=1e-12)


def test_at_a_speed_on_the_band_grid_each_frequency_band_reads_one_wavelength_band_exactly():
    # v = 10^1.6 m/s: band m (f_m = 1000 Hz 10^(m/10)) reads lambda = 10^(1.6 - 3 - m/10) m, the exact
    # centre of wavelength band n = 14 + m; no interpolation, the same by both rules
    levels = np.arange(35) * 1.7 - 20.0  # any spectrum: level of band n is levels[n + 3]
    v = 10 ** 1.6
    expected = levels[np.arange(-13, 11) + 14 + 3]
    for rule in C.RULES:
        np.testing.assert_allclose(C.wavelength_to_frequency(levels, v, rule), expected, atol=1e-9)


def test_a_spectrum_rising_10_db_per_band_differs_between_the_rules_as_calculated_by_hand():
    # at v = 10^(1.6 + 0.05) m/s every frequency band reads half-way (w = 0.5) between two bands, the
    # longer one weighted (1 - w); rising 10 dB per band towards the short wavelengths:
    # level rule: L + 5 dB; energy rule: L + 10 lg(0.5 + 0.5 * 10) = L + 7.404 dB; difference 2.404 dB
    levels = 10.0 * np.arange(35)
    v = 10 ** 1.65
    n = 30 + np.arange(-13, 11) - 16.5  # fractional band index read
    longer = 10.0 * (np.floor(n) + 3)
    lev = C.wavelength_to_frequency(levels, v, "level")
    en = C.wavelength_to_frequency(levels, v, "energy")
    np.testing.assert_allclose(lev, longer + 5.0, atol=1e-9)
    np.testing.assert_allclose(en, longer + 10 * math.log10(5.5), atol=1e-9)
    np.testing.assert_allclose(en - lev, 2.4036, atol=5e-5)
    # the largest difference for a 10 dB step, at w = (9 / ln 10 - 1) / 9 = 0.3232: 2.688 dB
    w = (9 / math.log(10) - 1) / 9
    v = 10 ** (1.6 - w / 10)
    d = C.wavelength_to_frequency(levels, v, "energy") - C.wavelength_to_frequency(levels, v, "level")
    np.testing.assert_allclose(d, 10 * math.log10(1 + 9 * w) - 10 * w, atol=1e-9)
    assert 10 * math.log10(1 + 9 * w) - 10 * w == pytest.approx(2.688, abs=1e-3)


def test_the_energy_rule_conserves_the_mean_square_and_the_level_rule_does_not():
    # the 24 frequency bands at v read a contiguous run of wavelength intervals: band k0 with weight
    # (1 - w), whole bands k0 + 1 .. k0 + 23, band k0 + 24 with weight w; the energy rule's mean squares
    # sum to exactly that (roughness uniform in lg lambda within each band)
    rng = np.random.default_rng(3)
    levels = rng.uniform(-20, 20, 35)
    v = 10 ** (1.6 - 0.37 / 10)  # w = 0.37
    q = 30 + np.arange(-13, 11) - 10 * math.log10(v) + 3
    k0, w = int(np.floor(q[0])), q[0] - np.floor(q[0])
    e = 10 ** (levels / 10)
    expected = (1 - w) * e[k0] + e[k0 + 1:k0 + 24].sum() + w * e[k0 + 24]
    def got(rule):
        return np.sum(10 ** (C.wavelength_to_frequency(levels, v, rule) / 10))

    assert got("energy") == pytest.approx(expected, rel=1e-12)
    assert abs(got("level") / expected - 1) > 1e-3


def test_a_band_the_speed_reads_without_a_level_is_named_not_taken_as_zero():
    levels = np.full(35, 0.0)
    levels[:3] = np.nan  # 2000, 1600, 1250 mm unresolved
    C.wavelength_to_frequency(levels, 40.0)  # 50 Hz reads 0.8 m: fine
    with pytest.raises(ValueError, match=r"read the wavelength bands 2000, 1600, 1250 mm, which have no level"):
        C.wavelength_to_frequency(levels, 80.0)  # 50 Hz reads 1.6 m


def test_a_silent_band_adds_nothing_by_the_energy_rule_and_is_read_alone_at_a_band_centre():
    # a resolved but smooth band is -inf: at a grid speed each band is read alone by both rules; half-way
    # between a silent band and one of 10 dB the energy rule gives 10 + 10 lg 0.5, the level rule silence
    levels = np.full(35, 10.0)
    levels[20] = -np.inf
    for rule in C.RULES:
        got = C.wavelength_to_frequency(levels, 10 ** 1.6, rule)
        assert not np.isnan(got).any() and np.isneginf(got).sum() == 1
    half = C.wavelength_to_frequency(levels, 10 ** 1.65, "energy")
    assert np.isclose(half, 10 + 10 * math.log10(0.5)).sum() == 2 and np.isfinite(half).all()
    assert np.isneginf(C.wavelength_to_frequency(levels, 10 ** 1.65, "level")).sum() == 2

# --- the total effective roughness and the sound power -------------------------------------------------

def test_total_effective_roughness_by_hand_flat_and_one_band_10_db_up():
    rail = np.zeros(35)
    rail[20] = 10.0
    a3 = T.CONTACT_FILTER[(50.0, 920.0)]
    got = C.total_effective_roughness(rail, np.zeros(35), a3)
    np.testing.assert_allclose(got, 10 * math.log10(2) + np.array(a3) + np.where(np.arange(35) == 20,
                               10 * math.log10(11 / 2), 0.0), atol=1e-12)  # 3.01 dB, band 20: 10.41 dB
    assert got[20] - a3[20] == pytest.approx(10.414, abs=1e-3)


def _by_hand(rail, brake, contact, sleeper_pad, diameter, axles, q, v, freight=False):
    """L'_W,eq,line per band at a grid speed v = 10^1.6 m/s written out from the Directive: each band m
    reads wavelength band n = 14 + m (no interpolation); 2.3.7, 2.3.8-2.3.10, 2.3.2 (v in km/h)."""
    assert v == 10 ** 1.6
    wheel = np.array(T.WHEEL_ROUGHNESS[brake])  # 1000 mm .. 0.8 mm: n = 0..31
    out = []
    for i, m in enumerate(range(-13, 11)):
        n = 14 + m
        r, wh, a3 = rail[n + 3], wheel[n], T.CONTACT_FILTER[contact][n + 3]
        lrtot = 10 * math.log10(10 ** (r / 10) + 10 ** (wh / 10)) + a3
        ltr = lrtot + T.TRACK_TRANSFER[sleeper_pad][i] + 10 * math.log10(axles)
        lveh = lrtot + T.VEHICLE_TRANSFER[diameter][i] + 10 * math.log10(axles)
        parts = [ltr, lveh] + ([lrtot + T.SUPERSTRUCTURE_TRANSFER[i] + 10 * math.log10(axles)] if freight else [])
        lw0 = 10 * math.log10(sum(10 ** (p / 10) for p in parts))
        out.append(lw0 + 10 * math.log10(q / (1000 * v * 3.6)))
    return np.array(out)


@pytest.mark.parametrize("case", ["flat", "one band up", "average network"])
def test_line_sound_power_equals_the_directive_written_out_by_hand(case):
    v = 10 ** 1.6  # 143.3 km/h
    rail = {"flat": np.full(35, 5.0), "one band up": np.where(np.arange(35) == 20, 15.0, 5.0),
            "average network": np.array(T.RAIL_ROUGHNESS["M"])}[case]
    veh = R.Vehicle("coach", axles=4, brake="disc", wheel_diameter=0.92, wheel_load=50e3)
    wagon = R.Vehicle("wagon", axles=2, brake="cast_iron", wheel_diameter=0.92, wheel_load=100e3, freight=True)
    r = R.rolling_noise(rail, R.Track("monoblock", "medium"), [R.TrafficClass(veh, 12.0, v), R.TrafficClass(wagon, 3.0, v)])
    h1 = _by_hand(rail, "disc", (50.0, 920.0), ("monoblock", "medium"), 920.0, 4, 12.0, v)
    h2 = _by_hand(rail, "cast_iron", (100.0, 920.0), ("monoblock", "medium"), 920.0, 2, 3.0, v, freight=True)
    np.testing.assert_allclose(r.line_power[0], h1, atol=0.01)
    np.testing.assert_allclose(r.line_power[1], h2, atol=0.01)
    total = 10 * np.log10(10 ** (h1 / 10) + 10 ** (h2 / 10))
    np.testing.assert_allclose(r.line_power_total, total, atol=0.01)
    la = 10 * math.log10(sum(10 ** ((x + a) / 10) for x, a in zip(total, T.A_WEIGHTING)))
    assert r.line_power_A == pytest.approx(la, abs=0.01)
    assert r.contact_columns == ((50.0, 920.0), (100.0, 920.0)) and r.diameters == (920.0, 920.0)


def test_doubled_traffic_is_3_db_up_and_the_flow_term_follows_the_speed():
    rail = np.array(T.RAIL_ROUGHNESS["M"])
    veh = R.Vehicle("coach", axles=4, brake="disc")
    tr = R.Track("biblock", "soft")
    one = R.rolling_noise(rail, tr, R.TrafficClass(veh, 10.0, 30.0))
    two = R.rolling_noise(rail, tr, R.TrafficClass(veh, 20.0, 30.0))
    np.testing.assert_allclose(two.line_power_total - one.line_power_total, 10 * math.log10(2), atol=1e-10)
    assert two.line_power_A - one.line_power_A == pytest.approx(3.0103, abs=1e-4)
    same = R.rolling_noise(rail, tr, [R.TrafficClass(veh, 10.0, 30.0)] * 2)
    np.testing.assert_allclose(same.line_power_total, two.line_power_total, atol=1e-10)
    # the flow term alone: at fixed power per vehicle, twice the speed spreads the vehicles over twice
    # the length, -3.01 dB per metre
    assert C.line_sound_power(100.0, 10.0, 40.0) - C.line_sound_power(100.0, 10.0, 20.0) == pytest.approx(-3.0103, abs=1e-4)
    assert C.line_sound_power(100.0, 3600.0, 1.0) == pytest.approx(100.0, abs=1e-12)  # one vehicle per metre


def test_speed_law_of_a_power_law_roughness_by_hand():
    # a total roughness rising s dB per band towards long wavelengths, read at two grid speeds a factor
    # 10^0.3 apart: each frequency band reads 3 bands longer, so L_R,TOT and L_W,0 rise 3 s dB and
    # L'_W,eq,line by 3 s - 10 lg(10^0.3) = 3 s - 3 dB in every band
    s = 1.5
    lrtot = -s * np.arange(35)
    v1, v2 = 10 ** 1.3, 10 ** 1.6
    for rule in C.RULES:
        f1, f2 = C.wavelength_to_frequency(lrtot, v1, rule), C.wavelength_to_frequency(lrtot, v2, rule)
        lw1 = C.rolling_sound_power(f1, T.TRACK_TRANSFER[("wooden", None)], 4)
        lw2 = C.rolling_sound_power(f2, T.TRACK_TRANSFER[("wooden", None)], 4)
        d = C.line_sound_power(lw2, 10.0, v2) - C.line_sound_power(lw1, 10.0, v1)
        np.testing.assert_allclose(d, 3 * s - 3.0, atol=1e-9)


def test_rolling_noise_rises_with_rail_roughness_by_the_energy_sum():
    # a rail 10 dB rougher than the wheel everywhere, then 20 dB: L_R,TOT follows 10 lg(10^(R/10) + 10^(W/10))
    veh = R.Vehicle("coach", axles=4, brake=tuple(np.full(35, -10.0)))
    tr = R.Track("monoblock", "medium")
    a = R.rolling_noise(np.full(35, 0.0), tr, R.TrafficClass(veh, 10.0, 10 ** 1.6))
    b = R.rolling_noise(np.full(35, 10.0), tr, R.TrafficClass(veh, 10.0, 10 ** 1.6))
    expected = 10 * math.log10(10 + 0.1) - 10 * math.log10(1 + 0.1)
    np.testing.assert_allclose(b.line_power_total - a.line_power_total, expected, atol=1e-10)


# --- pad class, band mapping, choices ----------------------------------------------------------------------

@pytest.mark.parametrize("k, cls", [(150e6, "soft"), (249.9e6, "soft"), (250e6, "medium"), (3.5e8, "medium"),
                                    (799e6, "medium"), (800e6, "hard"), (1000e6, "hard")])
def test_pad_class_from_stiffness(k, cls):
    assert C.pad_class(k) == cls


@pytest.mark.parametrize("k", [7e7, 149.9e6, 1.0001e9, float("nan"), float("inf"), "stiff"])
def test_pad_stiffness_outside_the_classes_is_refused_naming_the_key(k):
    with pytest.raises(ValueError, match=r"track\.pad\.stiffness = "):
        C.pad_class(k)


def test_contact_filter_and_wheel_transfer_columns_chosen_by_the_stated_rule():
    assert C.contact_filter_column(1e5, 1.15) == (100.0, 920.0)  # railgrowth's default wheel: P D = 115 kN m
    assert C.contact_filter_column(50e3, 0.36) == (50.0, 360.0)
    assert C.contact_filter_column(25e3, 0.92) == (25.0, 920.0)
    assert C.contact_filter_column(50e3, 0.70) == (50.0, 680.0)
    assert C.vehicle_transfer_diameter(1.15) == 1200.0 and C.vehicle_transfer_diameter(0.86) == 840.0
    with pytest.raises(ValueError, match="contact filter column"):
        C.contact_filter((75.0, 920.0))


def test_railgrowth_bands_map_onto_the_cnossos_bands_and_unresolved_bands_are_filled_and_labelled():
    from rail.studies.exports import rolling_noise_bands
    centres = rolling_noise_bands().centre
    level = np.linspace(10, -20, 35)
    level[:3] = np.nan  # longer than the period
    level[-2:] = np.nan  # shorter than the record resolves
    got, source = C.rail_roughness_on_bands(centres, level, fill=C.rail_roughness_class("M"), fill_source="Table G-1b M")
    np.testing.assert_array_equal(got[3:-2], level[3:-2])
    np.testing.assert_array_equal(got[:3], T.RAIL_ROUGHNESS["M"][:3])
    np.testing.assert_array_equal(got[-2:], T.RAIL_ROUGHNESS["M"][-2:])
    assert list(source[:4]) == ["Table G-1b M"] * 3 + ["model"] and source[-1] == "Table G-1b M"
    # without a fill the bands stay empty (never zero) and say so
    got, source = C.rail_roughness_on_bands(centres[5:9], [1.0, 2.0, 3.0, 4.0])
    assert np.isnan(got[:5]).all() and np.isnan(got[9:]).all() and list(got[5:9]) == [1.0, 2.0, 3.0, 4.0]
    assert source[0] == "" and source[5] == "model"
    # a nominal label names its band as its exact centre does (125 mm: exact 10^-0.9 = 125.9 mm)
    a, _ = C.rail_roughness_on_bands([0.125], [3.0])
    b, _ = C.rail_roughness_on_bands([10 ** -0.9], [3.0])
    assert a[12] == b[12] == 3.0


def test_a_sinusoid_from_railgrowths_export_keeps_its_level_on_the_cnossos_band():
    # a 10 um amplitude at 50 mm through railgrowth's own band processing: 16.99 dB re 1 um (rms 7.07 um)
    from rail.studies.exports import rolling_noise_bands, rolling_noise_levels
    L, J = 0.6, 64
    Z = np.zeros(2 * J + 1, complex)
    j = 12  # 0.6 m / 12 = 50 mm
    Z[J + j] = Z[J - j] = 10e-6 / 2
    level, _ = rolling_noise_levels(Z, L)
    got, source = C.rail_roughness_on_bands(rolling_noise_bands().centre, level)
    k = list(T.WAVELENGTH_LABELS_MM).index(50.0)
    assert got[k] == pytest.approx(16.99, abs=0.01) and source[k] == "model"


@pytest.mark.parametrize("bad, match", [
    ([0.11], r"wavelength 0.11 m is not a one-third-octave band .* the nearest is 100 mm"),
    ([0.1, 0.1], "names the band 100 mm again"),
])
def test_an_off_band_or_repeated_wavelength_is_refused(bad, match):
    with pytest.raises(ValueError, match=match):
        C.rail_roughness_on_bands(bad, np.zeros(len(bad)))


# --- input checks -------------------------------------------------------------------------------------------

@pytest.mark.parametrize("v", [float("nan"), float("inf"), 5.0, 120.0, -3.0, "fast"])
def test_a_speed_outside_the_tables_range_is_refused_naming_speed_and_range(v):
    with pytest.raises(ValueError, match=r"speed = .* is not allowed.*"):
        C.check_speed(v)
    with pytest.raises(ValueError, match=r"speed = "):
        C.wavelength_to_frequency(np.zeros(35), v)


def test_the_speed_range_is_where_the_bands_read_the_tables_ends():
    assert C.SPEED_MIN == pytest.approx(7.943, abs=1e-3) and C.SPEED_MAX == 100.0
    n = C.wavelength_index(C.SPEED_MIN)
    assert n.max() == pytest.approx(31, abs=1e-9)  # 10 kHz reads 0.8 mm
    assert C.wavelength_index(C.SPEED_MAX).min() == pytest.approx(-3, abs=1e-9)  # 50 Hz reads 2000 mm
    with pytest.raises(ValueError, match="7.94 .. 100 m/s"):
        R.TrafficClass(R.Vehicle("v"), 10.0, 7.9)


@pytest.mark.parametrize("kwargs, match", [
    ({"brake": "drum"}, r"brake = 'drum' is not allowed: Table G-1a gives cast_iron, composite, disc"),
    ({"axles": 0}, r"axles = 0 is not allowed"),
    ({"axles": float("nan")}, r"axles = nan is not allowed"),
    ({"wheel_load": float("nan")}, r"wheel_load = nan is not allowed"),
    ({"wheel_diameter": -0.9}, r"wheel_diameter = -0.9 is not allowed"),
])
def test_a_bad_vehicle_is_refused_naming_the_parameter(kwargs, match):
    with pytest.raises(ValueError, match=match):
        R.Vehicle("v", **kwargs)


def test_bad_track_traffic_and_roughness_are_refused_with_clear_messages():
    with pytest.raises(ValueError, match="sleeper = 'steel' is not allowed"):
        R.Track("steel")
    with pytest.raises(ValueError, match="pad = 'firm' is not allowed for monoblock"):
        R.Track("monoblock", "firm")
    with pytest.raises(ValueError, match="pad = 'soft' is not allowed for wooden"):
        R.Track("wooden", "soft")
    with pytest.raises(ValueError, match=r"vehicles_per_hour = 0 is not allowed"):
        R.TrafficClass(R.Vehicle("v"), 0, 30.0)
    with pytest.raises(ValueError, match=r"vehicles_per_hour = nan is not allowed"):
        R.TrafficClass(R.Vehicle("v"), float("nan"), 30.0)
    with pytest.raises(ValueError, match="without traffic there is no noise"):
        R.rolling_noise(np.zeros(35), R.Track(), [])
    with pytest.raises(ValueError, match="no roughness level in any band"):
        R.rolling_noise(np.full(35, np.nan), R.Track(), R.TrafficClass(R.Vehicle("v"), 1.0, 30.0))
    with pytest.raises(ValueError, match="rule = 'log' is not allowed"):
        C.wavelength_to_frequency(np.zeros(35), 30.0, "log")
    with pytest.raises(ValueError, match="rail roughness class = 'N'"):
        C.rail_roughness_class("N")


# --- the API -----------------------------------------------------------------------------------------------

def _growth_run(amplitudes, V=30.0, J=64, j=12):
    """A growth dataset of one cosine at line j (0.6 m / 12 = 50 mm) growing through the saves."""
    import xarray as xr
    n = np.arange(len(amplitudes)) * 1e5
    Z = np.zeros((len(n), 2 * J + 1), complex)
    Z[:, J + j] = Z[:, J - j] = np.asarray(amplitudes) / 2
    import yaml
    from rail.app import api
    study = api.load("default")  # the provenance a growth run writes: api.noise checks it (grown_for)
    return xr.Dataset({"Z_real": (("passage", "h"), Z.real), "Z_imag": (("passage", "h"), Z.imag)},
                      coords={"passage": n}, attrs={"bays": 1, "speed_m_per_s": V, "scenario": study.name,
                                                    "config": yaml.safe_dump(study.config, sort_keys=True)})


def test_api_noise_follows_the_growing_band_and_labels_every_band():
    from rail.app import api
    study = api.load("default")
    ds = api.noise(study, _growth_run([1e-6, 3e-6, 9e-6])).data
    k = list(T.WAVELENGTH_LABELS_MM).index(50.0)
    # Parseval: a cosine of amplitude a has rms a / sqrt(2): 20 lg(9 um / sqrt(2) / 1 um) = 16.08 dB
    assert ds["rail_roughness"].values[2, k] == pytest.approx(20 * math.log10(9 / math.sqrt(2)), abs=1e-9)
    assert ds["rail_roughness_source"].values[k] == "model"
    assert ds["rail_roughness_source"].values[0] == "CNOSSOS-EU Table G-1b class M"  # 2 m: longer than the 0.6 m period
    k315 = list(T.WAVELENGTH_LABELS_MM).index(315.0)  # resolved (the line 0.6 m / 2) but smooth: silence, not filled
    assert ds["rail_roughness"].values[2, k315] == -np.inf and ds["rail_roughness_source"].values[k315] == "model"
    # the study's wheel (radius 0.575 m, 100 kN) and pad (350 MN/m: medium), the traffic's 20,000 axles a day
    assert ds.attrs["pad_class"] == "medium" and ds.attrs["contact_filter_column_kN_mm"] == "(100.0, 920.0)"
    assert ds.attrs["vehicles_per_hour"] == pytest.approx(20000 / 24 / 4)
    veh = R.Vehicle("v", axles=4, brake="disc", wheel_diameter=1.15, wheel_load=1e5)
    by_hand = R.rolling_noise(ds["rail_roughness"].values[2], R.Track("monoblock", "medium"),
                              R.TrafficClass(veh, 20000 / 24 / 4, 30.0))
    assert ds["line_sound_power_A"].values[2] == pytest.approx(by_hand.line_power_A, abs=1e-9)
    change = ds["line_sound_power_A_change"].values
    assert change[0] == 0 and 0 < change[1] < change[2]  # the noise rises as the band grows
    for name in ds.data_vars:
        assert ds[name].attrs["units"] is not None and ds[name].attrs["long_name"]


def test_api_noise_refuses_a_fleet_run_for_a_scenario_without_its_fleet_and_a_speed_out_of_range():
    from rail.app import api
    from rail.setup.config import ConfigError
    study = api.load("default")
    g = _growth_run([1e-6])
    g.attrs["fleet_speeds"] = "30, 40"
    with pytest.raises(ConfigError, match="a fleet's run and default has no fleet"):
        api.noise(study, g)
    with pytest.raises(ValueError, match=r"growth speed = 5.0 m/s is not allowed"):
        api.noise(study, _growth_run([1e-6], V=5.0))
