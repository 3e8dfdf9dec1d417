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
import yaml

from .. import chain
from ..growth import BAND_GROWTH_SAVES
from ..growth_spectrum import fleet_rate_spectrum, settings_lines
from ..scenario import Scenario
from ..setup import build, config, inputs, io
from ..setup.targets import physics_part, read_part
from ..setup.study_files import study_cases
from ..studies import fleet as fleet_study
from ..studies import exports, rate_spectrum, runs
from ..studies import noise as noise_study
from ..studies import wheel_source

__all__ = ["Study", "load", "growth", "check_bands", "bands", "spectrum", "fleet_spectrum", "noise", "ROOT"]

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
    case = path.suffix not in (".yaml", ".yml") and str(name) != "default" and source.startswith("config/studies/")
    cfg = (config.resolve(defaults, schema, merged, source=source) if stem == "default" and not path.suffix
           else config.resolve_scenario_file(defaults, schema, merged, source=source, physics=not case))
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
    in [2, 256]), before anything is computed; a ConfigError names the argument, its value and range. A period
    given (bays) takes the log-spaced lines of that period without the band of figures.rate_spectrum.band,
    as a scenario file that sets its own period does (rail.setup.config.resolve_scenario_file).

    Parameters
    ----------
    study : Study
        The study whose settings are taken.
    door : str
        The function called, named in messages ("spectrum", "fleet_spectrum").
    **given
        shortest, longest [m], per_octave, bays, grid_phases [-]: None keeps the study's.

    Returns
    -------
    (dict, dict)
        The settings [SI] and the configuration holding them.
    """
    for name in ("per_octave", "bays", "grid_phases"):
        if given[name] is not None:
            given[name] = _count(name, given[name])  # a whole float (40.0) is taken as the int it is
    for name in ("shortest", "longest"):
        value = given[name]
        if value is not None and (isinstance(value, bool) or not isinstance(value, numbers.Real)):
            raise config.ConfigError(f"{name} = {value!r} is not allowed: it must be a wavelength in m.")
    s = dict(study.config["figures"]["rate_spectrum"])
    s.update({k: v for k, v in given.items() if v is not None})
    if given.get("bays") is not None:  # a period given here keeps its own lines, as a scenario file's own period does
        s["band"] = None
    cfg = config.deep_merge(study.config, {"figures": {"rate_spectrum": s}})
    try:
        config.validate_config(cfg, config.project_schema(), source=f"{door}(...) of {study.name}")
    except config.ConfigError as e:  # the schema names the key figures.rate_spectrum.<argument>
        raise config.ConfigError(str(e).replace("figures.rate_spectrum.", "argument ")) from None
    return s, cfg


def check_bands(study: Study, *, passages: int | None = None, option: str = "passages", view: str = "the band view") -> None:
    """Refuse, before computing, a growth run of a study whose band view (bands) cannot be made, so that
    no computed growth ends in a refusal: the band growth laws need BAND_GROWTH_SAVES = 3 saved
    passage counts at least (rail.growth.band_growth: the start and two saves), and a run of n
    passages saves n / growth.save_every + 1; the band view's files (limit spectrum, wheel roughness)
    are read too.

    Parameters
    ----------
    study : Study
    passages : int, optional
        Wheel passages of the run (default: the study's growth.passages), >= 1.
    option, view : str
        How the caller names the passages and the band view in the message (the command line:
        "--passages", "--bands").

    Returns
    -------
    None
        Only if the band view can be made.

    Raises
    ------
    rail.setup.config.ConfigError
        Naming the passages, growth.save_every, the saves they give and what would give three.
    """
    g = study.scenario.growth
    n = g.passages if passages is None else _count(option, passages)
    try:
        dataclasses.replace(g, passages=n)  # passages the run refuses (not a multiple of growth.save_every): named as it does
    except ValueError as e:
        raise config.ConfigError(f"{option} = {n}: {e}") from None
    saves = n // g.save_every + 1
    if saves < BAND_GROWTH_SAVES:
        given = f"{option} {n}" if passages is not None else f"growth.passages = {n}"
        at = " and ".join(f"{k * g.save_every:,}" for k in range(saves))
        need = (BAND_GROWTH_SAVES - 1) * g.save_every
        raise config.ConfigError(
            f"{view} is not possible with {given} and growth.save_every = {g.save_every} of scenario {study.name}: it fits each band's "
            f"growth to at least {BAND_GROWTH_SAVES} saved passage counts (the start and every growth.save_every passages), and "
            f"this run would save {saves} (at {at} passages); give {option} of at least {need} ({BAND_GROWTH_SAVES - 1} x "
            f"growth.save_every), or a growth.save_every of at most half the passages (a multiple of growth.passages_per_update "
            f"= {g.passages_per_update} that divides them), or leave out {view}. Nothing was computed.")
    inputs.band_inputs(study.config, study.scenario)  # the limit spectrum and the wheel roughness, read before computing


def _leaves(tree, prefix=()):
    """{key path: value} of a nested configuration's leaves (a list is one leaf)."""
    if not isinstance(tree, dict):
        return {prefix: tree}
    out = {}
    for k, v in tree.items():
        out.update(_leaves(v, prefix + (str(k),)))
    return out


def _same_value(key: tuple, a, b) -> bool:
    """Whether a recorded configuration value equals the study's: numbers by value (1 == 1.0), a file
    path the same file whether written relative to the project or resolved (rail.setup.inputs.FILE_KEYS)."""
    if key in inputs.FILE_KEYS and a and b and isinstance(a, str) and isinstance(b, str):
        pa, pb = Path(os.path.normpath(a)), Path(os.path.normpath(b))
        if pa.is_absolute() != pb.is_absolute():
            rel, ab = (pa, pb) if not pa.is_absolute() else (pb, pa)
            return ab.parts[-len(rel.parts):] == rel.parts
        return pa == pb
    return a == b


def _shown(value) -> str:
    text = "not given" if value is _ABSENT else yaml.safe_dump(value, default_flow_style=True, width=10**6).strip()
    text = text.removesuffix("...").strip()
    return text if len(text) <= 60 else text[:57] + "..."


_ABSENT = object()


def grown_for(study: Study, growth: xr.Dataset) -> list[str]:
    """What differs between the scenario and configuration a growth result was computed for (its
    attributes ``scenario`` and ``config``, rail.setup.io.finalize) and a study: the scenario's name
    and every configuration value the run recorded, outside the view settings (figures), the site
    measurements and the half-space quadrature (rail.setup.targets.physics_part: what no growth
    reads), and whether either has a fleet. [] when the result is the study's.

    Parameters
    ----------
    study : Study
    growth : xr.Dataset
        A growth result with the attributes ``scenario`` and ``config``.

    Returns
    -------
    list of str
        One "key: file's value / study's value" per difference, the scenario first.

    Raises
    ------
    rail.setup.config.ConfigError
        If the result carries no scenario or configuration to compare.
    """
    name, text = growth.attrs.get("scenario"), growth.attrs.get("config")
    if name is None or text is None:
        raise config.ConfigError(f"the growth result carries no {'scenario' if name is None else 'configuration'} (attribute "
                                 f"{'scenario' if name is None else 'config'}): it cannot be checked to be a run of {study.name}; "
                                 "give a growth file railgrowth run, rail.app.api.growth or the workflow wrote.")
    try:
        recorded = yaml.safe_load(text)
    except yaml.YAMLError:
        recorded = None
    if not isinstance(recorded, dict):
        raise config.ConfigError(f"the growth result's attribute config is not a configuration: it cannot be checked to be a run "
                                 f"of {study.name}.")
    out = [] if str(name) == study.name else [f"scenario: '{name}' / '{study.name}'"]
    if ("fleet" in recorded) != ("fleet" in study.config):
        out.append(f"fleet: {'given' if 'fleet' in recorded else 'not given'} / {'given' if 'fleet' in study.config else 'not given'}")
    # both sides as the physics reads them (rail.setup.targets.read_part: a key at its schema default or one the
    # chosen models leave unread is left out), so that a value the study sets and the file does not record
    # (the file's run took the default) counts as a difference too
    schema = config.project_schema()
    mine = _leaves(physics_part(read_part(study.config, schema)))
    try:
        theirs = _leaves({k: v for k, v in read_part(recorded, schema).items() if k not in ("figures", "measured")})
    except (KeyError, TypeError, ValueError):  # a configuration written before read_part: compared as recorded
        theirs = _leaves({k: v for k, v in recorded.items() if k not in ("figures", "measured")})
    theirs = {k: v for k, v in theirs.items() if k[:2] != ("numerics", "halfspace")}
    for key in mine:
        if key not in theirs and key[:2] != ("numerics", "halfspace") and key[0] != "fleet":
            theirs[key] = _ABSENT
    for key, value in theirs.items():
        other = mine.get(key, _ABSENT)
        if other is _ABSENT or not _same_value(key, value, other):
            if key[0] == "fleet" and ("fleet" in recorded) != ("fleet" in study.config):
                continue  # named once above
            out.append(f"{'.'.join(key)}: {_shown(value)} / {_shown(other)}")
    return out


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
        If growth is not a growth dataset; if it was computed for another scenario or configuration
        than the study's (grown_for: the band view would relabel its wavelengths, frequencies and
        traffic with the study's), naming what differs; if it holds fewer saved passage counts than
        the band growth laws need (BAND_GROWTH_SAVES).
    """
    if not isinstance(growth, xr.Dataset) or not {"Z_real", "Z_imag", "passage"} <= set(growth.variables):
        raise config.ConfigError("growth is not a growth result: give the dataset api.growth returns (or a growth file, opened).")
    differ = grown_for(study, growth)
    if differ:
        more = f"; and {len(differ) - 5} more" if len(differ) > 5 else ""
        raise config.ConfigError(
            f"the growth result was computed for another scenario or configuration than {study.name}: its band view would "
            f"carry {study.name}'s sleeper spacing, speed labels and traffic. What differs (the result's / {study.name}'s): "
            f"{'; '.join(differ[:5])}{more}. Give the scenario it was grown from (its attribute scenario: "
            f"'{growth.attrs.get('scenario')}'), or grow {study.name} again.")
    saves = int(growth.sizes["passage"])
    if saves < BAND_GROWTH_SAVES:
        stopped = f" (it stopped early: {growth.attrs['stopped']})" if growth.attrs.get("stopped") else ""
        raise config.ConfigError(f"the growth result holds {saves} saved passage count(s){stopped}: the band view fits each "
                                 f"band's growth to at least {BAND_GROWTH_SAVES} (rail.growth.band_growth).")
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
    s = {**s, "speeds": list(speeds)}  # a band of figures.rate_spectrum is resolved at the speeds asked for
    settings_lines(scn.L, scn.roughness.bays, scn.harmonics, s)
    source = inputs.wheel_source_spectra(cfg)  # the wheels' roughness as a source (None: none)
    if source is None:
        spectra = {v: rate_spectrum.spectrum_with_settings(scn, chain.receptance_table(scn, v), s) for v in speeds}
        ds = rate_spectrum.spectrum_dataset_of(spectra, scn)
    else:  # per speed, as the workflow's rate_spectrum_speed and rate_spectrum_map
        parts = []
        for v in speeds:
            tabs = chain.receptance_table(scn, v)
            one = rate_spectrum.spectrum_dataset_of({v: rate_spectrum.spectrum_with_settings(scn, tabs, s)}, scn)
            parts.append(wheel_source.with_wheel_source(one, scn, tabs, s, source))
        ds = xr.concat(parts, dim="speed", data_vars="minimal", coords="minimal", compat="override", combine_attrs="override").sortby("speed")
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
        wavelength; class_growth_rate and class_contribution over (class, wavelength); with the wheels' source
        (wheel_source, fleet.vehicles[*].wheel_source) its settled spectrum (rail.studies.wheel_source.fleet_source_dataset).

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
    lines = settings_lines(scn.L, scn.roughness.bays, scn.harmonics, s)
    fl = build.fleet(cfg)
    classes = fl.classes(scn, float(cfg["wheels"]["static_load"]))
    for c in classes:
        inputs.check_speed(cfg, c.speed, f"{study.name}: fleet spectrum")
    source = inputs.wheel_source_spectra(cfg)  # the wheels' roughness as a source (None: none), read before computing
    tables = chain.fleet_tables(classes)
    fs = fleet_rate_spectrum(classes, tables, lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]))
    ds = fleet_study.fleet_spectrum_dataset(fs, fl, classes)
    # as the workflow's fleet_class_spectrum and fleet_rate_spectrum (each class's arrays, then the fleet's source)
    ds = wheel_source.with_fleet_source(ds, fs, fl, classes, tables, s, source, scn.roughness.bays * scn.L)
    return io.finalize(ds, cfg, title="Growth-rate spectrum under the fleet", source="rail.app.api.fleet_spectrum",
                       scenario=study.name)


def noise(study: Study, growth: xr.Dataset, *, vehicles_per_hour: float | None = None, axles: int | None = None,
          brake: str | None = None, sleeper: str | None = None, pad: str | None = None, rule: str | None = None,
          fill: str | None = "config") -> noise_study.NoiseOutputs:
    """Rolling noise by CNOSSOS-EU (rail.noise, docs/noise.md) at every save of a growth run of the
    study (one train, or its fleet: one traffic class per vehicle type and speed, the line's levels their
    energy sum), its change since the start and grinding by noise (rail.studies.noise.noise_outputs,
    the one code path of the workflow's growth_noise and `railgrowth noise`): the rail roughness on
    CNOSSOS-EU's 35 wavelength bands (lines of the periodic profile summed per band, as the
    rolling-noise export), the total effective roughness, the sound power per vehicle and per metre of
    line of the traffic, per one-third-octave band 50 Hz .. 10 kHz and A-weighted; the cycle average,
    the band rms over Grassie, Saxon & Smith's ranges, and when each criterion of figures.noise trips.

    The wheel is the study's (diameter 2 x wheels.radius, load wheels.static_load: they choose Table
    G-2's column and G-3b's diameter by rail.noise's stated rules); the pad class is the study's
    track.pad.stiffness by rail.noise.cnossos.pad_class unless figures.noise.pad_class (or ``pad``)
    names one. Every other choice is figures.noise's unless an argument is given.

    Parameters
    ----------
    study : Study
        The study the run was grown from.
    growth : xr.Dataset
        The result of growth at one speed or under the study's fleet (or a growth file, opened): Z_real,
        Z_imag per passage.
    vehicles_per_hour : float, optional
        Q [1/h] of the vehicle class (default figures.noise.vehicles_per_hour, else traffic.axles_per_day
        / (24 h x axles)); of a fleet, its trains per hour in all (default: its trains per day / 24 h),
        shared among the classes by their weights.
    axles : int, optional
        Axles per vehicle N_a [-] (figures.noise.axles_per_vehicle); refused for a fleet, as that key is
        (its vehicles' positions: rail.setup.config's cross-checks).
    brake : str, optional
        "cast_iron", "composite" or "disc" (Table G-1a; figures.noise.wheel; of a fleet, for the
        vehicles without their own fleet.vehicles[*].brake).
    sleeper : str, optional
        "monoblock", "biblock", "wooden" or "direct" (figures.noise.sleeper).
    pad : str, optional
        "soft", "medium" or "hard" (figures.noise.pad_class; default: from track.pad.stiffness).
    rule : str, optional
        Wavelength-to-frequency rule, "energy" or "level" (figures.noise.rule).
    fill : str or None, optional
        Table G-1b class ("M" or "E") for the bands the run does not resolve, or None to leave them
        empty (then a speed that reads them is refused); default "config": figures.noise.fill. A kind:
        spectrum start fills them from its input spectrum instead. A band the run resolves but where
        the rail is smooth is silence (-inf), not filled.

    Returns
    -------
    rail.studies.noise.NoiseOutputs
        data: rail_roughness (passage, wavelength) with rail_roughness_source; total_effective_roughness,
        sound_power_track, sound_power_vehicle, sound_power, line_sound_power over (passage, frequency);
        the A-weighted totals, line_sound_power_A_change since the first save, the cycle average,
        band_rms over (passage, rms_range); the criteria as grinding_noise_* attributes; units, long
        names and provenance. csv: the noise export. trips: the criteria.

    Raises
    ------
    rail.setup.config.ConfigError
        If growth is not a growth result, axles for a fleet, or one computed for another scenario or
        configuration (grown_for, naming what differs), or an argument is outside figures.noise's
        schema (naming it); ValueError from rail.noise for a speed outside 7.94 .. 100 m/s, a pad
        stiffness without a class, no traffic (naming it).
    """
    if not isinstance(growth, xr.Dataset) or not {"Z_real", "Z_imag", "passage"} <= set(growth.variables):
        raise config.ConfigError("growth is not a growth result: give the dataset api.growth returns "
                                 "(or a growth file, opened).")
    if "speed_m_per_s" not in growth.attrs:
        raise config.ConfigError("growth is not a growth result (no attribute speed_m_per_s): give the dataset api.growth "
                                 "returns (or a growth file, opened).")
    differ = grown_for(study, growth)
    if differ:
        more = f"; and {len(differ) - 5} more" if len(differ) > 5 else ""
        raise config.ConfigError(
            f"the growth result was computed for another scenario or configuration than {study.name}: its noise would carry "
            f"{study.name}'s wheel, pad and traffic. What differs (the result's / {study.name}'s): {'; '.join(differ[:5])}{more}. "
            f"Give the scenario it was grown from (its attribute scenario: '{growth.attrs.get('scenario')}'), or grow "
            f"{study.name} again.")
    given = {"vehicles_per_hour": vehicles_per_hour, "axles_per_vehicle": axles, "wheel": brake, "sleeper": sleeper,
             "pad_class": pad, "rule": rule}
    given = {k: v for k, v in given.items() if v is not None}
    if fill != "config":
        given["fill"] = fill
    cfg = study.config
    if given:
        cfg = config.deep_merge(study.config, {"figures": {"noise": {**(study.config["figures"].get("noise") or {}), **given}}})
        try:
            config.validate_config(cfg, config.project_schema(), source=f"noise(...) of {study.name}")
        except config.ConfigError as e:  # the schema names the key figures.noise.<key>
            raise config.ConfigError(str(e).replace("figures.noise.", "argument ")) from None
    fl = build.fleet(cfg)
    if ("fleet_speeds" in growth.attrs) != (fl is not None):
        raise config.ConfigError(f"the growth result is a fleet's run and {study.name} has no fleet: give the fleet's scenario"
                                 if fl is None else f"the growth result is a one-train run and {study.name} has a fleet: give "
                                 f"its fleet's growth (results/fleet/{study.name}/growth.nc, railgrowth run without --speed)")
    b = inputs.band_inputs(cfg, study.scenario)
    out = noise_study.noise_outputs(growth, cfg, study.scenario, study.name, build.noise_settings(cfg),
                                    initial_spectrum=b["initial_spectrum"], traffic=b["traffic"], fleet=fl)
    data = io.finalize(out.data, cfg, title=f"CNOSSOS-EU rolling noise, scenario {study.name}", source="rail.app.api.noise",
                       scenario=study.name)
    return dataclasses.replace(out, data=data)
