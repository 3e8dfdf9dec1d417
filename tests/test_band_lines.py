"""Lines that resolve a frequency band at every speed (rail.growth_spectrum.band_lines, issue 54): the
lines near pinned-pinned at most 15 Hz apart over 900-1,400 Hz at 20-80 m/s, checked by computing each
speed's line frequencies, and the errors for a period too short or a band beyond L / K."""

import numpy as np
import pytest

from rail.growth_spectrum import band_lines, settings_lines, spectrum_lines

L, K = 0.6, 64


@pytest.mark.parametrize("bays", [9, 12, 24])
def test_the_band_is_resolved_at_every_speed(bays):
    speeds = [20.0, 30.0, 39.0, 40.0, 50.0, 60.0, 64.1, 80.0]
    lines = band_lines(L, bays, K, speeds, 900.0, 1400.0, 15.0)
    assert np.all(np.diff(lines) > 0)
    for V in speeds:
        f = V * lines / (bays * L)
        inside = f[(f >= 900.0) & (f <= 1400.0)]
        # neighbours inside the band, and the band's edges covered by a line at or beyond them
        assert np.max(np.diff(np.r_[f[f <= 900.0 + 1e-9].max(), inside, f[f >= 1400.0 - 1e-9].min()])) <= 15.0 + 1e-9, V
        # at least five lines within 1.00-1.15 f_pp (f_pp about 1,067 Hz on the default track)
        assert np.sum((f >= 1067.0) & (f <= 1.15 * 1067.0)) >= 5


def test_a_period_too_short_for_the_spacing_names_the_bays_needed():
    # 80 m/s on 8 bays: V / (N L) = 16.7 Hz > 15 Hz; 9 bays give 14.8 Hz
    with pytest.raises(ValueError, match="at least 9 bays"):
        band_lines(L, 8, K, [80.0], 900.0, 1400.0, 15.0)
    band_lines(L, 9, K, [80.0], 900.0, 1400.0, 15.0)


def test_a_band_beyond_the_shortest_wavelength_is_cut_at_l_over_k():
    # 1,400 Hz at 40 m/s is 28.6 mm; with K = 18 the tables reach L / K = 33.3 mm: K V / L = 1,200 Hz. The band is
    # resolved up to there (a user's scenario with fewer harmonics is not broken by the scenario files' default band)
    lines = band_lines(L, 24, 18, [40.0], 900.0, 1400.0, 15.0)
    f = 40.0 * lines / (24 * L)
    assert lines.max() == 24 * 18 and f.max() == pytest.approx(1200.0)
    assert np.max(np.diff(f)) <= 15.0 + 1e-9
    # at 20 m/s (K V / L = 600 Hz) no line of the band exists: none is added
    assert band_lines(L, 24, 18, [20.0], 900.0, 1400.0, 15.0).size == 0


@pytest.mark.parametrize("bad", [dict(low=0.0), dict(high=800.0), dict(spacing=float("nan")), dict(low=float("inf"))])
def test_bad_band_values_are_refused_naming_them(bad):
    args = dict(low=900.0, high=1400.0, spacing=15.0) | bad
    with pytest.raises(ValueError, match="band"):
        band_lines(L, 24, K, [40.0], **args)


def test_settings_lines_add_the_band_to_the_log_spaced_lines():
    s = {"shortest": 0.02, "longest": 0.6, "per_octave": 30, "speeds": [40.0, 60.0]}
    plain = settings_lines(L, 48, K, s)
    assert np.array_equal(plain, spectrum_lines(L, 48, K, 0.02, 0.6, 30))
    banded = settings_lines(L, 48, K, s | {"band": {"low": 900.0, "high": 1400.0, "spacing": 15.0}})
    assert set(plain) <= set(banded)
    assert np.array_equal(np.sort(banded), banded)
    assert set(band_lines(L, 48, K, [40.0, 60.0], 900.0, 1400.0, 15.0)) <= set(banded)


def test_scenario_files_resolve_the_band_unless_they_set_their_own_period():
    # issue 54: the scenario files' default spectrum settings resolve 900-1,400 Hz at every speed; a file that sets its
    # own period (a track cell's, the 2-bay surveys) keeps its own lines; a fleet's class spectra take fleet.spectrum's
    from pathlib import Path

    from rail.setup import config as rconfig

    root = Path(__file__).resolve().parents[1]
    schema = rconfig.load_yaml(root / "config/schema/config.schema.yaml")
    defaults = rconfig.validate_config(rconfig.load_yaml(root / "config/config.yaml"), schema, source="config/config.yaml")
    assert not defaults["figures"]["rate_spectrum"].get("band")  # config.yaml: the report's spectrum
    own = rconfig.resolve_scenario_file(defaults, schema, {"track": {"pad": {"stiffness": 1.5e8}}}, "soft.yaml")
    s = own["figures"]["rate_spectrum"]
    assert s["band"] == {"low": 900.0, "high": 1400.0, "spacing": 15.0}
    lines = settings_lines(L, int(s["bays"]), K, s)
    for V in s["speeds"]:
        f = np.sort(V * lines / (int(s["bays"]) * L))
        inside = f[(f >= 900.0 - 1e-9) & (f <= 1400.0 + 1e-9)]
        assert np.max(np.diff(inside)) <= 15.0 + 1e-9, V
    cell = rconfig.resolve_scenario_file(defaults, schema, {"figures": {"rate_spectrum": {"bays": 2}}}, "two.yaml")
    assert cell["figures"]["rate_spectrum"]["band"] is None
    import sys

    import yaml

    sys.path.insert(0, str(root / "tests"))
    from fleets import TWO_VEHICLES

    f_cfg = rconfig.resolve_scenario_file(defaults, schema, yaml.safe_load(TWO_VEHICLES), "fleet.yaml")
    assert "band" not in f_cfg["figures"]["rate_spectrum"]
