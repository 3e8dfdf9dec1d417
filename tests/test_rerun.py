"""Rerun triggers (issue 57, item 5): a job's params, which Snakemake compares with those of the run
that built its output, hold a configuration as the physics reads it (rail.setup.targets.read_part),
so that a key nothing reads, or one written at its default, reruns nothing, while every key the
physics reads still reruns what it changes.

The reference is rail.setup.build, not read_part: a key is read where the objects built from the
configuration change with it (the Scenario of a growth run or of a passage, the Track and cell of a
receptance table). The job counts are those of `snakemake -n` on a results tree marked up to date
(`--touch`): on d9d3375 the edits of the issue planned 21, 14, 12 and 12 jobs."""

import copy
import dataclasses
import re
import shutil
import subprocess
import sys
from collections import Counter

import numpy as np
import pytest
import yaml

from rail.setup import build
from rail.setup.config import ConfigError, deep_merge, resolve_scenario_file, validate_config
from rail.setup.plan import (FORCE_KEYS, GROWTH_FIGURE_KEYS, HALFSPACE_KEYS, RAIL_HEAD_KEYS, WEAR_CASE_KEYS,
                             config_part, physics_part, plan, read_part, track_part)
from rail.setup.study_files import study_cases
from rail.setup.tables import table_key

# Configurations in which every optional key is tried: the report's, the rail's flexibility (with and
# without the head's bending), the three wheelsets, and a track cell with a damper and random supports.
CELL = {"track": {"cell": {"bays": 2, "damper": {"mass": 4.0, "frequency": 1070.0},
                           "random": {"seed": 1, "spacing": 0.05}}},
        "roughness": {"bays": 2}, "speeds": [40.0], "numerics": {"track": {"harmonics": 36}},
        "figures": {"rate_spectrum": {"bays": 2}}}
CONTEXTS = {
    "report": {},
    "rail_rod_and_bending": {"rail_flexibility": {"model": "rod_and_bending"}},
    "rail_rod": {"rail_flexibility": {"model": "rod"}},
    "torsional_driven": {"wheelset": {"model": "torsional", "motor_inertia": 288.0}},
    "torsional_trailer": {"wheelset": {"model": "torsional"}},
    "rigid": {"wheelset": {"model": "rigid"}},
    "fixed_creepage": {"wheelset": {"model": "fixed_creepage"}},
    "cell": CELL,
    "wheel_source": {"wheel_source": {"roughness": "cast_iron"}},
}


def optional_keys(schema, node=None, key=""):
    """{dotted key: its schema node} of every key with a schema default (read through rail.setup.config.setting)."""
    node = schema if node is None else node
    out = {}
    for name, sub in node.get("properties", {}).items():
        dotted = f"{key}.{name}" if key else name
        if "$ref" in sub:
            sub = {**schema["$defs"][sub["$ref"].split("/")[-1]], **sub}
        if "default" in sub:
            out[dotted] = sub
        out.update(optional_keys(schema, sub, dotted))
    return out


def other_value(node):
    """A valid value of a key other than its default."""
    d = node["default"]
    if "enum" in node:
        return next(v for v in node["enum"] if v != d)
    if isinstance(d, bool):
        return not d
    hi = node.get("maximum", node.get("exclusiveMaximum"))
    if d is None:  # an optional number whose default is null (not assessed, or taken from another key)
        lo = node.get("minimum", node.get("exclusiveMinimum", 0.0))
        return 0.5 * (lo + hi) if hi is not None else lo + 1.0
    if isinstance(d, int) and node.get("type") == "integer":
        return d + 1
    if d == 0:
        return 0.5 * hi if hi is not None else 1.0
    return 0.8 * d if hi is not None and 1.25 * d >= hi else 1.25 * d


def nested(dotted, value):
    out = value
    for part in reversed(dotted.split(".")):
        out = {part: out}
    return out


def dotted_keys(d, key=""):
    """Every dotted key of a nested mapping, sections included."""
    out = set()
    for name, value in d.items():
        dotted = f"{key}.{name}" if key else name
        out |= {dotted} | (dotted_keys(value, dotted) if isinstance(value, dict) else set())
    return out


def same(a, b) -> bool:
    """Whether two built objects (dataclasses, arrays, tuples, numbers) are equal, field by field."""
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return type(a) is type(b) and all(same(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a))
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.shape(a) == np.shape(b) and bool(np.all(np.asarray(a) == np.asarray(b)))
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    return a == b


