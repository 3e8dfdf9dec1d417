"""The command line: ``railgrowth check <file>`` and ``railgrowth run <scenario>`` (argparse).

    railgrowth check config/scenarios/my_pad.yaml     validate a scenario file, as the workflow does
    railgrowth run soft_pad --speed 40                grow roughness; writes soft_pad_V40.nc here
    railgrowth run my_fleet --bands                   grow under the fleet (no --speed), with the band view
    railgrowth bands soft_pad soft_pad_V40.nc         the band view of a growth file written before
    railgrowth noise soft_pad soft_pad_V40.nc         its rolling noise (CNOSSOS-EU) and grinding by noise
    railgrowth noise my_fleet my_fleet_fleet.nc       a fleet's: one traffic class per vehicle and speed
    railgrowth spectrum default --speed 40            the growth-rate spectrum; default_spectrum.nc

A problem with the input is one line per problem naming file, key, value and valid range, and exit
status 2; nothing is computed before the input is valid (a missing or read-only folder of --out or
--checkpoint included; with --bands, passages too few for a band view: rail.app.api.check_bands). A
growth run that stops early because the model's assumptions broke (contact lost, multiple contact, at
any passage count, 0 included) writes what it computed and exits with 3, with --bands or without. The
growth file is written before any view of it (--bands), so no view loses it; the file is written whole
or not at all: an existing file at --out survives a failed write (rail.setup.io.write_netcdf), and a
failed checkpoint leaves no temporary file. ``bands`` and ``noise`` refuse a growth file grown for another
scenario or configuration, naming what differs (rail.app.api.grown_for). ``run`` (one train or a fleet) ends with one
line stating the noise change over the run (rail.studies.noise.change_line) where the noise can be
computed (rail.setup.inputs.noise_problem), else the reason.

Exit status by cause (docs/usage.md), every failure one line on stderr, never a traceback::

    0  done
    1  the model broke in a computation that keeps nothing (a spectrum, a growth step too large)
    2  invalid input (file, key, value or argument), before anything is computed
    3  a growth run stopped early (contact lost, multiple contact): the states it kept are written
    4  a resource failed during the run: a result or checkpoint could not be written (disk full, file
       too large, permissions), or the memory ran out
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from pathlib import Path

import yaml

from ..setup.config import ConfigError
from ..setup.io import write_netcdf

__all__ = ["main", "EXIT_MODEL", "EXIT_INPUT", "EXIT_PARTIAL", "EXIT_RESOURCE"]

EXIT_MODEL, EXIT_INPUT, EXIT_PARTIAL, EXIT_RESOURCE = 1, 2, 3, 4  # exit status by cause (module docstring)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="railgrowth", description="Rail roughness growth on tangent track (Sheng, Thompson & Jones).")
    p.add_argument("--root", type=Path, default=None, help="project folder holding config/ (default: this checkout)")
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("check", help="validate a scenario file (merged onto config/config.yaml)")
    c.add_argument("file", help="scenario YAML file, or a scenario name")
    r = sub.add_parser("run", help="grow roughness for a scenario at one speed (or under its fleet) and write a netCDF file")
    r.add_argument("scenario", help="'default', a name in config/scenarios/, or a YAML file")
    r.add_argument("--speed", type=float, default=None, help="train speed, m/s (leave out for a scenario with a fleet)")
    r.add_argument("--bands", action="store_true", help="also write the band view: <out>_bands.nc, _bands.csv, _narrowband.csv, "
                                                         "_rolling_noise_roughness.csv")
    r.add_argument("--passages", type=int, default=None, help="wheel passages (default: the scenario's growth.passages)")
    r.add_argument("--out", type=Path, default=None, help="output file (default: <scenario>_V<speed>.nc)")
    r.add_argument("--checkpoint", type=Path, default=None, help="resumable checkpoint file")
    b = sub.add_parser("bands", help="one-third-octave band view of a growth file of a scenario (bands, growth per band, grinding "
                                     "interval, exports)")
    b.add_argument("scenario", help="the scenario the growth file was grown from")
    b.add_argument("growth", type=Path, help="a growth file (railgrowth run, or the workflow's)")
    b.add_argument("--out", type=Path, default=None, help="band dataset (default: <growth>_bands.nc; the CSVs beside it)")
    z = sub.add_parser("noise", help="rolling noise (CNOSSOS-EU) at every save of a growth file of a scenario (one train, or its "
                                     "fleet: a traffic class per vehicle and speed), its change and grinding by noise (figures.noise)")
    z.add_argument("scenario", help="the scenario the growth file was grown from")
    z.add_argument("growth", type=Path, help="a growth file (railgrowth run, or the workflow's)")
    z.add_argument("--out", type=Path, default=None, help="noise dataset (default: <growth>_noise.nc; the CSV and figure beside it)")
    s = sub.add_parser("spectrum", help="growth-rate spectrum of a scenario about the smooth rail")
    s.add_argument("scenario", help="'default', a name in config/scenarios/, or a YAML file")
    s.add_argument("--speed", type=float, nargs="+", required=True, help="train speed(s), m/s")
    s.add_argument("--out", type=Path, default=None, help="output file (default: <scenario>_spectrum.nc)")
    return p


def _writable_target(option: str, path: Path | None) -> None:
    """ConfigError naming the option and the folder unless the file ``path`` can be written there
    (checked before computing, so that a long run does not end in a missing folder)."""
    if path is None:
        return
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ConfigError(f"{option} {path}: the folder {folder} does not exist (create it first).")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ConfigError(f"{option} {path}: the folder {folder} is not writable.")
    if path.is_dir():
        raise ConfigError(f"{option} {path}: is a folder; give a file name.")


def _what_runs(study) -> str:
    """The line `check` prints: what the scenario will run (a fleet's vehicles and speed classes, not the
    one-train speeds and wheels it leaves unused)."""
    from ..studies.validity import creepage_model_text

    scn = study.scenario
    rest = (f"roughness period {scn.roughness.bays} bay(s), normal contact {scn.contact_numerics.normal}, "
            f"wear path {scn.contact_numerics.path}")
    # the wheelset's modes, the rail head, the friction law, as results say; a fleet's wheelsets are stated per vehicle below
    creep = creepage_model_text(scn.material if "fleet" not in study.config else dataclasses.replace(scn.material, longitudinal=None))
    if creep:
        rest += f"; {creep}"
    from ..setup.build import wheel_source_settings, wheel_source_vehicles

    if wheel_source_settings(study.config) is not None:  # the wheels' roughness as a source (issue 58): its spectrum's results
        vehicles = wheel_source_vehicles(study.config)
        source = (study.config["wheel_source"]["roughness"] if vehicles is None else
                  ", ".join(f"{v} {r}" for v, (r, _) in vehicles.items()))
        folder = "spectrum" if vehicles is None else "fleet"
        rest += f"; the wheels' roughness a source: {source} (settled spectrum: results/{folder}/{study.name}/settled.png)"
    if "fleet" not in study.config:
        return (f"ok: scenario '{study.name}' is valid ({len(scn.speeds)} speed(s), {len(scn.wheels.positions)} wheel(s), "
                f"{rest}).")
    from ..setup.build import fleet_classes

    from ..creepage.choices import wheelset_model
    from ..setup.build import fleet
    from ..setup.config import setting
    from ..studies.fleet import wheelset_lines

    classes = fleet_classes(study.config, scn)
    vehicles = study.config["fleet"]["vehicles"]
    speeds = sorted({c.speed for c in classes})
    kinds = ", ".join(f"{v['name']} ({len(v['positions'])} axles, share {v['share']:g})" for v in vehicles)
    cfg = study.config
    # which wheelset each vehicle's axles run (issue 55): named per axle, or the wheelset section's on every axle
    motored = wheelset_model(setting(cfg, "wheelset.model")).modelled and setting(cfg, "wheelset.motor_inertia") > 0
    lines = [f"  wheelsets of {line}" for line in wheelset_lines(classes, fleet(cfg), motored)]
    named = cfg["fleet"].get("wheelsets") or {}
    used = {w for v in vehicles for w in ([v["wheelsets"]] if isinstance(v.get("wheelsets"), str) else v.get("wheelsets") or [])
            if isinstance(w, str)}
    lines += [f"  note: fleet.wheelsets.{n} is defined but no vehicle names it." for n in named if n not in used]
    if cfg.get("wheelset") is not None and all(v.get("wheelsets") is not None for v in vehicles):
        lines.append("  note: every vehicle names its wheelsets: of the wheelset section only wheelset.other_wheel is used.")
    return "\n".join([f"ok: scenario '{study.name}' is valid: a fleet of {len(vehicles)} vehicle type(s), {kinds}, at {len(speeds)} "
                      f"speed(s) ({', '.join(f'{v:.4g}' for v in speeds)} m/s): {len(classes)} (vehicle, speed) classes, {rest}; the "
                      "one-train keys speeds, wheels and contact.creepage are not used.", *lines])


def _os_line(e: OSError) -> str:
    """One line for a failed read or write: the file, then what the system said (or the message)."""
    what = " ".join(str(e.strerror or e).split())
    return f"{e.filename}: {what}" if e.filename else what


def main(argv=None) -> int:
    """Run the command line; returns the exit status by cause (0 ok, 1 the model broke in a computation
    that keeps nothing, 2 invalid input, 3 a growth run stopped early with a partial result, 4 a
    resource failed: a write, the memory). Every failure is one line on stderr, never a traceback.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: sys.argv[1:]).

    Returns
    -------
    int
        The exit status.
    """
    args = _parser().parse_args(argv)
    from ..contact import ContactError  # after parsing: --help answers without importing the model
    from ..growth import GrowthStepError
    from ..interaction import ContactLossError
    from . import api

    loaded = False  # an OSError before this is the input's (a file missing); after, a resource's
    try:
        if args.command in ("run", "spectrum", "bands", "noise"):
            _writable_target("--out", args.out)
        if args.command == "run":
            _writable_target("--checkpoint", args.checkpoint)
        study = api.load(args.file if args.command == "check" else args.scenario, root=args.root)
        loaded = True
        if args.command == "check":
            print(_what_runs(study))
            return 0
        if args.command == "bands":
            return _bands(api, study, args)
        if args.command == "noise":
            return _noise(api, study, args)
        if args.command == "run":
            if "fleet" not in study.config and args.speed is None:
                raise ConfigError(f"--speed is needed for {study.name}: a train speed in m/s (only a scenario with a fleet runs "
                                  "without it).")
            if args.speed is not None and not (args.speed > 0 and args.speed < float("inf")):
                raise ConfigError(f"--speed = {args.speed} m/s is not allowed: it must be a finite number > 0.")
            if args.bands:  # a band view the settings cannot give is refused now, not after the growth is computed
                api.check_bands(study, passages=args.passages, option="--passages", view="--bands")
            ds = api.growth(study, speed=args.speed, passages=args.passages, checkpoint=args.checkpoint)
            out = args.out or Path(f"{study.name}_fleet.nc" if args.speed is None else f"{study.name}_V{args.speed:g}.nc")
        else:
            ds = api.spectrum(study, speeds=args.speed)
            out = args.out or Path(f"{study.name}_spectrum.nc")
    except (ContactError, ContactLossError, GrowthStepError, FloatingPointError) as e:  # the model broke mid-way
        print(f"railgrowth: the computation stopped: {' '.join(str(e).split())}", file=sys.stderr)
        return EXIT_MODEL
    except (ConfigError, ValueError) as e:
        print(f"railgrowth: {e}", file=sys.stderr)
        return EXIT_INPUT
    except yaml.YAMLError as e:  # a file that is not YAML: one line with the file and the line
        print(f"railgrowth: not a valid YAML file: {' '.join(str(e).split())}", file=sys.stderr)
        return EXIT_INPUT
    except MemoryError:
        print("railgrowth: out of memory: the computation needs more than this machine has free; use fewer wheels, bays "
              "or spectrum lines, or a larger machine.", file=sys.stderr)
        return EXIT_RESOURCE
    except OSError as e:  # before loading: an input file or folder that does not exist or cannot be read;
        # after: a checkpoint that could not be written (rail.growth.CheckpointWriteError)
        print(f"railgrowth: {_os_line(e)}", file=sys.stderr)
        return EXIT_RESOURCE if loaded else EXIT_INPUT
    try:  # the growth first: no view of it can lose it
        write_netcdf(ds, out)
    except OSError as e:  # a full disk, a file-size limit: the old file at --out, if any, is whole
        print(f"railgrowth: --out: {_os_line(e)}", file=sys.stderr)
        return EXIT_RESOURCE
    from ..studies.validity import validity_text

    if validity_text(ds.attrs):
        print(f"validity: {validity_text(ds.attrs)}")
    stopped = bool(ds.attrs.get("stopped"))
    print(f"wrote {out} (partial: {ds.attrs['stopped']})" if stopped else f"wrote {out}")
    done = EXIT_PARTIAL if stopped else 0
    if args.command == "run":
        _noise_line(api, study, ds)
    if args.command == "run" and args.bands:
        return _bands_after_run(api, study, ds, out, done)
    return done


def _bands_after_run(api, study, ds, out: Path, done: int) -> int:
    """run --bands: the band view of the growth just written to ``out`` (the settings were checked
    before computing: api.check_bands). A run stopped early with too few saves for a band view says so
    and keeps its exit status 3; a band view that fails otherwise is one line, the growth file kept."""
    from ..growth import BAND_GROWTH_SAVES

    saves = int(ds.sizes["passage"])
    if done == EXIT_PARTIAL and saves < BAND_GROWTH_SAVES:
        print(f"band view not written: the run stopped with {saves} saved passage count(s), and the band view fits each band's "
              f"growth to at least {BAND_GROWTH_SAVES}; the growth file {out} holds every state kept.")
        return done
    try:
        _write_band_view(api.bands(study, ds), out.with_name(out.stem + "_bands.nc"))
    except OSError as e:
        print(f"railgrowth: --bands: {_os_line(e)} (the growth file {out} is written)", file=sys.stderr)
        return EXIT_RESOURCE
    except (ConfigError, ValueError) as e:
        print(f"railgrowth: --bands: {' '.join(str(e).split())} (the growth file {out} is written)", file=sys.stderr)
        return done or EXIT_INPUT
    return done


def _band_files(data_path: Path) -> dict:
    """The band view's files: the dataset and, beside it, the three CSV exports."""
    stem = data_path.with_suffix("")
    base = stem.name.removesuffix("_bands")
    return {"data": data_path, "bands_csv": stem.with_name(base + "_bands.csv"), "narrow_csv": stem.with_name(base + "_narrowband.csv"),
            "rolling_noise_csv": stem.with_name(base + "_rolling_noise_roughness.csv")}


