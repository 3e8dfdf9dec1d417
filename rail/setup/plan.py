"""The workflow's plan: every scenario, sweep, traffic case, fleet class, receptance table and study set
that the configuration and the files of config/ define, and every target list built from them.

``plan(config, schema)`` reads config/scenarios/, config/studies/, config/traffic_study.yaml, uncertainty.yaml,
stability.yaml, convergence.yaml and closure.yaml (of config/), resolves and validates each
scenario, builds it once (rail.setup.build.scenario: the checks that need physics stop here, naming
the file) and returns a frozen Plan. Nothing here imports snakemake: workflow/rules/common.smk only
maps wildcards to the Plan's answers, and tests/test_plan.py checks the Plan without Snakemake.

Conventions
-----------
- A speed becomes a file-name label in one way, ``speed_label`` (``fleet_speed_label`` for a fleet
  class, exact); a target's label becomes a speed again only here (``Plan.target_speed``), checked
  like a configured speed, and rules hand that speed to their scripts as a parameter.
- Scenario names: 'default' (config/config.yaml), a scenario file's stem, ``<study>-p<n>`` for the
  points of a sweep, ``traffic_study-<drive>-s<percent>`` for the traffic study's cases.
- Paths are relative to the project folder (``root``), as the workflow's targets are.
- The labels, configuration parts, fixed target sets and records are rail.setup.targets's (issue 44:
  this module stays under 800 lines); every one is importable from here as before.
"""

from __future__ import annotations

import functools
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

from ..chain import wheel_offsets
from ..roughness import RoughnessInputWarning
from .build import fleet_classes, model_notes, scenario, spectrum_scenario, wheel_source_settings
from .config import ConfigError, check_scenario_names, expand_sweep, load_yaml, resolve_scenario_file, scenario_files, schema_unit
from .inputs import check_inputs, check_speed, fleet_checked, noise_files, noise_problem, wheel_source_spectra
from .study_files import (SPEED_STUDY, check_convergence_study, class_estimate, class_key, read_studies, study_summary, traffic_cases,
                          uncertainty_study)
from .tables import table_key
from ..creepage.rail_flexibility_cell import table_seconds
from .targets import (CHARACTERISATION, DEFAULT_SOURCE, FORCE_FIGURES, FORCE_KEYS, GROWTH_FIGURE_KEYS, GROWTH_FIGURES,
                      HALFSPACE_FIGURES, HALFSPACE_KEYS, IRREGULAR_SPEED, PRIORITY_KERNELS, PRIORITY_TABLES,
                      REPORT_SUFFIXES, WEAR_CASE_KEYS, WEAR_FIGURES, Sweep, SweepPoint, Table, closure_label, config_part,
                      RAIL_HEAD_KEYS, case_base, fleet_speed_label, physics_part, read_part, speed_label, track_part,
                      wear_frequency_label, KnownNames, known_value)

__all__ = ["Plan", "Sweep", "SweepPoint", "Table", "plan", "speed_label", "fleet_speed_label", "config_part", "physics_part",
           "HALFSPACE_KEYS", "FORCE_KEYS", "WEAR_CASE_KEYS", "GROWTH_FIGURE_KEYS", "HALFSPACE_FIGURES", "FORCE_FIGURES",
           "WEAR_FIGURES", "GROWTH_FIGURES", "IRREGULAR_SPEED", "CHARACTERISATION", "REPORT_SUFFIXES",
           "PRIORITY_KERNELS", "PRIORITY_TABLES", "DEFAULT_SOURCE", "known_value", "wear_frequency_label",
           "closure_label", "track_part", "read_part", "case_base", "RAIL_HEAD_KEYS"]

def _offsets(scenarios) -> list[float]:
    """Offsets d between every ordered pair of wheels of the scenarios (0 first) [m]."""
    return sorted({d for s in scenarios for d in wheel_offsets(s)}, key=lambda d: (abs(d), d))


