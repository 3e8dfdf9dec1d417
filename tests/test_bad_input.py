"""Bad input never gives a quiet answer (issue 20): every item a regression test."""

import io
import re
import os

import numpy as np
import pytest
from model import scenario
from test_growth import MATERIAL, K, contact_spring, track
from test_workflow import job_counts, snakemake

from rail import chain
from rail import contact as C
from rail import growth as G
from rail import interaction as I
from rail import moving
from rail import roughness as R
from rail.setup import config as rconfig

# Runs snakemake or sphinx in a subprocess with a time limit: .ci/run runs these tests one at a time.
pytestmark = pytest.mark.workflow


def _with(cfg: dict, key: tuple, value) -> dict:
    """cfg with the nested key (a tuple of names) set to value (in place; returns cfg)."""
    node = cfg
    for k in key[:-1]:
        node = node[k]
    node[key[-1]] = value
    return cfg


# 2. names and keys that would silently replace something


def test_reserved_and_clashing_scenario_names_are_refused():
    with pytest.raises(rconfig.ConfigError, match=r"default\.yaml: the scenario name 'default' is reserved"):
        rconfig.check_scenario_names({"default": "config/scenarios/default.yaml"}, {})
    with pytest.raises(rconfig.ConfigError, match=r"the scenario name 'sweep_speed_pad-p0' has the form <study>-p<n>"):
        rconfig.check_scenario_names({"sweep_speed_pad-p0": "config/scenarios/sweep_speed_pad-p0.yaml"}, {})
    with pytest.raises(rconfig.ConfigError, match=r"'a' is also a point of the sweep"):
        rconfig.check_scenario_names({"a": "config/scenarios/a.yaml"}, {"a": "config/scenarios/s.yaml"})
    rconfig.check_scenario_names({"soft_pad": "x.yaml"}, {"s-p0": "s.yaml"})  # fine


