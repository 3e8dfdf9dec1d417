# Helpers that map a rule's wildcards to paths and params. What the workflow runs (every scenario, sweep, traffic case, fleet class,
# table and study set, every target list) is decided once, at start-up, by rail.setup.plan (a pure module, tested without Snakemake:
# tests/test_plan.py); the helpers only ask it. Rules live in the other .smk files; params hold configurations as the physics reads them.

import sys
from pathlib import Path

from snakemake.utils import validate

from rail.creepage.rail_flexibility_cell import cell_memory_mb
from rail.provenance import code_hash
from rail.setup.config import load_yaml, validate_config
from rail.setup.inputs import measured_decay_file
from rail.setup.oneoff import one_off_run_dir
from rail.setup.plan import (CHARACTERISATION, FORCE_KEYS, GROWTH_FIGURE_KEYS, GROWTH_FIGURES, HALFSPACE_FIGURES, HALFSPACE_KEYS,
                             IRREGULAR_SPEED, PRIORITY_KERNELS, PRIORITY_TABLES, REPORT_SUFFIXES, WEAR_CASE_KEYS, WEAR_FIGURES,
                             DEFAULT_SOURCE, fleet_speed_label, known_value, physics_part, plan, speed_label, wear_frequency_label)
from rail.setup.plan import config_part as _config_part

# Clear, actionable messages first (key, value, unit, valid range), then snakemake's own validation
# against the same schema; then the plan (its errors name the file, key and valid range). The schema's
# defaults of optional keys are read where they are used (rail.setup.config.setting), not written into
# the config: set_default=False keeps the config (and each job's part of it) what the user wrote.
SCHEMA = load_yaml(workflow.source_path("../../config/schema/config.schema.yaml"))
validate_config(config, SCHEMA, source=DEFAULT_SOURCE)
validate(config, "../../config/schema/config.schema.yaml", set_default=False)
PLAN = plan(config, SCHEMA)
for _note in PLAN.notes:  # a roughness input the period cannot hold in full, once per message
    print(_note, file=sys.stderr)
SCENARIOS = PLAN.scenarios


def code(script):
    """Hash of the rail sources that workflow/scripts/<script> imports (rail.provenance): a rule's
    params hold it, so that changing a module reruns exactly the jobs that depend on it."""
    return code_hash(Path(workflow.basedir, "workflow", "scripts", script))


def kernels(which):
    """The marker of the compiled kernels a rule's script calls: 'march' or 'tangent'."""
    return ancient(f"results/cache/kernels_{which}.txt")  # its age never reruns a job (each job's code hash does)


def config_part(keys, cfg=None):
    """The part of a configuration (default: this run's, as the physics reads it: PLAN.config) under the
    dotted keys: a job's params.cfg."""
    return _config_part(keys, PLAN.config if cfg is None else cfg)


def default_physics(*keys):
    """The default configuration's physics and the figure keys given: what a study script reads."""
    return {**physics_part(PLAN.config), **config_part(keys)}


def scenario_config(wildcards):
    """Resolved configuration of the scenario named by the wildcard 'scenario'."""
    return SCENARIOS[wildcards.scenario]


def physics_config(wildcards):
    """A scenario's configuration without figure settings, measurements and half-space quadrature."""
    return physics_part(SCENARIOS[wildcards.scenario])


def target_speed(wildcards):
    """The speed [m/s] of a scenario's target, checked (rail.setup.plan.Plan.target_speed)."""
    return PLAN.target_speed(wildcards.scenario, wildcards.speed)


def roughness_file(wildcards):
    """A scenario's roughness file, as an input so that editing it reruns the growth."""
    r = PLAN.objects[wildcards.scenario].roughness
    return [r.file] if r.kind in ("file", "profile", "spectrum") else []


# Receptance tables, named by their content (issue 36, rail.setup.tables, docs/workflow.md).

table_file = PLAN.table_file
def _table(wildcards):
    return PLAN.table(wildcards.track, wildcards.speed, wildcards.get("bays"))


def table_config(wildcards):
    """What a content-named table depends on: its track and track numerics (speed and period checked)."""
    return PLAN.track_part(_table(wildcards).scenario)


def table_offsets(wildcards):
    """The wheel offsets [m] a content-named table holds."""
    return _table(wildcards).offsets


