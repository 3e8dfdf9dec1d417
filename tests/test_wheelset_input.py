"""Issue 57, items 1 and 4: the wheelset's, the rail head's and the friction law's values are checked by
the one validation path (the schema, then the builder's physics checks), named by their key and file,
before any work starts; what the march cannot resolve is refused with the reason; what the results say
of the model is what runs. Each test failed on d9d3375."""

import dataclasses
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rail import contact as C
from rail.creepage.modes import LongitudinalModes
from rail.setup import build
from rail.setup import config as rconfig
from rail.creepage import wheelset as W
from rail.creepage.wheelset import Wheelset, wheelset_modes

ROOT = Path(__file__).resolve().parents[1]
TORSIONAL = {"model": "torsional"}


def _cli(capsys, path):
    from rail.app import cli

    code = cli.main(["check", str(path)])
    out, err = capsys.readouterr()
    return code, out, err


def _file(tmp_path, data, name="mine.yaml"):
    p = tmp_path / name
    p.write_text(yaml.safe_dump(data))
    return p


# item 1: one range per key, the schema's, and a bad file named


def test_the_schema_and_the_wheelset_state_one_range_per_key(schema):
    for name, (key, low, high) in W.RANGES.items():
        node = rconfig._schema_node(schema, key)
        assert (node.get("minimum"), node.get("maximum")) == (low, high), key
        for v in (low, high):  # a value the schema allows, the wheelset takes (2.0 m passed one and failed the other)
            Wheelset("torsional", **{"radius": 0.46, name: v})


@pytest.mark.parametrize("radius", [2.0, 0.05])
def test_a_wheel_radius_out_of_range_is_refused_by_check_naming_the_file_and_the_key(tmp_path, capsys, radius):
    p = _file(tmp_path, {"wheels": {"radius": radius}, "wheelset": TORSIONAL})
    code, out, err = _cli(capsys, p)
    assert code == 2 and out == ""
    assert err.count("\n") == 2 and err.startswith("railgrowth: invalid configuration:\n"), err
    assert f"{p}: wheels.radius = {radius} m is not allowed" in err and "[0.1, 1.5] m" in err
    assert "wheelset.radius" not in err


def test_a_value_the_dataclasses_refuse_is_a_config_error_naming_the_file(defaults, schema):
    # a value that reaches the builder without the schema (a backstop): named by its key and the file, not
    # a ValueError that the workflow's plan would let through to stop every target
    cfg = rconfig.resolve_scenario_file(defaults, schema, {"wheelset": TORSIONAL}, "mine.yaml")
    cfg = rconfig.deep_merge(cfg, {"wheels": {"radius": 2.0}})
    with pytest.raises(rconfig.ConfigError, match=r"mine\.yaml: wheels\.radius = 2\.0 m is not allowed"):
        build.scenario(cfg, "mine", "mine.yaml")


@pytest.fixture(scope="module")
def with_bad_wheelsets(tmp_path_factory):
    from rail.setup.plan import plan

    work = tmp_path_factory.mktemp("wheelsets")
    shutil.copytree(ROOT / "config", work / "config")
    files = {"zz_radius.yaml": {"wheels": {"radius": 2.0}, "wheelset": TORSIONAL},
             "zz_stiff.yaml": {"wheelset": {**TORSIONAL, "centre_inertia": 1e-3, "axle_stiffness": 1e9}},
             "zz_flat.yaml": {"contact": {"friction_decay": 5.0, "friction_static": 0.3, "friction_dynamic": 0.3}}}
    for name, data in files.items():
        (work / "config/scenarios" / name).write_text(yaml.safe_dump(data))
    here = Path.cwd()
    os.chdir(work)
    try:
        schema = rconfig.load_yaml("config/schema/config.schema.yaml")
        yield plan(rconfig.validate_config(rconfig.load_yaml("config/config.yaml"), schema), schema)
    finally:
        os.chdir(here)


