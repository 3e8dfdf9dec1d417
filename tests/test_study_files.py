"""Studies as study files (issue 57, item 9): the dynamic-creepage families are config/studies/<target>.yaml
(defaults and cases, as config/stability.yaml), their named targets are taken from the file, and
config/scenarios/ holds the users' own scenarios: a file copied there joins no named target.

tests/data/named_targets_before_study_files.json was recorded from the plan at 2be3675, before the change
(the 25 scenario files dyn_*.yaml and dynspeed_*.yaml, and targets picked by name prefix or a literal list in
workflow/rules/spectrum.smk): every named target's list of files, every scenario's resolved configuration (a
hash of it in key order: Snakemake compares a job's params as written), the table of every scenario and the
scenario order. The same lists from the plan now must be identical, so that every built result stays valid."""

import copy
import hashlib
import json
import os
import re
import shutil
from pathlib import Path

import pytest

from rail.setup.config import ConfigError, load_yaml, validate_config
from rail.setup.plan import plan
from rail.setup.study_files import study_file

ROOT = Path(__file__).resolve().parents[1]
BEFORE = json.loads((ROOT / "tests/data/named_targets_before_study_files.json").read_text())


def plan_at(root):
    here = Path.cwd()
    os.chdir(root)  # the plan's paths, as the workflow's, are relative to the project folder
    try:
        schema = load_yaml("config/schema/config.schema.yaml")
        return plan(validate_config(load_yaml("config/config.yaml"), schema), schema)
    finally:
        os.chdir(here)


@pytest.fixture(scope="module")
def P():
    return plan_at(ROOT)


def named_targets(P) -> dict:
    """Every named target's files, as the workflow's rules take them from the plan."""
    out = {
        "all": P.paper_figures(), "receptances": P.receptance_tables(), "sweeps": P.sweep_targets(), "bands": P.band_targets(),
        "any_wavelength": P.any_wavelength_targets(), "rate_spectrum_sweeps": P.rate_spectrum_sweep_targets(),
        "short_wave": P.short_wave_targets(), "track_characterisation": P.characterisation_targets(),
        "closure_study": P.closure_targets(), "irregular_track": P.irregular_targets(),
        "rail_flexibility": P.study_file_input("rail_flexibility"), "dynamic_creepage": P.study_file_input("dynamic_creepage"),
        "dynamic_creepage_speeds": P.study_file_input("dynamic_creepage_speeds"),
        "speed_study": [f for fs in P.speed_study_spectra().values() for f in fs], "traffic_study": P.traffic_study_inputs(),
        "uncertainty": P.uncertainty_members(), "convergence": P.convergence_points(), "report_candidates": P.report_candidates(),
    }
    return out | {f"study_{n}": P.study_targets(n) for n in P.study_names()}


def test_every_named_target_lists_the_same_files_as_before_the_study_files(P):
    now = named_targets(P)
    assert sorted(now) == sorted(BEFORE["targets"])
    for target, files in BEFORE["targets"].items():
        # the noise outputs beside the runs were added after the lists were recorded (issue 56; tests/test_plan.py checks them)
        assert [f for f in now[target] if not f.endswith(("_noise.png", "_noise.csv"))] == files, target


def _without_band(cfg):
    """A configuration without figures.rate_spectrum.band: the scenario files' default band (issue 54) was added
    after the configurations were recorded (rail.setup.config.SCENARIO_FILE_DEFAULTS; tests/test_band_lines.py)."""
    out = copy.deepcopy(cfg)
    (out.get("figures") or {}).get("rate_spectrum", {}).pop("band", None)
    return out


def test_every_scenario_resolves_as_before_and_reads_the_same_tables(P):
    # the study files' cases are the former scenario files: the same names, in the same order (a track is characterised
    # under the first scenario holding it), the same configuration key for key, the same tables
    assert list(P.scenarios) == BEFORE["scenarios"]
    configs = {n: hashlib.sha256(json.dumps(_without_band(P.scenarios[n]), default=str).encode()).hexdigest()[:16] for n in P.scenarios}
    assert configs == BEFORE["configs"]
    assert {n: P.table_file(n, P.objects[n].speeds[0]) for n in P.scenario_table} == BEFORE["tables"]
    assert P.characterised_tracks() == BEFORE["characterised_tracks"]
    assert P.speed_study_spectra() == BEFORE["speed_study_spectra"]


def test_the_named_study_targets_come_from_the_study_files(P):
    assert sorted(P.studies) == ["dynamic_creepage", "dynamic_creepage_speeds", "rail_flexibility"]
    for name, st in P.studies.items():
        assert P.study_file_targets(name)[:len(st["include"] + st["cases"])] == [
            f"results/spectrum/{n}/rate_spectrum.png" for n in st["include"] + st["cases"]]
    rules = (ROOT / "workflow/rules/spectrum.smk").read_text()
    assert not re.search(r"dyn_|dynspeed_|startswith", rules)  # no rule picks scenarios by name
    assert not re.search(r"startswith\(\"dyn", (ROOT / "rail/setup/plan.py").read_text())