def test_duplicated_yaml_key_is_refused_with_its_line(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text("track:\n  pad:\n    stiffness: 1.0e+8\n    stiffness: 2.0e+8\n")
    with pytest.raises(rconfig.ConfigError, match=r"s\.yaml, line 4: the key 'stiffness' is given twice in one mapping \(first at line 3\)"):
        rconfig.load_yaml(p)


@pytest.mark.parametrize(
    "text, message",
    [
        ("k,A_m,B_m\n3,1e-6,0\n3,2e-6,0\n", r"line 3: harmonic k = 3 is given twice \(first at line 2\)"),
        ("k,A_m,B_m\n", r"has a header but no harmonic"),
        ("k,A_m,B_m\n3,nan,0\n", r"line 2: the amplitudes nan,0 are not finite"),
    ],
)
def test_roughness_coefficient_file_problems_name_the_line(tmp_path, text, message):
    p = tmp_path / "r.csv"
    p.write_text(text)
    with pytest.raises(ValueError, match=message):
        I.read_roughness_coefficients(p)


def test_byte_order_mark_is_read_and_a_binary_file_is_named(tmp_path):
    p = tmp_path / "bom.csv"
    p.write_bytes("\ufeffk,A_m,B_m\n2,1e-6,0\n".encode("utf-8"))
    assert I.read_roughness_coefficients(p) == ([2], [1e-6], [0.0])
    b = tmp_path / "bin.csv"
    b.write_bytes(bytes(range(256)))
    with pytest.raises(ValueError, match=r"bin\.csv: is not a text \(UTF-8\) CSV file"):
        I.read_roughness_coefficients(b)
    with pytest.raises(ValueError, match=r"bin\.csv: is not a text \(UTF-8\) CSV file"):
        R.read_profile(b)


# 3. speeds and scenario names in target paths (dry runs: refused before any job)


@pytest.mark.slow
def test_target_speed_and_scenario_are_checked_before_any_job(root, tmp_path):
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    cases = {
        "results/growth/default/V5.nc": r"numerics\.track\.harmonics = 64 is not allowed at V = 5 m/s",
        "results/growth/default/Vinf.nc": r"target speed Vinf = inf m/s is not allowed",
        "results/receptance/default/V1e6.nc": r"target speed V1e6 = 1000000\.0 m/s is not allowed",
        "results/growth/nosuch/V40.nc": r"target names the scenario 'nosuch', which is not defined",
    }
    for target, message in cases.items():
        out = snakemake(root, "-n", target, cwd=tmp_path)
        assert out.returncode != 0, target
        assert re.search(message, out.stdout + out.stderr), (target, out.stderr[-800:])


# 4. NaN and inf are never valid


@pytest.mark.parametrize("key", [("contact", "friction_static"), ("growth", "step_tolerance"), ("track", "pad", "stiffness"),
                                 # the dynamic creepage's keys (issue 43): falling friction, the wheelset, the rail head
                                 ("contact", "friction_decay"), ("wheelset", "axle_stiffness"), ("wheelset", "damping"),
                                 ("track", "pad", "longitudinal_stiffness"), ("track", "rail", "head_height")])
@pytest.mark.parametrize("value", [float("nan"), float("inf")])
def test_nan_and_inf_fail_validation_naming_the_key(defaults, schema, key, value):
    base = {"wheelset": {"model": "torsional"}, "rail_flexibility": {"model": "rod_and_bending"}}  # the keys in use
    cfg = _with(rconfig.deep_merge(defaults, base), key, value)
    with pytest.raises(rconfig.ConfigError, match=re.escape(f"s.yaml: {'.'.join(key)} = {value!r} is not allowed: it must be a finite number")):
        rconfig.validate_config(cfg, schema, source="s.yaml")


def test_nan_wheel_position_fails_validation(defaults, schema):
    cfg = rconfig.deep_merge(defaults, {"wheels": {"positions": [0.0, float("nan")]}})
    with pytest.raises(rconfig.ConfigError, match=r"wheels\.positions\[1\] = nan is not allowed"):
        rconfig.validate_config(cfg, schema, source="s.yaml")


def test_a_vanishing_wheel_load_fails_validation(defaults, schema):
    # found by the fuzzing below: a static load of 3.9e-160 N passed, and the contact grid of a patch
    # that small asked for more memory than exists ("Maximum allowed size exceeded")
    cfg = rconfig.deep_merge(defaults, {"wheels": {"static_load": 3.9e-160}})
    with pytest.raises(rconfig.ConfigError, match=r"wheels\.static_load = 3\.9e-160 N is not allowed: it must be >= 1000 N"):
        rconfig.validate_config(cfg, schema, source="s.yaml")


# 5. the library checks its arguments


def test_library_functions_refuse_nonsense_with_the_quantity_named():
    tr = track()
    with pytest.raises(ValueError, match=r"rtol = 0 is not allowed: the quadrature tolerance must lie in \(0, 1\)"):
        moving.receptance_table(tr, 40.0, 4, rtol=0)
    with pytest.raises(ValueError, match=r"contact\.hertz_stiffness = -1 N/m is not allowed"):
        I.ContactSpring(-1)
    with pytest.raises(ValueError, match=r"growth\.save_every = 0 is not allowed: it must be >= 1"):
        G.GrowthSettings(1000, 100, 0, True, 0.05)
    with pytest.raises(ValueError, match=r"growth\.step_tolerance = nan is not allowed"):
        G.GrowthSettings(1000, 100, 100, True, float("nan"))
    m = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)
    with pytest.raises(ValueError, match=r"speed = 0\.0 m/s and delta = 0\.001 m are not allowed"):
        C.solve_tangential(np.full(3, 1e5), np.full(3, 0.006), m, 0.0, 1e-3, 8)
    with pytest.raises(ValueError, match=r"P and a must be 1-d arrays of one length"):
        C.solve_tangential(np.full(3, 1e5), np.full(4, 0.006), m, 40.0, 1e-3, 8)
    with pytest.raises(ValueError, match=r"normal force P = -1\.0 N is not allowed in the Hertz contact \(eq 23\): it must be a finite number >= 0"):
        C.hertz_half_length(np.array([1e5, -1.0]), 0.5, m)
    with pytest.raises(ValueError, match=r"normal force P = nan N is not allowed"):
        C.hertz_half_length(float("nan"), 0.5, m)
    with pytest.raises(ValueError, match=r"equivalent radius R = 0\.0 m is not allowed"):
        C.hertz_half_length(1e5, 0.0, m)
    assert C.hertz_half_length(0.0, 0.5, m) == 0.0  # no load, no patch: allowed
    from rail import decay

    with pytest.raises(ValueError, match=r"spacing = -1 m is not allowed: the sleeper spacing must be a finite number > 0"):
        decay.decay_distances(-1)
    with pytest.raises(ValueError, match=r"max_bays = inf is not allowed"):
        decay.decay_distances(0.6, float("inf"))


