"""railgrowth from Python and from the command line (issue 23): the worked example runs, the
command line validates before computing and writes a self-describing file."""

import runpy

import numpy as np
import pytest
import xarray as xr

from rail.app import api, cli
from rail.setup.config import ConfigError


def test_worked_example_runs(root, capsys):
    runpy.run_path(str(root / "docs/example.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "scenario soft_pad: pad stiffness" in out and "the largest harmonic is k =" in out
    assert "wavelengths that grow (mm):" in out and "dB per 100,000 passages" in out


def test_check_validates_a_scenario_file_and_names_the_problem(tmp_path, capsys):
    good = tmp_path / "stiff_pad.yaml"
    good.write_text("track:\n  pad:\n    stiffness: 1.0e+9\n")
    assert cli.main(["check", str(good)]) == 0
    assert "ok: scenario 'stiff_pad' is valid" in capsys.readouterr().out
    bad = tmp_path / "bad.yaml"
    bad.write_text("contact:\n  friction_static: .nan\n")
    assert cli.main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "bad.yaml: contact.friction_static = nan is not allowed" in err
    assert cli.main(["run", "nosuch", "--speed", "40"]) == 2
    assert "scenario 'nosuch' is not defined" in capsys.readouterr().err


def test_a_sweep_file_is_refused_by_load(root):
    with pytest.raises(ConfigError, match=r"is a sweep study"):
        api.load("sweep_speed_pad")


def test_run_writes_a_growth_file_with_its_scenario_and_units(tmp_path, capsys):
    out = tmp_path / "g.nc"
    assert cli.main(["run", "default", "--speed", "40", "--passages", "20000", "--out", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["scenario"] == "default" and "code_version" in ds.attrs
        assert list(ds["passage"].values) == [0, 10000, 20000]
        assert ds["level"].attrs["level_unit"] == "dB" and ds["level"].attrs["units"] == "1"
        assert np.all(np.isfinite(ds["profile"].values))
    assert cli.main(["run", "default", "--speed", "-4"]) == 2


# Issue 32, item 3: the command line and the API check exactly what the workflow checks at start-up
# (rail.setup.inputs.check_inputs, check_speed); each case below passed `railgrowth check` or `run`
# before.
@pytest.mark.parametrize("text, match", [
    ("roughness:\n  kind: profile\n  file: config/roughness/no_such_file.csv\n", r"roughness: .*no_such_file\.csv"),
    ("roughness:\n  kind: profile\n  file: config/roughness\n", r"roughness: .*config/roughness"),
    ("roughness:\n  kind: harmonic\n  wavelength: 0.07\n", r"roughness: .*0\.07"),
    ("measured:\n  decay_rate: {utf16}\n", r"measured\.decay_rate: "),
    ("track:\n  pad:\n    stiffness: 1.0e+300\n", r"track\.pad\.stiffness = 1e\+300 N/m is not allowed: it must be <= 1000000000000\.0 N/m"),
])
def test_check_refuses_what_the_workflow_refuses(tmp_path, capsys, text, match):
    utf16 = tmp_path / "decay.csv"
    utf16.write_text("band_centre_Hz,decay_rate_dB_per_m\n1000,2.0\n", encoding="utf-16")
    scen = tmp_path / "mine.yaml"
    scen.write_text(text.format(utf16=utf16))
    assert cli.main(["check", str(scen)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("railgrowth: ") and "Traceback" not in err
    assert re_search(match, err), err


def re_search(pattern, text):
    import re

    return re.search(pattern, text) is not None


def test_run_refuses_a_speed_the_workflow_refuses_before_computing(monkeypatch, capsys):
    # at 5 m/s the default harmonics do not reach the pinned-pinned frequency: the workflow refuses
    # results/growth/default/V5.nc; the command line refused nothing and wrote a result
    monkeypatch.setattr(api.chain, "receptance_table", lambda *a, **k: pytest.fail("computed before checking the speed"))
    assert cli.main(["run", "default", "--speed", "5"]) == 2
    assert "numerics.track.harmonics = 64 is not allowed at V = 5 m/s" in capsys.readouterr().err


def test_a_scenario_file_is_read_from_the_project_not_the_current_folder(root, tmp_path, monkeypatch):
    # a relative roughness.file names the project's file wherever the command runs from; a file of
    # the same relative name in the current folder is not read
    decoy = tmp_path / "config/roughness"
    decoy.mkdir(parents=True)
    (decoy / "synthetic_profile.csv").write_text("position_m,height_m\n0,0\n0.001,1\n")  # metres of height: nonsense
    monkeypatch.chdir(tmp_path)
    study = api.load("profile_example", root=root)
    assert study.config["roughness"]["file"] == str(root / "config/roughness/synthetic_profile.csv")