@dataclass(frozen=True, eq=False)
class Plan:
    """Everything the workflow runs, decided at start-up. Mappings are read-only views."""

    config: dict                         # the default configuration as the physics reads it (read_part)
    base_config: dict                    # the default configuration as a base for cases (read_part with base=True)
    schema: dict
    scenarios: Mapping                   # {name: resolved configuration as the physics reads it, read_part} (a name
                                         # left out raises its file's problem)
    sources: MappingProxyType            # {name: where it comes from, for messages}
    scenario_files: MappingProxyType     # {name: path} of config/scenarios/, and the cases of config/studies/
    sweeps: Mapping                      # {study: Sweep} (as scenarios)
    traffic_cases: MappingProxyType      # {case name: scenario mapping}
    traffic_study: dict | None           # config/traffic_study.yaml
    objects: Mapping                     # {name: rail.scenario.Scenario} (as scenarios)
    fleet_classes: Mapping               # {fleet scenario: (FleetClass, ...)} (as scenarios)
    fleet_spectrum_keys: MappingProxyType  # {fleet scenario: [class spectrum key per class]}
    fleet_spectrum_jobs: MappingProxyType  # {key: (first scenario holding it, class index)}
    tables: MappingProxyType             # {table key: Table}
    scenario_table: MappingProxyType     # {scenario: table key}
    fleet_tables: MappingProxyType       # {table key: Table} of the fleets
    fleet_table: MappingProxyType        # {fleet scenario: table key}
    uncertainty: MappingProxyType        # members, speed, interval, draws (empty without config/uncertainty.yaml)
    stability: dict
    convergence: dict
    convergence_values: MappingProxyType  # {(setting, value label): value}
    closure: dict
    notes: tuple                         # one line per roughness-input note, naming the scenarios
    broken: MappingProxyType             # {scenario file name: its problem}: left out of this run
    broken_sweeps: frozenset             # those of them that are sweep studies (sweep_targets names them, to stop there)
    studies: MappingProxyType            # {name: the study file config/studies/<name>.yaml} (study_files.read_studies)
    broken_studies: MappingProxyType     # {name: problem} of the study files that are not valid

    def left_out(self, name: str) -> str | None:
        """Why a scenario (or a sweep point, <study>-p<n>) is left out of this run, or None: its file in
        config/scenarios/ is not valid. Only the targets that need it stop, with this line."""
        return _left_out(name, self.broken, self.scenario_files)

    # -- scenarios ---------------------------------------------------------------------------

    @property
    def sweep_points(self) -> dict:
        """{point name: study} of every sweep point."""
        return {p.name: study for study, sw in self.sweeps.items() for p in sw.points}

    def require(self, name: str) -> dict:
        """A scenario's configuration, or one line naming the scenarios that exist."""
        if name not in self.scenarios:
            if self.left_out(name):
                raise ConfigError(self.left_out(name))
            raise ConfigError(f"target names the scenario '{name}', which is not defined: the scenarios are "
                              f"{', '.join(sorted(self.scenarios))} (config/scenarios/<name>.yaml).")
        return self.scenarios[name]

    @functools.lru_cache(maxsize=None)  # noqa: B019 - a Plan lives as long as the workflow
    def target_speed(self, name: str, label: str) -> float:
        """The speed [m/s] a target's file name gives ('V40' -> 40.0), checked like a configured speed: a
        finite number > 0 at which the scenario's harmonics reach the pinned-pinned frequency. The one
        place where a speed label becomes a number again."""
        cfg = self.require(name)
        try:
            V = float(label)
        except ValueError:
            raise ConfigError(f"target speed V{label} is not a number in m/s.") from None
        return check_speed(cfg, V, f"scenario {name}", f"target speed V{label}")

    def target_bays(self, label: str) -> int:
        """The roughness period N of a target's file name ('N8' -> 8), within the schema's bounds of a
        configured period (roughness.bays, figures.rate_spectrum.bays)."""
        vmax = self.schema["properties"]["figures"]["properties"]["rate_spectrum"]["properties"]["bays"]["maximum"]
        N = int(label)
        if not 2 <= N <= vmax:
            raise ConfigError(f"target period N{label} is not allowed: it must lie in [2, {vmax}] bays (as roughness.bays and "
                              "figures.rate_spectrum.bays in the configuration).")
        return N

    def track_part(self, name: str) -> dict:
        """The track and track numerics of a scenario: all its receptance tables depend on."""
        return track_part(self.scenarios[name])

    def track_name(self, name: str) -> str:
        """Tracks are shared: a scenario uses the track of the first scenario ('default' first, then in
        file order) whose track and track numerics equal its own."""
        key = track_part(self.scenarios[name])
        return next(other for other, cfg in self.scenarios.items() if track_part(cfg) == key)

    def not_a_fleet(self, name: str, what: str) -> None:
        """Refuse a one-train target (growth or spectrum per speed) of a scenario with a fleet."""
        if name in self.fleet_classes:
            raise ConfigError(f"scenario '{name}' has a fleet: its {what} per speed would run one train and leave the fleet out; "
                              f"build results/fleet/{name}/growth.nc or results/fleet/{name}/rate_spectrum.nc (study_{name}).")

    def growth_seconds(self, name: str) -> float:
        """Estimated CPU seconds of a scenario's growth loop: 0.5 s per update, wheel and bay at 61
        contact nodes (one core), as the square of the nodes; a fleet rolls every class's axles."""
        scn = self.objects[name]
        wheels = (sum(len(c.scenario.wheels.positions) for c in self.fleet_classes[name]) if name in self.fleet_classes
                  else len(scn.wheels.positions))
        updates = scn.growth.passages / scn.growth.passages_per_update
        return 0.5 * updates * wheels * scn.roughness.bays * (scn.contact_numerics.nodes / 61) ** 2 + self.cell_head_seconds(name)

    def cell_head_seconds(self, name: str) -> float:
        """Estimated CPU seconds of the rail head's table over a track cell that a growth run and a spectrum on the cell
        each build first (rail.creepage.rail_flexibility_cell.table_seconds; 0 without a cell head)."""
        scn = self.objects[name]
        return table_seconds(scn.material.rail_flexibility, scn.roughness.bays * scn.harmonics)

    def has_default_run(self, speed: float) -> bool:
        """Whether the default scenario runs at this speed (a growth run to compare with)."""
        return float(speed) in [float(v) for v in self.config["speeds"]]

    def overview_note(self, scenario: str, speed: float) -> str:
        """Why a scenario's overview at a speed [m/s] has no default comparison, or "" when it has one."""
        if scenario == "default" or self.has_default_run(speed):
            return ""
        runs = ", ".join(speed_label(v) for v in self.config["speeds"])
        return f"no default run at {speed_label(speed)} m/s (the default scenario runs at {runs} m/s): no comparison with the default"

    # -- receptance tables ---------------------------------------------------------------------

    def table_file(self, name: str, speed, bays=1) -> str:
        """The receptance table of scenario ``name`` at a speed (a label such as '40', or m/s), and for a
        roughness (or spectrum) period of N > 1 bays its Bloch tables (a track cell: the cell's table)."""
        label = speed if isinstance(speed, str) else speed_label(speed)
        suffix = "" if int(bays) == 1 else f"_N{int(bays)}"
        return f"results/receptance/{self.scenario_table[name]}/V{label}{suffix}.nc"

    def table(self, key: str, speed: str, bays: str | None = None) -> Table:
        """The table a receptance target names, its speed and period checked as those of the scenarios it
        serves; a scenario's name in the key's place is refused with the content-named path."""
        if key in self.tables:
            t = self.tables[key]
            self.target_speed(t.scenario, speed)
            if bays is not None:
                self.target_bays(bays)
            return t
        if key in self.scenarios:
            self.target_speed(key, speed)
            if bays is not None:
                self.target_bays(bays)
            if key in self.scenario_table:
                raise ConfigError(f"receptance tables are named by their content, not by a scenario: the table of scenario "
                                  f"'{key}' at V{speed} is {self.table_file(key, speed, bays or 1)} (docs/workflow.md).")
        known = "; ".join(f"{k} ({', '.join(v.scenarios[:3])})" for k, v in self.tables.items())
        raise ConfigError(f"target names the receptance table '{key}', which no scenario uses: the tables are {known}.")

    def fleet_speeds(self, name: str) -> list[float]:
        """The distinct class speeds of a fleet scenario [m/s], increasing."""
        return sorted({c.speed for c in self.fleet_classes[name]})

    def fleet_table_file(self, name: str, speed: float, bays: int) -> str:
        """The shared receptance table of a fleet scenario at one class speed (N > 1 bays: its Bloch tables)."""
        suffix = "" if bays == 1 else f"_N{bays}"
        return f"results/receptance/{self.fleet_table[name]}/fleet_V{fleet_speed_label(speed)}{suffix}.nc"

    def fleet_table_of(self, key: str, speed: str, bays: str | None = None) -> tuple[Table, float]:
        """The fleet table a target names and its class speed [m/s] (the label must be the exact label of
        a class speed of a fleet it serves); a scenario's name in the key's place is refused."""
        if key not in self.fleet_tables:
            if key in self.fleet_table:
                raise ConfigError(f"fleet receptance tables are named by their content, not by a scenario: those of fleet '{key}' are "
                                  f"{self.fleet_table_file(key, self.fleet_speeds(key)[0], int(bays or 1))} and the other class "
                                  "speeds (docs/workflow.md).")
            known = "; ".join(f"{k} ({', '.join(v.scenarios[:3])})" for k, v in self.fleet_tables.items()) or "none"
            raise ConfigError(f"target names the fleet receptance table '{key}', which no fleet scenario uses: the fleet tables are {known}.")
        t = self.fleet_tables[key]
        if bays is not None:
            self.target_bays(bays)
        speeds = {fleet_speed_label(v): v for name in t.scenarios for v in self.fleet_speeds(name)}
        if speed not in speeds:
            raise ConfigError(f"target names a fleet table '{key}' (fleets {', '.join(t.scenarios)}) at V{speed}, which is no class "
                              f"speed of those fleets: the speeds are {', '.join(sorted(speeds, key=float)) or 'none'} m/s.")
        return t, speeds[speed]

    def fleet_class_label(self, key: str) -> str:
        """What a class spectrum job (named by its content's hash) holds, for its message and log: the
        vehicle, the speed and every fleet scenario holding the class."""
        name, i = self.fleet_class_owner(key)
        holders = [n for n, keys in self.fleet_spectrum_keys.items() if key in keys]
        return f"{self.fleet_classes[name][i].label} (fleets: {', '.join(holders)})"

    def fleet_class_estimate(self, key: str):
        """Memory and CPU time of a class spectrum job (rail.setup.study_files.class_estimate)."""
        name, i = self.fleet_class_owner(key)
        return class_estimate(self.fleet_classes[name][i], self.scenarios[name]["figures"]["rate_spectrum"])

    def fleet_class_resources(self, key: str) -> dict:
        """A class spectrum job's resources: mem_mb its estimate x 1.3 + 300 [MB], runtime three times
        its estimated CPU time plus 10 min [min] (as the growth jobs')."""
        e = self.fleet_class_estimate(key)
        return {"mem_mb": int(300 + 1.3 * e.memory_mb), "runtime": int(10 + 3 * e.cpu_seconds / 60)}

    def fleet_class_owner(self, key: str) -> tuple[str, int]:
        """(scenario, class index) of a class spectrum job."""
        if key not in self.fleet_spectrum_jobs:
            raise ConfigError(f"target names the fleet class spectrum {key}, which no fleet scenario holds.")
        return self.fleet_spectrum_jobs[key]

    # -- target lists ----------------------------------------------------------------------------

    def paper_figures(self) -> list[str]:
        """Every report figure, its picture and its plotted data, and the 3-D growth plot of section 5."""
        nns = HALFSPACE_FIGURES + FORCE_FIGURES + WEAR_FIGURES + GROWTH_FIGURES
        return ([f"results/figures/fig{nn}.png" for nn in nns] + [f"results/data/fig{nn}.nc" for nn in nns]
                + ["results/growth/default/V40_3d.png"])

    def receptance_tables(self) -> list[str]:
        """Receptance tables of the default track at every configured speed."""
        return [self.table_file("default", v) for v in self.config["speeds"]]

    def study_names(self) -> list[str]:
        """The scenario files and sweep studies of config/scenarios/ (each a target study_<name>)."""
        points = self.sweep_points
        return [n for n in self.scenarios if n not in points and n not in self.traffic_cases and n != "default"] + sorted(self.sweeps)

    def run_file(self, name: str, speed) -> str:
        """A growth run of a scenario at a speed [m/s]."""
        return f"results/growth/{name}/V{speed_label(speed)}.nc"

    def study_targets(self, name: str) -> list[str]:
        """What study_<name> builds: per speed of the scenario (or per point of the sweep), the growth
        run's overview, band view and 3-D plot; for a sweep also its dataset and maps; for a fleet its
        growth, growth-rate spectrum, overview, band view (issue 45: the outputs of a one-train run) and noise."""
        if name in self.fleet_classes:  # and its noise where it can be computed (issue 56: rule fleet_noise)
            noise = [f"results/fleet/{name}/growth_noise.{x}" for x in ("png", "csv")] if noise_problem(self.scenarios[name]) is None else []
            settled = ([f"results/fleet/{name}/settled.{x}" for x in ("png", "csv", "md")]  # its wheels' source (rule fleet_settled_spectrum)
                       if wheel_source_settings(self.scenarios[name]) is not None else [])
            return [f"results/fleet/{name}/growth.nc", f"results/fleet/{name}/rate_spectrum.nc", f"results/fleet/{name}/rate_spectrum.png",
                    f"results/fleet/{name}/overview.png", f"results/fleet/{name}/bands.png", f"results/fleet/{name}/bands.csv", *noise,
                    *settled]
        if name in self.sweeps:
            runs = [(p.name, p.speed) for p in self.sweeps[name].points]
            extra = [f"results/sweeps/{name}.nc", f"results/sweeps/{name}.png"]
        else:
            runs = [(name, v) for v in self.objects[name].speeds]
            extra = []
        out = []
        for scen, v in runs:
            base = f"results/growth/{scen}/V{speed_label(v)}"
            out += [f"{base}_overview.png", f"{base}_bands.png", f"{base}_3d.png"]
            out += noise_files(self.scenarios, [(scen, v)])  # issue 56
        return out + extra

    def study_input(self, name: str):
        """The input of the rule study_<name>: its targets (study_targets) or, for a scenario file left out
        of the run (not valid: broken), a function of the wildcards that stops the run with the file's
        problem when, and only when, the target is asked for."""
        if name not in self.broken:
            return self.study_targets(name)

        def left_out(wildcards):
            raise ConfigError(self.left_out(name))

        return left_out

    def study_file_targets(self, name: str) -> list[str]:
        """What the named target of config/studies/<name>.yaml builds: of each case it includes and of each of
        its cases, in the file's order, what its ``builds`` says (the growth-rate spectrum's figure, or the
        case's study_<case> outputs, or nothing), then the outputs of the file's summary (rail.setup.study_files)."""
        st, out = self.studies[name], []
        for n in st["include"] + st["cases"]:
            if st["builds"][n] in ("spectrum", "settled") and n in self.scenarios:
                folder = "fleet" if n in self.fleet_classes else "spectrum"  # a fleet's: rules fleet_rate_spectrum, fleet_settled_spectrum
                out.append(f"results/{folder}/{n}/rate_spectrum.png")
                if st["builds"][n] == "settled":  # and the wheels' source (wheel_source, rule settled_spectrum)
                    out.append(f"results/{folder}/{n}/settled.png")
            elif st["builds"][n] == "study" and (n in self.scenarios or n in self.sweeps):
                out += self.study_targets(n)
        summary = {"speed_study": lambda: ["results/dynamic_creepage/speeds.png"], "closure_study": self.closure_targets,
                   "irregular_track": self.irregular_targets, "mitigation": lambda: ["results/mitigation/mitigation.png"]}
        return out + (summary[st["summary"]["kind"]]() if st["summary"] else [])

    def study_file_input(self, name: str):
        """The input of a study file's named target: its targets, or (a study file or one of its cases not
        valid, a case it includes not defined) a function that stops the run with why, if the target is asked for."""
        cases = self.studies[name]["include"] + self.studies[name]["cases"] if name in self.studies else []
        why = self.broken_studies.get(name) or next((self.left_out(n) for n in cases if self.left_out(n)), None) or next(
            (f"config/studies/{name}.yaml includes {n}, which no study file defines." for n in cases if n not in self.scenarios
             and n not in self.sweeps), None)

        def left_out(wildcards):
            raise ConfigError(why)

        return self.study_file_targets(name) if why is None else left_out

    def speed_study_spectra(self) -> dict[str, list[str]]:
        """The dynamic-creepage study over speed (issue 43, rule speed_study): each case of the study file whose
        summary is the speed study (config/studies/dynamic_creepage_speeds.yaml), by name, -> its per-speed
        spectra, results/spectrum/<name>/V<speed>.nc, at figures.rate_spectrum.speeds."""
        study = study_summary(self.studies, SPEED_STUDY).get("study")
        names = sorted(n for n in (self.studies[study]["cases"] if study else []) if n in self.scenarios)
        return {n: [f"results/spectrum/{n}/V{speed_label(v)}.nc" for v in self.scenarios[n]["figures"]["rate_spectrum"]["speeds"]]
                for n in names}

    def _periodic(self) -> list[str]:
        """Scenarios with a roughness period of N > 1 bays, neither sweep points nor fleets nor a study file's cases built
        for their settled spectrum (builds: settled, a spectrum's study: config/studies/mitigation.yaml's cells)."""
        points = set(self.sweep_points) | {n for st in self.studies.values() for n, b in st["builds"].items() if b == "settled"}
        return [n for n, scn in self.objects.items() if scn.roughness.bays > 1 and n not in points and n not in self.fleet_classes]

    def any_wavelength_targets(self) -> list[str]:
        """Narrow-band figures of the scenarios with a roughness period of N > 1 bays (not sweep points),
        and the aggregated datasets of the sweeps over such scenarios."""
        out = [f"results/growth/{n}/V{speed_label(self.objects[n].speeds[0])}_narrowband.png" for n in self._periodic()]
        for study, sw in self.sweeps.items():
            if any(self.objects[p.name].roughness.bays > 1 for p in sw.points):
                out += [f"results/sweeps/{study}.nc", f"results/sweeps/{study}.png"]
        return out

    def band_targets(self) -> list[str]:
        """Band views of the default runs at every configured speed and of the scenarios with a roughness
        period of N > 1 bays; the band map of every sweep over speed (not the closure study's)."""
        out = [f"results/growth/default/V{speed_label(v)}_bands.csv" for v in self.config["speeds"]]
        out += [f"results/growth/{n}/V{speed_label(self.objects[n].speeds[0])}_bands.csv" for n in self._periodic()]
        out += [f"results/sweeps/{study}_bands.png" for study, sw in self.sweeps.items()
                if "speed" in sw.keys and study not in self.closure_studies().values()]
        return out

    def noise_targets(self) -> list[str]:
        """The named target noise (issue 56): the noise of the runs of the named target bands (rail.setup.inputs.noise_files)."""
        runs = [("default", v) for v in self.config["speeds"]] + [(n, self.objects[n].speeds[0]) for n in self._periodic()]
        return noise_files(self.scenarios, runs)

    def sweep_targets(self) -> list[str]:
        """Aggregated dataset and map figure of every sweep study (one left out of the run included: its
        targets stop with its file's problem)."""
        return [f"results/sweeps/{s}.{ext}" for ext in ("nc", "png") for s in sorted({*self.sweeps, *self.broken_sweeps})]

    def sweep_runs(self, study: str) -> list[str]:
        """Growth runs of every point of a sweep study, in grid order."""
        return [self.run_file(p.name, p.speed) for p in self.sweeps[study].points]

    def rate_spectrum_sweep_targets(self) -> list[str]:
        """Spectrum maps of the sweep studies whose swept keys change the smooth rail's spectrum."""
        studies = [s for s, sw in self.sweeps.items() if any(not k.startswith("roughness.") for k in sw.keys)]
        return [f"results/spectrum_sweeps/{s}.{ext}" for ext in ("nc", "png") for s in sorted(studies)]

    def growth_figure_inputs(self, nn: str) -> dict:
        """The growth runs behind one of Figs 20, 21, 23-27 (nn = '20', ...), as {label: file}."""
        g = self.config["figures"]["growth"]
        v = [speed_label(x) for x in g["speeds"]]

        def run(scen, V):
            return f"results/growth/{scen}/V{V}.nc"

        n = int(nn)
        if n in (20, 21):
            return {f"{v[n - 20]} m/s": run("default", v[n - 20])}
        if n == 23:
            return {f"{x} m/s": run("default", x) for x in v}
        if n in (24, 25):
            cfg = self.scenarios[g["pad_scenario"]]
            return {f"railpad {self.config['track']['pad']['stiffness']:.2g} N/m": run("default", "40"),
                    f"railpad {cfg['track']['pad']['stiffness']:.2g} N/m": run(g["pad_scenario"], "40")}
        V = v[n - 26]
        wheels = len(self.scenarios[g["wheels_scenario"]]["wheels"]["positions"])
        return {"single wheel": run("default", V), f"{wheels} wheels": run(g["wheels_scenario"], V)}

    def growth_figures_labelled(self) -> dict:
        """The growth runs behind every one of Figs 20, 21, 23-27, as {nn: {label: file}}."""
        return {nn: self.growth_figure_inputs(nn) for nn in GROWTH_FIGURES}

    def growth_figures_runs(self) -> list[str]:
        """Every growth run Figs 20, 21, 23-27 are drawn from, each once."""
        return sorted({path for runs in self.growth_figures_labelled().values() for path in runs.values()})

    def wear_case_file(self, nn: str) -> str:
        """The wear case behind a figure of Figs 9-19 (Figs 9-11 use the second frequency, 1000 Hz)."""
        s = self.config["figures"]["wear"]
        n = int(nn)
        index = 1 if n <= 11 else (n - 12) // 2
        return f"results/wear/default/V{speed_label(s['speed'])}_f{wear_frequency_label(s['frequencies'][index])}.nc"

    def wear_figure_cases(self) -> list[str]:
        """Every wear case Figs 9-19 are drawn from, each once."""
        return sorted({self.wear_case_file(nn) for nn in WEAR_FIGURES})

    def wear_figure_config(self, nn: str) -> dict:
        """What a figure of Figs 9-19 reads: its wear case's keys, and for a wear spectrum (Figs 13, 15,
        17, 19) its wavenumber range."""
        n = int(nn)
        return config_part(WEAR_CASE_KEYS + (("figures.wear.spectrum_max_wavenumber",) if n >= 13 and n % 2 else ()), self.config)

    def wear_frequencies(self) -> dict:
        """{label: frequency [Hz]} of the configured wear cases."""
        return {wear_frequency_label(f): float(f) for f in self.config["figures"]["wear"]["frequencies"]}

    # -- the named studies -----------------------------------------------------------------------

    def closure_studies(self) -> dict:
        """{part: sweep} of the closure study (the roles run, soft and four of the summary closure_study of
        config/studies/closure_study.yaml); {} without it."""
        return {k: v for k, v in study_summary(self.studies, "closure_study").items() if k not in ("kind", "study")}

    def closure_values(self) -> list[float]:
        """The closure values s of the study, the same in each of its sweeps ([] without them)."""
        found = {}
        for study in self.closure_studies().values():
            if study not in self.sweeps or "contact.closure_scale" not in self.sweeps[study].keys:
                return []
            found[study] = [float(x) for x in self.sweeps[study].values_of("contact.closure_scale")]
        values = next(iter(found.values()), [])
        if any(v != values for v in found.values()):
            raise ValueError(f"the closure study's sweeps must use the same contact.closure_scale values: {found}")
        return values

    def closure_inputs(self) -> tuple[list[str], list]:
        """Every file the closure study aggregates, and what each is: ([paths], [[kind, s, speed or Hz]])."""
        paths, meta = [], []
        for tag, study in self.closure_studies().items():
            sw = self.sweeps[study]
            ki = sw.keys.index("contact.closure_scale")
            for p in sw.points:
                paths.append(self.run_file(p.name, p.speed))
                meta.append([tag, float(sw.values[ki][p.index[ki]]), float(p.speed)])
        for s in self.closure_values():
            for label, f in self.wear_frequencies().items():
                paths.append(f"results/closure/wear/s{closure_label(s)}_f{label}.nc")
                meta.append(["wear", s, f])
        paths.append("results/closure/wellposedness.nc")
        meta.append(["wellposed", 0.0, 0.0])
        return paths, meta

    def closure_targets(self) -> list[str]:
        """Outputs of the closure study (empty when its sweep files are absent)."""
        if not self.closure_values():
            return []
        return [f"results/closure/{n}" for n in ("closure.nc", "spectra.png", "wear_spectra.png", "conclusions.md", "conclusions.html")]

    def closure_wear_config(self, label: str) -> dict:
        """What a wear case reads of the default configuration, with the closure value its label names."""
        s = known_value({closure_label(x): x for x in self.closure_values()}, label, "closure value s",
                        "contact.closure_scale of config/studies/closure_study.yaml")
        return config_part(WEAR_CASE_KEYS, {**self.config, "contact": {**self.config["contact"], "closure_scale": s}})

    def characterised_tracks(self) -> list[str]:
        """Scenarios whose track differs from the default's and from every earlier one's: each track is
        characterised once, under results/tracks/<scenario>/."""
        return [name for name in self.scenarios if name != "default" and self.track_name(name) == name]

    def characterised_track_pattern(self) -> str:
        """The wildcard constraint of 'track' of the scenario characterisation rules (never matches if none)."""
        return "|".join(re.escape(name) for name in self.characterised_tracks()) or "(?!)"

    def characterisation_targets(self) -> list[str]:
        """Data and figures of every characterisation result of every track in use."""
        default = [f"results/{kind}/{name}.{ext}" for kind, ext in (("data", "nc"), ("figures", "png")) for name in CHARACTERISATION]
        return default + [f"results/tracks/{t}/{name}.{ext}" for t in self.characterised_tracks() for name in CHARACTERISATION
                          for ext in ("nc", "png")]

    def irregular_study(self) -> dict:
        """The irregular-track study's roles: uniform (the case each is shown beside), cases and random (a sweep),
        of the summary irregular_track of config/studies/irregular_track.yaml; {} without it."""
        return study_summary(self.studies, "irregular_track")

    def irregular_cases(self) -> list[str]:
        """The irregular-track cases that exist, each beside the uniform track (irregular_study)."""
        return [n for n in self.irregular_study().get("cases", []) if n in self.scenarios]

    def irregular_random_points(self) -> list[str]:
        """The random-track ensemble's scenarios (the points of the sweep of the role random)."""
        rnd = self.irregular_study().get("random")
        return [p.name for p in self.sweeps[rnd].points] if rnd in self.sweeps else []

    def irregular_targets(self) -> list[str]:
        """The named target irregular_track: each case's figure and the summary."""
        return [f"results/irregular/{c}.png" for c in self.irregular_cases()] + ["results/irregular/summary.png"]

    def traffic_study_inputs(self) -> list[str]:
        """The fleet spectra of the traffic study's cases, in the file's order (drives outer, spreads inner)."""
        return [f"results/fleet/{name}/rate_spectrum.nc" for name in self.traffic_cases]

    def traffic_study_labels(self) -> list:
        """[drive, spread] of every case, in the order of traffic_study_inputs."""
        study = self.traffic_study or {"drives": [], "spreads": []}
        return [[d, float(s)] for d in study["drives"] for s in study["spreads"]]

    def convergence_table(self, setting: str) -> dict:
        """The receptance table a contact or growth point uses (the default track at the study's speed)."""
        if self.convergence["settings"][setting]["quantity"] == "force":
            return {}
        return {"table": self.table_file("default", self.convergence["speed"])}

    def uncertainty_members(self) -> list[str]:
        """Every ensemble member's spectrum, in member order."""
        return [f"results/uncertainty/members/m{m}.nc" for m in range(len(self.uncertainty.get("members", [])))]

    def uncertainty_member(self, label: str) -> dict:
        """The configuration of one ensemble member (its draws applied): physics and spectrum settings."""
        members = self.uncertainty.get("members", [])
        m = int(label)
        if not 0 <= m < len(members):
            raise ConfigError(f"target names the ensemble member m{label}, which config/uncertainty.yaml does not "
                              f"hold: the members are m0 .. m{len(members) - 1}.")
        cfg = members[m]["cfg"]
        return {**physics_part(cfg), "figures": {"rate_spectrum": cfg["figures"]["rate_spectrum"]}}

    def stability_config(self, case: str) -> dict:
        """What a stability case reads of the default configuration (its job's params.cfg, the base its
        overrides are merged onto): base_config without the keys the case leaves unread (case_base)."""
        return case_base(self.base_config, self.stability["cases"][case].get("overrides", {}), self.schema)

    def convergence_points(self) -> list[str]:
        """Every point of the convergence study, references included."""
        return [f"results/convergence/points/{s}/{v}.nc" for s, v in self.convergence_values]

    def report_candidates(self) -> list[str]:
        """What the HTML report shows of the named studies and every scenario's study, if built (the
        workflow adds the per-scenario files it finds on disk)."""
        found = [t for name in self.study_names() for t in self.study_targets(name)]
        return found + self.closure_targets() + self.sweep_targets() + self.rate_spectrum_sweep_targets() + self.any_wavelength_targets() + [
            "results/stability/outcomes.html", "results/convergence/error_vs_time.png", "results/convergence/summary.html",
            "results/traffic_study/spectra.png", "results/uncertainty/band_interval.png"]