def test_non_finite_roughness_is_named_as_roughness():
    tr = track()
    tab = moving.receptance_table(tr, 40.0, 4)
    Z = np.zeros(9, dtype=complex)
    Z[6] = Z[2] = np.nan
    with pytest.raises(ValueError, match=r"the roughness coefficients are not finite"):
        I.solve_forces(tab, I.Wheels(1350.0, 0.575, 1e5, (0.0,)), I.ContactSpring(1.4e9), I.Roughness(Z), tr.L)


# 6. a checkpoint that cannot be read never blocks a run


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04 truncated", os.urandom(300)])
def test_unreadable_checkpoint_is_moved_aside_and_the_run_starts_afresh(tmp_path, content):
    ck = tmp_path / "run.npz"
    ck.write_bytes(content)
    log = io.StringIO()
    tr = track()
    tab = moving.receptance_table(tr, 40.0, K)
    scn = scenario(tr, MATERIAL, contact_spring(), K=K, passages=10000, step=10000)
    got = chain.grow(scn, tab, I.Roughness.smooth(K), checkpoint=ck, progress=log, on_mismatch="restart")
    assert "cannot be read" in log.getvalue() and "starting afresh" in log.getvalue()
    assert (tmp_path / "run.npz.unreadable").read_bytes() == content
    fresh = chain.grow(scn, tab, I.Roughness.smooth(K), progress=io.StringIO())
    np.testing.assert_array_equal(got.Z, fresh.Z)


# Property-based: fuzzed CSV files and configuration values either pass or fail with a message
# that names the file or the key (Hypothesis; no other exception type, no traceback)

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_READERS = {
    "k,A_m,B_m": I.read_roughness_coefficients,
    "position_m,height_m": R.read_profile,
    "wavelength_m,level_dB": R.read_third_octave_spectrum,
}
_cell = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), st.integers(-5, 60).map(str),
                  st.sampled_from(["", "abc", "1e-6", "-0.1", "1,2", "\ufeff", "nan"]))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(header=st.sampled_from(sorted(_READERS) + ["x,y", ""]), rows=st.lists(st.lists(_cell, min_size=0, max_size=4), max_size=6),
       which=st.sampled_from(sorted(_READERS)), raw=st.one_of(st.none(), st.binary(max_size=40)))
def test_fuzzed_csv_either_reads_finite_values_or_names_the_file(tmp_path, header, rows, which, raw):
    p = tmp_path / "fuzz.csv"
    if raw is not None:
        p.write_bytes(raw)
    else:
        p.write_text(header + "\n" + "".join(",".join(r) + "\n" for r in rows))
    try:
        out = _READERS[which](p)
    except ValueError as e:
        assert str(p) in str(e)
        return
    for arr in out:
        assert len(arr) > 0 and np.all(np.isfinite(np.asarray(arr, dtype=float)))


_KEYS = [("contact", "friction_static"), ("contact", "creepage"), ("growth", "passages"), ("growth", "save_every"),
         ("growth", "step_tolerance"), ("track", "pad", "stiffness"), ("wheels", "positions"), ("roughness", "bays"),
         ("numerics", "contact", "nodes"), ("numerics", "track", "harmonics"), ("speeds",), ("material", "poisson_ratio")]
