# Helpers that turn the configuration into target lists. Rules live in the other .smk files.

import sys
import warnings
from pathlib import Path

import numpy as np

from snakemake.utils import validate

from rail.chain import wheel_offsets as wheel_offsets_of
from rail.provenance import code_hash
from rail.roughness import RoughnessInputWarning
from rail.setup.build import PASSAGE_KEYS
from rail.setup.build import scenario as build_scenario
from rail.setup.build import fleet_classes as build_fleet_classes
from rail.setup.inputs import check_inputs, check_speed, measured_decay_file
from rail.setup.tables import table_key
from rail.studies.convergence import check_study as check_convergence_study
from rail.studies.fleet import class_key as fleet_class_key
from rail.studies.fleet import traffic_cases
from rail.setup.build import spectrum_scenario as build_spectrum_scenario
from rail.setup.config import ConfigError, check_scenario_names, expand_sweep, load_yaml, resolve_scenario_file, scenario_files, validate_config

# Clear, actionable messages first (key, value, unit, valid range), then snakemake's own
# validation against the same schema.
SCHEMA = load_yaml(workflow.source_path("../../config/schema/config.schema.yaml"))
validate_config(config, SCHEMA, source="configuration (config/config.yaml and --config/--configfile)")
validate(config, "../../config/schema/config.schema.yaml")

# Scenarios: config/scenarios/<name>.yaml (or .yml; both for one name is refused) holds only the keys that differ from the defaults.
# Each is merged onto the validated defaults and validated itself (errors name its file), at
# start-up, before any job runs. "default" is the configuration itself.
# A scenario with a top-level "sweep:" (dotted key or "speed" -> list) is a study: it expands into
# one scenario per grid point, named <study>-p<n>, aggregated into results/sweeps/<study>.nc.
SCENARIO_DIR = Path("config/scenarios")
SCENARIOS = {"default": config}
_SOURCES = {"default": "configuration (config/config.yaml and --config/--configfile)"}
SWEEPS = {}
SCENARIO_FILES = scenario_files(SCENARIO_DIR)
for _path in SCENARIO_FILES.values():
    _scen = load_yaml(_path)
    if "sweep" in _scen:
        _keys, _values, _points = expand_sweep(config, SCHEMA, _scen, str(_path))
        SWEEPS[_path.stem] = {"keys": _keys, "values": _values, "points": []}
        for _n, (_index, _assignment, _cfg) in enumerate(_points):
            _name = f"{_path.stem}-p{_n}"
            SCENARIOS[_name] = _cfg
            _SOURCES[_name] = f"{_path} (sweep point {', '.join(f'{k} = {v}' for k, v in _assignment.items())})"
            _speeds = [_assignment["speed"]] if "speed" in _assignment else _cfg["speeds"][:1]
            SWEEPS[_path.stem]["points"].append({"name": _name, "index": _index, "speed": _speeds[0]})
    else:
        SCENARIOS[_path.stem] = resolve_scenario_file(config, SCHEMA, _scen, source=str(_path))
        _SOURCES[_path.stem] = str(_path)
# The traffic study (config/traffic_study.yaml, named target traffic_study): one fleet scenario per
# (drive, spread), traffic_study-<drive>-s<percent>, resolved and validated as a scenario file.
TRAFFIC_FILE = Path("config/traffic_study.yaml")
TRAFFIC_CASES = {}
if TRAFFIC_FILE.exists():
    try:
        _cases = traffic_cases(load_yaml(TRAFFIC_FILE))
    except ValueError as _e:
        raise ConfigError(f"invalid configuration:\n  {_e}") from None
    for _name, _scen in _cases.items():
        if _name in SCENARIOS:
            raise ConfigError(f"invalid configuration:\n  config/scenarios/{_name}.yaml: the name is a case of the traffic study "
                              "(config/traffic_study.yaml): rename the file.")
        SCENARIOS[_name] = resolve_scenario_file(config, SCHEMA, _scen, source=f"{TRAFFIC_FILE} (case {_name})")
        _SOURCES[_name] = f"{TRAFFIC_FILE} (case {_name})"
        TRAFFIC_CASES[_name] = _scen
# Every scenario is built once here (rail.setup.build.scenario): the constraints that need physics
# (rail damping, harmonics reaching the pinned-pinned frequency) fail at start-up, naming the file.
check_scenario_names(
    {name: str(p) for name, p in SCENARIO_FILES.items()},
    {pt["name"]: str(SCENARIO_FILES[study]) for study, sw in SWEEPS.items() for pt in sw["points"]},
)
SCENARIO_OBJECTS = {_name: build_scenario(_cfg, _name, _SOURCES[_name]) for _name, _cfg in SCENARIOS.items()}
# A fleet (rail.fleet, docs/traffic.md; workflow/rules/fleet.smk): its growth and growth-rate spectrum
# are results/fleet/<scenario>/growth.nc and rate_spectrum.nc, from one receptance table per (track,
# speed) shared by every vehicle and fleet scenario at that speed. Its (vehicle, speed) classes are
# built here, so that a speed the harmonics cannot serve or a roughness tied to one speed stops here.
FLEET_CLASSES = {}
_FLEET_PROBLEMS = []
for _name, _cfg in SCENARIOS.items():
    if "fleet" not in _cfg:
        continue
    _src = _SOURCES[_name]
    if _name in {p["name"] for sw in SWEEPS.values() for p in sw["points"]}:
        _FLEET_PROBLEMS.append(f"{_src}: a sweep of a fleet scenario is not run by the workflow (its points' growth rules run "
                               "one train at one speed); give each case its own scenario file.")
        continue
    if _cfg["track"].get("cell") is not None:
        _FLEET_PROBLEMS.append(f"{_src}: fleet with track.cell is not run by the workflow (its tables are the cell's, "
                               "not one per speed shared by the vehicles); run it with rail.app.api.")
        continue
    _r = _cfg["roughness"]
    if _r.get("kind") == "harmonic" and _r.get("wavelength") is None:
        _FLEET_PROBLEMS.append(f"{_src}: roughness.frequency = {_r.get('frequency')!r} Hz sets the wavelength at one speed: "
                               "under a fleet at several speeds give roughness.wavelength (m) instead.")
        continue
    try:
        _classes = build_fleet_classes(_cfg, SCENARIO_OBJECTS[_name])
        for _c in _classes:
            check_speed(_cfg, _c.speed, f"{_src}: fleet class {_c.label}")
    except ConfigError as _e:
        _FLEET_PROBLEMS.append(str(_e).replace("invalid configuration:\n  ", f"{_src}: "))
        continue
    FLEET_CLASSES[_name] = _classes