def _left_out(name: str, broken, files) -> str | None:
    """Plan.left_out from the problems ``broken`` ({file name: problem}) and the scenario ``files``."""
    m = re.fullmatch(r"(.+)-p\d+", name)
    stem = name if name in broken else m.group(1) if m and m.group(1) in broken else None
    if stem is None:
        return None
    return f"target needs the scenario '{name}', which is left out of this run: {files[stem]} is not valid: {broken[stem]}"


# -- building the plan ---------------------------------------------------------------------------


def _class_keys(cfg: dict, name: str, source: str) -> list[str]:
    """The class spectrum keys of a fleet scenario (class_key), each with its vehicle's wheels' roughness where the
    fleet's wheels are a source (a file that cannot be read: the scenario's ConfigError, as check_inputs words it)."""
    try:
        wheels = (wheel_source_spectra(cfg) or {}).get("vehicles", {})
    except (OSError, ValueError) as e:
        raise ConfigError(f"scenario {name} ({source}): {e}") from None
    return [class_key(c, cfg["figures"]["rate_spectrum"], wheels.get(c.vehicle))
            for c in fleet_classes(cfg, spectrum_scenario(cfg, name, source))]


def plan(config: dict, schema: dict, root=".") -> Plan:
    """The workflow's plan from a validated configuration and the files of ``root``/config/.

    Parameters
    ----------
    config : dict
        The resolved, validated configuration (config/config.yaml with --config/--configfile).
    schema : dict
        config/schema/config.schema.yaml.
    root : path
        The project folder (paths in messages and targets are relative to it).

    Returns
    -------
    Plan

    Raises
    ------
    ConfigError
        One line per problem, naming the file, the key and what is allowed.
    """
    root = Path(root)
    broken = {}  # {scenario file name: problem}: a file that is not valid stops only the targets that need it
    sweep_files = set()  # the scenario files that are sweep studies
    try:
        studies, study_cases, broken_studies = read_studies(root)
    except ValueError as e:
        raise ConfigError(f"invalid configuration:\n  {e}") from None
    scenarios, sources, sweeps, files = _scenarios(config, schema, root, broken, sweep_files, study_cases)
    traffic_file = root / "config/traffic_study.yaml"
    traffic_study = load_yaml(traffic_file) if traffic_file.exists() else None
    cases = _traffic_cases(config, schema, traffic_study, traffic_file, scenarios, sources)
    check_scenario_names({name: str(p) for name, p in files.items()},
                         {p.name: str(files[study]) for study, sw in sweeps.items() for p in sw.points})
    owner = {**{name: name for name in files if name in scenarios},
             **{p.name: study for study, sw in sweeps.items() for p in sw.points}}  # the file each scenario comes from

    def each(names, step):
        """step(name) for every name; a ConfigError of a scenario file's scenario leaves that file out."""
        out = {}
        for name in list(names):
            if owner.get(name) in broken:
                continue
            try:
                out[name] = step(name)
            except ConfigError as e:
                if name not in owner:  # config.yaml, a traffic case: every target needs it
                    raise
                broken.setdefault(owner[name], _one_problem(e))
        return out

    objects = each(scenarios, lambda name: scenario(scenarios[name], name, sources[name]))
    classes = _fleet_classes(scenarios, sources, sweeps, objects, each)
    spectrum_keys = each(classes, lambda name: _class_keys(scenarios[name], name, sources[name]))
    notes = _input_notes(scenarios, sources, objects, each)
    for name in [n for n in scenarios if owner.get(n) in broken]:  # every scenario of a file left out
        for d in (scenarios, sources, objects, classes, spectrum_keys):
            d.pop(name, None)
    for study in [s for s in sweeps if s in broken]:
        del sweeps[study]
    notes += [f"railgrowth: note (scenario {name}, {sources[name]}): {line}" for name, scn in objects.items()
              for line in model_notes(scn)]  # what a valid scenario runs that its keys might not say
    spectrum_jobs = {}
    for name, keys in spectrum_keys.items():
        for i, k in enumerate(keys):
            spectrum_jobs.setdefault(k, (name, i))
    notes = [f"railgrowth: note: {files[name]} is not valid, so it is left out of this run: only the targets that need it stop "
             f"(the others run): {' '.join(problem.split())}" for name, problem in sorted(broken.items())] + notes
    tables, scenario_table = {}, {}
    for name in scenarios:
        if name in classes:  # a fleet's tables hold every vehicle's offsets
            continue
        offsets = _offsets([objects[name]])
        key = table_key(track_part(scenarios[name]), offsets)
        scenario_table[name] = key
        tables.setdefault(key, Table(name, offsets)).scenarios.append(name)
    fleet_tables, fleet_table = {}, {}
    for name in classes:
        offsets = _offsets([c.scenario for c in classes[name]])
        key = table_key(track_part(scenarios[name]), offsets)
        fleet_table[name] = key
        fleet_tables.setdefault(key, Table(name, offsets)).scenarios.append(name)
    convergence = load_yaml(root / "config/convergence.yaml")
    try:  # NaN, a negative or a misspelt setting stop here, naming the key (not as a KeyError in a job)
        check_convergence_study(convergence)
    except ValueError as e:
        raise ConfigError(str(e)) from None
    ro = MappingProxyType
    def left_out(name: str) -> str | None:
        return _left_out(name, broken, files)

    return Plan(
        config=scenarios["default"], base_config=read_part(config, schema, base=True), schema=schema,
        scenarios=KnownNames(scenarios, left_out), sources=ro(sources), scenario_files=ro(files),
        sweeps=KnownNames(sweeps, left_out), traffic_cases=ro(cases), traffic_study=traffic_study, objects=KnownNames(objects, left_out),
        fleet_classes=KnownNames(classes, left_out),
        fleet_spectrum_keys=ro(spectrum_keys), fleet_spectrum_jobs=ro(spectrum_jobs), tables=ro(tables),
        scenario_table=ro(scenario_table), fleet_tables=ro(fleet_tables), fleet_table=ro(fleet_table),
        uncertainty=ro(uncertainty_study(config, schema, root / "config/uncertainty.yaml")),
        stability=load_yaml(root / "config/stability.yaml"), convergence=convergence,
        convergence_values=ro({(name, f"{float(v):g}"): float(v) for name, s in convergence["settings"].items()
                               for v in s["values"] + [s["reference"]]}),
        closure=load_yaml(root / "config/closure.yaml"), notes=tuple(notes), broken=ro(broken),
        broken_sweeps=frozenset(sweep_files & set(broken)), studies=ro(studies), broken_studies=ro(broken_studies))


