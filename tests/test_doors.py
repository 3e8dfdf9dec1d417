"""Issue 45 (doors that disagree): the command line, the API and the workflow accept and refuse the
same input with the same one-line message, before anything is computed; library functions refuse
nonsense naming the parameter, its value and the valid range."""

import math
import re

import pytest

from rail.app import api, cli
from rail.setup.config import ConfigError

from fleets import TWO_VEHICLES

FLEET = TWO_VEHICLES


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


# item 10: a YAML alias bomb (nine lines, 9**9 values once expanded) ended in a MemoryError inside the
# schema's validator after 44 s; it is refused while the file is read, before anything is built
def test_a_yaml_alias_bomb_is_refused_while_reading_naming_the_file(tmp_path, capsys):
    lines, prev = ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]'], "a"
    for name in "bcdefghi":
        lines.append(f"{name}: &{name} [{', '.join([f'*{prev}'] * 9)}]")
        prev = name
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text("\n".join(lines) + "\n")
    assert cli.main(["check", str(bomb)]) == 2
    err = capsys.readouterr().err.strip()
    assert re.fullmatch(r"railgrowth: .*bomb\.yaml: holds more than 100000 values once its aliases \(\*name\) are expanded: .*", err)
    with pytest.raises(ConfigError, match=r"bomb\.yaml: holds more than 100000 values"):
        api.load(bomb)


def test_a_yaml_file_with_a_few_aliases_is_read_as_written(tmp_path):
    from rail.setup.config import load_yaml

    path = tmp_path / "aliases.yaml"
    path.write_text("pad: &pad {stiffness: 1.0e+9, loss_factor: 0.2}\ntrack:\n  pad: *pad\n")
    assert load_yaml(path) == {"pad": {"stiffness": 1.0e9, "loss_factor": 0.2}, "track": {"pad": {"stiffness": 1.0e9, "loss_factor": 0.2}}}


# item 11: library functions refuse nonsense naming the parameter, its value and the valid range
# (validated in the Python wrappers: the compiled kernels are untouched)
NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize("speed", [-40.0, NAN, 0.0, INF])
def test_carter_refuses_a_speed_that_is_not_a_finite_positive_number(speed):
    import numpy as np

    from rail import contact as C

    m = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)
    with pytest.raises(ValueError, match=rf"^carter: speed = {speed!r} m/s is not allowed: it must be a finite number > 0 "
                                         r"\(valid range \(0, inf\)\)\.$"):
        C.carter(np.zeros(1), 1e5, m, speed, 0.46)


def test_carter_keeps_its_numbers_for_valid_input():
    # Carter's total force mu P (1 - (c/a)^2) with 1 - c/a = |gamma| / (pi k mu p0): written out here
    import numpy as np

    from rail import contact as C
    from rail.contact.hertz import compliance, hertz_half_length

    m = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)
    a = float(hertz_half_length(1e5, 0.46, m))
    frac = 0.001 / (np.pi * compliance(m) * 0.3 * 1e5 / (np.pi * a * 0.008))
    assert C.carter(np.zeros(1), 1e5, m, 40.0, 0.46)[2] == pytest.approx(0.3 * 1e5 * (1 - (1 - frac) ** 2), rel=1e-12)


@pytest.mark.parametrize("omega", [NAN, INF, -1.0, [10.0, NAN]])
def test_halfspace_receptance_refuses_a_frequency_that_is_not_finite_and_non_negative(omega):
    from rail import halfspace

    m = halfspace.ElasticMaterial(2.1e11, 0.25, 7850.0)
    with pytest.raises(ValueError, match=r"^omega = .+ rad/s is not allowed: it must be a finite number >= 0 \(valid range \[0, inf\)\)\.$"):
        halfspace.point_receptance_imag(omega, m)
    if not isinstance(omega, list):
        with pytest.raises(ValueError, match=r"^omega = .+ rad/s is not allowed"):
            halfspace.surface_displacement(0.01, omega, m)


@pytest.mark.parametrize("nu", [0.7, 0.5, -1.0, NAN])
def test_contact_material_refuses_a_poisson_ratio_outside_the_isotropic_range(nu):
    from rail import contact as C

    with pytest.raises(ValueError, match=rf"^poisson_ratio = {nu!r} is not allowed: it must lie in \(-1, 0\.5\)"):
        C.ContactMaterial(2.1e11, nu, 0.008, 0.46, 0.3, 0.3, -0.001)