if _FLEET_PROBLEMS:
    raise ConfigError("invalid configuration:\n  " + "\n  ".join(_FLEET_PROBLEMS))
# The spectrum of each class is a job of its own, named by a hash of the class (vehicle, speed, track,
# contact, ...) and the spectrum's settings, so that a class held by several fleets (the same vehicle
# at the same speed in the traffic study's cases) is computed once: {scenario: [key per class]}, and
# {key: (the first scenario holding it, its index there)}.
FLEET_SPECTRUM_KEYS = {}
FLEET_SPECTRUM_JOBS = {}
for _name in FLEET_CLASSES:
    _settings = SCENARIOS[_name]["figures"]["rate_spectrum"]
    _keys = [fleet_class_key(_c, _settings)
             for _c in build_fleet_classes(SCENARIOS[_name], build_spectrum_scenario(SCENARIOS[_name], _name, _SOURCES[_name]))]
    FLEET_SPECTRUM_KEYS[_name] = _keys
    for _i, _k in enumerate(_keys):
        FLEET_SPECTRUM_JOBS.setdefault(_k, (_name, _i))


# Every input file is read and checked here, before any job runs (its errors name the file and line),
# by the function railgrowth and rail.app.api call too (rail.setup.inputs.check_inputs). A track's
# measured decay rate, one CSV file (band_centre_Hz,decay_rate_dB_per_m), is measured.decay_rate or
# config/measured/<scenario>_decay_rate.csv.
# A roughness input the period cannot hold in full (bands left out, a short record repeated) is said
# here once per message, in one line naming the scenarios (their jobs say it in their logs too);
# Python's display of the warning added a line of rail's source to it.
with warnings.catch_warnings(record=True) as _caught:
    warnings.simplefilter("always", RoughnessInputWarning)
    _said = {}
    for _name, _scn in SCENARIO_OBJECTS.items():
        _before = len(_caught)
        check_inputs(SCENARIOS[_name], _scn, _name, _SOURCES[_name])
        for _w in _caught[_before:]:
            if issubclass(_w.category, RoughnessInputWarning):
                _said.setdefault(str(_w.message), []).append(_name)
for _w in _caught:  # any other warning as Python shows it
    if not issubclass(_w.category, RoughnessInputWarning):
        warnings.warn_explicit(_w.message, _w.category, _w.filename, _w.lineno)
for _text, _names in _said.items():
    print(f"railgrowth: note (scenario {', '.join(_names)}): {_text}", file=sys.stderr)


def checked_speed(scenario, label):
    """The speed (m/s) of a target's file name ('V40' -> 40.0), checked like a configured speed:
    a finite number > 0 at which the scenario's harmonics reach the pinned-pinned frequency."""
    if scenario not in SCENARIOS:
        raise ConfigError(f"target names the scenario '{scenario}', which is not defined: the scenarios are "
                          f"{', '.join(sorted(SCENARIOS))} (config/scenarios/<name>.yaml).")
    try:
        V = float(label)
    except ValueError:
        raise ConfigError(f"target speed V{label} is not a number in m/s.") from None
    return check_speed(SCENARIOS[scenario], V, f"scenario {scenario}", f"target speed V{label}")


def checked_bays(label):
    """The roughness period N of a target's file name ('N8' -> 8), within the schema's bounds of a
    configured period (roughness.bays, figures.rate_spectrum.bays)."""
    vmax = SCHEMA["properties"]["figures"]["properties"]["rate_spectrum"]["properties"]["bays"]["maximum"]
    N = int(label)
    if not 2 <= N <= vmax:
        raise ConfigError(f"target period N{label} is not allowed: it must lie in [2, {vmax}] bays (as roughness.bays and "
                          "figures.rate_spectrum.bays in the configuration).")
    return N


def scenario_config(wildcards):
    """Resolved configuration of the scenario named by the wildcard 'scenario'."""
    return SCENARIOS[wildcards.scenario]


def track_name(name):
    """Tracks are shared: a scenario uses the table of the first scenario ('default' first, then
    in file order) whose track and track numerics equal its own."""
    key = (SCENARIOS[name]["track"], SCENARIOS[name]["numerics"]["track"])
    for other, cfg in SCENARIOS.items():
        if (cfg["track"], cfg["numerics"]["track"]) == key:
            return other
    return name


def track_config(wildcards):
    """The part of the configuration a fleet's receptance table depends on (its track and numerics), so
    that changing anything else does not recompute it. The target's speed (and period) is checked first."""
    checked_speed(wildcards.track, wildcards.speed)
    if hasattr(wildcards, "bays"):
        checked_bays(wildcards.bays)
    return _track_part(wildcards.track)


def _track_part(name):
    """The track and track numerics of a scenario's configuration."""
    cfg = SCENARIOS[name]
    return {"track": cfg["track"], "numerics": {"track": cfg["numerics"]["track"]}}


# Shared receptance tables, named by their content (issue 36, docs/workflow.md): a table depends on the
# track, the track numerics and the wheel offsets of the scenarios it serves, so its folder is
# results/receptance/<table_key of exactly that>/ (rail.setup.tables). Scenarios with the same track,
# numerics and wheels share it; adding a scenario renames no table and reruns no other job, and a
# change of a track parameter names another table (so whatever reads it reruns).
# {key: {"scenario": the first scenario holding it, "offsets": [m], "scenarios": [names]}}.
def _own_offsets(name):
    """Offsets d between every ordered pair of a scenario's wheels (0 first) [m]."""
    return sorted(set(wheel_offsets_of(SCENARIO_OBJECTS[name])), key=lambda d: (abs(d), d))


TABLES = {}
SCENARIO_TABLE = {}
for _name in SCENARIOS:
    if _name in FLEET_CLASSES:  # a fleet's tables hold every vehicle's offsets (fleet_table_file)
        continue
    _key = table_key(_track_part(_name), _own_offsets(_name))
    SCENARIO_TABLE[_name] = _key
    TABLES.setdefault(_key, {"scenario": _name, "offsets": _own_offsets(_name), "scenarios": []})["scenarios"].append(_name)


