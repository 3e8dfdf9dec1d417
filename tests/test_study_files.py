"""Studies as study files (issue 57, item 9): the dynamic-creepage families are config/studies/<target>.yaml
(defaults and cases, as config/stability.yaml), their named targets are taken from the file, and
config/scenarios/ holds the users' own scenarios: a file copied there joins no named target.

tests/data/named_targets_before_study_files.json was recorded from the plan at 2be3675, before the change
(the 25 scenario files dyn_*.yaml and dynspeed_*.yaml, and targets picked by name prefix or a literal list in
workflow/rules/spectrum.smk): every named target's list of files, every scenario's resolved configuration (a
hash of it in key order: Snakemake compares a job's params as written), the table of every scenario and the
scenario order. The same lists from the plan now must be identical, so that every built result stays valid.

tests/data/named_targets_before_closure_irregular_short_wave.json was recorded in the same way from the plan at
3c3fde9, before the closure study (closure*.yaml, picked by the literal CLOSURE_STUDIES), the irregular track
(irregular_*.yaml, IRREGULAR_NAMES) and the short-wave study (nonhertzian.yaml and short_wave_study*.yaml, a literal
list in Plan.short_wave_targets) became the study files closure_study.yaml, irregular_track.yaml and
short_wave.yaml, with the noise files added since the first recording, every sweep's keys, values, points and
units, the closure study's inputs and their roles, and the irregular-track study's cases and the parts of their
configurations its rules are handed (by a script of that change that computed, with the plan methods of 3c3fde9,
what test_every_named_target_scenario_and_sweep_is_as_before_... computes now: short_wave, closure_study and
irregular_track then from short_wave_targets, closure_targets and irregular_targets).
`snakemake -n --forceall` of every affected target (closure_study, irregular_track, short_wave, sweeps, bands,
any_wavelength, noise, rate_spectrum_sweeps, track_characterisation, dynamic_creepage_speeds and the study_<name> of
each moved file) planned the same jobs, with the same inputs, outputs, wildcards, priorities and resources, before
and after (compared by hand)."""

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
BEFORE_57B = json.loads((ROOT / "tests/data/named_targets_before_closure_irregular_short_wave.json").read_text())
STUDY_FILES = ["closure_study", "dynamic_creepage", "dynamic_creepage_speeds", "irregular_track", "rail_flexibility",
               "short_wave", "spectrum_band", "track_mitigation", "wheel_source"]
# study files added after the recordings: the recorded plans are compared with the plan without them, and
# test_the_study_files_added_since_the_recordings_change_no_other_target checks that they add their own alone
ADDED_SINCE = ["spectrum_band", "track_mitigation", "wheel_source"]


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


@pytest.fixture(scope="module")
def P_recorded(tmp_path_factory):
    """The plan of this checkout's config/ without the study files added since the recordings (ADDED_SINCE)."""
    root = tmp_path_factory.mktemp("recorded")
    shutil.copytree(ROOT / "config", root / "config")
    for name in ADDED_SINCE:
        (root / "config" / "studies" / f"{name}.yaml").unlink()
    return plan_at(root)


def named_targets(P) -> dict:
    """Every named target's files, as the workflow's rules take them from the plan."""
    out = {
        "all": P.paper_figures(), "receptances": P.receptance_tables(), "sweeps": P.sweep_targets(), "bands": P.band_targets(),
        "noise": P.noise_targets(), "any_wavelength": P.any_wavelength_targets(), "rate_spectrum_sweeps": P.rate_spectrum_sweep_targets(),
        "track_characterisation": P.characterisation_targets(), **{name: P.study_file_input(name) for name in P.studies},
        "speed_study": [f for fs in P.speed_study_spectra().values() for f in fs], "traffic_study": P.traffic_study_inputs(),
        "uncertainty": P.uncertainty_members(), "convergence": P.convergence_points(), "report_candidates": P.report_candidates(),
    }
    return out | {f"study_{n}": P.study_targets(n) for n in P.study_names()}


def _without_noise(files):
    """Files without the noise outputs added since the first recording (issue 56: rule growth_noise)."""
    return [f for f in files if not f.endswith(("_noise.png", "_noise.csv"))]


def test_every_named_target_lists_the_same_files_as_before_the_study_files(P_recorded):
    now = named_targets(P_recorded)
    assert sorted(set(now) - {"noise"}) == sorted(BEFORE["targets"])
    for target, files in BEFORE["targets"].items():
        assert _without_noise(now[target]) == files, target