@pytest.mark.parametrize("length, period, message", [
    (3.0, -0.6, r"^period = -0\.6 m is not allowed: it must be a finite number > 0"),
    (3.0, 0.0, r"^period = 0\.0 m is not allowed"),
    (3.0, NAN, r"^period = nan m is not allowed"),
    (-3.0, 0.6, r"^length = -3\.0 m is not allowed: it must be a finite number >= 0"),
    (INF, 0.6, r"^length = inf m is not allowed"),
])
def test_record_segments_refuses_a_negative_or_non_finite_length_or_period(length, period, message):
    from rail.roughness import record_segments

    with pytest.raises(ValueError, match=message):
        record_segments(length, period)
    assert record_segments(3.0, 0.6) == (5, 0.0) and record_segments(0.5, 0.6) == (0, 0.5)


# item 7: `check` passed a profile height of 1e6 m, a spectrum band at 1e6 dB and a decay rate in kHz
# under a Hz header; every file value is now checked against a stated plausible range where it is read
# (rail.roughness, rail.decay, rail.interaction), so every door refuses it in one line
def _profile(tmp_path, height):
    x = [i * 0.001 for i in range(700)]
    rows = [f"{xi:.3f},{(1e-6 if i % 2 else -1e-6):.1e}" for i, xi in enumerate(x)]
    rows[10] = f"{x[10]:.3f},{height}"
    path = tmp_path / "profile.csv"
    path.write_text("position_m,height_m\n" + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("file, key, make, message", [
    ("profile", "roughness", lambda t: _profile(t, "1e6"),
     r"profile\.csv, line 12: height 1e\+06 m is not allowed: a rail-head roughness profile lies within ±10 mm "
     r"\(valid range \[-0\.01, 0\.01\] m\)"),
    ("spectrum", "roughness", None,
     r"spectrum\.csv, line 3: level 1e\+06 dB re 1 µm is not allowed: a rail or wheel roughness level lies in \[-80, 60\] dB re 1 µm"),
    ("decay", "measured.decay_rate", None,
     r"decay\.csv, line 2: band_centre_Hz = 0\.1 Hz is not allowed: it looks like kHz \(0\.1 kHz = 100 Hz\); a one-third-octave "
     r"band centre of a track decay rate lies in \[10, 20000\] Hz"),
    ("coefficients", "roughness", None, r"coefficients\.csv, line 2: the amplitudes 1\.0,0\.0 m are not allowed: .*±10 mm"),
])
def test_check_refuses_implausible_file_values_naming_file_line_value_and_range(tmp_path, capsys, file, key, make, message):
    spectrum = tmp_path / "spectrum.csv"
    spectrum.write_text("wavelength_m,level_dB\n0.1,2.0\n0.08,1e6\n0.063,1.0\n")
    decay = tmp_path / "decay.csv"
    decay.write_text("band_centre_Hz,decay_rate_dB_per_m\n0.1,10.0\n0.125,8.0\n5.0,0.5\n")
    coefficients = tmp_path / "coefficients.csv"
    coefficients.write_text("k,A_m,B_m\n1,1.0,0.0\n")
    path = make(tmp_path) if make else {"spectrum": spectrum, "decay": decay, "coefficients": coefficients}[file]
    text = {"profile": f"roughness:\n  kind: profile\n  file: {path}\n",
            "spectrum": f"roughness:\n  kind: spectrum\n  file: {path}\n",
            "coefficients": f"roughness:\n  kind: file\n  file: {path}\n",
            "decay": f"measured:\n  decay_rate: {path}\n"}[file]
    scen = tmp_path / "mine.yaml"
    scen.write_text(text)
    assert cli.main(["check", str(scen)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err and f": {key}: " in err
    assert re.search(message, err), err


@pytest.mark.parametrize("header, value, message", [
    ("height_mm", "5", None),  # 5 mm: a large but possible height
    ("height_m", "0.005", None),
    ("height_mm", "30", r"height 30 mm = 0\.03 m is not allowed: it looks like µm \(30 µm\)"),
    ("height_um", "2e4", r"height 20000 µm = 0\.02 m is not allowed: a rail-head"),
    ("height_m", "nan", r"is not finite"),
])
def test_a_profile_height_is_read_within_ten_millimetres_either_way(tmp_path, header, value, message):
    from rail.roughness import read_profile_record

    path = _profile(tmp_path, value)
    path.write_text(path.read_text().replace("height_m", header))
    if message is None:
        assert read_profile_record(path).z[10] == pytest.approx(float(value) * (1e-3 if header == "height_mm" else 1.0))
    else:
        with pytest.raises(ValueError, match=message):
            read_profile_record(path)


def test_a_spectrum_level_in_micrometres_is_checked_as_decibels(tmp_path):
    from rail.roughness import read_spectrum_table

    path = tmp_path / "s.csv"
    path.write_text("wavelength_m,level_um\n0.1,2.0\n0.08,1e6\n")
    with pytest.raises(ValueError, match=r"s\.csv, line 3: level 1e\+06 µm = 120 dB re 1 µm is not allowed"):
        read_spectrum_table(path)
    path.write_text("wavelength_m,level_um\n0.1,2.0\n0.08,0.5\n")
    assert read_spectrum_table(path).level_dB == pytest.approx([20 * __import__("math").log10(2.0), 20 * __import__("math").log10(0.5)])


def test_a_decay_rate_above_a_hundred_db_per_metre_is_refused(tmp_path):
    from rail.decay import read_measured_decay_rate

    path = tmp_path / "d.csv"
    path.write_text("band_centre_Hz,decay_rate_dB_per_m\n100,10.0\n125,1000\n")
    with pytest.raises(ValueError, match=r"d\.csv, line 3: decay_rate_dB_per_m = 1000 dB/m is not allowed: a track decay rate lies "
                                         r"in \(0, 100\] dB/m"):
        read_measured_decay_rate(path)


# item 8: one cross-key check of a fleet for every door (rail.setup.inputs.fleet_checked): a fleet on a
# voided-sleeper track passed `check` and was refused by the workflow; `check` describes what runs; a
# fleet.speeds of the wrong type names the accepted forms
VOIDED_SPECTRUM = {"bays": 4, "shortest": 0.02, "longest": 0.14, "per_octave": 12}  # the cell's period: fleet.spectrum
VOIDED = """track:
  cell:
    bays: 4
    ballast: [1.0, 1.0e-3, 1.0, 1.0]
roughness:
  bays: 4
numerics:
  track:
    harmonics: 36
"""
FLEET_VOIDED = FLEET + "  spectrum: {bays: 4, shortest: 0.02, longest: 0.14, per_octave: 12}\n" + VOIDED  # a fleet's spectrum: fleet.spectrum
CELL_MESSAGE = (r"mix\.yaml: fleet with track\.cell is not allowed: a fleet's receptance tables are one per speed shared by "
                r"its vehicles, a track cell's are its own Bloch tables")


def test_a_fleet_file_setting_figures_rate_spectrum_is_told_to_set_fleet_spectrum(tmp_path):
    # issue 45, item 14: a fleet's class spectra take fleet.spectrum (defaults sized for 2 cores, 8 GB);
    # figures.rate_spectrum in a fleet file would be silently unused, so it is refused in one line
    from rail.setup.config import load_yaml, project_schema, resolve_scenario_file

    path = tmp_path / "mix.yaml"
    path.write_text(FLEET + "figures:\n  rate_spectrum:\n    per_octave: 30\n")
    with pytest.raises(ConfigError, match=r"mix\.yaml: figures\.rate_spectrum\.per_octave is not used by a fleet: its class spectra "
                                          r"take fleet\.spectrum \(docs/traffic\.md\); set fleet\.spectrum\.per_octave instead\.$"):
        api.load(path)
    path.write_text(FLEET + "figures:\n  rate_spectrum:\n    speeds: [40.0]\n")  # speeds: unused by a fleet, harmless
    study = api.load(path)
    assert {k: study.config["figures"]["rate_spectrum"][k] for k in ("bays", "shortest", "longest", "per_octave", "eps", "grid_phases")} == {
        "bays": 5, "shortest": 0.02, "longest": 0.3, "per_octave": 6, "eps": 1.0e-9, "grid_phases": 1}  # the schema's fleet defaults
    defaults = load_yaml(api.ROOT / "config/config.yaml")
    own = resolve_scenario_file(defaults, project_schema(), load_yaml(_written(FLEET + "  spectrum: {bays: 8, per_octave: 12}\n", tmp_path)),
                                "own.yaml")
    assert own["figures"]["rate_spectrum"]["bays"] == 8 and own["figures"]["rate_spectrum"]["per_octave"] == 12
    assert own["figures"]["rate_spectrum"]["longest"] == 0.3  # the other keys: the defaults


def _written(text, tmp_path):
    path = tmp_path / "own.yaml"
    path.write_text(text)
    return path


def test_a_fleet_on_a_track_cell_is_refused_by_check_and_the_api_as_by_the_workflow(tmp_path, capsys, nothing_computed):
    path = tmp_path / "mix.yaml"
    path.write_text(FLEET_VOIDED)
    assert cli.main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert re.fullmatch(rf"railgrowth: .*{CELL_MESSAGE}.*", err) and "\n" not in err, err
    with pytest.raises(ConfigError, match=CELL_MESSAGE):
        api.load(path)


def test_the_plan_refuses_a_fleet_on_a_track_cell_with_the_same_line(root, tmp_path, schema, defaults):
    import shutil

    from rail.setup.plan import plan

    shutil.copytree(root / "config", tmp_path / "config")
    for f in (tmp_path / "config/scenarios").iterdir():
        f.unlink()
    (tmp_path / "config/traffic_study.yaml").unlink(missing_ok=True)
    (tmp_path / "config/uncertainty.yaml").unlink(missing_ok=True)
    (tmp_path / "config/scenarios/mix.yaml").write_text(FLEET_VOIDED)
    P = plan(defaults, schema, tmp_path)  # the file is left out of the run (item 9): its targets stop with the line
    assert "mix" in P.broken and "mix" not in P.fleet_classes
    with pytest.raises(ConfigError, match=CELL_MESSAGE):
        P.require("mix")


def test_check_of_a_fleet_describes_its_vehicles_and_speed_classes_not_the_unused_one_train_keys(fleet_file, capsys):
    assert cli.main(["check", str(fleet_file)]) == 0
    out = capsys.readouterr().out.strip()
    assert out == ("ok: scenario 'mix' is valid: a fleet of 2 vehicle type(s), loco (2 axles, share 0.4), coach (2 axles, share "
                   "0.6), at 3 speed(s) (37.33, 40, 42.67 m/s): 6 (vehicle, speed) classes, roughness period 1 bay(s), normal "
                   "contact nonhertzian, wear path patch; dynamic creepage from the rail's longitudinal flexibility (rod on the pads' "
                   "shear springs and the head's bending rotation (e = 91.1 mm), k_x = 1e+07 N/m per support) "
                   "(rail.creepage.rail_flexibility); the one-train keys speeds, wheels and contact.creepage are not used.\n"
                   # issue 55: a scenario file starts from the rail's flexibility (rail.setup.config.scenario_file_physics)
                   # issue 55: which wheelset each vehicle's axles run (no wheelset section: the report's fixed creepage)
                   "  wheelsets of loco: every axle (2) the report's fixed creepage (no wheelset section)\n"
                   "  wheelsets of coach: every axle (2) the report's fixed creepage (no wheelset section)")


def test_fleet_speeds_of_the_wrong_type_names_the_accepted_forms(tmp_path, capsys):
    path = tmp_path / "mix.yaml"
    path.write_text(FLEET.replace("  speeds: {distribution: uniform, low: 36.0, high: 44.0, classes: 3}", "  speeds: [40.0, 44.0]"))
    assert cli.main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert ("fleet.speeds = [40.0, 44.0] has the wrong type: it must be of type object (a mapping; the accepted forms are, e.g., "
            "{values: [40.0, 44.0], weights: [0.5, 0.5]}; or {distribution: normal, mean: 40.0, std: 4.0, classes: 5}; or "
            "{distribution: uniform, low: 36.0, high: 44.0, classes: 3})") in err, err


# item 12: no traceback for a failure a user can cause, exit status by cause (input 2, model 1 or 3,
# resource 4), a stopped run writes what it kept, no temporary file left behind
def test_a_failed_out_write_is_one_line_naming_the_file_and_exit_4(tmp_path, monkeypatch, capsys):
    import errno

    import numpy as np
    import xarray as xr

    small = xr.Dataset({"a": ("x", np.arange(3.0), {"units": "m", "long_name": "a"})})
    monkeypatch.setattr(api, "growth", lambda *a, **k: small)

    def full_disk(self, path, *args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full_disk)
    out = tmp_path / "g.nc"
    assert cli.main(["run", "default", "--speed", "40", "--out", str(out)]) == cli.EXIT_RESOURCE == 4
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err, err
    assert err.startswith(f"railgrowth: --out: could not write {out}: [Errno 28] No space left on device. Free space there:"), err
    assert list(tmp_path.iterdir()) == []


def test_a_failed_checkpoint_write_names_the_file_exits_4_and_leaves_no_temporary_file(tmp_path, monkeypatch, capsys):
    import errno

    from rail import growth

    def too_large(file, **arrays):
        with open(file, "wb") as f:
            f.write(b"PK partial")
        raise OSError(errno.EFBIG, "File too large")

    monkeypatch.setattr(growth.np, "savez", too_large)
    ck = tmp_path / "ck.npz"
    assert cli.main(["run", "default", "--speed", "40", "--passages", "20000", "--checkpoint", str(ck),
                     "--out", str(tmp_path / "g.nc")]) == 4
    err = capsys.readouterr().err.strip()
    assert err == (f"railgrowth: {ck}: could not write the checkpoint at 10000 passages: File too large (no checkpoint was "
                   "written yet; free space or give another --checkpoint, then run again to resume)"), err
    assert list(tmp_path.iterdir()) == []


def test_contact_lost_at_the_start_writes_the_state_it_kept_and_exits_3_as_multiple_contact_does(tmp_path, capsys):
    # a harmonic of 0.2 mm at 40 mm: the linear force falls to -194 kN, the contact is lost at 0 passages
    scen = tmp_path / "lost.yaml"
    scen.write_text("roughness:\n  kind: harmonic\n  amplitude: 2.0e-4\n  wavelength: 0.04\ngrowth:\n  passages: 20000\n")
    out = tmp_path / "lost.nc"
    assert cli.main(["run", str(scen), "--speed", "40", "--out", str(out)]) == 3
    captured = capsys.readouterr()
    assert f"wrote {out} (partial: growth stopped at 0 passages: contact lost: wheel 0" in captured.out
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert list(ds["passage"].values) == [0] and ds.attrs["stopped"].startswith("growth stopped at 0 passages: contact lost")
        assert float(ds["force"].min()) < 0  # the linear model's force where the contact was lost, as it was computed


# Hypothesis over the command line's check and the API with fleets and track cells: any value either
# runs (check says ok in one line; the API reaches the computation) or is refused, one line per problem
# naming it, never a traceback; nothing is computed here (the computation is replaced by a marker)
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_FUZZ_KEYS = [("fleet", "vehicles", 0, "positions"), ("fleet", "vehicles", 0, "static_load"), ("fleet", "vehicles", 0, "share"),
              ("fleet", "vehicles", 0, "creepage"), ("fleet", "vehicles", 0, "name"), ("fleet", "vehicles", 1, "unsprung_mass"),
              ("fleet", "speeds"), ("fleet", "speeds", "low"), ("fleet", "speeds", "high"), ("fleet", "speeds", "classes"),
              ("fleet", "speeds", "distribution"), ("fleet", "speeds", "values"), ("track", "cell", "bays"),
              ("track", "cell", "ballast"), ("track", "cell", "spacing"), ("roughness", "bays")]
_FUZZ_VALUE = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**4, 10**4), st.text(max_size=4), st.none(),
                        st.booleans(), st.lists(st.one_of(st.floats(-10.0, 400.0), st.sampled_from([float("nan"), float("inf")])), max_size=4),
                        st.sampled_from([{"values": [40.0], "weights": [1.0]}, {"distribution": "normal", "mean": 40.0},
                                         [36.0, 44.0], 0.0, 1e300, -1.0, 4]))


class _Reached(Exception):
    """The computation was reached: every check passed."""


def _set(tree, key, value):
    node = tree
    for k in key[:-1]:
        node = node.setdefault(k, {}) if isinstance(node, dict) else node[k]
    node[key[-1]] = value


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=st.sampled_from(_FUZZ_KEYS), value=_FUZZ_VALUE, cell=st.booleans(), fleet=st.booleans(),
       bays=st.one_of(st.none(), st.integers(-3, 10**6), st.floats(allow_nan=True, allow_infinity=True)))