def _write_band_view(b, data_path: Path) -> None:
    """Write a band view (rail.studies.exports.BandOutputs) and say where and the grinding interval."""
    files = _band_files(data_path)
    write_netcdf(b.data, files["data"])
    for key in ("bands_csv", "narrow_csv", "rolling_noise_csv"):
        files[key].write_text(getattr(b, key))
    print(f"wrote {', '.join(str(f) for f in files.values())}")
    print(f"grinding interval: {b.data.attrs['grinding_interval_text']}")


def _view_of_growth_file(view, study, path: Path):
    """``view(study, growth)`` (api.bands or api.noise) of the growth file at ``path``, read and never moved;
    a file grown for another scenario or configuration is refused naming the file and what differs."""
    import xarray as xr

    if not path.is_file():
        raise ConfigError(f"{path}: no such growth file.")
    with xr.open_dataset(path) as g:
        growth = g.load()
    try:
        return view(study, growth)
    except ConfigError as e:
        raise ConfigError(f"{path}: {str(e).removeprefix('the growth result ')}") from None


def _bands(api, study, args) -> int:
    """railgrowth bands: the band view of a growth file."""
    view = _view_of_growth_file(api.bands, study, args.growth)
    _write_band_view(view, args.out or args.growth.with_name(args.growth.stem + "_bands.nc"))
    return 0