def test_every_named_target_scenario_and_sweep_is_as_before_the_closure_irregular_and_short_wave_study_files(P_recorded):
    from rail.setup.plan import config_part

    def h(x):
        return hashlib.sha256(json.dumps(x, default=str).encode()).hexdigest()[:16]

    B = BEFORE_57B
    now = named_targets(P_recorded)
    assert sorted(now) == sorted(B["targets"])
    for target, files in B["targets"].items():
        assert now[target] == files, target
    assert list(P_recorded.scenarios) == B["scenarios"] and P_recorded.study_names() == B["study_names"]
    assert {n: h(_without_band(P_recorded.scenarios[n], P_recorded.sources[n])) for n in P_recorded.scenarios} == B["configs"]
    assert {n: P_recorded.table_file(n, P_recorded.objects[n].speeds[0]) for n in P_recorded.scenario_table} == B["tables"]
    assert P_recorded.characterised_tracks() == B["characterised_tracks"]
    assert {s: {"keys": sw.keys, "values": sw.values, "points": [[p.name, list(p.index), p.speed] for p in sw.points], "units": sw.units}
            for s, sw in P_recorded.sweeps.items()} == B["sweeps"]
    paths, meta = P_recorded.closure_inputs()
    assert [P_recorded.closure_values(), paths, meta] == [B["closure"]["values"], B["closure"]["inputs"], B["closure"]["meta"]]
    assert {f"{v:g}": h(P_recorded.closure_wear_config(f"{v:g}")) for v in P_recorded.closure_values()} == B["closure"]["wear_config"]
    rnd, irr = P_recorded.irregular_random_points(), B["irregular"]
    assert [P_recorded.irregular_cases(), rnd] == [irr["cases"], irr["random_points"]]
    assert {c: h(config_part(("track",), P_recorded.scenarios[c])) for c in P_recorded.irregular_cases()} == irr["case_cfg"]
    assert h(config_part(("track", "numerics.track"), P_recorded.scenarios[P_recorded.irregular_study()["uniform"]])) == irr["uniform_cfg"]
    assert {n: h(config_part(("track",), P_recorded.scenarios[n])) for n in rnd} == irr["random_cfg"]
    assert {n: P_recorded.scenarios[n]["track"]["cell"]["random"].get("spacing", 0.0) for n in rnd} == irr["spreads"]


def _without_band(cfg, source=""):
    """A configuration without figures.rate_spectrum.band: the scenario files' default band (issue 54) was added
    after the configurations were recorded (rail.setup.config.SCENARIO_FILE_DEFAULTS; tests/test_band_lines.py); and,
    for a file of config/scenarios/, without the full physics it starts from since issue 55 (the rail's flexibility and
    the wheelset of rail.setup.config.scenario_file_physics), where the file does not set them itself; for a case of the
    traffic study, without the full physics it was re-run with (the rail's flexibility, each vehicle's wheelsets and the
    fleet spectrum's band resolved at the study's class speeds, config/traffic_study.yaml); and for a case of the
    irregular track, without the full physics its study file now starts from (the rail's flexibility on the cell and the
    motored wheelset, config/studies/irregular_track.yaml's defaults)."""
    from rail.setup.config import scenario_file_physics

    out = copy.deepcopy(cfg)
    (out.get("figures") or {}).get("rate_spectrum", {}).pop("band", None)
    if source.startswith("config/traffic_study.yaml"):  # the traffic study re-run with the full physics (issue 55)
        out.pop("rail_flexibility", None)
        for v in out["fleet"]["vehicles"]:
            v.pop("wheelsets", None)
        out["fleet"]["spectrum"].pop("band", None)
        if not out["fleet"]["spectrum"]:
            out["fleet"].pop("spectrum")
        out["figures"]["rate_spectrum"]["speeds"] = load_yaml(ROOT / "config/config.yaml")["figures"]["rate_spectrum"]["speeds"]
    if source.startswith("config/studies/irregular_track.yaml"):  # the irregular track re-run with the full physics (issue 55)
        out.pop("rail_flexibility", None)
        out.pop("wheelset", None)
    if source.startswith("config/scenarios/"):
        own = load_yaml(ROOT / source.split(" (")[0])
        for section in scenario_file_physics({"contact": {"creepage": -0.001}}, {k: own[k] for k in own if k != "contact"}):
            if section not in own:
                out.pop(section, None)
    return out