def test_fuzzed_fleets_and_track_cells_run_or_are_refused_in_one_line_per_problem(tmp_path, capsys, key, value, cell, fleet, bays):
    import yaml

    scen = yaml.safe_load(FLEET)
    if cell or key[0] == "track":
        scen = {**scen, **yaml.safe_load(VOIDED)}
    if not fleet and key[0] != "fleet":
        del scen["fleet"]
    if cell or key[0] == "track":  # the spectrum's period is the cell's: a fleet's in fleet.spectrum, else figures.rate_spectrum
        if isinstance(scen.get("fleet"), dict):
            scen["fleet"]["spectrum"] = dict(VOIDED_SPECTRUM)
        else:
            scen["figures"] = {"rate_spectrum": dict(VOIDED_SPECTRUM)}
    _set(scen, key, value)
    path = tmp_path / "fuzz.yaml"
    path.write_text(yaml.safe_dump(scen))
    code = cli.main(["check", str(path)])
    out, err = capsys.readouterr()
    assert code in (0, 2), (code, err)
    if code == 0:
        # one ok line; a fleet then states each vehicle's wheelsets, a line per vehicle (issue 55)
        lines = out.splitlines()
        vehicles = [v["name"] for v in scen["fleet"]["vehicles"]] if isinstance(scen.get("fleet"), dict) else []
        assert lines[0].startswith("ok: scenario 'fuzz' is valid") and len(lines) == 1 + len(vehicles), out
        assert [ln.split(":")[0] for ln in lines[1:]] == [f"  wheelsets of {v}" for v in vehicles], out
    else:
        assert err.startswith("railgrowth: ") and "Traceback" not in err, err
        lines = err.rstrip("\n").split("\n")
        assert all(line.startswith("  ") and "fuzz.yaml" in line for line in lines[1:]), err  # one line per problem, named
        return
    study = api.load(path)  # check said ok: the API loads it too, and checks its arguments before computing
    saved = api.chain.fleet_tables, api.chain.receptance_table
    api.chain.fleet_tables = api.chain.receptance_table = lambda *a, **k: (_ for _ in ()).throw(_Reached())
    try:
        call = (lambda: api.fleet_spectrum(study, bays=bays)) if "fleet" in study.config else (
            lambda: api.spectrum(study, speeds=40.0, bays=bays))
        try:
            call()
        except _Reached:
            # a whole number (an int or a whole float such as 40.0, taken as the int) within the schema's range
            assert bays is None or (math.isfinite(bays) and bays == int(bays) and 2 <= bays <= 256), bays
        except ConfigError as e:
            assert "bays" in str(e) and "Traceback" not in str(e), str(e)
    finally:
        api.chain.fleet_tables, api.chain.receptance_table = saved