def table_file(name, speed, bays=1):
    """The receptance table of scenario ``name`` at a speed (a label such as '40', or m/s), and for a
    roughness (or spectrum) period of N > 1 bays its Bloch tables (a track cell: the cell's table)."""
    label = speed if isinstance(speed, str) else speed_label(speed)
    suffix = "" if int(bays) == 1 else f"_N{int(bays)}"
    return f"results/receptance/{SCENARIO_TABLE[name]}/V{label}{suffix}.nc"


def _table(wildcards):
    """The entry of TABLES a receptance target names; a scenario's name in its place is refused with
    the content-named path of that scenario's table."""
    key = wildcards.track
    if key in TABLES:
        return TABLES[key]
    if key in SCENARIOS:
        checked_speed(key, wildcards.speed)
        if hasattr(wildcards, "bays"):
            checked_bays(wildcards.bays)
        if key in SCENARIO_TABLE:
            raise ConfigError(f"receptance tables are named by their content, not by a scenario: the table of scenario "
                              f"'{key}' at V{wildcards.speed} is {table_file(key, wildcards.speed, wildcards.get('bays', 1))} "
                              "(docs/workflow.md).")
    known = "; ".join(f"{k} ({', '.join(v['scenarios'][:3])})" for k, v in TABLES.items())
    raise ConfigError(f"target names the receptance table '{key}', which no scenario uses: the tables are {known}.")


def table_config(wildcards):
    """What a content-named table depends on: its track and track numerics. The target's speed (and
    period) are checked first, as a speed of the scenarios it serves."""
    t = _table(wildcards)
    checked_speed(t["scenario"], wildcards.speed)
    if hasattr(wildcards, "bays"):
        checked_bays(wildcards.bays)
    return _track_part(t["scenario"])


def table_offsets(wildcards):
    """The wheel offsets [m] a content-named table holds (those of the scenarios it serves, all equal)."""
    return _table(wildcards)["offsets"]


def physics_config(wildcards):
    """A scenario's configuration without the figure settings, site measurements and half-space
    quadrature (which no growth computation reads: the contact damping has its own, Fig. 6)."""
    return _physics(SCENARIOS[wildcards.scenario])


def _physics(cfg):
    """A configuration without figures, measured and numerics.halfspace."""
    out = {k: v for k, v in cfg.items() if k not in ("figures", "measured", "numerics")}
    return {**out, "numerics": {k: v for k, v in cfg["numerics"].items() if k != "halfspace"}}


def default_physics(*keys):
    """The default configuration's physics (as physics_config) and the figure keys given: what a
    study script reads through rail.setup.build.scenario."""
    return {**_physics(config), **config_part(keys)}


def config_part(keys, cfg=None):
    """The part of a configuration (default: this run's) under the dotted keys, nested as there.

    Each job is handed exactly the configuration its script reads, as params.cfg. Params are a
    rerun trigger, so an edit of the configuration reruns the jobs that read it and no other,
    and each result records (io.finalize) the configuration it was computed from."""
    cfg = config if cfg is None else cfg
    out = {}
    for key in keys:
        *parents, leaf = key.split(".")
        src, dst = cfg, out
        for p in parents:
            src, dst = src[p], dst.setdefault(p, {})
        dst[leaf] = src[leaf]
    return out


# What each report figure reads of the configuration (its rule's params.cfg). A figure drawn from
# another job's result carries that job's keys too, so that it records all it was computed from
# (its reruns do not grow: a change of those keys reruns the job it is drawn from anyway).
HALFSPACE_KEYS = ("material", "contact.hertz_stiffness", "numerics.halfspace", "figures.halfspace")
FORCE_KEYS = tuple(k for k in PASSAGE_KEYS if k != "wear")  # the forces of one passage (rail.chain.solve_forces)
WEAR_CASE_KEYS = PASSAGE_KEYS + ("figures.wear.speed", "figures.wear.amplitude")
GROWTH_FIGURE_KEYS = ("figures.growth", "figures.wear.spectrum_max_wavenumber")


# Code dependencies: a rule's params hold code("<script>"), the hash of every rail source its script
# imports, followed through all imports (rail.provenance), so that changing a module reruns exactly
# the jobs that depend on it (params changes are a rerun trigger). Derived from the imports, it
# cannot go stale; tests/test_architecture.py checks that every rule with a script has it.
def code(script):
    """Hash of the rail sources that workflow/scripts/<script> imports."""
    return code_hash(Path(workflow.basedir, "workflow", "scripts", script))


# Report figures produced so far, by section of the report.
HALFSPACE_FIGURES = ["02", "03", "04", "05", "06"]


FORCE_FIGURES = ["08", "22"]
WEAR_FIGURES = [f"{n:02d}" for n in range(9, 20)]
GROWTH_FIGURES = ["20", "21", "23", "24", "25", "26", "27"]


def growth_table(wildcards):
    """The receptance table a growth run needs: its scenario's track at its speed (the Bloch tables
    for a roughness periodic over N > 1 bays)."""
    not_a_fleet(wildcards.scenario, "growth")
    checked_speed(wildcards.scenario, wildcards.speed)
    return table_file(wildcards.scenario, wildcards.speed, SCENARIO_OBJECTS[wildcards.scenario].roughness.bays)


def roughness_file(wildcards):
    """A scenario's roughness file, as an input so that editing it reruns the growth."""
    r = SCENARIO_OBJECTS[wildcards.scenario].roughness
    return [r.file] if r.kind in ("file", "profile", "spectrum") else []