def test_every_scenario_resolves_as_before_and_reads_the_same_tables(P_recorded):
    # the study files' cases are the former scenario files: the same names, in the same order (a track is characterised
    # under the first scenario holding it), the same configuration key for key, the same tables
    assert list(P_recorded.scenarios) == BEFORE["scenarios"]
    configs = {n: hashlib.sha256(json.dumps(_without_band(P_recorded.scenarios[n], P_recorded.sources[n]), default=str).encode()).hexdigest()[:16]
               for n in P_recorded.scenarios}
    assert configs == BEFORE["configs"]
    assert {n: P_recorded.table_file(n, P_recorded.objects[n].speeds[0]) for n in P_recorded.scenario_table} == BEFORE["tables"]
    assert P_recorded.characterised_tracks() == BEFORE["characterised_tracks"]
    assert P_recorded.speed_study_spectra() == BEFORE["speed_study_spectra"]


def test_the_study_files_added_since_the_recordings_change_no_other_target(P, P_recorded):
    """A study file added since the recordings (ADDED_SINCE) brings its own cases and targets and changes no other
    scenario's configuration, table or target."""
    now, before = named_targets(P), named_targets(P_recorded)
    added = [n for n in P.scenarios if n not in P_recorded.scenarios]
    assert [n for n in P.scenarios if n in P_recorded.scenarios] == list(P_recorded.scenarios)
    assert all(n.startswith(("tenhz_", "ws_", "tm_")) for n in added) and added, added
    assert {n: P.scenarios[n] for n in P_recorded.scenarios} == dict(P_recorded.scenarios)
    mine = {name for name in ADDED_SINCE} | {f"study_{n}" for n in added}
    assert sorted(set(now) - mine) == sorted(before)
    for target in before:  # every file it had, and the new ones are the new cases' own (or their tracks' tables)
        assert set(before[target]) <= set(now[target]), target
        extra = [f for f in now[target] if f not in set(before[target])]
        assert all(any(n in f for n in added) or f.startswith("results/receptance/") for f in extra), (target, extra[:3])
        if target not in ("receptances", "track_characterisation", "report_candidates"):
            assert now[target] == before[target], target


def test_the_named_study_targets_come_from_the_study_files(P):
    assert sorted(P.studies) == STUDY_FILES
    for name, st in P.studies.items():
        spectra = [n for n in st["include"] + st["cases"] if st["builds"][n] in ("spectrum", "settled")]
        assert [t for t in P.study_file_targets(name) if t.startswith("results/spectrum/")] == [
            f for n in spectra for f in [f"results/spectrum/{n}/rate_spectrum.png"]
            + ([f"results/spectrum/{n}/settled.png"] if st["builds"][n] == "settled" else [])]
    assert P.study_file_targets("short_wave")[1:] == P.study_targets("short_wave_study") + P.study_targets("short_wave_study_report")
    assert P.study_file_targets("closure_study") == P.closure_targets() and P.closure_studies() == {
        "run": "closure", "soft": "closure_soft_pad", "four": "closure_class87"}
    assert P.study_file_targets("irregular_track") == P.irregular_targets()
    # no rule, and no line of the plan, picks scenarios by a name or a name's prefix: no case of a study file is
    # named in them, in quotes, and no wildcard is constrained to a prefix
    names = [n for st in P.studies.values() for n in st["cases"]]
    for f in ("workflow/rules/spectrum.smk", "workflow/rules/irregular.smk", "workflow/rules/closure.smk", "workflow/rules/common.smk",
              "rail/setup/plan.py", "rail/setup/targets.py"):
        text = (ROOT / f).read_text()
        assert not re.search(r"startswith\(\"dyn|\"(irregular|closure|dyn|dynspeed)_\[", text), f
        assert [n for n in names if f'"{n}"' in text or f"'{n}'" in text] == [], f


def test_config_scenarios_holds_no_study_family_and_its_readme_lists_every_file():
    names = sorted(p.name for p in (ROOT / "config/scenarios").glob("*.y*ml"))
    assert not [n for n in names if n.startswith(("dyn_", "dynspeed_", "closure", "irregular_", "short_wave", "nonhertzian"))]
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


