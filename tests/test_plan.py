"""The workflow's plan (rail.setup.plan) without Snakemake: every target list the workflow built before
the plan was a module of its own (issue 46), reproduced from the plan alone.

The expected lists (tests/data/plan_expected.json) were taken from `snakemake -n --forceall <target>`
of the workflow at f51cf5e, whose common.smk built them at parse time: an independent reference, not
numbers the code under test produced."""

import json
import os
from pathlib import Path

import numpy as np
import pytest

from rail.setup.config import ConfigError, load_yaml, validate_config
from rail.setup.inputs import noise_files
from rail.setup.plan import IRREGULAR_SPEED, plan, speed_label

ROOT = Path(__file__).resolve().parents[1]
EXPECTED = json.loads((ROOT / "tests/data/plan_expected.json").read_text())
TARGETS, JOBS = EXPECTED["targets"], EXPECTED["jobs"]


@pytest.fixture(scope="module")
def P():
    here = Path.cwd()
    os.chdir(ROOT)  # the plan's paths, as the workflow's, are relative to the project folder
    try:
        schema = load_yaml("config/schema/config.schema.yaml")
        config = validate_config(load_yaml("config/config.yaml"), schema)
        yield plan(config, schema)
    finally:
        os.chdir(here)


def test_the_default_target_is_the_report_figures(P):
    assert P.paper_figures() == TARGETS["all"]
    assert P.receptance_tables() == TARGETS["receptances"]


def _without_noise(targets):
    """Targets without the noise outputs added since the lists were frozen (issue 56: rule growth_noise)."""
    return [t for t in targets if not t.endswith(("_noise.png", "_noise.csv"))]


@pytest.mark.parametrize("target,method", [
    ("sweeps", "sweep_targets"), ("bands", "band_targets"), ("any_wavelength", "any_wavelength_targets"),
    ("rate_spectrum_sweeps", "rate_spectrum_sweep_targets"), ("short_wave", "study_file_targets"),
    ("track_characterisation", "characterisation_targets"), ("closure_study", "study_file_targets"),
    ("irregular_track", "study_file_targets"),
])
def test_every_named_target_list_is_reproduced(P, target, method):
    # short_wave, closure_study and irregular_track: the study files config/studies/<target>.yaml (issue 57)
    got = _without_noise(getattr(P, method)(*[target] * (method == "study_file_targets")))
    if target == "track_characterisation":  # tracks added since the lists were frozen: six files each
        added = [t for t in got if any(f"/tracks/{name}/" in t for name in ADDED_TRACKS)]
        assert len(added) == 6 * len(ADDED_TRACKS)
        got = [t for t in got if t not in added]
    assert got == TARGETS[target]


# scenario files added after the lists were frozen (issue 43's dynamic-creepage study): one-train scenario
# files at the default speeds, whose study targets are those of nonhertzian (a case of config/studies/short_wave.yaml)
# under their own name
# the tracks they add, each characterised under the first scenario with it (by name): the 1e9 N/m pad of
# dyn_rail_pinned_stiff and dynspeed_*_stiff. dyn_rail_shear_soft and dyn_rail_shear_stiff change only the pads'
# longitudinal stiffness, which no vertical track result reads (rail.setup.targets.RAIL_HEAD_KEYS): their track is
# the default's (issue 57, item 5)
ADDED_TRACKS = ("dyn_rail_pinned_stiff", "tm_dampers_39", "tm_dampers_60")  # and the damper cells of track_mitigation.yaml
ADDED_SINCE = ("ws_disc", "ws_cast_iron", "ws_rail_cast_iron",
               "dyn_fixed", "dyn_rigid", "dyn_trailer", "dyn_trailer_independent", "dyn_driven", "dyn_rail", "dyn_rail_trailer",
               "dyn_rail_driven", "dyn_rail_pinned", "dyn_rail_pinned_slow",
               "dyn_rail_pinned_stiff", "dyn_rail_shear_soft", "dyn_rail_shear_stiff") + tuple(
    f"dynspeed_{m}{t}" for m in ("fixed", "trailer", "driven", "rail", "falling", "together") for t in ("", "_stiff")) + tuple(
    f"tenhz_{m}" for m in ("fixed", "driven", "rail", "falling", "together", "together_soft", "together_stiff")) + tuple(  # spectrum_band.yaml
    f"tm_{m}_{v}" for m in ("default", "dampers", "soft", "stiff", "trailer") for v in (39, 60))  # track_mitigation.yaml