def growth_figure_inputs(nn):
    """The growth runs behind one of Figs 20, 21, 23-27 (nn = '20', ...), as {label: file}."""
    g = config["figures"]["growth"]
    v = [speed_label(x) for x in g["speeds"]]
    run = lambda scen, V: f"results/growth/{scen}/V{V}.nc"  # noqa: E731
    n = int(nn)
    if n in (20, 21):
        return {f"{v[n - 20]} m/s": run("default", v[n - 20])}
    if n == 23:
        return {f"{x} m/s": run("default", x) for x in v}
    if n in (24, 25):
        cfg = SCENARIOS[g["pad_scenario"]]
        return {
            f"railpad {config['track']['pad']['stiffness']:.2g} N/m": run("default", "40"),
            f"railpad {cfg['track']['pad']['stiffness']:.2g} N/m": run(g["pad_scenario"], "40"),
        }
    V = v[n - 26]
    return {"single wheel": run("default", V), f"{len(SCENARIOS[g['wheels_scenario']]['wheels']['positions'])} wheels": run(g["wheels_scenario"], V)}


def growth_figures_labelled(wildcards=None):
    """The growth runs behind every one of Figs 20, 21, 23-27, as {nn: {label: file}} (evaluated only
    when the figures are planned: the scenarios they name may be absent otherwise)."""
    return {nn: growth_figure_inputs(nn) for nn in GROWTH_FIGURES}


def growth_figures_runs(wildcards=None):
    """Every growth run Figs 20, 21, 23-27 are drawn from, each once."""
    return sorted({path for runs in growth_figures_labelled().values() for path in runs.values()})


def any_wavelength_targets():
    """Narrow-band figures of the scenarios with a roughness period of N > 1 bays (not sweep points),
    and the aggregated datasets of the sweeps over such scenarios."""
    sweep_points = {p["name"] for sw in SWEEPS.values() for p in sw["points"]}
    out = [f"results/growth/{name}/V{speed_label(scn.speeds[0])}_narrowband.png" for name, scn in SCENARIO_OBJECTS.items()
           if scn.roughness.bays > 1 and name not in sweep_points and name not in FLEET_CLASSES]
    for study, sw in SWEEPS.items():
        if any(SCENARIO_OBJECTS[p["name"]].roughness.bays > 1 for p in sw["points"]):
            out += [f"results/sweeps/{study}.nc", f"results/sweeps/{study}.png"]
    return out


def band_limit_file(wildcards):
    """The limit spectrum and the wheel roughness (if any) of a scenario's band view, as inputs so
    that editing them reruns it."""
    b = SCENARIOS[wildcards.scenario]["figures"]["bands"]
    return [f for f in (b["limit"], b.get("wheel_roughness")) if f]


def band_targets():
    """Band views (CSV, dataset, figure) of the default runs at every configured speed and of the
    scenarios with a roughness period of N > 1 bays (not sweep points)."""
    sweep_points = {p["name"] for sw in SWEEPS.values() for p in sw["points"]}
    out = [f"results/growth/default/V{speed_label(v)}_bands.csv" for v in config["speeds"]]
    out += [f"results/growth/{name}/V{speed_label(scn.speeds[0])}_bands.csv" for name, scn in SCENARIO_OBJECTS.items()
            if scn.roughness.bays > 1 and name not in sweep_points and name not in FLEET_CLASSES]
    # the band map over speed of every sweep study that varies the speed (not the closure study's,
    # which has its own target)
    out += [f"results/sweeps/{study}_bands.png" for study, sw in SWEEPS.items()
            if "speed" in sw["keys"] and study not in CLOSURE_STUDIES.values()]
    return out


def growth_runs():
    """The 3-D growth plot of the default track at 40 m/s (section 5)."""
    return ["results/growth/default/V40_3d.png"]


def wear_frequency_label(f):
    """Excitation frequency in a file name: 533.333 -> '533'."""
    return f"{float(f):.0f}"


def wear_case_file(nn):
    """The wear case behind a figure of Figs 9-19 (nn = '09', ...; Figs 9-11 use the second frequency, 1000 Hz)."""
    s = config["figures"]["wear"]
    n = int(nn)
    index = 1 if n <= 11 else (n - 12) // 2
    return f"results/wear/default/V{speed_label(s['speed'])}_f{wear_frequency_label(s['frequencies'][index])}.nc"


def wear_figure_cases():
    """Every wear case Figs 9-19 are drawn from, each once."""
    return sorted({wear_case_file(nn) for nn in WEAR_FIGURES})


def wear_figure_config(nn):
    """What a figure of Figs 9-19 (nn = '09', ...) reads: its wear case's keys, and for a wear
    spectrum (Figs 13, 15, 17, 19) its wavenumber range."""
    n = int(nn)
    return config_part(WEAR_CASE_KEYS + (("figures.wear.spectrum_max_wavenumber",) if n >= 13 and n % 2 else ()))


def wear_table(wildcards):
    """The receptance table of a wear case's scenario ('track' is a scenario here: default) at its speed."""
    return table_file(wildcards.track, wildcards.speed)


def wear_frequency(wildcards):
    """The configured frequency (Hz) whose label is the wildcard 'freq'."""
    known = {wear_frequency_label(f): float(f) for f in config["figures"]["wear"]["frequencies"]}
    return known_value(known, wildcards.freq, "wear frequency f", "figures.wear.frequencies")


def known_value(known, label, what, key):
    """The value a target's file-name label names, or one line saying which labels exist."""
    if label not in known:
        raise ConfigError(f"target names the {what}{label}, which is not configured: the labels are "
                          f"{', '.join(sorted(known))} ({key}).")
    return known[label]


def paper_figures():
    """Every report figure: its picture and its plotted data."""
    return expand(
        ["results/figures/fig{nn}.png", "results/data/fig{nn}.nc"],
        nn=HALFSPACE_FIGURES + FORCE_FIGURES + WEAR_FIGURES + GROWTH_FIGURES,
    ) + growth_runs()


def speed_label(v):
    """Speed in a file name: 40.0 -> '40', 37.5 -> '37.5'."""
    return f"{float(v):g}"


def receptance_tables():
    """Receptance tables of the default track at every configured speed."""
    return [table_file("default", v) for v in config["speeds"]]


def sweep_runs(wildcards):
    """Growth runs of every point of a sweep study, in grid order."""
    return [f"results/growth/{p['name']}/V{speed_label(p['speed'])}.nc" for p in SWEEPS[wildcards.study]["points"]]


def sweep_targets():
    """Aggregated dataset and map figure of every sweep study."""
    return expand(["results/sweeps/{study}.nc", "results/sweeps/{study}.png"], study=sorted(SWEEPS))


