"""Issue 45 (doors that disagree): the command line, the API and the workflow accept and refuse the
same input with the same one-line message, before anything is computed; library functions refuse
nonsense naming the parameter, its value and the valid range."""

import re

import pytest

from rail.app import api, cli
from rail.setup.config import ConfigError

FLEET = """fleet:
  vehicles:
    - name: loco
      positions: [0.0, 3.3]
      static_load: 1.0e+5
      unsprung_mass: 1350.0
      creepage: [-0.001, -0.001]
      share: 0.4
    - name: coach
      positions: [0.0, 2.6]
      static_load: 5.0e+4
      unsprung_mass: 800.0
      creepage: [0.0005, 0.0005]
      share: 0.6
  speeds: {distribution: uniform, low: 36.0, high: 44.0, classes: 3}
"""


@pytest.fixture(scope="module")
def default_study():
    return api.load("default")


@pytest.fixture
def nothing_computed(monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("computed before the arguments were checked")

    monkeypatch.setattr(api.chain, "receptance_table", never)
    monkeypatch.setattr(api.chain, "fleet_tables", never)
    monkeypatch.setattr(api.chain, "grow", never)


@pytest.fixture
def fleet_file(tmp_path):
    path = tmp_path / "mix.yaml"
    path.write_text(FLEET)
    return path


# item 5: at 5 m/s the default harmonics (64) do not reach the pinned-pinned frequency: run and the
# workflow refuse it; spectrum computed it
def test_spectrum_refuses_a_speed_the_workflow_refuses_before_computing(default_study, nothing_computed, capsys):
    with pytest.raises(ConfigError, match=r"default: spectrum: .*numerics\.track\.harmonics = 64 is not allowed at V = 5 m/s"):
        api.spectrum(default_study, speeds=[40.0, 5.0])
    assert cli.main(["spectrum", "default", "--speed", "5"]) == 2
    err = capsys.readouterr().err
    assert "numerics.track.harmonics = 64 is not allowed at V = 5 m/s" in err and "Traceback" not in err


def test_spectrum_refuses_a_speed_above_the_schemas_bound(default_study, nothing_computed):
    with pytest.raises(ConfigError, match=r"speed = 400\.0 m/s is not allowed: it must lie in \(0, 300\] m/s"):
        api.spectrum(default_study, speeds=400.0)


# item 6: a fleet scenario's one-train spectrum left the fleet out without a word
def test_spectrum_of_a_fleet_scenario_is_refused_naming_the_fleet_spectrum(fleet_file, nothing_computed, capsys):
    study = api.load(fleet_file)
    with pytest.raises(ConfigError, match=r"^mix has a fleet: spectrum would compute one train .* rail\.app\.api\.fleet_spectrum"):
        api.spectrum(study, speeds=40.0)
    assert cli.main(["spectrum", str(fleet_file), "--speed", "40"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "mix has a fleet" in err and "results/fleet/mix/rate_spectrum.nc" in err


# item 10: the API's spectrum settings are checked as the schema checks figures.rate_spectrum
@pytest.mark.parametrize("kwargs, message", [
    ({"bays": 10**6}, r"argument bays = 1000000 is not allowed: it must be <= 256 .*valid range \[2, 256\]"),
    ({"bays": 1}, r"argument bays = 1 is not allowed: it must be >= 2"),
    ({"per_octave": 10**5}, r"argument per_octave = 100000 is not allowed: it must be <= 300"),
    ({"grid_phases": 100}, r"argument grid_phases = 100 is not allowed: it must be <= 16"),
    ({"longest": float("nan")}, r"argument longest = nan is not allowed: it must be a finite number"),
    ({"shortest": -1.0}, r"argument shortest = -1\.0 m is not allowed"),
])
def test_spectrum_settings_are_checked_as_the_schema_checks_them_before_computing(default_study, nothing_computed, kwargs, message):
    with pytest.raises(ConfigError, match=message):
        api.spectrum(default_study, speeds=40.0, **kwargs)