def table_content(cfg):
    """What a receptance table is built from: the track, its numerics and its cell (rail.setup.build)."""
    return build.track(cfg), build.track_cell(cfg)


@pytest.fixture(scope="module")
def config(defaults, schema):
    return validate_config(defaults, schema)


def resolved(config, schema, overrides):
    # each context its own models (not the full physics a scenario file starts from: the context "report" is the report's)
    return resolve_scenario_file(config, schema, overrides, source="test", physics=False)


@pytest.mark.parametrize("context", list(CONTEXTS))
def test_a_key_is_left_out_exactly_when_the_built_physics_does_not_change_with_it(config, schema, context):
    base = resolved(config, schema, CONTEXTS[context])
    scn, table = build.scenario(base), table_content(base)
    tried = 0
    for key, node in optional_keys(schema).items():
        if key.startswith("fleet."):  # the fleet's spectrum settings: copied into figures.rate_spectrum by resolve
            continue
        try:
            cfg = resolved(config, schema, deep_merge(CONTEXTS[context], nested(key, other_value(node))))
            built = build.scenario(cfg)
        except ConfigError:  # a key of a section the context has not (a wheelset's without its model), a refused model
            continue
        tried += 1
        # the noise settings are read by the noise rule's own object, not the scenario (rail.setup.build.noise_settings)
        # and the wheels' source by the spectrum's jobs (rail.setup.build.wheel_source_settings)
        physics_same = (same(built, scn) and same(build.noise_settings(cfg), build.noise_settings(base))
                        and build.wheel_source_settings(cfg) == build.wheel_source_settings(base))
        assert (read_part(cfg, schema) == read_part(base, schema)) == physics_same, (context, key, physics_same)
        table_same = same(table_content(cfg), table)
        assert (track_part(read_part(cfg, schema)) == track_part(read_part(base, schema))) == table_same, (context, key)
        keys = [table_key(track_part(read_part(c, schema)), [0.0]) for c in (cfg, base)]
        assert (keys[0] == keys[1]) == table_same, (context, key)
    assert tried >= 2


def test_every_optional_key_is_read_in_some_context(config, schema):
    # the contexts reach every key: none is left out everywhere (which the test above would not see)
    read = set()
    for overrides in CONTEXTS.values():
        base = resolved(config, schema, overrides)
        for key, node in optional_keys(schema).items():
            try:
                cfg = resolved(config, schema, deep_merge(overrides, nested(key, other_value(node))))
            except ConfigError:
                continue
            if read_part(cfg, schema) != read_part(base, schema):
                read.add(key)
    assert read == {k for k in optional_keys(schema) if not k.startswith("fleet.")}
    assert set(RAIL_HEAD_KEYS) <= read


@pytest.mark.parametrize("context", list(CONTEXTS))
def test_a_key_written_at_its_default_is_read_as_if_absent(config, schema, context):
    base = read_part(resolved(config, schema, CONTEXTS[context]), schema)
    for key, node in optional_keys(schema).items():
        if key in dotted_keys(CONTEXTS[context]):  # the context's own value: the default there is an edit
            continue
        try:
            cfg = resolved(config, schema, deep_merge(CONTEXTS[context], nested(key, node["default"])))
        except ConfigError:
            continue
        assert read_part(cfg, schema) == base, (context, key)


def test_the_read_part_is_a_valid_configuration_that_builds_the_same_physics(config, schema):
    for overrides in CONTEXTS.values():
        cfg = resolved(config, schema, deep_merge(overrides, {"contact": {"friction_decay": 0.0},
                                                              "track": {"pad": {"longitudinal_stiffness": 2.0e7}}}))
        part = validate_config(read_part(cfg, schema), schema)
        assert same(build.scenario(part), build.scenario(cfg))
        assert part is not cfg and cfg["contact"]["friction_decay"] == 0.0  # the configuration itself is left as it was


def test_a_base_keeps_what_a_case_could_switch_on(config, schema):
    cfg = resolved(config, schema, {"track": {"pad": {"longitudinal_stiffness": 2.0e7}},
                                    "contact": {"friction_decay": 0.0},
                                    "wheelset": {"model": "fixed_creepage", "wheel_inertia": 60.0}})
    base = read_part(cfg, schema, base=True)
    assert base["track"]["pad"]["longitudinal_stiffness"] == 2.0e7 and base["wheelset"]["wheel_inertia"] == 60.0
    assert "friction_decay" not in base["contact"]
    case = deep_merge(base, {"wheelset": {"model": "torsional"}, "rail_flexibility": {"model": "rod"}})
    full = deep_merge(cfg, {"wheelset": {"model": "torsional"}, "rail_flexibility": {"model": "rod"}})
    assert same(build.scenario(validate_config(case, schema)), build.scenario(validate_config(full, schema)))