def sweep_keys(wildcards):
    """Swept keys of a study (dotted config keys or 'speed')."""
    return SWEEPS[wildcards.study]["keys"]


def sweep_values(wildcards):
    """Values of each swept key."""
    return SWEEPS[wildcards.study]["values"]


def sweep_indices(wildcards):
    """Grid index of every point, in the order of sweep_runs."""
    return [list(p["index"]) for p in SWEEPS[wildcards.study]["points"]]


# Closure sensitivity study (named target closure_study): three sweep files over
# contact.closure_scale, single wheel at two speeds, softer railpad and four wheels.
CLOSURE_STUDIES = {"run": "closure", "soft": "closure_soft_pad", "four": "closure_class87"}


def closure_values():
    """The closure values s of the study, the same in each of its sweep files."""
    found = {}
    for tag, study in CLOSURE_STUDIES.items():
        if study not in SWEEPS or "contact.closure_scale" not in SWEEPS[study]["keys"]:
            return []
        sw = SWEEPS[study]
        found[study] = [float(x) for x in sw["values"][sw["keys"].index("contact.closure_scale")]]
    values = next(iter(found.values()))
    if any(v != values for v in found.values()):
        raise ValueError(f"the closure study's sweep files must use the same contact.closure_scale values: {found}")
    return values


def closure_label(s):
    """Closure value in a file name: 0.01 -> '0.01'."""
    return f"{float(s):g}"


def closure_inputs(wildcards=None):
    """Every file the closure study aggregates, and what each is: ([paths], [[kind, s, speed or Hz]])."""
    paths, meta = [], []
    for tag, study in CLOSURE_STUDIES.items():
        sw = SWEEPS[study]
        ki = sw["keys"].index("contact.closure_scale")
        for p in sw["points"]:
            paths.append(f"results/growth/{p['name']}/V{speed_label(p['speed'])}.nc")
            meta.append([tag, float(sw["values"][ki][p["index"][ki]]), float(p["speed"])])
    w = config["figures"]["wear"]
    for s in closure_values():
        for f in w["frequencies"]:
            paths.append(f"results/closure/wear/s{closure_label(s)}_f{wear_frequency_label(f)}.nc")
            meta.append(["wear", s, float(f)])
    paths.append("results/closure/wellposedness.nc")
    meta.append(["wellposed", 0.0, 0.0])
    return paths, meta


def closure_wear_config(wildcards):
    """What a wear case reads of the default configuration, with the closure value of the wildcard 's'."""
    s = known_value({closure_label(x): x for x in closure_values()}, wildcards.s, "closure value s",
                    "contact.closure_scale of config/scenarios/closure*.yaml")
    return config_part(WEAR_CASE_KEYS, {**config, "contact": {**config["contact"], "closure_scale": s}})


def closure_targets():
    """Outputs of the closure study (empty when its sweep files are absent)."""
    if not closure_values():
        return []
    return [f"results/closure/{n}" for n in ("closure.nc", "spectra.png", "wear_spectra.png", "conclusions.md", "conclusions.html")]


# Numerical studies (workflow/rules/studies.smk): the stability suite and the convergence study.
STABILITY = load_yaml(workflow.source_path("../../config/stability.yaml"))
CONVERGENCE = load_yaml(workflow.source_path("../../config/convergence.yaml"))
try:  # NaN, a negative or a misspelt setting stop here, naming the key (not as a KeyError in a job)
    check_convergence_study(CONVERGENCE)
except ValueError as _e:
    raise ConfigError(str(_e)) from None
CLOSURE = load_yaml(workflow.source_path("../../config/closure.yaml"))
# Every point of the convergence study, references included: (setting, value label) -> value.
CONVERGENCE_VALUES = {
    (name, f"{float(v):g}"): float(v) for name, s in CONVERGENCE["settings"].items() for v in s["values"] + [s["reference"]]
}


def convergence_points():
    """Every point of the convergence study: (setting, value label), references included."""
    return list(CONVERGENCE_VALUES)


def convergence_table(wildcards):
    """The receptance table a contact or growth point uses (the default track at the study's speed)."""
    if CONVERGENCE["settings"][wildcards.setting]["quantity"] == "force":
        return {}
    return {"table": table_file("default", CONVERGENCE["speed"])}


# Suffixes of the outputs a report shows (figures, CSV exports, markdown and HTML tables).
REPORT_SUFFIXES = (".png", ".csv", ".md", ".html")


def built_studies():
    """Every output of the named studies and of every scenario's study that exists on disk (for the
    HTML report of report_all), whatever is built, of a scenario still defined, and nothing else,
    so that the report of one user study needs only that study built (docs/workflow.md)."""
    found = [t for name in study_names() for t in study_targets(name)]
    found += closure_targets() + sweep_targets() + rate_spectrum_sweep_targets() + any_wavelength_targets() + [
        "results/stability/outcomes.html", "results/convergence/error_vs_time.png", "results/convergence/summary.html",
        "results/traffic_study/spectra.png", "results/uncertainty/band_interval.png",
    ] + [str(f) for f in sorted(Path("results/irregular").glob("*.png"))]
    # per scenario: its growth runs' views and exports, its growth-rate spectrum, a fleet's results
    for folder in ("results/growth", "results/spectrum", "results/fleet"):
        for f in sorted(Path(folder).glob("*/*")):
            if f.parent.name in SCENARIOS and f.suffix in REPORT_SUFFIXES:
                found.append(str(f))
    for folder, names in (("results/sweeps", SWEEPS), ("results/spectrum_sweeps", SWEEPS)):
        for f in sorted(Path(folder).glob("*")):
            if f.suffix in REPORT_SUFFIXES and any(f.stem == s or f.stem.startswith(f"{s}_") for s in names):
                found.append(str(f))
    return [f for f in dict.fromkeys(found) if Path(f).exists()]


def built_paper_figures():
    """The report figures (paper_figures) that exist on disk."""
    return [f for f in paper_figures() if Path(f).exists()]


# Growth-rate spectrum (workflow/rules/spectrum.smk)