def test_every_study_target_is_reproduced_scenarios_sweeps_and_fleets(P):
    expected = {t.removeprefix("study_"): v for t, v in TARGETS.items() if t.startswith("study_")}
    for name in ADDED_SINCE:
        expected[name] = [t.replace("/nonhertzian/", f"/{name}/") for t in expected["nonhertzian"]]
    assert sorted(P.study_names()) == sorted(expected)
    for name, targets in expected.items():
        got = P.study_targets(name)
        assert _without_noise(got) == targets, name
        # issue 56: beside each one-train run's overview, its noise where it can be computed
        runs = [(t.split("/")[2], float(t.split("/V")[-1].removesuffix("_overview.png"))) for t in targets
                if t.startswith("results/growth/") and t.endswith("_overview.png")]
        assert [t for t in got if t not in targets] == noise_files(P.scenarios, runs), name


def test_the_noise_target_holds_the_band_runs_whose_noise_can_be_computed(P):
    bands = [t.removesuffix("_bands.csv") for t in P.band_targets() if t.endswith("_bands.csv")]
    got = P.noise_targets()
    assert got and all(t.rsplit("_noise.", 1)[0] in bands for t in got)
    assert "results/growth/default/V40_noise.png" in got and "results/growth/default/V40_noise.csv" in got


def test_the_sweeps_points_in_grid_order(P):
    for study in P.sweeps:
        job = JOBS[f"sweep_aggregate/{study}"]
        assert P.sweep_runs(study) == job["input"]
        assert P.sweeps[study].keys == job["params"]["swept"]
        assert P.sweeps[study].values == job["params"]["grid"]
        assert [list(p.index) for p in P.sweeps[study].points] == job["params"]["indices"]
    spectra = {k.split("/")[1] for k in JOBS if k.startswith("rate_spectrum_sweep/")}
    assert {t.split("/")[-1][:-3] for t in P.rate_spectrum_sweep_targets() if t.endswith(".nc")} == spectra
    for study in spectra:
        runs = [f"results/spectrum/{p.name}/V{speed_label(p.speed)}.nc" for p in P.sweeps[study].points]
        assert runs == JOBS[f"rate_spectrum_sweep/{study}"]["input"]


def test_the_traffic_study_fleet_classes_and_their_shared_spectra(P):
    job = JOBS["traffic_study_summary"]
    assert P.traffic_study_inputs() == job["input"]
    assert P.traffic_study_labels() == job["params"]["cases"]
    # issue 45: a class job is named <vehicle>_V<speed>_<hash>; the frozen lists name it by the hash alone,
    # the same hash (its content), so the frozen name is the part after the last "_"
    def frozen(key):
        return key.rsplit("_", 1)[-1]

    # since the traffic study's full-physics re-run (issue 55) its classes read the rail's flexibility, their wheelsets and
    # the band's lines: other hashes, the same jobs. Each case's class list maps position by position onto the frozen one,
    # one to one, so the cases share their classes as before, and each job reads the frozen job's table and parameters
    renamed = {}
    for name in P.traffic_cases:
        old = [f.rsplit("/", 1)[-1][:-4] for f in JOBS[f"fleet_rate_spectrum/{name}"]["input"]]
        assert len(old) == len(P.fleet_spectrum_keys[name])
        for k, o in zip(P.fleet_spectrum_keys[name], old):
            assert renamed.setdefault(frozen(k), o) == o
    assert len(set(renamed.values())) == len(renamed) == 21
    for key, (name, i) in P.fleet_spectrum_jobs.items():
        job = JOBS[f"fleet_class_spectrum/{renamed[frozen(key)]}"]
        c = P.fleet_classes[name][i]
        bays = int(P.scenarios[name]["figures"]["rate_spectrum"]["bays"])
        assert [P.fleet_table_file(name, c.speed, bays)] == [f for f in job["input"] if "receptance" in f]
        assert job["params"]["job"] == [name, i, c.speed]
        # issue 45, item 14: the hash-named job says what it holds (its message and the first line of its log)
        label = P.fleet_class_label(key)
        assert label.startswith(f"{c.label} (fleets: ") and name in label