_value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**6, 10**6), st.text(max_size=5), st.none(),
                   st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=3), st.booleans())


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=st.sampled_from(_KEYS), value=_value)
def test_fuzzed_configuration_value_passes_or_names_its_key(defaults, schema, key, value):
    from rail.setup import build

    cfg = _with(rconfig.deep_merge(defaults, {}), key, value)
    try:
        build.scenario(rconfig.validate_config(cfg, schema, source="fuzz.yaml"), "fuzz", "fuzz.yaml")
    except (rconfig.ConfigError, ValueError) as e:
        text = str(e)
        assert "fuzz.yaml" in text or key[-1] in text, text
        assert key[-1] in text or any(k in text for k in key) or "speed" in text, text


# the configurations that pass are run to the end of a small target: the receptance table at the
# first speed and one growth update of every wheel (reduced numerics); values around and beyond the
# valid ranges, so that some pass and some fail
_RUN_KEYS = {
    ("contact", "friction_static"): st.floats(0.2, 0.6), ("contact", "friction_dynamic"): st.floats(0.05, 0.4),
    ("contact", "creepage"): st.floats(-0.01, 0.01), ("contact", "closure_scale"): st.floats(-0.5, 5.0),
    ("track", "pad", "stiffness"): st.floats(-1e8, 5e9), ("track", "pad", "loss_factor"): st.floats(-0.1, 1.0),
    ("material", "poisson_ratio"): st.floats(-1.2, 0.6), ("wheels", "static_load"): st.floats(-1e4, 2e5),
    ("wheels", "positions"): st.lists(st.floats(-5.0, 30.0), min_size=1, max_size=3),
    ("roughness", "bays"): st.integers(-1, 3), ("numerics", "contact", "nodes"): st.integers(5, 21),
}
_SMALL = {"numerics": {"track": {"harmonics": 36}, "contact": {"nodes": 15}}, "speeds": [40.0],
          "growth": {"passages": 1000, "passages_per_update": 1000, "save_every": 1000}}


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data(), key=st.sampled_from(sorted(_RUN_KEYS)))
@pytest.mark.slow
def test_fuzzed_configuration_that_passes_runs_to_a_finite_result(defaults, schema, data, key):
    from rail.setup import build

    inside = _RUN_KEYS[key]
    value = data.draw(st.one_of(inside, inside, inside, st.sampled_from([float("nan"), float("inf"), None])))
    cfg = _with(rconfig.deep_merge(defaults, _SMALL), key, value)
    try:
        scn = build.scenario(rconfig.validate_config(cfg, schema, source="fuzz.yaml"), "fuzz", "fuzz.yaml")
    except (rconfig.ConfigError, ValueError) as e:
        assert key[-1] in str(e), str(e)
        return
    table = chain.receptance_table(scn, scn.speeds[0])
    history = chain.grow(scn, table, progress=io.StringIO())
    assert history.Z.shape[0] == 2 and history.Z.shape[1] > 0
    tables = table if isinstance(table, (tuple, list)) else (table,)
    assert all(np.all(np.isfinite(t.A)) for t in tables) and np.all(np.isfinite(history.Z))


def test_a_large_sweep_runs_only_when_confirmed(defaults, schema):
    # 7. a sweep of 101 speeds plans 101 growth runs: refused with its size unless confirmed in its file
    big = {"sweep": {"speed": [20.0 + 0.1 * i for i in range(101)]}, "growth": {"passages": 10000}}
    with pytest.raises(rconfig.ConfigError, match=r"big\.yaml: the sweep has 101 points .* 'confirm_large_sweep: true'"):
        rconfig.expand_sweep(defaults, schema, big, "big.yaml")
    keys, values, points = rconfig.expand_sweep(defaults, schema, {**big, "confirm_large_sweep": True}, "big.yaml")
    assert len(points) == 101


def test_a_failed_netcdf_write_names_the_file_and_the_space(tmp_path):
    # 7. the netCDF library's own words for a full disk are only "HDF error": the message names the
    # file and the free space (a folder that is not writable gives the same path through the code)
    import xarray as xr

    from rail.setup import io as rio

    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        if os.access(folder, os.W_OK):  # root ignores the permission: make the target a folder instead
            target = folder
        else:
            target = folder / "x.nc"
        with pytest.raises(OSError, match=r"could not write .*\. Free space there: .* MiB, data .* MiB"):
            rio.write_netcdf(xr.Dataset({"a": ("x", np.arange(3.0))}), target)
    finally:
        folder.chmod(0o700)


