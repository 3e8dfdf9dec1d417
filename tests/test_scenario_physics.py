"""The full physics a scenario file starts from (issue 55, rail.setup.config.scenario_file_physics): the rail's
longitudinal flexibility and, for one train, a torsional wheelset, motored where the train's creepage drives and a
trailer where it brakes or rolls; a file that sets either keeps its own, a fleet its vehicles' wheelsets, config.yaml
the report's model (so that `snakemake -j2` still reproduces the report), and a study file's case what its file says."""

import pytest

from rail.app import api, cli
from rail.setup.config import MOTORED_WHEELSET, TRAILER_WHEELSET, resolve_scenario_file, scenario_file_physics


@pytest.fixture(scope="module")
def resolved(defaults, schema):
    from rail.setup.config import validate_config

    config = validate_config(defaults, schema)
    return lambda scen, **kw: resolve_scenario_file(config, schema, scen, source="test.yaml", **kw)


def test_a_scenario_file_starts_from_the_rail_flexibility_and_the_wheelset_its_creepage_calls_for(resolved):
    driven = resolved({})  # config.yaml's creepage, -0.001: a driving wheel
    assert driven["rail_flexibility"]["model"] == "rod_and_bending"
    assert driven["wheelset"]["model"] == "torsional" and driven["wheelset"]["motor_inertia"] == MOTORED_WHEELSET["motor_inertia"] > 0
    for creepage in (0.0, 0.002):  # rolling or braked: no motor in the slip
        ws = resolved({"contact": {"creepage": creepage}})["wheelset"]
        assert ws["model"] == "torsional" and ws["motor_inertia"] == 0 and ws == {**ws, **TRAILER_WHEELSET}


def test_a_file_that_sets_a_model_keeps_its_own_and_a_study_case_keeps_its_files(resolved):
    own = resolved({"wheelset": {"model": "fixed_creepage"}, "rail_flexibility": {"model": "none"}})
    assert own["wheelset"] == {"model": "fixed_creepage"} and own["rail_flexibility"] == {"model": "none"}
    rigid = resolved({"wheelset": {"model": "rigid"}})
    assert rigid["wheelset"]["model"] == "rigid" and rigid["rail_flexibility"]["model"] == "rod_and_bending"
    case = resolved({}, physics=False)
    assert "wheelset" not in case and "rail_flexibility" not in case
    fleet = scenario_file_physics({"contact": {"creepage": -0.001}}, {"fleet": {}})
    assert "wheelset" not in fleet and fleet["rail_flexibility"]["model"] == "rod_and_bending"  # the vehicles' own wheelsets


def test_the_report_keeps_its_model_and_the_report_studies_pin_it():
    assert api.load("default").scenario.material.rail_flexibility is None  # config.yaml: the report's
    assert api.load("default").scenario.material.longitudinal is None
    for name in ("soft_pad", "class87"):  # report sections 6.4 and 6.5: the report's model, pinned in the file
        m = api.load(name).scenario.material
        assert m.rail_flexibility is None and m.longitudinal is None, name
    for name in ("profile_example", "spectrum_n16"):
        m = api.load(name).scenario.material
        assert m.rail_flexibility is not None and m.longitudinal is not None, name
    assert api.load("dyn_fixed").scenario.material.rail_flexibility is None  # a study case: what its file says


def test_check_says_which_model_a_scenario_file_runs(capsys):
    assert cli.main(["check", "profile_example"]) == 0
    out = capsys.readouterr().out
    assert "torsional wheelset (driven" in out and "rail's longitudinal flexibility" in out, out


def test_a_zero_creepage_with_the_dynamic_creepage_is_refused_at_start_up_naming_the_key(resolved):
    # found by the mitigation study (config/studies/track_mitigation.yaml): a trailer rolling at exactly 0 left the smooth
    # rail's reference without a steady traction, and its Newton steps failed after minutes ("did not settle"); now
    # refused before any computation. The report's fixed creepage at 0 stays allowed, and a small creepage runs.
    from rail.setup import build

    problems = build.dynamic_creepage_problems(resolved({"contact": {"creepage": 0.0}}), "zero.yaml")
    assert len(problems) == 1 and "contact.creepage = 0.0 is not allowed" in problems[0] and "zero.yaml" in problems[0]
    assert "rail_flexibility.model rod_and_bending" in problems[0]
    report = resolved({"contact": {"creepage": 0.0}, "wheelset": {"model": "fixed_creepage"}, "rail_flexibility": {"model": "none"}})
    assert build.dynamic_creepage_problems(report, "zero.yaml") == []
    assert not [p for p in build.dynamic_creepage_problems(resolved({"contact": {"creepage": 1.0e-4}}), "small.yaml")
                if "creepage" in p.split(":")[1]]


def test_a_fleet_axle_at_zero_creepage_with_the_dynamic_creepage_is_refused_at_start_up_naming_the_vehicle(resolved):
    # found by the fleet source's benchmark (tests/benchmarks/bench_wheel_source_fleet.py): a coach whose trailing axles
    # rolled at exactly 0 under the rail's flexibility stopped after minutes ("did not settle"), as the one train did
    from rail.setup import build

    coach = {"name": "coach", "positions": [0.0, 2.6], "static_load": 6.0e4, "unsprung_mass": 900.0, "share": 0.5}
    loco = {"name": "loco", "positions": [0.0, 3.3], "static_load": 1.0e5, "unsprung_mass": 1350.0, "share": 0.5, "creepage": [-0.001, -0.001]}
    fleet = {"vehicles": [loco, {**coach, "creepage": [0.0, 0.0008]}], "speeds": {"values": [40.0], "weights": [1.0]}}
    problems = [p for p in build.dynamic_creepage_problems(resolved({"fleet": fleet}), "f.yaml") if "creepage =" in p]
    assert len(problems) == 1 and "fleet.vehicles[1] (coach).creepage = [0.0, 0.0008]" in problems[0] and "axle(s) 0" in problems[0]
    assert "f.yaml" in problems[0]
    rolling = {**fleet, "vehicles": [loco, {**coach, "creepage": [1.0e-4, 0.0008]}]}
    assert not [p for p in build.dynamic_creepage_problems(resolved({"fleet": rolling}), "f.yaml") if "creepage =" in p]
    report = resolved({"fleet": fleet, "rail_flexibility": {"model": "none"}})  # every axle the report's fixed creepage
    assert not [p for p in build.dynamic_creepage_problems(report, "f.yaml") if "creepage =" in p]
