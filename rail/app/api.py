"""railgrowth from Python: load a scenario, grow roughness, compute a growth-rate spectrum.

Every function is keyword-only after its first argument and returns an xarray Dataset with units,
long names, the resolved configuration and provenance (rail.setup.io.finalize), the same as the
workflow writes. A worked example is docs/example.py (run by the tests).

    from rail.app import api
    study = api.load("soft_pad")
    ds = api.growth(study, speed=40.0, passages=20000)
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
import sys
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from .. import chain
from ..growth_spectrum import fleet_rate_spectrum, spectrum_lines
from ..scenario import Scenario
from ..setup import build, config, inputs, io
from ..setup.study_files import study_cases
from ..studies import fleet as fleet_study
from ..studies import exports, rate_spectrum, runs

__all__ = ["Study", "load", "growth", "bands", "spectrum", "fleet_spectrum", "ROOT"]

ROOT = Path(__file__).resolve().parents[2]  # the project folder holding config/


@dataclass(frozen=True)
class Study:
    """A scenario and the resolved configuration it was built from.

    name     : the scenario's name ("default" or the stem of config/scenarios/<name>.yaml)
    scenario : rail.scenario.Scenario
    config   : the resolved, validated configuration (dict), stored in every result file
    """

    name: str
    scenario: Scenario
    config: dict


def _speed(name: str, value) -> float:
    """value [m/s] as a float if it is a finite number > 0 (not a bool or a string), else a ConfigError naming it."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not (0 < float(value) < math.inf):
        raise config.ConfigError(f"{name} = {value!r} is not allowed: it must be a finite number > 0 (a train speed in m/s).")
    return float(value)


def _speeds(value) -> list[float]:
    """speeds as a list of floats [m/s]: one finite number > 0 or a non-empty sequence of them."""
    single = isinstance(value, numbers.Real) and not isinstance(value, bool)
    try:
        out = [value] if single else [] if isinstance(value, (str, bytes, dict)) else list(value)
    except TypeError:  # not a sequence
        out = []
    bad = [v for v in out if isinstance(v, bool) or not isinstance(v, numbers.Real) or not (0 < float(v) < math.inf)]
    if not out or bad:
        which = f" ({bad[0]!r} is not)" if bad and not single else ""
        raise config.ConfigError(f"speeds = {value!r} is not allowed: it must be a finite number > 0 (m/s) or a non-empty "
                                 f"list of them{which}.")
    return [float(v) for v in out]