# -- the plan: the params of every job, before and after an edit of config/config.yaml ----------------

EDITS_READ_BY_NOTHING = {
    "track.pad.longitudinal_stiffness": {"track": {"pad": {"longitudinal_stiffness": 2.0e7}}},
    "track.rail.head_height": {"track": {"rail": {"head_height": 0.08}}},
    "contact.friction_decay: 0.0": {"contact": {"friction_decay": 0.0}},
    "rail_flexibility: {model: none}": {"rail_flexibility": {"model": "none"}},
    "wheelset: {model: fixed_creepage, ...}": {"wheelset": {"model": "fixed_creepage", "wheel_inertia": 60.0}},
}


@pytest.fixture(scope="module")
def small_root(root, tmp_path_factory):
    """The project's config/ with a few scenario files: the report figures', one on the rail's flexibility
    (whose table must not change with the pads' longitudinal stiffness either), a torsional wheelset and a cell."""
    top = tmp_path_factory.mktemp("plan")
    shutil.copytree(root / "config", top / "config", ignore=shutil.ignore_patterns("scenarios", "studies"))
    (top / "config/scenarios").mkdir()
    (top / "config/studies").mkdir()
    for name in ("soft_pad", "class87"):
        shutil.copy(root / f"config/scenarios/{name}.yaml", top / "config/scenarios")
    cases = study_cases(root)
    study = {"cases": {name: cases[name][1] for name in ("dyn_rail_shear_soft", "dyn_driven", "irregular_dampers")}}
    (top / "config/studies/two.yaml").write_text(yaml.safe_dump(study, sort_keys=False))
    return top


def job_params(P) -> dict:
    """What the workflow's rules hand their jobs as configuration (workflow/rules/*.smk through common.smk),
    and the tables' names: {job: params}."""
    out = {f"scenario {n}": P.scenarios[n] for n in P.scenarios}
    out |= {f"table {n}": (P.scenario_table[n], P.track_part(n)) for n in P.scenario_table}
    out |= {f"fleet table {n}": P.fleet_table[n] for n in P.fleet_table}
    for name, keys in (("halfspace", HALFSPACE_KEYS), ("fig08", FORCE_KEYS + ("figures.fig08",)),
                       ("fig22", FORCE_KEYS + ("figures.fig22",)), ("wear_cases", WEAR_CASE_KEYS),
                       ("growth_figures", GROWTH_FIGURE_KEYS)):
        out[name] = config_part(keys, P.config)
    out["studies"] = physics_part(P.config)
    out |= {f"stability {c}": P.stability_config(c) for c in P.stability["cases"]}
    out |= {f"uncertainty m{m}": P.uncertainty_member(str(m)) for m in range(len(P.uncertainty["members"]))}
    out |= {f"wear figure {nn}": P.wear_figure_config(nn) for nn in ("09", "13")}
    out |= {f"closure wear {s}": P.closure_wear_config(f"{s:g}") for s in P.closure_values()}
    return out


@pytest.fixture(scope="module")
def before(config, schema, small_root):
    return job_params(plan(config, schema, small_root))


# What reads each edit there: dyn_rail_shear_soft has the rail's flexibility with the head's bending, so it reads
# config.yaml's head height (its pads' longitudinal stiffness is its own); the traffic study's cases, re-run with the
# rail's flexibility (issue 55), read both, and so does the irregular track's damper cell (its study re-run with the rail's
# flexibility on the cell, issue 55); nothing else reads any of them.
TRAFFIC = [f"scenario traffic_study-{d}-s{s}" for d in ("driven", "braked") for s in (0, 5, 10, 20)] + ["scenario irregular_dampers"]
READ_BY = {"track.rail.head_height": ["scenario dyn_rail_shear_soft", *TRAFFIC], "track.pad.longitudinal_stiffness": TRAFFIC}