def _one_problem(e: ConfigError) -> str:
    """A ConfigError's problems without the heading ("invalid configuration:"), one per line."""
    lines = str(e).split("\n")
    return "\n".join(x.strip() for x in (lines[1:] if len(lines) > 1 and lines[0].endswith(":") else lines))


def _scenarios(config: dict, schema: dict, root: Path, broken: dict, broken_sweeps: set, cases: dict):
    """Scenarios of config/scenarios/<name>.yaml and the cases of config/studies/ (only the keys that differ
    from the defaults; ``cases``: {name: (source, keys)}), in the order of their names, each resolved and
    validated (errors name its file), each as the physics reads it (read_part: what the jobs' params are made
    from); "default" is the configuration itself. A file (or case) with a top-level "sweep:" is a study: one
    scenario per grid point, named <study>-p<n>. A file (or case) that is not valid is left out, its problem in
    ``broken`` under its name; ``files`` maps every name to its file (a case: its study file and case)."""
    scenarios, sources, sweeps = {"default": read_part(config, schema)}, {"default": DEFAULT_SOURCE}, {}
    files = scenario_files(root / "config/scenarios")
    both = sorted(set(files) & set(cases))
    if both:
        raise ConfigError(f"invalid configuration:\n  {files[both[0]]}: the scenario name '{both[0]}' is also "
                          f"{cases[both[0]][0]}; rename the file.")
    files = dict(sorted({**files, **{n: src for n, (src, _) in cases.items()}}.items()))
    for name, path in files.items():
        src = str(path)
        try:
            scen = cases[name][1] if name in cases else load_yaml(path)
            if "sweep" not in scen:
                scenarios[name] = read_part(resolve_scenario_file(config, schema, scen, source=src, physics=name not in cases), schema)
                sources[name] = src
                continue
            broken_sweeps.add(name)  # kept only if the file is left out
            keys, values, points = expand_sweep(config, schema, scen, src, physics=name not in cases)
        except ConfigError as e:
            broken[name] = _one_problem(e)
            continue
        swept = []
        for n, (index, assignment, cfg) in enumerate(points):
            point = f"{name}-p{n}"
            scenarios[point] = read_part(cfg, schema)
            sources[point] = f"{src} (sweep point {', '.join(f'{k} = {v}' for k, v in assignment.items())})"
            speed = assignment["speed"] if "speed" in assignment else cfg["speeds"][0]
            swept.append(SweepPoint(point, tuple(index), speed))
        sweeps[name] = Sweep(keys, values, tuple(swept), [schema_unit(schema, k) for k in keys])
    return scenarios, sources, sweeps, files