def test_a_bad_wheelset_file_stops_only_the_targets_that_need_it(with_bad_wheelsets):
    D = with_bad_wheelsets
    assert set(D.broken) == {"zz_radius", "zz_stiff"}
    assert D.target_speed("soft_pad", "40") == 40.0  # another scenario runs
    with pytest.raises(rconfig.ConfigError,
                       match=r"config/scenarios/zz_radius\.yaml: wheels\.radius = 2\.0 m is not allowed"):
        D.require("zz_radius")
    with pytest.raises(rconfig.ConfigError,
                       match=r"zz_stiff\.yaml: wheelset: .* above the .* Hz the contact march resolves"):
        D.require("zz_stiff")
    # item 4a: the flat law is said at start-up
    flat = [n for n in D.notes if "zz_flat" in n]
    assert len(flat) == 1 and "friction constant, mu = 0.3" in flat[0] and "has no effect" in flat[0]


# item 4a: a flat friction law is not called falling


def test_a_flat_friction_law_is_said_to_be_flat_and_runs_the_step_laws_result():
    from rail.studies.validity import creepage_model_text

    m0 = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)
    flat = dataclasses.replace(m0, friction_decay=5.0)
    text = creepage_model_text(flat)
    assert "falling" not in text.replace("falling law is flat", "") and "friction constant, mu = 0.3" in text
    assert "friction falling with slip" in creepage_model_text(dataclasses.replace(flat, friction_static=0.4))
    # what the note says: the same traction as the report's law with one coefficient
    P = 1e5 * (1 + 0.1 * np.sin(2 * np.pi * np.arange(300) / 41))
    a = C.hertz_half_length(P, 0.46, m0)
    delta, _, M = C.rolling_grid(1.05 * float(a.max()), 0.6, 31)
    q0 = C.solve_tangential(P, a, m0, 40.0, delta, M).Q
    q5 = C.solve_tangential(P, a, flat, 40.0, delta, M).Q
    assert np.max(np.abs(q5 - q0)) <= 1e-9 * np.max(np.abs(q0))


# item 4b: the modes as they are, and refused where the march cannot resolve them


def test_a_near_massless_motor_gives_the_chains_own_modes():
    # J_m = 1e-9 kg m^2: modes 0 and the wheels against the centre, sqrt(2 k_a (1 / J_w + 2 / J_c)) = 239 Hz
    # (in phase); not excited at the wheel, the antisymmetric torsion sqrt(2 k_a / J_w) = 80 Hz and the motor on
    # its coupling, sqrt(k_c (1 / J_m + 1 / J_c')) ~ sqrt(k_c / J_m) = 5.03 MHz. d9d3375: 0, 0, 239 Hz
    ws = Wheelset("torsional", 0.575, wheel_inertia=40.0, centre_inertia=10.0, axle_stiffness=5e6, motor_inertia=1e-9,
                  coupling_stiffness=1e6)
    m = wheelset_modes(ws)
    f = np.array(m.omega) / (2 * np.pi)
    assert f[0] == 0 and f.size == 2
    assert f[1] == pytest.approx(np.sqrt(2 * 5e6 * (1 / 40 + 2 / 10)) / (2 * np.pi), rel=1e-6)
    idle = sorted(m.unexcited)
    assert idle[0] == pytest.approx(np.sqrt(2 * 5e6 / 40) / (2 * np.pi), rel=1e-6)
    assert idle[1] == pytest.approx(np.sqrt(1e6 / 1e-9) / (2 * np.pi), rel=1e-6)
    from rail.studies.validity import creepage_model_text

    m0 = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)
    text = creepage_model_text(dataclasses.replace(m0, longitudinal=m))
    assert "modes at 0, 239 Hz; not excited at this wheel: 80, 5.03e+06 Hz" in text