def table_speed(wildcards):
    """The speed [m/s] of a table target, checked as a speed of the scenarios it serves."""
    return PLAN.target_speed(_table(wildcards).scenario, wildcards.speed)


def table_bays(wildcards):
    """The period N of a table target (1 for the one-bay tables)."""
    return PLAN.target_bays(wildcards.bays) if "bays" in wildcards.keys() else 1


def table_priority(wildcards):
    """After the kernels' compile, the tables of more wheels first."""
    return PRIORITY_TABLES + min(len(table_offsets(wildcards)), PRIORITY_KERNELS - PRIORITY_TABLES - 1)


def growth_table(wildcards):
    """The table a growth run needs: its track at its speed (Bloch tables for N > 1 bays)."""
    PLAN.not_a_fleet(wildcards.scenario, "growth")
    target_speed(wildcards)
    return table_file(wildcards.scenario, wildcards.speed, PLAN.objects[wildcards.scenario].roughness.bays)


def rate_spectrum_table(wildcards):
    """The Bloch tables of the spectrum's N-bay period (figures.rate_spectrum.bays) at the speed."""
    PLAN.not_a_fleet(wildcards.scenario, "rate_spectrum")
    target_speed(wildcards)
    return table_file(wildcards.scenario, wildcards.speed, SCENARIOS[wildcards.scenario]["figures"]["rate_spectrum"]["bays"])


def growth_runtime(wildcards):
    """Cluster runtime of a growth or fleet growth job [min]: three times its estimated CPU time plus 10 min."""
    return int(10 + 3 * PLAN.growth_seconds(wildcards.scenario) / 60)


def growth_priority(wildcards):
    """Its estimated CPU seconds, longest first, below the tables it needs."""
    return 1 + min(int(PLAN.growth_seconds(wildcards.scenario)), PRIORITY_TABLES - 2)


# Growth runs' views and the report figures.

def scenario_overview_inputs(wildcards):
    """The run, and the default scenario's run at the same speed when the default runs there."""
    out = {"run": f"results/growth/{wildcards.scenario}/V{wildcards.speed}.nc"}
    if wildcards.scenario != "default" and PLAN.has_default_run(target_speed(wildcards)):
        out["default"] = f"results/growth/default/V{wildcards.speed}.nc"
    return out


def scenario_overview_note(wildcards):
    """Why the overview has no default comparison, or "" when it has one."""
    return "" if wildcards.scenario == "default" else PLAN.overview_note(wildcards.scenario, target_speed(wildcards))


def growth_3d_axis(wildcards):
    """Wavenumber for the default scenario (the report's section 5), wavelength for any other."""
    return "wavenumber" if wildcards.scenario == "default" else "wavelength"


def band_limit_file(wildcards):
    """The limit spectrum, wheel roughness and input spectrum (it fills the rolling-noise export) of a band view, as inputs."""
    b, r = SCENARIOS[wildcards.scenario]["figures"]["bands"], SCENARIOS[wildcards.scenario]["roughness"]
    return [f for f in (b["limit"], b.get("wheel_roughness"), r.get("file") if r.get("kind") == "spectrum" else None) if f]


def wear_table(wildcards):
    """The table of a wear case's scenario ('track' is a scenario here: default) at its speed."""
    return table_file(wildcards.track, wildcards.speed)


def wear_frequency(wildcards):
    """The configured frequency [Hz] whose label is the wildcard 'freq'."""
    return known_value(PLAN.wear_frequencies(), wildcards.freq, "wear frequency f", "figures.wear.frequencies")


def closure_wear_config(wildcards):
    """What a closure wear case reads of the default configuration, at the closure value of 's'."""
    return PLAN.closure_wear_config(wildcards.s)


def convergence_table(wildcards):
    return PLAN.convergence_table(wildcards.setting)


def rate_spectrum_speeds(wildcards):
    """The per-speed spectra of a scenario (figures.rate_spectrum.speeds)."""
    return [f"results/spectrum/{wildcards.scenario}/V{speed_label(v)}.nc"
            for v in SCENARIOS[wildcards.scenario]["figures"]["rate_spectrum"]["speeds"]]


# Sweeps (workflow/rules/sweeps.smk, spectrum.smk).

