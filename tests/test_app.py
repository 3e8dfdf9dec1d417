"""railgrowth from Python and from the command line (issue 23): the worked example runs, the
command line validates before computing and writes a self-describing file."""

import re
import runpy

import numpy as np
import pytest
import xarray as xr

from rail.app import api, cli
from rail.setup.config import ConfigError


@pytest.mark.slow
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
    assert re.search(match, err), err


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


# issue 32: the arguments of the Python API are checked before anything is computed, with one line
# naming the argument, its value and what is allowed


@pytest.mark.parametrize("speeds", ["89", "40", [], (), [40.0, float("nan")], float("nan"), -4.0, 0, True, [40.0, True],
                                    [40.0, "50"], None, float("inf")])
def test_spectrum_refuses_speeds_that_are_not_positive_numbers_before_computing(default_study, nothing_computed, speeds):
    # a string is not a list of speeds ('89' is not 8 and 9 m/s); bools are not speeds
    with pytest.raises(ConfigError, match=r"^speeds = .+ is not allowed: it must be a finite number > 0 \(m/s\) or a non-empty "
                                          r"list of them"):
        api.spectrum(default_study, speeds=speeds)


def test_spectrum_refuses_settings_it_cannot_resolve_before_computing(default_study, nothing_computed):
    with pytest.raises(ConfigError, match=r"^bays = 'x' is not allowed: it must be a whole number >= 1\.$"):
        api.spectrum(default_study, speeds=40.0, bays="x")
    with pytest.raises(ValueError, match=r"a roughness period of 2 bays spaces the lines by 50 % at 0\.6 m, coarser than 1/30 octave"):
        api.spectrum(default_study, speeds=40.0, bays=2)


@pytest.mark.parametrize("kwargs, message", [
    ({"speed": "40"}, r"^speed = '40' is not allowed: it must be a finite number > 0 \(a train speed in m/s\)\.$"),
    ({"speed": True}, r"^speed = True is not allowed: it must be a finite number > 0"),
    ({"speed": float("nan")}, r"^speed = nan is not allowed: it must be a finite number > 0"),
    ({"speed": -40.0}, r"^speed = -40\.0 is not allowed: it must be a finite number > 0"),
    ({"speed": 40.0, "passages": -10}, r"^passages = -10 is not allowed: it must be a whole number >= 1\.$"),
    ({"speed": 40.0, "passages": "20000"}, r"^passages = '20000' is not allowed: it must be a whole number >= 1\.$"),
])
def test_growth_refuses_a_speed_or_passages_that_are_not_numbers_in_range_before_computing(default_study, nothing_computed,
                                                                                          kwargs, message):
    with pytest.raises(ConfigError, match=message):
        api.growth(default_study, **kwargs)


def test_load_refuses_a_name_or_changes_of_the_wrong_kind():
    with pytest.raises(ConfigError, match=r"^name = 123 is not allowed: it must be 'default', a scenario's name "
                                          r"\(config/scenarios/<name>\.yaml\) or the path of a scenario YAML file\.$"):
        api.load(123)
    for changes in ([1, 2], "track", 3):
        with pytest.raises(ConfigError, match=r"^changes = .+ is not allowed: it must be a dict nested like the YAML"):
            api.load("x", changes=changes)


# issue 32: a result file is written whole or not at all, and an output folder that is missing is
# found before the computation, not after it