def test_a_wheelset_mode_above_the_marchs_nyquist_frequency_is_refused_at_start_up(defaults, schema, tmp_path, capsys):
    # 318 kHz: the wheels against the centre
    stiff = {"wheelset": {**TORSIONAL, "centre_inertia": 1e-3, "axle_stiffness": 1e9}}
    p = _file(tmp_path, stiff)
    code, out, err = _cli(capsys, p)
    assert code == 2 and err.count("\n") == 2, err
    line = err.splitlines()[1]
    assert line.startswith(f"  {p}: wheelset: ") and "3.18e+05 Hz, above the" in line and "Nyquist" in line
    assert "wheelset.centre_inertia" in line and "wheelset.axle_stiffness" in line
    # the bound is the step's: V / (2 Delta) at the slowest configured speed, Delta of the rolling grid
    cfg = rconfig.resolve_scenario_file(defaults, schema, stiff, "x.yaml")
    V = min(rconfig.configured_speeds(cfg))
    m = build.passage_scenario(rconfig.resolve_scenario_file(defaults, schema, {}, "x.yaml")).material
    a = float(C.hertz_half_length(cfg["wheels"]["static_load"], m.wheel_radius, m))
    delta = C.rolling_grid(1.02 * a, cfg["track"]["sleeper"]["spacing"], cfg["numerics"]["contact"]["nodes"])[0]
    assert f"the {V / (2 * delta):.0f} Hz the contact march resolves at V = {V:g} m/s" in line
    # a real wheelset (the case dyn_driven of config/studies/dynamic_creepage.yaml) passes
    from rail.setup.study_files import study_cases

    driven = study_cases(ROOT)["dyn_driven"][1]
    assert build.dynamic_creepage_problems(rconfig.resolve_scenario_file(defaults, schema, driven, "d.yaml"), "d.yaml") == []


def test_the_march_refuses_a_mode_above_its_own_nyquist_frequency():
    m0 = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)
    P = np.full(200, 1e5)
    a = C.hertz_half_length(P, 0.46, m0)
    delta, _, M = C.rolling_grid(1.05 * float(a.max()), 0.6, 31)
    nyquist = 40.0 / (2 * delta)
    for f, ok in ((0.9 * nyquist, True), (1.1 * nyquist, False)):
        modes = LongitudinalModes((0.0, 2 * np.pi * f), (0.0, 0.02), (1e-3, 1e-9), 0.0)
        m = dataclasses.replace(m0, longitudinal=modes)
        if ok:
            assert np.all(np.isfinite(C.solve_tangential(P, a, m, 40.0, delta, M).Q))
        else:
            with pytest.raises(C.ContactError, match="above the .* Hz the contact march resolves"):
                C.solve_tangential(P, a, m, 40.0, delta, M)


def test_a_run_stopped_on_a_smooth_rail_does_not_blame_a_harmonic():
    from rail.growth import stop_message

    Z = np.zeros(11, dtype=complex)
    line = stop_message(0, Z, Z, C.ContactError("the dynamic creepage did not settle."), period=0.6)
    assert "-480" not in line and "The rail is still smooth" in line and "did not settle" in line
    Z1 = Z.copy()
    Z1[7] = 1e-6  # harmonic 2 of 5: a roughness that can be named
    assert "wavelength 300 mm" in stop_message(5, Z, Z1, C.ContactError("x."), period=0.6)


# item 4c: a pad longitudinal stiffness that would make u_bar unbounded


@pytest.mark.parametrize("k", [1e-6, 1e5])
def test_a_vanishing_pad_longitudinal_stiffness_is_refused_at_check(tmp_path, capsys, k):
    p = _file(tmp_path, {"rail_flexibility": {"model": "rod_and_bending"},
                         "track": {"pad": {"longitudinal_stiffness": k}}})
    code, out, err = _cli(capsys, p)
    assert code == 2 and err.count("\n") == 2, err
    assert f"{p}: track.pad.longitudinal_stiffness = {k!r} N/m is not allowed: it must be >= 1000000.0 N/m" in err


def test_the_rail_head_and_the_schema_state_one_range_for_the_pads_longitudinal_stiffness(schema):
    from rail.creepage.rail_flexibility import MIN_LONGITUDINAL_STIFFNESS, RailHead

    node = rconfig._schema_node(schema, "track.pad.longitudinal_stiffness")
    assert node["minimum"] == MIN_LONGITUDINAL_STIFFNESS and "exclusiveMinimum" not in node
    tr = build.passage_scenario(rconfig.validate_config(rconfig.load_yaml(ROOT / "config/config.yaml"), schema)).track
    RailHead(tr, longitudinal_stiffness=MIN_LONGITUDINAL_STIFFNESS)
    with pytest.raises(ValueError, match=r"track\.pad\.longitudinal_stiffness = 100000\.0 N/m is not allowed"):
        RailHead(tr, longitudinal_stiffness=1e5)