@pytest.mark.parametrize("edit", list(EDITS_READ_BY_NOTHING))
def test_an_edit_changes_the_configuration_of_the_jobs_that_read_it_alone(config, schema, small_root, before, edit):
    edited = validate_config(deep_merge(config, EDITS_READ_BY_NOTHING[edit]), schema)
    after = job_params(plan(edited, schema, small_root))
    assert after.keys() == before.keys()
    assert sorted(job for job in before if after[job] != before[job]) == sorted(READ_BY.get(edit, []))


def test_a_wheel_mass_edit_changes_what_reads_the_wheel_and_nothing_else(config, schema, small_root, before):
    P = plan(validate_config(deep_merge(config, {"wheels": {"mass": 1400.0}}), schema), schema, small_root)
    after = job_params(P)
    changed = {job for job in before if after[job] != before[job]}
    # the wheel's mass is its receptance -1 / (m omega^2) (rail.interaction.Wheels): every passage, growth run and
    # spectrum, every stability case and ensemble member; never a table (the track alone), the half-space or the
    # figures' own settings. A fleet's vehicles carry their own unsprung mass, but its scenario keeps wheels.mass.
    assert not any(job.startswith(("table", "fleet table")) for job in changed)
    assert {"halfspace", "growth_figures"}.isdisjoint(changed)
    assert {"fig08", "fig22", "wear_cases", "studies", "wear figure 09", "wear figure 13"} <= changed
    assert {f"scenario {n}" for n in P.scenarios} <= changed
    assert {j for j in before if j.startswith(("stability", "uncertainty", "closure wear"))} <= changed


def test_the_pads_longitudinal_stiffness_names_no_table_even_where_the_rail_is_flexible(config, schema, small_root):
    P = plan(config, schema, small_root)
    # dyn_rail_shear_soft differs from the default only in the pads' shear stiffness, read by the rail head alone
    assert P.scenario_table["dyn_rail_shear_soft"] == P.scenario_table["default"]
    assert P.scenarios["dyn_rail_shear_soft"]["track"]["pad"]["longitudinal_stiffness"] == 5.0e6  # read by its spectrum


# -- the workflow: jobs planned after each edit, on a results tree marked up to date -------------------

def snakemake(root, workdir, *args):
    cmd = [sys.executable, "-m", "snakemake", "-s", str(root / "Snakefile"), *args]
    out = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    return out.stdout


def planned(output: str) -> Counter:
    """{rule: jobs} of a dry run (a receptance job is shown by its message)."""
    found = re.findall(r"^(?:local)?rule (\w+):$|^Job \d+: (receptance) table", output, re.M)
    return Counter(a or b for a, b in found)


@pytest.mark.workflow
@pytest.mark.slow
def test_the_default_target_reruns_nothing_for_edits_nothing_reads_and_what_reads_the_wheel_mass(root, tmp_path):
    shutil.copytree(root / "config", tmp_path / "config")
    text = (tmp_path / "config/config.yaml").read_text()
    dry = snakemake(root, tmp_path, "-n")
    files = [f.strip() for line in re.findall(r"^\s+output: (.*)$", dry, re.M) for f in line.split(",")]
    files += re.findall(r"receptance tables? (results/receptance/[0-9a-f]{10}/V[^\s,:]+\.nc)", dry)
    for f in files:
        (tmp_path / f).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / f).touch()
    snakemake(root, tmp_path, "--touch", "--forceall", "-j1", "-q")  # records every job's params, as a run would
    assert "Nothing to be done" in snakemake(root, tmp_path, "-n")

    def edited(change):  # the keys added at the end of their sections, the rest of config.yaml as it was
        cfg = copy.deepcopy(yaml.safe_load(text))
        (tmp_path / "config/config.yaml").write_text(yaml.safe_dump(deep_merge(cfg, change), sort_keys=False))
        return planned(snakemake(root, tmp_path, "-n"))

    everything = {}
    for change in EDITS_READ_BY_NOTHING.values():
        everything = deep_merge(everything, change)
    assert edited(everything) == {}  # on d9d3375: 21 jobs (each edit alone: 21, 21, 14, 12, 12)
    # the wheel's mass: the 7 growth runs, the forces of Figs 8 and 22, the wear cases, and the figures drawn from
    # them; no receptance table, no half-space figure
    assert edited({"wheels": {"mass": 1400.0}}) == {"growth": 7, "fig08": 1, "fig22": 1, "wear_cases": 1,
                                                    "wear_figures": 1, "growth_figures": 1, "growth_3d": 1, "all": 1}