def test_growth_step_and_roughness_frequency_are_checked_when_the_scenario_is_built(defaults, schema):
    # 3. passages not a multiple of the save interval, and 5. a roughness frequency 0 (a division by
    # zero inside the job before): refused when the scenario is built, at start-up
    from rail.scenario import InitialRoughness
    from rail.setup import build

    cfg = rconfig.validate_config(rconfig.deep_merge(defaults, {"growth": {"passages": 25000}}), schema, "s.yaml")
    with pytest.raises(ValueError, match=r"growth\.save_every = 10000 must be a multiple of growth\.passages_per_update = 10000 "
                       r"and divide growth\.passages = 25000"):
        build.scenario(cfg, "s", "s.yaml")
    with pytest.raises(ValueError, match=r"roughness\.frequency = 0\.0 Hz is not allowed"):
        InitialRoughness("harmonic", 1e-5, 0.0, None, None)


def test_wear_refuses_a_roughness_with_other_harmonics_than_the_forces():
    # 5. a roughness with fewer harmonics than the table used to grow only those, silently
    from rail import wear as W

    tr = track()
    tab = moving.receptance_table(tr, 40.0, 8)
    F = I.solve_forces(tab, I.Wheels(1350.0, 0.575, 1e5, (0.0,)), I.ContactSpring(1.4e9), I.Roughness.smooth(4), tr.L)
    with pytest.raises(ValueError, match=r"the roughness has 4 harmonics and the forces 8"):
        W.bay_wear(F, 0, I.Roughness.smooth(4), MATERIAL, W.WearLaw(7850.0, 2.5e-9), C.ContactNumerics(41, "default", 1.0, "report", "wheel"))


@pytest.mark.slow
def test_a_bad_measured_decay_rate_found_by_name_stops_the_workflow_at_start_up(root, tmp_path):
    # 7. a measured decay-rate file found by its name (config/measured/<track>_decay_rate.csv, no
    # config key) was read only by its job, after 151 s of computation: now before any job
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    (tmp_path / "config/measured").mkdir(exist_ok=True)
    (tmp_path / "config/measured/default_decay_rate.csv").write_text("band_centre_Hz,decay_rate_dB_per_m\n100,2.0\n125,abc\n")
    out = snakemake(root, "-n", "results/figures/fig06.png", cwd=tmp_path)
    assert out.returncode != 0
    assert re.search(r"scenario default \(.*\): config/measured/default_decay_rate\.csv \(the track's measured decay "
                     r"rate\): .*line 3", out.stdout + out.stderr), out.stderr[-800:]


@pytest.mark.slow
def test_a_bad_limit_spectrum_stops_the_workflow_at_start_up(root, tmp_path):
    # the limit file of the band view is read before any job: a non-finite level names file and line
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    (tmp_path / "config/roughness/example_limit.csv").write_text("wavelength_m,level_dB\n0.1,5\n0.05,nan\n")
    out = snakemake(root, "-n", "results/figures/fig06.png", cwd=tmp_path)
    assert out.returncode != 0
    assert re.search(r"figures\.bands\.limit: config/roughness/example_limit\.csv, line 3: '0\.05,nan' is not finite", out.stdout + out.stderr)


@pytest.mark.slow
def test_a_spectrum_period_too_short_for_its_resolution_stops_the_workflow_at_start_up(root, tmp_path):
    # figures.rate_spectrum: 16 bays cannot resolve 0.6 m at 30 lines per octave; before, the
    # spectrum job said so only after its receptance tables (40 s per speed)
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    (tmp_path / "short.yaml").write_text("figures:\n  rate_spectrum:\n    bays: 16\n")
    out = snakemake(root, "-n", "rate_spectrum", "--configfile", str(tmp_path / "short.yaml"), cwd=tmp_path)
    assert out.returncode != 0
    assert re.search(r"figures\.rate_spectrum: a roughness period of 16 bays spaces the lines by 6\.2 % at 0\.6 m, "
                     r"coarser than 1/30 octave \(2\.3 %\): use at least 43 bays", out.stdout + out.stderr), out.stderr[-800:]