def test_fleet_class_jobs_and_logs_are_named_by_vehicle_and_speed_and_stay_unique(P):
    import re

    rule = (ROOT / "workflow/rules/fleet.smk").read_text()
    constraint = re.search(r'rule fleet_class_spectrum:.*?key="([^"]+)"', rule, re.S).group(1)
    assert 'log:\n        "logs/fleet/classes/{key}.log"' in rule
    keys = list(P.fleet_spectrum_jobs)
    assert len(keys) == len(set(keys)) == len({k.rsplit("_", 1)[-1] for k in keys}) > 4  # one job per content
    for key, (name, i) in P.fleet_spectrum_jobs.items():
        c = P.fleet_classes[name][i]
        assert key.startswith(f"{c.vehicle}_V{c.speed:.4g}_"), key
        assert re.fullmatch(constraint, key), key
    # the same vehicle at the same speed in two traffic cases (other creepage or speed spread): two names
    by_class = {}
    for key, (name, i) in P.fleet_spectrum_jobs.items():
        c = P.fleet_classes[name][i]
        by_class.setdefault((c.vehicle, f"{c.speed:.4g}"), set()).add(key)
    assert any(len(v) > 1 for v in by_class.values())


# Tables renamed since the lists were frozen: {recorded key: the scenario it served}. irregular_random's points write
# track.cell.random.distribution at its default (uniform), irregular_dampers track.cell.damper.position (0.5): a table
# is named by its track as the physics reads it, without the defaults, as the same file without the keys would be
# (issue 57, item 5; tests/test_rerun.py)
RENAMED_TABLES = {"3c57af5515": "irregular_dampers", "f67d844a76": "irregular_random-p0",
                  "37338b3a3e": "irregular_random-p1", "56e6046792": "irregular_random-p2",
                  "5a3f52de93": "irregular_random-p3", "878c798fa9": "irregular_random-p4",
                  "f336956d2d": "irregular_random-p5"}


def test_every_receptance_table_and_its_offsets(P):
    tables = JOBS["tables"]
    for path, offsets in tables.items():
        key, file = path.split("/")[2:]
        if key in RENAMED_TABLES:
            key = P.scenario_table[RENAMED_TABLES[key]]
            assert key not in {p.split("/")[2] for p in tables}, key
        if file.startswith("fleet_V"):
            t, V = P.fleet_table_of(key, file[len("fleet_V"):-3].split("_N")[0], None)
        else:
            label = file[1:-3].split("_N")[0]
            t = P.table(key, label)
        assert t.offsets == offsets, path


def test_the_irregular_track_study(P):
    job = JOBS["irregular_summary"]
    cases = [f"results/growth/{c}/V{IRREGULAR_SPEED}.nc" for c in P.irregular_cases()]
    random = [f"results/growth/{n}/V{IRREGULAR_SPEED}.nc" for n in P.irregular_random_points()]
    assert cases + [f"results/growth/irregular_uniform/V{IRREGULAR_SPEED}.nc"] + random == job["input"]
    assert {n: P.scenarios[n]["track"]["cell"]["random"].get("spacing", 0.0) for n in P.irregular_random_points()} == job["params"]["spreads"]