# item 4d: a file-size limit below what Snakemake writes first names the file


def test_a_file_size_limit_below_a_rule_file_names_the_file():
    from rail.setup.runtime import check_file_size_limit

    with pytest.raises(OSError, match=r"ulimit -f\) is 10240 bytes, below .*workflow/rules/\w+\.smk \(\d+ bytes\)"):
        check_file_size_limit(ROOT, limit=10240)
    check_file_size_limit(ROOT, limit=2**40)


@pytest.mark.workflow
@pytest.mark.slow
def test_snakemake_under_a_small_file_size_limit_names_the_file():
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (10 * 1024, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))

    r = subprocess.run([sys.executable, "-m", "snakemake", "-n", "results/growth/soft_pad/V40.nc"], cwd=ROOT,
                       capture_output=True, text=True, timeout=300, preexec_fn=limit)
    assert r.returncode != 0
    assert re.search(r"ulimit -f\) is 10240 bytes, below \S+\.smk", r.stdout + r.stderr), r.stderr[-2000:]


# Must show: Hypothesis over the wheelset, rail-head and friction keys, through the API and the command line:
# any value is either taken (the model built finite, a short computation finite) or refused in one line
# naming its key. Bounded time: the check-level path only, each example within the deadline.

_KEYS = [("wheels", "radius"), ("wheelset", "model"), ("wheelset", "other_wheel"), ("wheelset", "wheel_inertia"),
         ("wheelset", "centre_inertia"), ("wheelset", "axle_stiffness"), ("wheelset", "motor_inertia"),
         ("wheelset", "coupling_stiffness"), ("wheelset", "damping"), ("track", "rail", "head_height"),
         ("track", "pad", "longitudinal_stiffness"), ("track", "pad", "longitudinal_loss_factor"),
         ("track", "pad", "longitudinal_viscous_damping"), ("rail_flexibility", "model"),
         ("contact", "friction_static"),
         ("contact", "friction_dynamic"), ("contact", "friction_decay")]
_value = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-10.0, 10.0), st.floats(1e-3, 1e10),
                   st.integers(-10**9, 10**9),
                   st.sampled_from(["torsional", "rigid", "fixed_creepage", "none", "rod", "rod_and_bending",
                                    "in_phase", "independent", "abc", ""]),
                   st.none(), st.booleans(), st.lists(st.floats(0.0, 1.0), max_size=2))
_base = st.sampled_from([{}, {"wheelset": {"model": "torsional"}},
                         {"wheelset": {"model": "torsional", "motor_inertia": 288.0}},
                         {"wheelset": {"model": "rigid"}}, {"rail_flexibility": {"model": "rod_and_bending"}},
                         {"contact": {"friction_decay": 0.5, "friction_static": 0.4}}])


_QUIET = [HealthCheck.function_scoped_fixture, HealthCheck.too_slow]


def _changes(base, key, value):
    out = rconfig.deep_merge(base, {})
    node = out
    for k in key[:-1]:
        if not isinstance(node.get(k), dict):
            node[k] = {}
        node = node[k]
    node[key[-1]] = value
    if key[0] == "wheelset" and "model" not in out["wheelset"]:
        out["wheelset"]["model"] = "torsional"
    return out


def _names_key(text, key):
    problems = [x for x in text.splitlines()[1:] if x.strip()]
    return len(problems) == 1 and (".".join(key) in problems[0] or ".".join(key[:-1]) in problems[0])