def rate_spectrum_table(wildcards):
    """The Bloch tables of the spectrum's N-bay period (figures.rate_spectrum.bays) at the speed."""
    not_a_fleet(wildcards.scenario, "rate_spectrum")
    checked_speed(wildcards.scenario, wildcards.speed)
    # the Bloch tables of the scenario's own track and wheels (a track cell: the cell's one table, the
    # growth runs'); content-named, so every scenario with that track and those wheels shares them
    return table_file(wildcards.scenario, wildcards.speed, SCENARIOS[wildcards.scenario]["figures"]["rate_spectrum"]["bays"])


def rate_spectrum_speeds(wildcards):
    """The per-speed spectra of a scenario (figures.rate_spectrum.speeds)."""
    speeds = SCENARIOS[wildcards.scenario]["figures"]["rate_spectrum"]["speeds"]
    return [f"results/spectrum/{wildcards.scenario}/V{speed_label(v)}.nc" for v in speeds]


def rate_spectrum_sweep_points(wildcards):
    """The spectrum of every point of a sweep study, at the point's speed, in grid order."""
    return [f"results/spectrum/{p['name']}/V{speed_label(p['speed'])}.nc" for p in SWEEPS[wildcards.study]["points"]]


def rate_spectrum_sweep_targets():
    """Spectrum maps of the sweep studies whose swept keys change the smooth rail's spectrum."""
    studies = [s for s, sw in SWEEPS.items() if any(not k.startswith("roughness.") for k in sw["keys"])]
    return expand(["results/spectrum_sweeps/{study}.nc", "results/spectrum_sweeps/{study}.png"], study=sorted(studies))


def _differing_keys(a, b, prefix=""):
    """Dotted keys whose values differ between two configuration mappings."""
    keys = []
    for k in sorted(set(a) | set(b), key=str):
        x, y = a.get(k), b.get(k)
        if isinstance(x, dict) and isinstance(y, dict):
            keys += _differing_keys(x, y, f"{prefix}{k}.")
        elif x != y:
            keys.append(f"{prefix}{k}")
    return keys


def _value_at(cfg, key):
    """The value under a dotted key of a configuration mapping (None where it is absent)."""
    for part in key.split("."):
        cfg = cfg.get(part) if isinstance(cfg, dict) else None
    return cfg


def one_off_run_dir(configfiles):
    """runs/<name>-<hash> for a configuration that differs from config/config.yaml (a one-off run:
    --configfile my_changes.yaml gives runs/my_changes-<hash>), with runs/<...>/config pointing to
    this project's config/ (so that scenario and input files resolve as here); None for the
    defaults. <hash> is that of the differing keys and their resolved values, so two configurations
    of the same file name get their own folders and one configuration always the same one.
    A one-off run never writes over the default results."""
    import hashlib
    import json
    import re as _re

    changed = _differing_keys(config, load_yaml("config/config.yaml"))
    if not changed:
        return None
    stems = [_re.sub(r"[^A-Za-z0-9_-]", "_", Path(f).stem) for f in configfiles]
    content = json.dumps({k: _value_at(config, k) for k in changed}, sort_keys=True, default=str)
    digest = hashlib.sha256(content.encode()).hexdigest()[:8]
    name = f"{'_'.join(stems) or 'overrides'}-{digest}"
    run = Path("runs") / name
    run.mkdir(parents=True, exist_ok=True)
    link = run / "config"
    if not link.exists():
        link.symlink_to(Path("config").resolve(), target_is_directory=True)
    print(f"one-off configuration (differs from config/config.yaml in {', '.join(changed[:6])}"
          f"{', ...' if len(changed) > 6 else ''}): it writes under {run}/ and leaves results/ untouched.", file=sys.stderr)
    return run


# A user's own study (issue 23): every scenario file, and every sweep study, is a target
# study_<name> that builds its growth runs, one-page overviews, band views and the 3-D plots.

def scenario_overview_inputs(wildcards):
    """The run, and the default scenario's run at the same speed when the default runs there."""
    out = {"run": f"results/growth/{wildcards.scenario}/V{wildcards.speed}.nc"}
    if wildcards.scenario != "default" and float(wildcards.speed) in [float(v) for v in config["speeds"]]:
        out["default"] = f"results/growth/default/V{wildcards.speed}.nc"
    return out


def scenario_overview_note(wildcards):
    """Why the overview has no default comparison (said on the figure and in the log), or "" when it has one."""
    if wildcards.scenario == "default" or float(wildcards.speed) in [float(v) for v in config["speeds"]]:
        return ""
    runs = ", ".join(f"{float(v):g}" for v in config["speeds"])
    return (f"no default run at {float(wildcards.speed):g} m/s (the default scenario runs at {runs} m/s): "
            "no comparison with the default")


def growth_3d_axis(wildcards):
    """The 3-D plot's across axis: wavenumber for the default scenario (the plot of the report's
    section 5, drawn as the report describes it), wavelength (log, mm) for every other scenario."""
    return "wavenumber" if wildcards.scenario == "default" else "wavelength"


def study_names():
    """The scenario files and sweep studies of config/scenarios/ (each a target study_<name>)."""
    points = {p["name"] for sw in SWEEPS.values() for p in sw["points"]}
    return [n for n in SCENARIOS if n not in points and n not in TRAFFIC_CASES and n != "default"] + sorted(SWEEPS)


def study_targets(name):
    """What study_<name> builds: per speed of the scenario (or per point of the sweep), the growth
    run's overview, band view and 3-D plot; for a sweep also its dataset and maps."""
    if name in FLEET_CLASSES:
        return fleet_targets(name)
    if name in SWEEPS:
        runs = [(p["name"], p["speed"]) for p in SWEEPS[name]["points"]]
        extra = [f"results/sweeps/{name}.nc", f"results/sweeps/{name}.png"]
    else:
        runs = [(name, v) for v in SCENARIO_OBJECTS[name].speeds]
        extra = []
    out = []
    for scen, v in runs:
        base = f"results/growth/{scen}/V{speed_label(v)}"
        out += [f"{base}_overview.png", f"{base}_bands.png", f"{base}_3d.png"]
    return out + extra


def short_wave_targets():
    """What the named target short_wave builds (issue 31), of the scenario files that define it:
    config/scenarios/nonhertzian.yaml's growth-rate spectrum, the studies short_wave_study and
    short_wave_study_report."""
    out = ["results/spectrum/nonhertzian/rate_spectrum.png"] if "nonhertzian" in SCENARIOS else []
    for name in ("short_wave_study", "short_wave_study_report"):
        if name in SCENARIOS:
            out += study_targets(name)
    return out