def test_config_scenarios_holds_no_study_family_and_its_readme_lists_every_file():
    names = sorted(p.name for p in (ROOT / "config/scenarios").glob("*.y*ml"))
    assert not [n for n in names if n.startswith(("dyn_", "dynspeed_"))]
    readme = (ROOT / "config/scenarios/README.md").read_text()
    assert [n for n in names if f"`{n}`" not in readme] == []
    studies = (ROOT / "config/studies/README.md").read_text()
    assert [p.name for p in (ROOT / "config/studies").glob("*.yaml") if f"`{p.name}`" not in studies] == []


@pytest.fixture()
def project(tmp_path):
    """A copy of the project's config/ (the plan reads nothing else)."""
    shutil.copytree(ROOT / "config", tmp_path / "config")
    return tmp_path


def test_a_copy_of_a_study_case_in_config_scenarios_joins_no_named_target(P, project):
    # issue 57: a user who copied dyn_rail.yaml as dyn_rail_mine.yaml joined rail_flexibility without knowing it
    (project / "config/scenarios/dyn_rail_mine.yaml").write_text("rail_flexibility: {model: rod}\n")
    (project / "config/scenarios/dynspeed_mine.yaml").write_text("rail_flexibility: {model: rod}\n")
    Q = plan_at(project)
    assert "dyn_rail_mine" in Q.scenarios and "dynspeed_mine" in Q.scenarios
    for name in P.studies:
        assert Q.study_file_targets(name) == P.study_file_targets(name)
    assert Q.speed_study_spectra() == P.speed_study_spectra()
    assert Q.study_targets("dyn_rail_mine")  # its own study target, study_dyn_rail_mine


def test_a_users_study_file_is_a_named_target_of_its_cases(project):
    (project / "config/studies/my_pads.yaml").write_text(
        "defaults: {figures: {rate_spectrum: {bays: 2, shortest: 0.03, longest: 0.06, per_octave: 4, grid_phases: 1, speeds: [40.0]}}}\n"
        "cases:\n  my_soft: {track: {pad: {stiffness: 1.0e+8}}}\n  my_stiff: {track: {pad: {stiffness: 1.0e+9}}}\n")
    Q = plan_at(project)
    assert Q.study_file_input("my_pads") == ["results/spectrum/my_soft/rate_spectrum.png", "results/spectrum/my_stiff/rate_spectrum.png"]
    assert Q.scenarios["my_stiff"]["track"]["pad"]["stiffness"] == 1.0e9
    assert Q.scenarios["my_soft"]["figures"]["rate_spectrum"]["speeds"] == [40.0]  # the defaults under the case's keys
    assert Q.sources["my_soft"] == "config/studies/my_pads.yaml (case my_soft)"


def test_a_study_case_that_is_not_valid_stops_only_its_own_targets(P, project):
    path = project / "config/studies/rail_flexibility.yaml"
    path.write_text(path.read_text().replace("longitudinal_stiffness: 5.0e+6", "longitudinal_stiffness: -5.0e+6"))
    Q = plan_at(project)
    assert "dyn_rail_shear_soft" not in Q.scenarios and "dyn_rail" in Q.scenarios
    assert Q.study_file_input("dynamic_creepage") == P.study_file_input("dynamic_creepage")
    stop = Q.study_file_input("rail_flexibility")
    with pytest.raises(ConfigError, match=r"config/studies/rail_flexibility\.yaml \(case dyn_rail_shear_soft\).*"
                                          r"track\.pad\.longitudinal_stiffness = -5000000\.0 N/m is not allowed"):
        stop(None)


def test_a_study_file_that_is_not_valid_or_a_name_given_twice_is_refused_naming_the_file(project):
    (project / "config/studies/bad.yaml").write_text("cases: {a: {}}\nsweep: {speed: [20.0]}\n")
    Q = plan_at(project)
    assert "unknown key sweep" in Q.broken_studies["bad"] and "config/studies/bad.yaml" in Q.broken_studies["bad"]
    with pytest.raises(ConfigError, match="unknown key sweep"):
        Q.study_file_input("bad")(None)
    (project / "config/studies/bad.yaml").unlink()
    (project / "config/scenarios/dyn_rail.yaml").write_text("{}\n")
    with pytest.raises(ConfigError, match=r"config/scenarios/dyn_rail\.yaml: the scenario name 'dyn_rail' is also "
                                          r"config/studies/rail_flexibility\.yaml \(case dyn_rail\)"):
        plan_at(project)


@pytest.mark.parametrize("data, message", [
    ({"cases": {}}, "cases must map each case's name"),
    ({"cases": {"a": 3}}, r"cases\.a = 3 is not allowed"),
    ({"cases": {"a b": {}}}, "case name 'a b' is not allowed"),
    ({"cases": {"a": {"sweep": {"speed": [20.0]}}}}, "a sweep is not a case of a study file"),
    ({"cases": {"a": None}, "include": "dyn_fixed"}, "include = 'dyn_fixed' is not allowed"),
    ({"cases": {"a": None}, "speed_study": True}, "only config/studies/dynamic_creepage_speeds.yaml may set it"),
])
def test_a_study_file_is_checked_naming_the_file_and_key(data, message):
    with pytest.raises(ValueError, match=message):
        study_file("config/studies/x.yaml", data)