def test_a_whole_float_period_given_to_the_api_is_taken_as_the_int_it_is():
    """bays=4.0 (a whole number given as a float, as a fuzzed or computed value may be) reaches the lines as 4, an int;
    4.5 is refused naming the argument (found by the fuzz of fleets and track cells: the float went on as given)."""
    study = api.load("default")
    s, _ = api._spectrum_settings(study, "spectrum", shortest=None, longest=None, per_octave=None, bays=4.0, grid_phases=None)
    assert s["bays"] == 4 and type(s["bays"]) is int
    with pytest.raises(ConfigError, match=r"bays = 4.5 is not allowed: it must be a whole number"):
        api._spectrum_settings(study, "spectrum", shortest=None, longest=None, per_octave=None, bays=4.5, grid_phases=None)


DAMPERS_FLEX = """track:
  cell:
    bays: 2
    damper: {mass: 4.0, frequency: 1070.0, loss_factor: 0.35, position: 0.5}
roughness:
  bays: 2
numerics:
  track:
    harmonics: 36
figures:
  rate_spectrum: {bays: 2, shortest: 0.02, longest: 0.07, per_octave: 12}
rail_flexibility:
  model: rod_and_bending
"""


def test_a_track_cell_with_rail_dampers_and_the_rails_flexibility_passes_check_and_the_api(tmp_path, capsys):
    # issue 55: refused at start-up ("rail_flexibility.model ... is not allowed with track.cell") until the rail head
    # had the track cell's own receptances (rail.creepage.rail_flexibility_cell); now one ok line, and the head on the cell's supports
    from rail.creepage.rail_flexibility_cell import CellHead

    path = tmp_path / "dampers.yaml"
    path.write_text(DAMPERS_FLEX)
    assert cli.main(["check", str(path)]) == 0
    captured = capsys.readouterr()
    assert "not allowed" not in captured.err and len(captured.out.splitlines()) == 1, captured
    head = api.load(path).scenario.material.rail_flexibility
    assert isinstance(head, CellHead) and len(head.cell.dampers) == 2 and head.bending