def growth_runtime(wildcards):
    """Cluster runtime of a growth job (minutes), scaled from the job: 0.5 s CPU per update, wheel
    and bay at 61 contact nodes (README, one core), as the square of the nodes; three times that,
    plus 10 min for start-up and the tables' reading, so that a slow node does not kill it."""
    return int(10 + 3 * growth_seconds(wildcards.scenario) / 60)


def growth_seconds(name):
    """Estimated CPU seconds of a scenario's growth loop: 0.5 s per update, wheel and bay at 61
    contact nodes (one core), as the square of the nodes."""
    scn = SCENARIO_OBJECTS[name]
    updates = scn.growth.passages / scn.growth.passages_per_update
    return 0.5 * updates * len(scn.wheels.positions) * scn.roughness.bays * (scn.contact_numerics.nodes / 61) ** 2


# Job priorities (Snakemake starts the ready job of highest priority first; a priority is not passed
# on to the jobs a job needs). The figure set's longest chain is the first compile of the contact
# march, then the four-wheel growth runs: compile first, then the tables (the most wheels first),
# then the growth runs, longest first; figures and the half-space jobs fill the gaps.
PRIORITY_KERNELS = 100
PRIORITY_TABLES = 50


def table_priority(wildcards):
    """Priority of a receptance table job: after the kernels' compile, the tables of more wheels first."""
    return PRIORITY_TABLES + min(len(table_offsets(wildcards)), PRIORITY_KERNELS - PRIORITY_TABLES - 1)


def growth_priority(wildcards):
    """Priority of a growth job: its estimated CPU seconds (growth_seconds), longest first, below the
    tables it needs."""
    return 1 + min(int(growth_seconds(wildcards.scenario)), PRIORITY_TABLES - 2)


def kernels(which):
    """The marker of the compiled kernels a rule's script calls: 'march' (rail.contact, every
    growth and wear job) or 'tangent' (also rail.contact.tangent, the growth-rate spectrum)."""
    # ancient: the marker's age never reruns a job (each job's own code hash does)
    return ancient(f"results/cache/kernels_{which}.txt")


# Traffic as a fleet (issue 35, docs/traffic.md, workflow/rules/fleet.smk).

def not_a_fleet(name, what):
    """Refuse a one-train target (growth per speed, spectrum per speed) of a scenario with a fleet: it
    would run one train and leave the fleet out."""
    if name in FLEET_CLASSES:
        raise ConfigError(f"scenario '{name}' has a fleet: its {what} per speed would run one train and leave the fleet out; "
                          f"build results/fleet/{name}/growth.nc or results/fleet/{name}/rate_spectrum.nc (study_{name}).")


def fleet_speed_label(v):
    """A fleet class's speed in a file name, exact: float(label) == v (40.0 -> '40', 33.6 -> '33.6').
    The classes of a distribution need not be round numbers, and a table must be at the class's speed."""
    text = repr(float(v))
    return text[:-2] if text.endswith(".0") else text


def _fleet_offsets_of(name):
    """Offsets d between every ordered pair of axles of every vehicle of a fleet scenario (0 first) [m]."""
    return sorted({d for c in FLEET_CLASSES[name] for d in wheel_offsets_of(c.scenario)}, key=lambda d: (abs(d), d))


# A fleet's tables are named by their content too (issue 36): the track, its numerics and the offsets
# of the fleet's vehicles. Fleets of the same vehicles on one track share them (the traffic study's
# cases); a fleet of other vehicles gets its own, so adding a fleet scenario reruns no other.
# {key: {"scenario": the first fleet holding it, "offsets": [m], "scenarios": [names]}}
FLEET_TABLES = {}
FLEET_TABLE = {}
for _name in FLEET_CLASSES:
    _key = table_key(_track_part(_name), _fleet_offsets_of(_name))
    FLEET_TABLE[_name] = _key
    FLEET_TABLES.setdefault(_key, {"scenario": _name, "offsets": _fleet_offsets_of(_name), "scenarios": []})["scenarios"].append(_name)


def fleet_table_file(name, speed, bays):
    """The shared receptance table of a fleet scenario at one class speed (a roughness period of N > 1
    bays: its Bloch tables), named by its content (FLEET_TABLES)."""
    suffix = "" if bays == 1 else f"_N{bays}"
    return f"results/receptance/{FLEET_TABLE[name]}/fleet_V{fleet_speed_label(speed)}{suffix}.nc"


def fleet_speeds(name):
    """The distinct class speeds of a fleet scenario [m/s], increasing."""
    return sorted({c.speed for c in FLEET_CLASSES[name]})


def fleet_growth_tables(wildcards):
    """The tables a fleet growth run reads, one per class speed (in fleet_speeds order)."""
    bays = SCENARIO_OBJECTS[wildcards.scenario].roughness.bays
    return [fleet_table_file(wildcards.scenario, v, bays) for v in fleet_speeds(wildcards.scenario)]


def fleet_class_spectra(wildcards):
    """The class spectra a fleet spectrum combines, in the order of its classes."""
    return [f"results/fleet/classes/{k}.npz" for k in FLEET_SPECTRUM_KEYS[wildcards.scenario]]


def fleet_class_owner(wildcards):
    """(scenario, class index) of a class spectrum job."""
    if wildcards.key not in FLEET_SPECTRUM_JOBS:
        raise ConfigError(f"target names the fleet class spectrum {wildcards.key}, which no fleet scenario holds.")
    return FLEET_SPECTRUM_JOBS[wildcards.key]


def fleet_class_table(wildcards):
    """The Bloch tables of the spectrum's period (figures.rate_spectrum.bays) at a class's speed."""
    name, i = fleet_class_owner(wildcards)
    bays = int(SCENARIOS[name]["figures"]["rate_spectrum"]["bays"])
    return fleet_table_file(name, FLEET_CLASSES[name][i].speed, bays)


def fleet_class_config(wildcards):
    """The configuration of the scenario a class spectrum job builds its class from."""
    return SCENARIOS[fleet_class_owner(wildcards)[0]]