# issue 32: library functions refuse nonsense with one line naming the argument, its value and the
# valid range, instead of returning numbers


@pytest.mark.parametrize("P, a, message", [
    (-1.0, 0.006, r"normal force P = -1\.0 N is not allowed in the Hertz pressure \(eq 22\): it must be a finite number >= 0\."),
    (float("nan"), 0.006, r"normal force P = nan N is not allowed in the Hertz pressure \(eq 22\)"),
    (float("inf"), 0.006, r"normal force P = inf N is not allowed"),
    (1e5, 0.0, r"half-length a = 0\.0 m is not allowed in the Hertz pressure \(eq 22\): it must be a finite number > 0\."),
    (1e5, -0.006, r"half-length a = -0\.006 m is not allowed"),
])
def test_hertz_pressure_refuses_a_negative_or_infinite_force_and_a_half_length_not_above_zero(P, a, message):
    with pytest.raises(ValueError, match=message):
        C.hertz_pressure(np.linspace(-0.01, 0.01, 5), P, a, MATERIAL)


def test_stationary_receptance_refuses_a_frequency_that_is_not_finite():
    from rail import track as T

    for omega in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match=rf"omega = {omega} rad/s is not allowed in the stationary receptance: it must be a "
                                             r"finite scalar != 0"):
            T.stationary_receptance(0.1, 0.0, omega, track())


def test_min_harmonics_refuses_a_speed_not_above_zero():
    from rail import track as T

    for speed in (0.0, -40.0, float("nan")):
        with pytest.raises(ValueError, match=rf"speed = {speed} m/s is not allowed in min_harmonics: it must be a finite number > 0"):
            T.min_harmonics(track(), speed)


def test_boussinesq_refuses_a_distance_not_above_zero(steel):
    from rail import halfspace as H

    for r, shown in ((0.0, "0.0"), (-0.01, "-0.01"), (np.array([0.01, -0.02]), "-0.02")):
        with pytest.raises(ValueError, match=rf"r = {re.escape(shown)} m is not allowed in Boussinesq's formula \(eq 17\): it must "
                                             r"be a finite number > 0"):
            H.boussinesq(r, steel)


def test_rayleigh_speed_ratio_refuses_a_poisson_ratio_outside_its_range():
    from rail import halfspace as H

    for nu in (0.7, 0.5, -1.0, float("nan")):
        with pytest.raises(ValueError, match=rf"poisson_ratio = {nu} is not allowed: it must lie in \(-1\.0, 0\.5\)"):
            H.rayleigh_speed_ratio(nu)


def test_wear_depth_refuses_negative_or_infinite_work():
    from rail import wear as W

    law = W.WearLaw(7850.0, 2.5e-9)
    with pytest.raises(ValueError, match=r"frictional work = -1\.0 J/m\^2 is not allowed in the wear law \(eq 49\): it must be a "
                                         r"finite number >= 0\."):
        law.depth(-1)
    with pytest.raises(ValueError, match=r"frictional work = nan J/m\^2 is not allowed"):
        law.depth(np.array([1.0, np.nan]))


@pytest.mark.parametrize("period", [0.0, -2.4, float("nan"), float("inf")])
def test_roughness_coefficients_refuse_a_period_not_above_zero(period):
    message = rf"period = {period} m is not allowed: the roughness period N L must be a finite number > 0\."
    with pytest.raises(ValueError, match=message):
        R.profile_coefficients(np.linspace(0.0, 2.4, 49), 1e-6 * np.sin(np.linspace(0.0, 20.0, 49)), period, 64)
    with pytest.raises(ValueError, match=message):
        R.spectrum_coefficients(np.array([0.1, 0.05]), np.array([0.0, -3.0]), period, 64, seed=1)