def _count(name: str, value) -> int:
    """value as an int if it is a whole number >= 1 (not a bool or a string), else a ConfigError naming it."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value < 1 or value != int(value):
        raise config.ConfigError(f"{name} = {value!r} is not allowed: it must be a whole number >= 1.")
    return int(value)


def load(name: str = "default", *, root: str | Path | None = None, changes: dict | None = None) -> Study:
    """Build a scenario from the project's configuration, validated as the workflow does.

    Parameters
    ----------
    name : str
        "default" (config/config.yaml) or a scenario file's stem (config/scenarios/<name>.yaml or .yml),
        or the path of any scenario YAML file.
    root : path, optional
        Folder holding config/ (default: this checkout).
    changes : dict, optional
        Keys to change on top (nested like the YAML, e.g. {"track": {"pad": {"stiffness": 1e8}}}),
        validated too; anything but a dict (or None) is refused.

    Returns
    -------
    Study

    Raises
    ------
    rail.setup.config.ConfigError
        Naming the file, key, value and valid range of every problem; a sweep file is refused (its
        points are scenarios of the workflow: snakemake -j2 sweeps); a name that is not a string or
        path, or changes that are not a dict, are refused naming the argument.
    """
    if not isinstance(name, (str, os.PathLike)):
        raise config.ConfigError(f"name = {name!r} is not allowed: it must be 'default', a scenario's name "
                                 "(config/scenarios/<name>.yaml) or the path of a scenario YAML file.")
    if changes is not None and not isinstance(changes, dict):
        raise config.ConfigError(f"changes = {changes!r} is not allowed: it must be a dict nested like the YAML "
                                 "(e.g. {'track': {'pad': {'stiffness': 1e8}}}) or None.")
    if root is not None and not isinstance(root, (str, os.PathLike)):
        raise config.ConfigError(f"root = {root!r} is not allowed: it must be the path of the folder holding config/.")
    root = Path(root) if root is not None else ROOT
    schema = config.load_yaml(root / "config/schema/config.schema.yaml")
    defaults = config.validate_config(config.load_yaml(root / "config/config.yaml"), schema, source="config/config.yaml")
    path = Path(name)
    if path.suffix in (".yaml", ".yml"):
        source, stem, scen = str(path), path.stem, config.load_yaml(path)
    elif str(name) == "default":
        source, stem, scen = "config/config.yaml", "default", {}
    else:
        files = config.scenario_files(root / "config/scenarios")  # <name>.yaml or <name>.yml, not both
        try:
            cases = study_cases(root)  # the cases of config/studies/*.yaml, by name (rail.setup.study_files)
        except ValueError as e:
            raise config.ConfigError(str(e)) from None
        if str(name) in cases and str(name) not in files:
            (source, scen), stem = cases[str(name)], str(name)
            source = source.replace(f"{root}/", "")
        elif str(name) not in files:
            raise config.ConfigError(f"scenario '{name}' is not defined: the scenarios are default, {', '.join(files)} "
                                     f"(config/scenarios/), and the cases {', '.join(cases)} of config/studies/.")
        else:
            path = files[str(name)]
            source, stem, scen = str(path.relative_to(root)), name, config.load_yaml(path)
    if "sweep" in scen:
        raise config.ConfigError(f"{source} is a sweep study: its grid points are scenarios of the workflow "
                                 "(snakemake -j2 sweeps); load one point's keys as changes instead.")
    merged = config.deep_merge(scen, changes or {})
    cfg = (config.resolve(defaults, schema, merged, source=source) if stem == "default" and not path.suffix
           else config.resolve_scenario_file(defaults, schema, merged, source=source))
    cfg = inputs.resolve_paths(cfg, root)  # its files relative to the project, not the current folder
    scn = build.scenario(cfg, stem, source)
    inputs.check_inputs(cfg, scn, stem, source, root)  # as the workflow does at start-up
    return Study(stem, scn, cfg)


def growth(study: Study, *, speed: float | None = None, passages: int | None = None, checkpoint=None,
           progress=sys.stderr) -> xr.Dataset:
    """Roughness growth of a study at one speed from its initial roughness (secs 4-5), or under the
    study's fleet (config key ``fleet``: every (vehicle, speed) class each update, rail.chain.grow_fleet).

    Parameters
    ----------
    study : Study
    speed : float
        Train speed [m/s], finite and > 0; not given for a study with a fleet (its speeds are the fleet's).
    passages : int, optional
        Wheel passages (default: the study's growth.passages), >= 1; a multiple of growth.save_every.
    checkpoint : path, optional
        Resumable checkpoint (a killed run resumes from it).
    progress : file
        Where progress lines go.

    Returns
    -------
    xr.Dataset
        As results/growth/<scenario>/V<speed>.nc: levels and profiles at every saved passage count,
        roughness coefficients, growth rates, the wheel force.

    Raises
    ------
    rail.setup.config.ConfigError
        If speed is not a finite number > 0 or passages not a whole number >= 1 (before computing).
    """
    scn = study.scenario
    if passages is not None:
        scn = dataclasses.replace(scn, growth=dataclasses.replace(scn.growth, passages=_count("passages", passages)))
    if "fleet" in study.config:
        if speed is not None:
            raise config.ConfigError(f"speed = {speed!r} is not allowed for {study.name}: its fleet sets the speeds "
                                     "(fleet.speeds); leave speed out.")
        return _fleet_growth(study, scn, checkpoint, progress)
    if speed is None:
        raise config.ConfigError(f"speed is needed for {study.name}: a train speed in m/s (a finite number > 0).")
    speed = _speed("speed", speed)
    speed = inputs.check_speed(study.config, speed, f"{study.name}: growth")
    table = chain.receptance_table(scn, speed)
    history = chain.grow(scn, table, checkpoint=checkpoint, identity={"config": study.config}, progress=progress,
                         on_mismatch="restart")
    ds = runs.growth_dataset(scn, table, history, speed, warn=progress)
    return io.finalize(ds, study.config, title=f"Roughness growth at {speed:g} m/s", source="rail.app.api.growth",
                       scenario=study.name)


def _fleet_growth(study: Study, scn: Scenario, checkpoint, progress) -> xr.Dataset:
    """growth under the study's fleet: one table per speed, shared by the vehicles (rail.chain.fleet_tables)."""
    fl = build.fleet(study.config)
    classes = fl.classes(scn, float(study.config["wheels"]["static_load"]))
    for c in classes:
        inputs.check_speed(study.config, c.speed, f"{study.name}: fleet growth")
    tables = chain.fleet_tables(classes)
    history = chain.grow_fleet(classes, tables, checkpoint=checkpoint, identity={"config": study.config}, progress=progress,
                               on_mismatch="restart")
    ds = fleet_study.fleet_growth_dataset(classes, tables, history, fl)
    return io.finalize(ds, study.config, title="Roughness growth under the fleet", source="rail.app.api.growth",
                       scenario=study.name)


def _spectrum_settings(study: Study, door: str, **given) -> tuple[dict, dict]:
    """The spectrum settings (figures.rate_spectrum) of a study with the arguments given, and the
    configuration holding them, checked as the schema checks the configured ones (ranges, e.g. bays
    in [2, 256]), before anything is computed; a ConfigError names the argument, its value and range."""
    for name in ("per_octave", "bays", "grid_phases"):
        if given[name] is not None:
            _count(name, given[name])
    for name in ("shortest", "longest"):
        value = given[name]
        if value is not None and (isinstance(value, bool) or not isinstance(value, numbers.Real)):
            raise config.ConfigError(f"{name} = {value!r} is not allowed: it must be a wavelength in m.")
    s = dict(study.config["figures"]["rate_spectrum"])
    s.update({k: v for k, v in given.items() if v is not None})
    cfg = config.deep_merge(study.config, {"figures": {"rate_spectrum": s}})
    try:
        config.validate_config(cfg, config.project_schema(), source=f"{door}(...) of {study.name}")
    except config.ConfigError as e:  # the schema names the key figures.rate_spectrum.<argument>
        raise config.ConfigError(str(e).replace("figures.rate_spectrum.", "argument ")) from None
    return s, cfg


def bands(study: Study, growth: xr.Dataset) -> exports.BandOutputs:
    """One-third-octave bands of a growth run of the study (one train or its fleet), growth per band,
    the grinding interval with its band (passages, years, MGT) and the exports, as the workflow's
    growth_bands and fleet_bands (rail.studies.exports.band_outputs: one code path).

    Parameters
    ----------
    study : Study
        The study the run was grown from (its figures.bands settings, limit, wheel roughness, input
        spectrum and traffic).
    growth : xr.Dataset
        The result of growth (or a growth file the workflow wrote, opened).

    Returns
    -------
    rail.studies.exports.BandOutputs
        data: the band dataset (as results/.../V<speed>_bands.nc or results/fleet/<scenario>/bands.nc,
        with units and provenance); bands_csv, narrow_csv, rolling_noise_csv: the exports' texts.

    Raises
    ------
    rail.setup.config.ConfigError
        If growth is not a growth dataset.
    """
    if not isinstance(growth, xr.Dataset) or not {"Z_real", "Z_imag", "passage"} <= set(growth.variables):
        raise config.ConfigError("growth is not a growth result: give the dataset api.growth returns (or a growth file, opened).")
    b = exports.band_outputs(growth, study.scenario.L, study.config["figures"]["bands"], study.name,
                             **inputs.band_inputs(study.config, study.scenario))
    data = io.finalize(b.data, study.config, title=f"One-third-octave roughness bands, scenario {study.name}",
                       source="rail.app.api.bands", scenario=study.name)
    return dataclasses.replace(b, data=data)


def spectrum(study: Study, *, speeds, shortest: float | None = None, longest: float | None = None,
             per_octave: int | None = None, bays: int | None = None, grid_phases: int | None = None) -> xr.Dataset:
    """Growth-rate spectrum of a study about the smooth rail at one or more speeds (rail.growth_spectrum).

    Parameters
    ----------
    study : Study
    speeds : float or sequence of float
        Train speeds [m/s], each finite and > 0; a sequence must not be empty (a string is refused).
    shortest, longest : float, optional
        Wavelength range [m] (default: figures.rate_spectrum of the study).
    per_octave : int, optional
        Lines per octave at least.
    bays : int, optional
        Roughness period N of the lines [bays]; must resolve the longest wavelength.
    grid_phases : int, optional
        Contact grids averaged over.

    Returns
    -------
    xr.Dataset
        As results/spectrum/<scenario>/rate_spectrum.nc: growth rate, drift, dB per 100,000
        passages over (speed, wavelength).

    Raises
    ------
    rail.setup.config.ConfigError, ValueError
        Naming the argument, before computing: a study with a fleet (its spectrum is fleet_spectrum);
        speeds not a finite number > 0 or a non-empty sequence of them, or a speed the workflow and
        growth refuse (rail.setup.inputs.check_speed: above 300 m/s, or too slow for the harmonics to
        reach the pinned-pinned frequency); per_octave, bays, grid_phases not whole numbers, or any
        setting outside the schema's range of figures.rate_spectrum (bays in [2, 256]); a wavelength
        range the lines cannot span (rail.growth_spectrum.spectrum_lines).
    """
    if "fleet" in study.config:
        raise config.ConfigError(f"{study.name} has a fleet: spectrum would compute one train at the speeds given and leave "
                                 "the fleet out; its spectrum is rail.app.api.fleet_spectrum (workflow: "
                                 f"results/fleet/{study.name}/rate_spectrum.nc).")
    speeds = _speeds(speeds)
    s, cfg = _spectrum_settings(study, "spectrum", shortest=shortest, longest=longest, per_octave=per_octave, bays=bays,
                                grid_phases=grid_phases)
    for v in speeds:  # as run, growth and the workflow's targets check a speed (rail.setup.inputs.check_speed)
        inputs.check_speed(cfg, v, f"{study.name}: spectrum")
    scn = build.spectrum_scenario(cfg, study.name)
    spectrum_lines(scn.L, scn.roughness.bays, scn.harmonics, float(s["shortest"]), float(s["longest"]), int(s["per_octave"]))
    spectra = {v: rate_spectrum.spectrum_with_settings(scn, chain.receptance_table(scn, v), s) for v in speeds}
    ds = rate_spectrum.spectrum_dataset_of(spectra, scn)
    return io.finalize(ds, cfg, title="Growth-rate spectrum", source="rail.app.api.spectrum", scenario=study.name)


def fleet_spectrum(study: Study, *, shortest: float | None = None, longest: float | None = None,
                   per_octave: int | None = None, bays: int | None = None, grid_phases: int | None = None) -> xr.Dataset:
    """Growth-rate spectrum about the smooth rail under a study's fleet (docs/traffic.md): the
    traffic-weighted rate per wavelength with each (vehicle, speed) class's contribution, per fleet
    passage and per year (rail.growth_spectrum.fleet_rate_spectrum, rail.studies.fleet).

    Parameters
    ----------
    study : Study
        With a fleet (config key ``fleet``).
    shortest, longest : float, optional
        Wavelength range [m] (default: figures.rate_spectrum of the study).
    per_octave, bays, grid_phases : int, optional
        As spectrum.

    Returns
    -------
    xr.Dataset
        growth_rate, growth_dB_per_1e5_trains, growth_dB_per_1e5_axles, growth_dB_per_year over
        wavelength; class_growth_rate and class_contribution over (class, wavelength).

    Raises
    ------
    rail.setup.config.ConfigError
        If the study has no fleet, or an argument is not allowed (as spectrum).
    """
    if "fleet" not in study.config:
        raise config.ConfigError(f"{study.name} has no fleet: give the key fleet (docs/traffic.md), or use spectrum.")
    s, cfg = _spectrum_settings(study, "fleet_spectrum", shortest=shortest, longest=longest, per_octave=per_octave, bays=bays,
                                grid_phases=grid_phases)
    scn = build.spectrum_scenario(cfg, study.name)
    lines = spectrum_lines(scn.L, scn.roughness.bays, scn.harmonics, float(s["shortest"]), float(s["longest"]), int(s["per_octave"]))
    fl = build.fleet(cfg)
    classes = fl.classes(scn, float(cfg["wheels"]["static_load"]))
    for c in classes:
        inputs.check_speed(cfg, c.speed, f"{study.name}: fleet spectrum")
    fs = fleet_rate_spectrum(classes, chain.fleet_tables(classes), lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]))
    ds = fleet_study.fleet_spectrum_dataset(fs, fl)
    return io.finalize(ds, cfg, title="Growth-rate spectrum under the fleet", source="rail.app.api.fleet_spectrum",
                       scenario=study.name)