def test_a_copy_of_a_closure_or_irregular_case_in_config_scenarios_joins_no_study(P, project):
    # a sweep over the closure value named as the study's were, and a track cell named as the irregular cases
    (project / "config/scenarios/closure_mine.yaml").write_text("sweep:\n  contact.closure_scale: [0.5, 1.0]\n  speed: [40.0]\n")
    (project / "config/scenarios/irregular_mine.yaml").write_text(
        "track: {cell: {bays: 4, ballast: [1.0, 0.5, 1.0, 1.0]}}\nroughness: {bays: 4}\nspeeds: [40.0]\nnumerics: {track: {harmonics: 36}}\n")
    Q = plan_at(project)
    assert "closure_mine" in Q.sweeps and "irregular_mine" in Q.scenarios
    assert Q.closure_studies() == P.closure_studies() and Q.closure_inputs() == P.closure_inputs()
    assert Q.irregular_cases() == P.irregular_cases() and Q.irregular_targets() == P.irregular_targets()
    assert "results/sweeps/closure_mine_bands.png" in Q.band_targets()  # a sweep over speed of its own, not the closure study's
    assert "results/sweeps/closure_soft_pad_bands.png" not in Q.band_targets()


def test_the_study_files_sweeps_are_sweeps_of_the_plan_named_by_their_file_and_case(P):
    assert {"closure", "closure_soft_pad", "closure_class87", "irregular_random"} <= set(P.sweeps)
    assert P.sources["closure-p0"] == ("config/studies/closure_study.yaml (case closure) (sweep point contact.closure_scale = 0.01, "
                                       "speed = 20.0)")
    assert P.sweeps["closure"].values == [[0.01, 0.1, 0.3, 1.0, 2.0, 4.0], [20.0, 40.0]]  # the defaults' values, the case's speeds
    assert P.sweeps["closure_soft_pad"].values == [[0.01, 0.1, 0.3, 1.0, 2.0, 4.0], [40.0]]
    assert P.study_targets("closure")[-2:] == ["results/sweeps/closure.nc", "results/sweeps/closure.png"]  # study_closure kept


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


def test_a_summary_named_by_two_study_files_is_refused_naming_both(project):
    (project / "config/studies/my_closure.yaml").write_text(
        "summary: {kind: closure_study, run: a, soft: a, four: a}\ncases:\n  a: {sweep: {contact.closure_scale: [1.0]}}\n")
    with pytest.raises(ConfigError, match=r"config/studies/my_closure\.yaml: summary closure_study is also "
                                          r"config/studies/closure_study\.yaml's"):
        plan_at(project)


def test_a_study_file_that_is_not_valid_stops_its_summarys_target_alone(P, project):
    path = project / "config/studies/irregular_track.yaml"
    path.write_text(path.read_text().replace("cases: [irregular_voided,", "cases: [irregular_nosuch,"))
    Q = plan_at(project)
    assert "summary.cases = ['irregular_nosuch'" in Q.broken_studies["irregular_track"]
    with pytest.raises(ConfigError, match=r"config/studies/irregular_track\.yaml: summary\.cases .* must be a list of cases of the file"):
        Q.study_file_input("irregular_track")(None)
    assert Q.irregular_targets() == ["results/irregular/summary.png"] and Q.study_file_input("closure_study") == P.study_file_input("closure_study")


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
    ({"cases": {"a": None}, "include": "dyn_fixed"}, "include = 'dyn_fixed' is not allowed"),
    ({"cases": {"a": None}, "speed_study": True}, "unknown key speed_study"),
    ({"cases": {"a": None}, "builds": "figures"}, "builds = 'figures' is not allowed: it must be one of spectrum, settled, study, none"),
    ({"cases": {"a": None}, "builds": {"b": "study"}}, r"builds = \{'b': 'study'\} is not allowed"),
    ({"cases": {"a": None}, "summary": "closure"}, "summary = 'closure' is not allowed: it must be a mapping with a kind, one of"),
    ({"cases": {"a": None}, "summary": {"kind": "speed_study", "run": "a"}}, "summary.run is not known: the roles of summary speed_study are none"),
    ({"cases": {"a": None}, "summary": {"kind": "closure_study", "run": "a", "soft": "a"}},
     r"summary\.four = None is not allowed: it must be one case"),
    ({"cases": {"a": None}, "summary": {"kind": "irregular_track", "uniform": "a", "cases": "a"}},
     r"summary\.cases = 'a' is not allowed: it must be a list"),
    ({"cases": {"a": None}, "summary": {"kind": "irregular_track", "uniform": "b", "cases": ["a"]}},
     r"summary\.uniform = 'b' is not allowed.*\(a\)"),
])
def test_a_study_file_is_checked_naming_the_file_and_key(data, message):
    with pytest.raises(ValueError, match=message):
        study_file("config/studies/x.yaml", data)