def _noise_line(api, study, ds) -> None:
    """run (one train or a fleet): one line with the noise change over the run, or why there is none
    (cheap: the CNOSSOS-EU chain on the bands of each save)."""
    from ..setup.inputs import noise_problem
    from ..studies.noise import change_line

    why = noise_problem(study.config, float(ds.attrs["speed_m_per_s"]))  # a fleet: its class speeds
    if why is None:
        try:
            print(change_line(api.noise(study, ds).data))
            return
        except (ConfigError, ValueError) as e:
            why = " ".join(str(e).split())
    print(f"noise: not computed: {why}")


def _noise(api, study, args) -> int:
    """railgrowth noise: the noise over traffic of a growth file (dataset, CSV, figure)."""
    from ..plotting.noise import noise_over_traffic
    from ..studies.noise import change_line

    out = _view_of_growth_file(api.noise, study, args.growth)
    data_path = args.out or args.growth.with_name(args.growth.stem + "_noise.nc")
    stem = data_path.with_suffix("")
    files = {"data": data_path, "csv": stem.with_name(stem.name + ".csv"), "figure": stem.with_name(stem.name + ".png")}
    write_netcdf(out.data, files["data"])
    files["csv"].write_text(out.csv)
    noise_over_traffic(out.data, study.name).savefig(files["figure"], dpi=150, bbox_inches="tight")
    print(f"wrote {', '.join(str(f) for f in files.values())}")
    print(change_line(out.data))
    for c in ("rise", "average", "band_rms"):
        print(f"grinding by noise: {out.data.attrs[f'grinding_noise_{c}_text']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
