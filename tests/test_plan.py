"""The workflow's plan (rail.setup.plan) without Snakemake: every target list the workflow built before
the plan was a module of its own (issue 46), reproduced from the plan alone.

The expected lists (tests/data/plan_expected.json) were taken from `snakemake -n --forceall <target>`
of the workflow at f51cf5e, whose common.smk built them at parse time: an independent reference, not
numbers the code under test produced."""

import json
import os
from pathlib import Path

import pytest

from rail.setup.config import ConfigError, load_yaml, validate_config
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


@pytest.mark.parametrize("target,method", [
    ("sweeps", "sweep_targets"), ("bands", "band_targets"), ("any_wavelength", "any_wavelength_targets"),
    ("rate_spectrum_sweeps", "rate_spectrum_sweep_targets"), ("short_wave", "short_wave_targets"),
    ("track_characterisation", "characterisation_targets"), ("closure_study", "closure_targets"),
    ("irregular_track", "irregular_targets"),
])
def test_every_named_target_list_is_reproduced(P, target, method):
    assert getattr(P, method)() == TARGETS[target]


# scenario files added after the lists were frozen (issue 43's dynamic-creepage study): one-train scenario
# files at the default speeds, whose study targets are those of nonhertzian.yaml under their own name
ADDED_SINCE = ("dyn_fixed", "dyn_rigid", "dyn_trailer", "dyn_trailer_independent", "dyn_driven", "dyn_rail", "dyn_rail_trailer",
               "dyn_rail_driven")


def test_every_study_target_is_reproduced_scenarios_sweeps_and_fleets(P):
    expected = {t.removeprefix("study_"): v for t, v in TARGETS.items() if t.startswith("study_")}
    for name in ADDED_SINCE:
        expected[name] = [t.replace("/nonhertzian/", f"/{name}/") for t in expected["nonhertzian"]]
    assert sorted(P.study_names()) == sorted(expected)
    for name, targets in expected.items():
        assert P.study_targets(name) == targets, name


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
        assert [f"results/spectrum/{p.name}/V{speed_label(p.speed)}.nc" for p in P.sweeps[study].points] == JOBS[f"rate_spectrum_sweep/{study}"]["input"]


def test_the_traffic_study_fleet_classes_and_their_shared_spectra(P):
    job = JOBS["traffic_study_summary"]
    assert P.traffic_study_inputs() == job["input"]
    assert P.traffic_study_labels() == job["params"]["cases"]
    for name in P.traffic_cases:
        assert [f"results/fleet/classes/{k}.npz" for k in P.fleet_spectrum_keys[name]] == JOBS[f"fleet_rate_spectrum/{name}"]["input"]
    for key, (name, i) in P.fleet_spectrum_jobs.items():
        job = JOBS[f"fleet_class_spectrum/{key}"]
        c = P.fleet_classes[name][i]
        bays = int(P.scenarios[name]["figures"]["rate_spectrum"]["bays"])
        assert [P.fleet_table_file(name, c.speed, bays)] == [f for f in job["input"] if "receptance" in f]
        assert job["params"]["job"] == [name, i, c.speed]


def test_every_receptance_table_and_its_offsets(P):
    tables = JOBS["tables"]
    for path, offsets in tables.items():
        key, file = path.split("/")[2:]
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


def test_the_uncertainty_closure_convergence_and_figure_sets(P):
    assert P.uncertainty_members() == JOBS["uncertainty_ensemble"]["input"]
    assert P.uncertainty["draws"] == JOBS["uncertainty_ensemble"]["params"]["draws"]
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