# issue 32, item 5: a limit spectrum and an initial roughness spectrum in mm stop `check` (and the
# workflow, through rail.setup.inputs.check_inputs) before anything is computed
@pytest.mark.parametrize("key, text, message", [
    ("figures:\n  bands:\n    limit: {f}\n", "wavelength_m,level_dB\n250,10\n200,9\n",
     r"figures\.bands\.limit: .*mm\.csv, line 2: wavelength 250 m is not allowed: it looks like millimetres \(0\.25 m\)"),
    ("figures:\n  bands:\n    limit: {f}\n", "wavelength_m,level_dB\n0.25,10\n0.19,9\n",
     r"figures\.bands\.limit: .*mm\.csv, line 3: wavelength 0\.19 m is not a one-third-octave band centre: the nearest band is 0\.2 m"),
    ("roughness:\n  kind: spectrum\n  file: {f}\n", "wavelength_m,level_dB\n100,10\n80,9\n",
     r"roughness: .*mm\.csv, line 2: wavelength 100 m is not allowed: it looks like millimetres \(0\.1 m\)"),
])
def test_check_refuses_spectra_in_millimetres_at_start_up(tmp_path, capsys, key, text, message):
    from rail.app import cli

    f = tmp_path / "mm.csv"
    f.write_text(text)
    scen = tmp_path / "mine.yaml"
    scen.write_text(key.format(f=f))
    assert cli.main(["check", str(scen)]) == 2
    err = capsys.readouterr().err
    assert re.search(message, err), err


# issue 32 (item 8): a band given twice in a measured decay rate or a roughness spectrum is refused,
# naming the file, its line and the band's first line (a blank line does not shift the numbers)


@pytest.mark.parametrize(
    "read, text, message",
    [
        ("decay", "band_centre_Hz,decay_rate_dB_per_m\n100,5\n125,4\n100.0,3\n",
         r"bad\.csv, line 4: band_centre_Hz = 100 Hz is given twice \(first at line 2\); give each band once\."),
        ("spectrum", "wavelength_m,level_dB\n0.1,3\n\n0.08,2\n0.1,4\n",
         r"bad\.csv, line 5: wavelength 0\.1 m appears twice \(first at line 2\); give each band once\."),
    ],
)
def test_a_band_given_twice_is_refused_naming_the_file_and_both_lines(tmp_path, read, text, message):
    from rail import decay

    path = tmp_path / "bad.csv"
    path.write_text(text)
    reader = decay.read_measured_decay_rate if read == "decay" else R.read_third_octave_spectrum
    with pytest.raises(ValueError, match=message):
        reader(path)


def test_a_profile_position_that_does_not_increase_is_named_at_its_line_after_a_blank_line(tmp_path):
    path = tmp_path / "profile.csv"
    path.write_text("position_m,height_m\n0,0\n\n0.001,1e-6\n0.001,2e-6\n")
    with pytest.raises(ValueError, match=r"profile\.csv, line 5: position 0\.001 m does not increase \(previous 0\.001 m\)"):
        R.read_profile(path)


# issue 32 (item 8, C): a truncated intermediate netCDF file (a killed job, a full disk) made every
# rerun fail with "NetCDF: HDF error"; it is now named, moved aside, and rebuilt by the next run


