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