def sweep_runs(wildcards):
    return PLAN.sweep_runs(wildcards.study)


def rate_spectrum_sweep_points(wildcards):
    return [f"results/spectrum/{p.name}/V{speed_label(p.speed)}.nc" for p in PLAN.sweeps[wildcards.study].points]


def sweep_keys(wildcards):
    return PLAN.sweeps[wildcards.study].keys


def sweep_values(wildcards):
    return PLAN.sweeps[wildcards.study].values


def sweep_indices(wildcards):
    return [list(p.index) for p in PLAN.sweeps[wildcards.study].points]


def sweep_units(wildcards):
    return PLAN.sweeps[wildcards.study].units


# Track characterisation (workflow/rules/characterisation.smk).

def characterisation_track(wildcards):
    """Name of the characterised track: the wildcard 'track', 'default' where there is none."""
    return wildcards.get("track", "default")


def characterisation_config(wildcards):
    return SCENARIOS[characterisation_track(wildcards)]


def characterisation_speeds(wildcards):
    return [float(v) for v in characterisation_config(wildcards)["speeds"]]


def measured_decay_rate(wildcards):
    """The track's measured decay-rate CSV, if any: drawn beside the model's decay rate."""
    file, _ = measured_decay_file(characterisation_config(wildcards), characterisation_track(wildcards))
    return [file] if file else []


# Traffic as a fleet (workflow/rules/fleet.smk) and the uncertainty ensemble.

def fleet_growth_tables(wildcards):
    """The tables a fleet growth run reads, one per class speed (in fleet_speeds order)."""
    bays = PLAN.objects[wildcards.scenario].roughness.bays
    return [PLAN.fleet_table_file(wildcards.scenario, v, bays) for v in PLAN.fleet_speeds(wildcards.scenario)]


def fleet_class_spectra(wildcards):
    return [f"results/fleet/classes/{k}.npz" for k in PLAN.fleet_spectrum_keys[wildcards.scenario]]


def fleet_class_table(wildcards):
    """The Bloch tables of the spectrum's period at a class's speed."""
    name, i = PLAN.fleet_class_owner(wildcards.key)
    return PLAN.fleet_table_file(name, PLAN.fleet_classes[name][i].speed, int(SCENARIOS[name]["figures"]["rate_spectrum"]["bays"]))


def fleet_class_config(wildcards):
    return SCENARIOS[PLAN.fleet_class_owner(wildcards.key)[0]]


def fleet_class_params(wildcards):
    """[scenario, class index, speed] of a class spectrum job."""
    name, i = PLAN.fleet_class_owner(wildcards.key)
    return [name, i, PLAN.fleet_classes[name][i].speed]


def fleet_table(wildcards):
    return PLAN.fleet_table_of(wildcards.track, wildcards.speed, wildcards.get("bays"))


def fleet_track_config(wildcards):
    return PLAN.track_part(fleet_table(wildcards)[0].scenario)


def fleet_offsets(wildcards):
    return fleet_table(wildcards)[0].offsets


def fleet_table_speed(wildcards):
    return fleet_table(wildcards)[1]


def uncertainty_member_config(wildcards):
    return PLAN.uncertainty_member(wildcards.member)


# The HTML report of whatever is built (rule report_all).

def built_studies():
    """Every output of the named studies and of every scenario's study that exists on disk, of a
    scenario still defined, and nothing else (docs/workflow.md)."""
    found = PLAN.report_candidates() + [str(f) for f in sorted(Path("results/irregular").glob("*.png"))]
    for folder in ("results/growth", "results/spectrum", "results/fleet"):
        found += [str(f) for f in sorted(Path(folder).glob("*/*")) if f.parent.name in SCENARIOS and f.suffix in REPORT_SUFFIXES]
    for folder in ("results/sweeps", "results/spectrum_sweeps"):
        found += [str(f) for f in sorted(Path(folder).glob("*")) if f.suffix in REPORT_SUFFIXES
                  and any(f.stem == s or f.stem.startswith(f"{s}_") for s in PLAN.sweeps)]
    return [f for f in dict.fromkeys(found) if Path(f).exists()]


def built_paper_figures():
    return [f for f in PLAN.paper_figures() if Path(f).exists()]