def test_a_truncated_intermediate_file_is_named_and_moved_aside(tmp_path):
    import xarray as xr

    from rail.setup import io as rio

    path = tmp_path / "V40.nc"
    rio.write_netcdf(xr.Dataset({"a": ("x", np.arange(1000.0))}), path)
    whole = path.read_bytes()
    path.write_bytes(whole[: len(whole) // 2])
    with pytest.raises(rio.UnreadableIntermediateError, match=(
            rf"^{re.escape(str(path))} is unreadable \(NetCDF: HDF error\) and has been moved aside to "
            rf"{re.escape(str(path))}\.unreadable: run snakemake again to rebuild it\.$")):
        rio.open_intermediate(path)
    assert not path.exists()
    assert (tmp_path / "V40.nc.unreadable").read_bytes() == whole[: len(whole) // 2]


@pytest.mark.slow
def test_a_truncated_receptance_table_is_rebuilt_by_the_next_run(root, tmp_path):
    import shutil

    shutil.copytree(root / "config", tmp_path / "config")
    target = "results/growth/default/V40.nc"
    # the table's path: content-named (issue 36), as the dry run's table job names it
    name = re.search(r"receptance table (results/receptance/[0-9a-f]{10}/V40\.nc):", snakemake(root, "-n", target, cwd=tmp_path).stdout).group(1)
    table = tmp_path / name
    table.parent.mkdir(parents=True)
    table.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(200))  # the start of a netCDF4 file, cut short
    plan = snakemake(root, "-n", target, cwd=tmp_path)
    assert plan.returncode == 0, plan.stderr
    # the table is there and looks up to date (the contact march is compiled once first)
    assert job_counts(plan.stdout) == {"growth": 1, "compile_kernels": 1}
    run = snakemake(root, "-j1", target, cwd=tmp_path)
    assert run.returncode != 0
    log = (tmp_path / "logs/growth/default/V40.log").read_text()
    assert f"{name} is unreadable (NetCDF: HDF error) and has been moved aside to " \
           f"{name}.unreadable: run snakemake again to rebuild it." in log
    again = snakemake(root, "-n", target, cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert job_counts(again.stdout) == {"receptance": 1, "growth": 1}  # the table is built again (the march is compiled)


# issue 32: the command line fuzzed. Any scenario file (fuzzed values of the keys above, YAML that is
# not a mapping, random bytes) gives `railgrowth check` exit 0 or 2, one line per problem on stderr
# naming the file, never a traceback
_yaml_text = st.one_of(
    st.builds(lambda key, value: _nested_yaml(key, value), st.sampled_from(_KEYS), _value),
    st.text(max_size=40).map(lambda t: t.encode("utf-8")), st.binary(max_size=40),
).map(lambda t: t if isinstance(t, bytes) else t.encode("utf-8"))


def _nested_yaml(key, value):
    import yaml

    return yaml.safe_dump(_nested(key, value))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=_yaml_text)
def test_fuzzed_scenario_file_through_the_command_line_is_accepted_or_refused_in_one_line(tmp_path, capsys, text):
    from rail.app import cli

    f = tmp_path / "fuzz.yaml"
    f.write_bytes(text)
    code = cli.main(["check", str(f)])
    out, err = capsys.readouterr()
    assert code in (0, 2), (code, err)
    if code == 0:
        assert out.startswith("ok: scenario 'fuzz' is valid")
    else:
        assert err.startswith("railgrowth: ") and "Traceback" not in err, err


def _nested(key, value):
    node = value
    for k in reversed(key):
        node = {k: node}
    return node


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=st.sampled_from(_KEYS), value=_value, speed=st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=3),
                                                                  st.none(), st.booleans(), st.integers(-5, 400)))
def test_fuzzed_api_calls_are_accepted_or_refused_naming_the_argument(key, value, speed):
    # issue 32: the API fuzzed: load with fuzzed changes, then growth's speed checked before computing
    from rail.app import api

    try:
        study = api.load("default", changes=_nested(key, value))
    except (rconfig.ConfigError, ValueError) as e:
        assert key[-1] in str(e) or "speed" in str(e) or "harmonics" in str(e), str(e)
        return
    original = api.chain.receptance_table
    api.chain.receptance_table = lambda *a, **k: (_ for _ in ()).throw(_Reached())
    try:
        api.growth(study, speed=speed)
    except _Reached:
        assert isinstance(speed, (int, float)) and not isinstance(speed, bool) and 0 < speed <= 300
    except (rconfig.ConfigError, ValueError) as e:
        assert "speed" in str(e), str(e)
    finally:
        api.chain.receptance_table = original


class _Reached(Exception):
    """The computation was reached: the arguments passed every check."""


def test_a_denormal_speed_is_refused_naming_speeds_not_an_overflow(schema, defaults):
    # found by the fuzz above: speeds [2.2e-311] made min_harmonics overflow (int of infinity) in the
    # physics check, an OverflowError instead of a line naming the key
    from rail.setup import build
    from rail.setup.config import validate_config
    from rail.track import min_harmonics

    cfg = validate_config({**defaults, "speeds": [2.225073858507e-311]}, schema)
    problems = build.physics_problems(cfg, "config")
    assert len(problems) == 1 and "speeds" in problems[0] and "2.225073858507e-311" in problems[0]
    with pytest.raises(ValueError, match="speed = 2.225073858507e-311 m/s is not allowed"):
        min_harmonics(build.scenario(validate_config(defaults, schema)).track, 2.225073858507e-311)