def _traffic_cases(config, schema, study, path, scenarios, sources) -> dict:
    """The traffic study's cases (one fleet scenario per (drive, spread)), resolved and validated as
    scenario files and added to the scenarios."""
    if study is None:
        return {}
    try:
        cases = traffic_cases(study)
    except ValueError as e:
        raise ConfigError(f"invalid configuration:\n  {e}") from None
    for name, scen in cases.items():
        if name in scenarios:
            raise ConfigError(f"invalid configuration:\n  config/scenarios/{name}.yaml: the name is a case of the traffic study "
                              "(config/traffic_study.yaml): rename the file.")
        # the scenario files' start (issue 55): the rail's flexibility; each vehicle names its wheelsets in the study's file
        scenarios[name] = read_part(resolve_scenario_file(config, schema, scen, source=f"{path} (case {name})"), schema)
        sources[name] = f"{path} (case {name})"
    return cases


def _fleet_classes(scenarios, sources, sweeps, objects, each) -> dict:
    """The (vehicle, speed) classes of every fleet scenario, so that a speed the harmonics cannot serve
    or a roughness tied to one speed stops here (``each``: a scenario file's problem leaves the file out)."""
    points = {p.name for sw in sweeps.values() for p in sw.points}

    def classes(name):
        src = sources[name]
        if name in points:
            raise ConfigError(f"{src}: a sweep of a fleet scenario is not run by the workflow (its points' growth rules run "
                              "one train at one speed); give each case its own scenario file.")
        return fleet_checked(scenarios[name], objects[name], src)  # the cross-key checks of every door

    return each([n for n, cfg in scenarios.items() if "fleet" in cfg and n in objects], classes)


def _input_notes(scenarios, sources, objects, each) -> list[str]:
    """Every input file read and checked (its errors name the file and line; rail.setup.inputs), and the
    notes of a roughness input the period cannot hold in full, one line per message naming the
    scenarios. Any other warning is passed on as Python shows it."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RoughnessInputWarning)
        said = {}
        def check(name):
            before = len(caught)
            check_inputs(scenarios[name], objects[name], name, sources[name])
            for w in caught[before:]:
                if issubclass(w.category, RoughnessInputWarning):
                    said.setdefault(str(w.message), []).append(name)

        each(objects, check)  # a scenario file whose input files are not valid is left out
    for w in caught:
        if not issubclass(w.category, RoughnessInputWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return [f"railgrowth: note (scenario {', '.join(names)}): {text}" for text, names in said.items()]