def _taken_is_finite(study):
    m = study.scenario.material
    if m.longitudinal is not None:
        om, ze, c = m.longitudinal.arrays()
        assert np.all(np.isfinite(om)) and np.all(np.isfinite(c)) and np.all(c >= 0)
        assert np.all(np.isfinite(m.longitudinal.receptance(2 * np.pi * np.array([10.0, 300.0, 3000.0]))))
    if m.rail_flexibility is not None:
        from rail.creepage.rail_flexibility import smeared_rod_receptance

        assert np.isfinite(smeared_rod_receptance(m.rail_flexibility, 2 * np.pi * 300.0))
    # the short computation: the steady traction at the static load with this friction and wheel (Carter)
    from rail.contact.steady import carter

    Q = carter(0.0, study.scenario.wheels.static_load, m, 40.0, m.wheel_radius)[2]
    assert np.isfinite(Q)


@settings(max_examples=60, deadline=30000, suppress_health_check=_QUIET)
@given(base=_base, key=st.sampled_from(_KEYS), value=_value)
def test_fuzzed_wheelset_rail_head_and_friction_values_through_the_api(base, key, value):
    from rail.app import api

    try:
        study = api.load("default", changes=_changes(base, key, value))
    except rconfig.ConfigError as e:
        assert _names_key(str(e), key), str(e)
        return
    _taken_is_finite(study)


@settings(max_examples=30, deadline=30000, suppress_health_check=_QUIET)
@given(base=_base, key=st.sampled_from(_KEYS), value=_value)
def test_fuzzed_wheelset_rail_head_and_friction_values_through_the_command_line(tmp_path, capsys, base, key, value):
    p = tmp_path / "fuzz.yaml"
    p.write_text(yaml.safe_dump(_changes(base, key, value)))
    code, out, err = _cli(capsys, p)
    assert code in (0, 2), (code, err)
    if code == 0:
        assert out.startswith("ok: scenario 'fuzz' is valid") and err == ""
    else:
        assert err.startswith("railgrowth: ") and "Traceback" not in err and str(p) in err, err
        assert _names_key(err, key), err


# ... and a value taken runs: one growth update of reduced numerics (the wheelset's and the friction law's
# keys; the rail head's tables took 80-300 s a value here, so its keys stop at the check above)
_RUN = {("wheels", "radius"): st.floats(0.05, 2.0), ("wheelset", "wheel_inertia"): st.floats(0.5, 200.0),
        ("wheelset", "centre_inertia"): st.floats(1e-4, 100.0), ("wheelset", "axle_stiffness"): st.floats(1e3, 2e9),
        ("wheelset", "motor_inertia"): st.floats(0.0, 1000.0), ("wheelset", "coupling_stiffness"): st.floats(1e2, 2e9),
        ("wheelset", "damping"): st.floats(-0.1, 1.0), ("contact", "friction_static"): st.floats(0.2, 0.6),
        ("contact", "friction_decay"): st.floats(0.0, 10.0)}
_SMALL = {"numerics": {"track": {"harmonics": 36}, "contact": {"nodes": 15}}, "speeds": [40.0],
          "growth": {"passages": 1000, "passages_per_update": 1000, "save_every": 1000},
          "contact": {"friction_static": 0.35}, "wheelset": {"model": "torsional"}}


@pytest.mark.slow
@settings(max_examples=20, deadline=None, suppress_health_check=_QUIET)
@given(data=st.data(), key=st.sampled_from(sorted(_RUN)))
def test_fuzzed_wheelset_and_friction_values_that_are_taken_run_to_a_finite_result(data, key):
    import io

    from rail import chain
    from rail.app import api

    value = data.draw(st.one_of(_RUN[key], _RUN[key], st.sampled_from([float("nan"), float("inf"), None])))
    try:
        study = api.load("default", changes=_changes(_SMALL, key, value))
    except rconfig.ConfigError as e:
        assert _names_key(str(e), key), str(e)
        return
    scn = study.scenario
    table = chain.receptance_table(scn, 40.0)
    history = chain.grow(scn, table, progress=io.StringIO())
    assert np.all(np.isfinite(history.Z))
    if history.stopped:  # a broken assumption found mid-run: one line saying why, what was saved kept
        assert "\n" not in history.stopped and history.stopped.startswith("growth stopped at "), history.stopped
    else:
        assert history.Z.shape[0] == 2