def test_a_failed_write_leaves_the_old_file_whole_and_no_partial_file(tmp_path, monkeypatch):
    from rail.setup import io as rio

    target = tmp_path / "result.nc"
    rio.write_netcdf(xr.Dataset({"a": ("x", np.arange(3.0))}), target)
    old = target.read_bytes()

    def fails_midway(self, path, *args, **kwargs):
        with open(path, "wb") as f:  # some bytes written, then the disk is full
            f.write(b"\x89HDF\r\n\x1a\n partial")
        raise OSError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", fails_midway)
    with pytest.raises(OSError, match=r"could not write .*result\.nc: NetCDF: HDF error\. Free space there"):
        rio.write_netcdf(xr.Dataset({"b": ("x", np.ones(4))}), target)
    assert target.read_bytes() == old
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.nc"]
    monkeypatch.undo()
    rio.write_netcdf(xr.Dataset({"b": ("x", np.ones(4))}), target)  # a write that succeeds replaces it
    with xr.open_dataset(target) as ds:
        assert list(ds.data_vars) == ["b"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.nc"]


@pytest.mark.parametrize("option", ["--out", "--checkpoint"])
def test_run_refuses_a_missing_output_folder_before_computing(tmp_path, monkeypatch, capsys, option):
    def never(*args, **kwargs):
        raise AssertionError("computed before the output folder was checked")

    monkeypatch.setattr(api, "growth", never)
    missing = tmp_path / "no_such_folder"
    assert cli.main(["run", "default", "--speed", "40", option, str(missing / "g.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"railgrowth: {option} {missing / 'g.nc'}: the folder {missing} does not exist (create it first)."
    assert not missing.exists()


def test_spectrum_refuses_an_output_that_is_a_folder_before_computing(tmp_path, monkeypatch, capsys):
    def never(*args, **kwargs):
        raise AssertionError("computed before the output was checked")

    monkeypatch.setattr(api, "spectrum", never)
    assert cli.main(["spectrum", "default", "--speed", "40", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.strip() == f"railgrowth: --out {tmp_path}: is a folder; give a file name."


# issue 32 (item 6): a scenario file may end in .yml as well as .yaml; two files of one name are refused


def test_load_finds_a_scenario_file_ending_in_yml(root, tmp_path):
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    (tmp_path / "config/scenarios/stiff_pad.yml").write_text("track:\n  pad:\n    stiffness: 1.0e+9\n")
    study = api.load("stiff_pad", root=tmp_path)
    assert study.config["track"]["pad"]["stiffness"] == 1.0e9


def test_load_refuses_two_scenario_files_of_one_name(root, tmp_path):
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    (tmp_path / "config/scenarios/soft_pad.yml").write_text("track:\n  pad:\n    stiffness: 1.0e+9\n")
    with pytest.raises(ConfigError, match=r"soft_pad\.yaml and .*soft_pad\.yml: both give the scenario name 'soft_pad'; keep one of them"):
        api.load("soft_pad", root=tmp_path)


# Issue 32 (unclear cases): a file that does not exist, a project folder that does not exist and a
# file that is not YAML give one line and exit 2, never a traceback
@pytest.mark.parametrize("argv, message", [
    (["check", "/nonexistent.yaml"], r"^railgrowth: /nonexistent\.yaml: No such file or directory$"),
    (["--root", "/nonexistent", "check", "default"], r"^railgrowth: /nonexistent/config/schema/config\.schema\.yaml: No such file"),
    (["check", "{tab}"], r"^railgrowth: .*tab\.yaml, line 2, column 1: not valid YAML: found character '\\t' that cannot start any token"),
])
def test_command_line_failures_are_one_line(tmp_path, capsys, argv, message):
    import re

    tab = tmp_path / "tab.yaml"
    tab.write_text("track:\n\tpad: 1\n")
    assert cli.main([a.format(tab=tab) for a in argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and re.search(message, err), err


# Issue 57, item 2: the command line never discards a computed growth. `run --bands` with 10,000
# passages computed the growth and then exited 2 ("band growth needs at least 3 saved passage
# counts, got 2") writing nothing; a run stopped by multiple contact with --bands exited 2 and wrote
# nothing (without --bands: exit 3 and the partial file).
def test_run_with_bands_refuses_a_run_too_short_for_the_band_view_before_computing(tmp_path, nothing_computed, capsys):
    out = tmp_path / "x.nc"
    assert cli.main(["run", "default", "--speed", "40", "--passages", "10000", "--out", str(out), "--bands"]) == cli.EXIT_INPUT
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith("railgrowth: --bands is not possible with --passages 10000 and growth.save_every "
                                              "= 10000 of scenario default: it fits each band's growth to at least 3 saved "
                                              "passage counts"), err
    assert "this run would save 2 (at 0 and 10,000 passages); give --passages of at least 20000" in err
    assert list(tmp_path.iterdir()) == []


def test_run_with_bands_stopped_by_multiple_contact_writes_the_partial_file_and_exits_3(tmp_path, capsys):
    # the report's contact at 30 um, 10 mm: multiple contact at 0 passages (tests/test_normal_chain.py)
    mine = tmp_path / "rough.yaml"
    mine.write_text("contact:\n  normal: report\nnumerics:\n  contact:\n    nodes: 41\nroughness:\n  kind: harmonic\n"
                    "  amplitude: 3.0e-5\n  wavelength: 0.01\n")
    out = tmp_path / "rough.nc"
    assert cli.main(["run", str(mine), "--speed", "40", "--passages", "20000", "--out", str(out), "--bands"]) == cli.EXIT_PARTIAL
    said = capsys.readouterr().out
    assert f"wrote {out} (partial: growth stopped at 0 passages: multiple contact" in said
    assert (f"band view not written: the run stopped with 1 saved passage count(s), and the band view fits each band's growth "
            f"to at least 3; the growth file {out} holds every state kept.") in said
    with xr.open_dataset(out) as ds:
        assert list(ds["passage"].values) == [0] and "multiple contact" in ds.attrs["stopped"]
    assert not (tmp_path / "rough_bands.nc").exists()


@pytest.fixture(scope="module")
def default_growth(default_study):
    """api.growth of the default scenario at 40 m/s over 20,000 passages (3 saves; about 3 s)."""
    import io

    return api.growth(default_study, speed=40.0, passages=20000, progress=io.StringIO())


def test_run_with_bands_of_a_run_stopped_after_three_saves_writes_the_growth_and_its_band_view_and_exits_3(tmp_path, monkeypatch,
                                                                                                            capsys, default_growth):
    stopped = default_growth.copy()
    stopped.attrs["stopped"] = "growth stopped at 20000 passages: contact lost (a stand-in); every state saved up to here is kept."
    monkeypatch.setattr(api, "growth", lambda *a, **k: stopped)
    out = tmp_path / "x.nc"
    assert cli.main(["run", "default", "--speed", "40", "--passages", "20000", "--out", str(out), "--bands"]) == cli.EXIT_PARTIAL
    said = capsys.readouterr().out
    assert said.index(f"wrote {out} (partial: ") < said.index(f"wrote {tmp_path / 'x_bands.nc'}")  # the growth first
    assert out.exists() and (tmp_path / "x_bands.csv").exists()


# Issue 57, item 3: `railgrowth bands <scenario with sleeper spacing 0.65> results/growth/default/V40.nc`
# relabelled every wavelength and frequency (0.6 m / 66.7 Hz became 0.65 m / 61.5 Hz) with the same
# levels; `bands` compares the file's scenario and configuration with the study's
def test_bands_refuses_a_growth_file_of_another_configuration_naming_what_differs(tmp_path, capsys, default_growth):
    from rail.setup.io import write_netcdf

    growth = tmp_path / "V40.nc"
    write_netcdf(default_growth, growth)
    wide = api.load("default", changes={"track": {"sleeper": {"spacing": 0.65}}})
    with pytest.raises(ConfigError, match=r"was computed for another scenario or configuration than default: .* What differs "
                                          r"\(the result's / default's\): track\.sleeper\.spacing: 0\.6 / 0\.65\. Give"):
        api.bands(wide, default_growth)
    mine = tmp_path / "wide.yaml"  # a scenario file: its contact defaults differ from config.yaml's too
    mine.write_text("track:\n  sleeper:\n    spacing: 0.65\n")
    assert cli.main(["bands", str(mine), str(growth), "--out", str(tmp_path / "wide_bands.nc")]) == cli.EXIT_INPUT
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith(f"railgrowth: {growth}: was computed for another scenario or configuration than wide"), err
    assert "scenario: 'default' / 'wide'" in err and "track.sleeper.spacing: 0.6 / 0.65" in err, err
    assert not list(tmp_path.glob("wide_bands*"))
    # its own scenario views it, over the period the file was grown for
    assert cli.main(["bands", "default", str(growth), "--out", str(tmp_path / "own.nc")]) == 0
    with xr.open_dataset(tmp_path / "own.nc") as b:
        assert b.attrs["period_m"] == pytest.approx(0.6, rel=1e-12)


def test_bands_refuses_a_file_run_at_a_default_the_study_changes(default_growth):
    # A key at its schema default is not recorded in a result (rail.setup.targets.read_part), so a study that
    # sets it otherwise (friction falling with slip) must still differ from the file: the comparison goes
    # both ways (a one-way check over the file's keys let this through)
    falling = api.load("default", changes={"contact": {"friction_decay": 5.0, "friction_static": 0.4}})
    with pytest.raises(ConfigError, match=r"contact\.friction_decay: not given / 5"):
        api.bands(falling, default_growth)