# The recorded draws were made on a CPU with AVX-512. A lognormal draw is median * exp(log(factor) z),
# and numpy dispatches its vectorised exp and log by CPU feature (AVX-512 or AVX2 code, each accurate to
# a few units in the last place), so on another CPU a draw may differ in its last digit (issue 57: 1 ULP
# seen with AVX-512 disabled). They are compared to a relative tolerance of 1e-13 (some 500 ULP): far
# below what a change of seed, stream or distribution does to a draw (its spread, 10-100 %).
DRAW_RTOL = 1e-13


def assert_draws_match_the_recording(draws):
    recorded = JOBS["uncertainty_ensemble"]["params"]["draws"]
    assert sorted(draws) == sorted(recorded)
    for key, values in draws.items():
        assert len(values) == len(recorded[key]), key
        np.testing.assert_allclose(values, recorded[key], rtol=DRAW_RTOL, atol=0, err_msg=key)


def test_the_recorded_draws_hold_on_a_cpu_without_avx512():
    """The draws made with numpy's AVX-512 code disabled (numpy 2.4's group names; a CPU without AVX-512
    runs this code anyway) match the recording to the stated tolerance: the other CPU's path, checked here."""
    import subprocess
    import sys

    code = ("import json, rail.uncertainty as U, rail.setup.config as C; u = C.load_yaml('config/uncertainty.yaml'); "
            "print(json.dumps({k: v.tolist() for k, v in U.sample(u['parameters'], u['members'], u['seed']).items()}))")
    env = {**os.environ, "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR", "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert_draws_match_the_recording(json.loads(out.stdout))


def test_the_uncertainty_closure_convergence_and_figure_sets(P):
    assert P.uncertainty_members() == JOBS["uncertainty_ensemble"]["input"]
    assert_draws_match_the_recording(P.uncertainty["draws"])
    assert P.uncertainty["interval"] == JOBS["uncertainty_ensemble"]["params"]["interval"]
    paths, meta = P.closure_inputs()
    assert paths == JOBS["closure_aggregate"]["input"] and meta == JOBS["closure_aggregate"]["params"]["meta"]
    assert P.convergence_points() == JOBS["convergence_aggregate"]["input"]
    assert P.growth_figures_runs() == JOBS["growth_figures"]["input"]
    assert P.growth_figures_labelled() == JOBS["growth_figures"]["params"]["runs"]
    assert P.wear_figure_cases() == JOBS["wear_figures"]["input"]
    assert {nn: P.wear_case_file(nn) for nn in JOBS["wear_figures"]["params"]["cases"]} == JOBS["wear_figures"]["params"]["cases"]


def test_a_target_speed_is_read_from_its_label_once_and_checked(P):
    assert P.target_speed("default", "40") == 40.0
    assert P.target_speed("default", "37.5") == 37.5
    with pytest.raises(ConfigError, match=r"target speed Vfast is not a number in m/s"):
        P.target_speed("default", "fast")
    with pytest.raises(ConfigError, match=r"target names the scenario 'nosuch', which is not defined"):
        P.target_speed("nosuch", "40")
    with pytest.raises(ConfigError, match=r"target speed Vinf = inf m/s is not allowed"):
        P.target_speed("default", "inf")


def test_no_workflow_function_parses_a_speed_back_from_a_label():
    # issue 46: a speed travels as a file label one way; scripts read it from params
    import re

    offenders = []
    for f in sorted((ROOT / "workflow").rglob("*")):
        if f.suffix in (".py", ".smk") or f.name == "Snakefile":
            for n, line in enumerate(f.read_text().splitlines(), 1):
                if re.search(r"(float|int)\((snakemake\.)?(wildcards|w)\.(speed|bays)\b|(float|int)\(w(ildcards)?\.get\(", line):
                    offenders.append(f"{f.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not offenders, "\n".join(offenders)
    assert len((ROOT / "workflow/rules/common.smk").read_text().splitlines()) < 300


def test_every_sweep_coordinate_carries_the_unit_the_schema_states(P):
    # issue 46: the unit table of rail.studies.datasets gave a swept relative spread
    # (track.cell.random.spacing) "m" and any other leaf "see config/schema"; the units now come from the schema
    from rail.setup.config import schema_unit
    from rail.studies.datasets import sweep_coords

    rnd = P.sweeps["irregular_random"]
    assert rnd.units[rnd.keys.index("track.cell.random.spacing")] == "1"
    assert P.schema["properties"]["track"]["properties"]["cell"]["properties"]["random"]["properties"]["spacing"]["unit"] == "-"
    for study, sw in P.sweeps.items():
        dims, coords = sweep_coords(sw.keys, sw.values, sw.units)
        assert [coords[d][2]["units"] for d in dims] == [schema_unit(P.schema, k) for k in sw.keys], study
    assert schema_unit(P.schema, "speed") == "m/s" and schema_unit(P.schema, "track.pad.stiffness") == "N/m"
    assert schema_unit(P.schema, "track.rail.loss_factor") == "1"  # through the schema's $defs
    with pytest.raises(KeyError, match="track.pad.nosuch: not a key"):
        schema_unit(P.schema, "track.pad.nosuch")


def test_a_wheelset_in_the_configuration_reaches_the_single_passage_jobs(P):
    """The wear figures' jobs (one passage, rail.setup.build.passage_scenario) read the wheelset when the
    configuration has one, and their params are unchanged when it has none (the report's figures)."""
    from rail.setup.build import passage_scenario
    from rail.setup.plan import FORCE_KEYS, WEAR_CASE_KEYS, config_part
    assert "wheelset" not in config_part(WEAR_CASE_KEYS, P.config)
    assert passage_scenario(config_part(WEAR_CASE_KEYS, P.config)).material.longitudinal is None
    wheelset = load_yaml(ROOT / "config/studies/dynamic_creepage.yaml")["cases"]["dyn_trailer"]["wheelset"]
    with_wheelset = {**P.config, "wheelset": wheelset}
    part = config_part(WEAR_CASE_KEYS, with_wheelset)
    assert part["wheelset"] == wheelset
    assert passage_scenario(part).material.longitudinal is not None
    assert "wheelset" not in config_part(FORCE_KEYS, with_wheelset)  # the forces do not read it


# Issue 45 (item 9): one broken draft file in config/scenarios stopped every target, studies that do
# not use it included; it now leaves out only its own scenarios, says so once at start-up (a note), and
# a target that needs it stops with the file's problem
DRAFTS = {
    "draft.yaml": "track:\n  pad:\n    stiffness: -1.0\n",  # the schema refuses it
    "draft_sweep.yaml": "sweep:\n  track.pad.stiffness: [3.5e+8, -1.0e+8]\n",  # one point refused
    "draft_tab.yaml": "track:\n\tpad: 1\n",  # not YAML
    "draft_fleet.yaml": ("fleet:\n  vehicles:\n    - {name: loco, positions: [0.0, 3.3], static_load: 1.0e+5, unsprung_mass: 1350.0, "
                         "creepage: [-0.001, -0.001], share: 1.0}\n  speeds: {values: [40.0], weights: [1.0]}\n"
                         "  spectrum: {bays: 4, shortest: 0.02, longest: 0.14, per_octave: 12}\n"
                         "track:\n  cell:\n    bays: 4\n    ballast: [1.0, 1.0e-3, 1.0, 1.0]\nroughness:\n  bays: 4\n"
                         "numerics:\n  track:\n    harmonics: 36\n"),  # refused by the fleet's cross-key check
    "draft_input.yaml": "roughness:\n  kind: spectrum\n  file: config/roughness/draft_levels.csv\n",  # refused reading its file
}


@pytest.fixture(scope="module")
def with_drafts(tmp_path_factory):
    import shutil

    work = tmp_path_factory.mktemp("drafts")
    shutil.copytree(ROOT / "config", work / "config")
    (work / "config/roughness/draft_levels.csv").write_text("wavelength_m,level_dB\n0.1,2.0\n0.08,1e6\n")
    for name, text in DRAFTS.items():
        (work / "config/scenarios" / name).write_text(text)
    here = Path.cwd()
    os.chdir(work)
    try:
        schema = load_yaml("config/schema/config.schema.yaml")
        config = validate_config(load_yaml("config/config.yaml"), schema)
        yield plan(config, schema)
    finally:
        os.chdir(here)


def test_a_broken_scenario_file_leaves_out_only_its_own_scenarios(P, with_drafts):
    D = with_drafts
    assert sorted(D.broken) == sorted(name[:-5] for name in DRAFTS)
    assert D.study_names() == P.study_names() and D.paper_figures() == P.paper_figures()
    assert [D.study_targets(n) for n in D.study_names()] == [P.study_targets(n) for n in P.study_names()]
    assert D.traffic_study_inputs() == P.traffic_study_inputs() and D.irregular_targets() == P.irregular_targets()
    for name in D.broken:
        assert name not in D.scenarios and name not in D.objects and name not in D.sweeps


def test_a_broken_scenario_file_is_said_once_at_start_up(with_drafts):
    notes = [n for n in with_drafts.notes if "is not valid, so it is left out of this run" in n]
    assert len(notes) == len(DRAFTS) and all("\n" not in n for n in notes)
    assert ("railgrowth: note: config/scenarios/draft.yaml is not valid, so it is left out of this run: only the targets that "
            "need it stop (the others run): config/scenarios/draft.yaml: track.pad.stiffness = -1.0 N/m is not allowed") in "\n".join(notes)


@pytest.mark.parametrize("ask, message", [
    (lambda D: D.require("draft"), r"config/scenarios/draft\.yaml: track\.pad\.stiffness = -1\.0 N/m is not allowed"),
    (lambda D: D.scenarios["draft"], r"config/scenarios/draft\.yaml: track\.pad\.stiffness = -1\.0 N/m"),
    (lambda D: D.target_speed("draft", "40"), r"config/scenarios/draft\.yaml: track\.pad\.stiffness"),
    (lambda D: D.study_input("draft")(None), r"config/scenarios/draft\.yaml: track\.pad\.stiffness"),
    (lambda D: D.require("draft_tab"), r"config/scenarios/draft_tab\.yaml, line 2, column 1: not valid YAML"),
    (lambda D: D.sweep_runs("draft_sweep"), r"draft_sweep\.yaml \(sweep point track\.pad\.stiffness = -100000000\.0\)"),
    (lambda D: D.require("draft_sweep-p0"), r"draft_sweep\.yaml \(sweep point track\.pad\.stiffness = -100000000\.0\)"),
    (lambda D: D.fleet_classes["draft_fleet"], r"draft_fleet\.yaml: fleet with track\.cell is not allowed"),
    (lambda D: D.objects["draft_input"], r"draft_levels\.csv, line 3: level 1e\+06 dB re 1 µm is not allowed"),
])
def test_a_target_that_needs_a_broken_scenario_file_stops_naming_its_problem(with_drafts, ask, message):
    with pytest.raises(ConfigError, match=r"^target needs the scenario '[\w-]+', which is left out of this run: "
                                          r"config/scenarios/draft\w*\.yaml is not valid: (.|\n)*" + message):
        ask(with_drafts)


def test_a_broken_sweep_study_stays_a_target_of_sweeps_that_stops(P, with_drafts):
    assert with_drafts.broken_sweeps == {"draft_sweep"}
    assert set(with_drafts.sweep_targets()) == set(P.sweep_targets()) | {"results/sweeps/draft_sweep.nc", "results/sweeps/draft_sweep.png"}


def test_a_fleets_default_class_spectra_fit_a_two_core_8_GB_machine(P):
    # issue 45, item 14: a fleet's class spectrum was sized by figures.rate_spectrum (a scenario file's
    # 222 lines of a 48-bay period on two grids: about 6.9 GB and 47 min CPU for a four-axle class);
    # fleet.spectrum's defaults give 31 lines of a 5-bay period on one grid
    from rail.setup import build
    from rail.setup.config import load_yaml, project_schema, resolve_scenario_file
    from rail.setup.study_files import CLASS_MEMORY_MB, class_estimate

    vehicle = {"name": "loco", "positions": [0.0, 3.3, 10.0, 13.3], "static_load": 1.0e5, "unsprung_mass": 1350.0,
               "creepage": [-0.001] * 4, "share": 1.0}
    fleet = {"vehicles": [vehicle], "speeds": {"distribution": "uniform", "low": 45.0, "high": 55.0, "classes": 3}}
    cfg = resolve_scenario_file(load_yaml(ROOT / "config/config.yaml"), project_schema(), {"fleet": fleet}, "mix.yaml")
    classes = build.fleet_classes(cfg, build.spectrum_scenario(cfg, "mix"))
    est = [class_estimate(c, cfg["figures"]["rate_spectrum"]) for c in classes]
    assert {(e.lines, e.axles) for e in est} == {(31, 4)}
    key = next(k for k, (name, i) in P.fleet_spectrum_jobs.items() if P.fleet_classes[name][i].vehicle == "class87")
    e = P.fleet_class_estimate(key)  # a traffic-study class: the default lines and the band's (config/traffic_study.yaml)
    name = P.fleet_spectrum_jobs[key][0]
    s = P.scenarios[name]["figures"]["rate_spectrum"]
    from rail.growth_spectrum import settings_lines
    K = int(P.scenarios[name]["numerics"]["track"]["harmonics"])
    assert (e.lines, e.axles) == (len(settings_lines(0.6, 5, K, s)), 4) and e.lines > 31
    res = P.fleet_class_resources(key)
    extra, factor = 300, 1.3  # mem_mb = its estimate x 1.3 + 300 (rail.setup.plan.Plan.fleet_class_resources)
    assert res["mem_mb"] == int(extra + factor * e.memory_mb) and res["runtime"] == int(10 + 3 * e.cpu_seconds / 60)
    assert "PLAN.fleet_class_resources(w.key)" in (ROOT / "workflow/rules/fleet.smk").read_text()
    mem_mb = [extra + factor * x.memory_mb for x in est]
    assert 2 * max(mem_mb) <= 6000  # two jobs under -j2 leave 2 GB of 8 GB for the system and Snakemake
    assert max(e.cpu_seconds for e in est) <= 600  # minutes, not half an hour, on one core
    # the coefficients cover every measured job (max_rss, MB; lines x axles): traffic study, first attempt
    # (61 x 4: locomotive 1893, coach 2183), at 31 x 4 (926-1485), and issue 45's class87 at 40 m/s (31 x 4)
    # and the full-physics re-run's classes (73 x 4 with the band: 957-1,397 MB, 2026-12-02)
    for lines, axles, rss in ((61, 4, 1893), (61, 4, 2183), (31, 4, 1485), (31, 4, MEASURED_CLASS87_RSS), (73, 4, 1397)):
        assert CLASS_MEMORY_MB[0] + CLASS_MEMORY_MB[1] * lines * axles >= rss
    # the settings a fleet had before: one job alone would not have fitted beside another in 8 GB
    old = dict(cfg["figures"]["rate_spectrum"], bays=48, shortest=0.0, longest=0.6, per_octave=30, grid_phases=2)
    scn = build.spectrum_scenario({**cfg, "figures": {**cfg["figures"], "rate_spectrum": old}}, "mix")
    before = class_estimate(build.fleet_classes(cfg, scn)[0], old)
    assert before.lines == 222 and extra + factor * before.memory_mb > 8000


MEASURED_CLASS87_RSS = 1184  # max_rss of benchmarks/fleet/classes/class87_V40_263e4cb40354cd39.tsv (docs/traffic.md)


def test_the_plan_module_stays_under_800_lines_and_keeps_every_name():
    # issue 44: no module of rail/ over 800 lines; the labels, configuration parts, fixed target sets and
    # records moved to rail.setup.targets are the same objects under rail.setup.plan
    import rail.setup.plan as plan_module
    import rail.setup.targets as targets

    assert len((ROOT / "rail/setup/plan.py").read_text().splitlines()) < 800
    assert all(getattr(plan_module, name) is getattr(targets, name) for name in targets.__all__)
    assert all(hasattr(plan_module, name) for name in plan_module.__all__)


def test_the_speed_study_reads_every_case_of_its_study_file_at_its_own_speeds(P):
    """Rule speed_study's inputs (issue 43), read here from the study file itself: every case of
    config/studies/dynamic_creepage_speeds.yaml, one spectrum per speed of its figures.rate_spectrum.speeds
    (the file's defaults unless the case gives its own)."""
    study = load_yaml(ROOT / "config/studies/dynamic_creepage_speeds.yaml")
    assert len(study["cases"]) == 12  # six mechanisms (fixed, trailer, driven, rail, falling, together) on two tracks
    got = P.speed_study_spectra()
    assert sorted(got) == sorted(study["cases"])
    for name, case in study["cases"].items():
        speeds = ((case or {}).get("figures") or study["defaults"]["figures"])["rate_spectrum"].get(
            "speeds", study["defaults"]["figures"]["rate_spectrum"]["speeds"])
        assert got[name] == [f"results/spectrum/{name}/V{v:g}.nc" for v in speeds]
    assert got["dynspeed_together_stiff"][0].endswith("/V40.nc")  # not at 20 m/s (the file says why)


def test_rail_flexibility_target_is_dyn_fixed_and_every_case_of_its_study_file(P):
    """The named target rail_flexibility: dyn_fixed for comparison (included from dynamic_creepage.yaml) and
    every case of config/studies/rail_flexibility.yaml, read from the file (a new case joins the target without
    an edit of the rule; a file in config/scenarios/ joins none: tests/test_study_files.py)."""
    study = load_yaml(ROOT / "config/studies/rail_flexibility.yaml")
    assert study["include"] == ["dyn_fixed"] and len(study["cases"]) == 8
    got = P.study_file_targets("rail_flexibility")
    want = ["dyn_fixed"] + list(study["cases"])
    assert sorted(got) == sorted(f"results/spectrum/{n}/rate_spectrum.png" for n in want)


def test_a_cells_jobs_ask_the_cluster_for_the_rail_heads_table_they_build_first(P):
    """A growth run or a spectrum on a track cell with the rail's flexibility first builds the head's table over the cell
    (rail.chain.cell_head_ready), about 9 min of CPU for the irregular track's 8-bay cells: the growth job's runtime
    estimate holds it (rule rate_spectrum_speed adds three times it, workflow/rules/spectrum.smk), and nothing is added
    where there is no cell head."""
    from rail.creepage.rail_flexibility_cell import table_seconds
    scn = P.objects["irregular_stiff_pad"]
    head = scn.material.rail_flexibility
    assert P.cell_head_seconds("irregular_stiff_pad") == table_seconds(head, scn.roughness.bays * scn.harmonics) > 300
    assert P.growth_seconds("irregular_stiff_pad") > P.cell_head_seconds("irregular_stiff_pad")
    assert P.cell_head_seconds("irregular_dampers") < P.cell_head_seconds("irregular_voided") < P.cell_head_seconds("irregular_stiff_pad")
    assert P.cell_head_seconds("default") == 0.0 and P.cell_head_seconds("irregular_uniform") == 0.0
    # and the memory they peak at (growth 1,838 MB there and up to 2,353 MB on the random 8-bay cells, the spectrum 3,382 MB;
    # against the uniform track's rules' 1,600 and 1,400)
    from rail.creepage.rail_flexibility_cell import cell_memory_mb
    assert cell_memory_mb(scn, 1600, 2.0) > 2353 and cell_memory_mb(scn, 1400, 4.5) > 3382
    assert cell_memory_mb(P.objects["default"], 1400, 4.5) == 1400