def fleet_class_params(wildcards):
    """[scenario, class index, speed] of a class spectrum job."""
    name, i = fleet_class_owner(wildcards)
    return [name, i, FLEET_CLASSES[name][i].speed]


def fleet_table_speeds(wildcards):
    """The class speeds [m/s] of a fleet job's tables, in the order of its input files."""
    return fleet_speeds(wildcards.scenario)


def fleet_offsets(wildcards):
    """Offsets d between every ordered pair of axles of every vehicle of the fleets a table serves (0
    first) [m] (rail.chain.fleet_tables)."""
    return _fleet_table(wildcards)["offsets"]


def _fleet_table(wildcards):
    """The entry of FLEET_TABLES a fleet table target names; a scenario's name in its place is refused
    with the content-named path."""
    key = wildcards.track
    if key in FLEET_TABLES:
        return FLEET_TABLES[key]
    if key in FLEET_TABLE:
        raise ConfigError(f"fleet receptance tables are named by their content, not by a scenario: those of fleet '{key}' are "
                          f"{fleet_table_file(key, fleet_speeds(key)[0], int(wildcards.get('bays', 1)))} and the other class "
                          "speeds (docs/workflow.md).")
    known = "; ".join(f"{k} ({', '.join(v['scenarios'][:3])})" for k, v in FLEET_TABLES.items()) or "none"
    raise ConfigError(f"target names the fleet receptance table '{key}', which no fleet scenario uses: the fleet tables are {known}.")


def fleet_track_config(wildcards):
    """What a fleet table depends on: the track part of its fleets' configuration; the speed checked
    as a class speed of a fleet it serves."""
    t = _fleet_table(wildcards)
    if hasattr(wildcards, "bays"):
        checked_bays(wildcards.bays)
    speeds = {fleet_speed_label(v) for name in t["scenarios"] for v in fleet_speeds(name)}
    if wildcards.speed not in speeds:
        raise ConfigError(f"target names a fleet table '{wildcards.track}' (fleets {', '.join(t['scenarios'])}) at V{wildcards.speed}, "
                          f"which is no class speed of those fleets: the speeds are {', '.join(sorted(speeds, key=float)) or 'none'} m/s.")
    return _track_part(t["scenario"])


def fleet_growth_runtime(wildcards):
    """Cluster runtime of a fleet growth job (minutes), scaled as growth_runtime: every update rolls
    every class, so the wheels per update are the sum of the classes' axles."""
    scn = SCENARIO_OBJECTS[wildcards.scenario]
    wheels = sum(len(c.scenario.wheels.positions) for c in FLEET_CLASSES[wildcards.scenario])
    updates = scn.growth.passages / scn.growth.passages_per_update
    seconds = 0.5 * updates * wheels * scn.roughness.bays * (scn.contact_numerics.nodes / 61) ** 2
    return int(10 + 3 * seconds / 60)


def fleet_targets(name):
    """What study_<name> builds for a fleet scenario: its growth run and its growth-rate spectrum
    (dataset and figure)."""
    return [f"results/fleet/{name}/growth.nc", f"results/fleet/{name}/rate_spectrum.nc", f"results/fleet/{name}/rate_spectrum.png"]


def traffic_study_inputs(wildcards=None):
    """The fleet spectra of the traffic study's cases, in the file's order (drives outer, spreads inner)."""
    return [f"results/fleet/{name}/rate_spectrum.nc" for name in TRAFFIC_CASES]


def traffic_study_cases(wildcards=None):
    """[drive, spread] of every case, in the order of traffic_study_inputs."""
    study = load_yaml(TRAFFIC_FILE)
    return [[d, float(s)] for d in study["drives"] for s in study["spreads"]]


# Uncertainty of the inputs (config/uncertainty.yaml, rail.uncertainty, named target uncertainty): the
# members' configurations, drawn with the seed and validated here (a draw outside a key's range stops
# the workflow naming the member and the key).
UNCERTAINTY_FILE = Path("config/uncertainty.yaml")
UNCERTAINTY = {}
if UNCERTAINTY_FILE.exists():
    from rail import uncertainty as _unc

    _u = load_yaml(UNCERTAINTY_FILE)
    try:
        _draws = _unc.sample(_u["parameters"], _u["members"], _u["seed"])
        _unc.band_statistics(np.zeros((1, 1)), _u["interval"])  # the interval's quantiles checked
    except (ValueError, KeyError) as _e:
        raise ConfigError(f"invalid configuration:\n  {UNCERTAINTY_FILE}: {_e}") from None
    _members = []
    for _m in range(int(_u["members"])):
        _vals = {k: float(v[_m]) for k, v in _draws.items()}
        try:
            _cfg = _unc.member_config(config, _vals)
        except ValueError as _e:
            raise ConfigError(f"invalid configuration:\n  {UNCERTAINTY_FILE}: {_e}") from None
        _cfg["figures"]["rate_spectrum"].update(_u["spectrum"])
        _src = f"{UNCERTAINTY_FILE} (member {_m}: {', '.join(f'{k} = {v:.6g}' for k, v in _vals.items())})"
        _cfg = validate_config(_cfg, SCHEMA, source=_src)
        build_spectrum_scenario(_cfg, f"uncertainty-m{_m}", _src)  # physics constraints, naming the member
        _members.append({"cfg": _cfg, "values": _vals})
    UNCERTAINTY = {"members": _members, "speed": float(_u["speed"]), "interval": list(_u["interval"]),
                   "draws": {k: [float(x) for x in v] for k, v in _draws.items()}}


def uncertainty_member_config(wildcards):
    """The configuration of one ensemble member (its draws applied), physics part."""
    m = int(wildcards.member)
    if not 0 <= m < len(UNCERTAINTY.get("members", [])):
        raise ConfigError(f"target names the ensemble member m{wildcards.member}, which config/uncertainty.yaml does not "
                          f"hold: the members are m0 .. m{len(UNCERTAINTY.get('members', [])) - 1}.")
    cfg = UNCERTAINTY["members"][m]["cfg"]
    return {**_physics(cfg), "figures": {"rate_spectrum": cfg["figures"]["rate_spectrum"]}}


def uncertainty_members(wildcards=None):
    """Every member's spectrum, in member order."""
    return [f"results/uncertainty/members/m{m}.nc" for m in range(len(UNCERTAINTY.get("members", [])))]
