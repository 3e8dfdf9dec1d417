"""Result datasets that explain themselves: units, long names, configuration and versions.

Attributes do not survive xarray arithmetic, so they are attached here, at the boundary,
just before a dataset is written.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import platform
import re
import subprocess
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from .. import __version__

__all__ = ["FIGURE_MODEL_ATTRS", "integer_like", "data_var", "package_versions", "cf_units", "code_version", "finalize", "write_netcdf",
           "open_intermediate", "UnreadableIntermediateError"]

def data_var(dims, data, units: str, long_name: str, **extra) -> tuple:
    """One variable or coordinate of a result dataset, with its units and long name attached.

    The form xarray takes for ``xr.Dataset(data_vars=..., coords=...)``; every result dataset of
    rail.studies builds its variables with it, so that ``finalize`` finds ``units`` on each.

    Parameters
    ----------
    dims : str or tuple of str
        The dimension names.
    data : array_like
        The values [``units``].
    units : str
        The unit (``"m/N"``, ``"dB"``, ``"1"``; ``cf_units`` maps it for netCDF readers).
    long_name : str
        What the variable is, in words.
    **extra
        Further attributes (for example ``position_scheme``).

    Returns
    -------
    tuple
        ``(dims, ndarray, attrs)`` with ``attrs = {"units": units, "long_name": long_name, **extra}``.
    """
    return (dims, np.asarray(data), {"units": units, "long_name": long_name, **extra})


# what every figure's data states as values (rail.studies.validity.model_attributes; finalize insists)
FIGURE_MODEL_ATTRS = ("wear_path", "normal_contact")
# a float attribute within this fraction of an integer is written as that integer (a fleet's mean wheels
# per passage summed from its weights, 3.9999999999999996, is 4): a few units of the last place of a double
INTEGER_LIKE_TOLERANCE = 1e-12


def integer_like(value):
    """``value`` as an int where it is a float within INTEGER_LIKE_TOLERANCE (relative) of an integer,
    else unchanged (a bool, an int, a string, NaN and inf included).

    Parameters
    ----------
    value : any
        An attribute's value.

    Returns
    -------
    int or the value
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (float, np.floating)):
        return value
    x = float(value)
    if not np.isfinite(x) or abs(x) >= 2.0 ** 53:
        return value
    n = round(x)
    return int(n) if abs(x - n) <= INTEGER_LIKE_TOLERANCE * max(1.0, abs(x)) else value


_PACKAGES = ("numpy", "scipy", "numba", "xarray", "netCDF4", "pandas", "matplotlib", "snakemake")


def package_versions() -> dict[str, str]:
    """Versions of railgrowth, Python and the scientific packages it runs on.

    Returns
    -------
    dict
        {package: version}.
    """
    out = {"railgrowth": __version__, "python": platform.python_version()}
    for name in _PACKAGES:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


_LEVEL = re.compile(r"^dB(?P<weighting>\(A\))?(?: re (?P<ref>.+))?$")
_PER_PASSAGES = re.compile(r"^(?P<unit>\S+) per (?P<n>[0-9]+) (?:(?P<kind>axle|train) )?passages$")


def cf_units(units: str) -> tuple[str, dict]:
    """A unit string that udunits parses (CF conventions), and the attributes that say the rest.

    * levels in decibels ("dB", "dB re 1 um", "dB(A) re 1 pW"): units "1" (a level is a number), with
      level_unit "dB", level_reference the reference ("1 um", meaning 1 µm rms) and, for dB(A),
      frequency_weighting "A";
    * "dB/m" (a decay rate): "1/m" with level_unit "dB";
    * rates per N passages ("um per 100000 passages", "dB per 100000 axle passages", "dB per 100000
      train passages"): the unit scaled to one passage ("1e-05 um": the value times 1e-05 um is the
      amount per wheel passage), with per "passage" (or "axle passage", "train passage");
    * anything else unchanged. The original string is kept in units_text whenever it changes.

    Parameters
    ----------
    units : str
        A unit as the results state it.

    Returns
    -------
    tuple of (str, dict)
        The CF unit and the extra attributes (empty where the unit is unchanged).
    """
    m = _LEVEL.match(units)
    if m:
        extra = {"level_unit": "dB", "units_text": units}
        if m.group("weighting"):  # an A-weighted level (IEC 61672-1), dB(A)
            extra["frequency_weighting"] = "A"
        if m.group("ref"):
            extra["level_reference"] = m.group("ref") + " rms" if "um" in m.group("ref") else m.group("ref")
        return "1", extra
    if units == "dB/m":
        return "1/m", {"level_unit": "dB", "units_text": units}
    m = _PER_PASSAGES.match(units)
    if m:
        scale = f"{1 / int(m.group('n')):g}"
        level = m.group("unit") == "dB"  # a level change: a number, in dB
        unit = scale if m.group("unit") in ("1", "dB") else f"{scale} {m.group('unit')}"
        return unit, {"per": f"{m.group('kind')} passage" if m.group("kind") else "passage", "units_text": units,
                      **({"level_unit": "dB"} if level else {})}
    return units, {}


def code_version() -> str:
    """The commit of the code (git), "<commit> with uncommitted changes", or "unknown" outside git.

    Returns
    -------
    str
    """
    root = Path(__file__).resolve().parents[2]
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, timeout=10)
        if commit.returncode != 0:
            return "unknown (not a git checkout)"
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", "rail", "workflow", "Snakefile"],
                               cwd=root, capture_output=True, text=True, timeout=10)
        return commit.stdout.strip() + (" with uncommitted changes" if dirty.stdout.strip() else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown (git not available)"


def finalize(ds: xr.Dataset, config: dict, *, title: str, source: str, scenario: str | None = None) -> xr.Dataset:
    """Attach the resolved configuration, versions and provenance; insist on units and long names.

    Raises ValueError naming every variable or coordinate that lacks ``units`` or ``long_name``,
    so an unlabelled number can never reach a result file.

    Parameters
    ----------
    ds : xr.Dataset
        The result, each variable and coordinate with units and long_name.
    config : dict
        The configuration it was computed from (stored as YAML text).
    title, source : str
        What the dataset is and what computed it (the function).
    scenario : str, optional
        The scenario's name.

    Returns
    -------
    xr.Dataset
        ``ds`` with its attributes set: the configuration, the versions (package_versions), the code
        (code_version), the time and the CF conventions; units mapped for udunits (cf_units).
    """
    missing = [
        f"{name} ({attr})"
        for name, var in list(ds.data_vars.items()) + list(ds.coords.items())
        for attr in ("units", "long_name")
        if attr not in var.attrs
    ]
    if missing:
        raise ValueError(f"dataset '{title}' lacks attributes: {', '.join(missing)}")
    unstated = [k for k in FIGURE_MODEL_ATTRS if title.startswith("Figure ") and k not in ds.attrs]
    if unstated:  # every figure's data states its model choices as values (README; rail.studies.validity.model_attributes)
        raise ValueError(f"dataset '{title}' does not state its {' and '.join(unstated)} (rail.studies.validity.model_attributes; "
                         "'none' where the figure uses none)")
    ds = ds.copy()
    for dim in ds.dims:  # a coordinate on every dimension (CF): an index where the data has none
        if dim not in ds.coords:
            ds = ds.assign_coords({dim: (dim, np.arange(ds.sizes[dim]), {"units": "1", "long_name": f"index along {dim}"})})
    for name in list(ds.data_vars) + list(ds.coords):
        units, extra = cf_units(str(ds[name].attrs["units"]))
        ds[name].attrs.update(units=units, **extra)
    for name in ds.coords:  # the position along the rail is the X axis (CF axis attribute)
        if name in ("position", "x") and ds[name].attrs["units"] == "m":
            ds[name].attrs["axis"] = "X"
    ds.attrs.update({k: integer_like(v) for k, v in ds.attrs.items()})  # 4, not 3.9999999999999996
    ds.attrs.update(
        title=title,
        source=source,
        scenario=scenario if scenario is not None else str(config.get("name", "not stated")),
        code_version=code_version(),
        date_created=datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        references="Sheng, Thompson & Jones, Modelling rail roughness growth on tangent tracks, ISVR",
        config=yaml.safe_dump(config, sort_keys=True),
        package_versions=yaml.safe_dump(package_versions(), sort_keys=True),
        Conventions="CF-1.10",
    )
    return ds


def write_netcdf(ds: xr.Dataset, path) -> None:
    """Write a dataset to netCDF4 (complex values must already be split into real parts).

    The dataset is written to a temporary file in the target's folder and renamed over the target
    (os.replace, atomic): a write that fails leaves an existing file at ``path`` whole and no partial
    file behind. A failed write (the netCDF library says only "HDF error" when the disk is full) names
    the file, the free space left and the size of the data.

    Parameters
    ----------
    ds : xr.Dataset
        The result (finalize), complex values split.
    path : str or Path
        The target file.

    Returns
    -------
    None

    Raises
    ------
    OSError
        A write that failed, naming the file, the free space and the data's size.
    """
    import os
    import shutil
    import uuid
    from pathlib import Path

    path = Path(path)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:12]}.tmp")
    try:
        ds.to_netcdf(tmp, engine="netcdf4")
        os.replace(tmp, path)
    except BaseException as e:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        if not isinstance(e, (OSError, RuntimeError)):
            raise
        folder = path.parent if path.parent.exists() else Path(".")
        free = shutil.disk_usage(folder).free
        need = sum(v.nbytes for v in ds.variables.values())
        raise OSError(f"could not write {os.fspath(path)}: {e}. Free space there: {free / 2**20:.1f} MiB, data "
                      f"{need / 2**20:.1f} MiB (a full disk or a read-only folder gives this error).") from e


class UnreadableIntermediateError(OSError):
    """An intermediate result file exists but cannot be read (truncated or corrupt); it was moved aside."""


def open_intermediate(path) -> xr.Dataset:
    """An intermediate result (a netCDF file the workflow wrote, e.g. results/receptance/<track>/V40.nc),
    read whole into memory (the file is closed again).

    A file that exists but cannot be read (truncated by a killed job or a full disk: the netCDF
    library says only "NetCDF: HDF error") is renamed to <name>.unreadable, so that the next
    snakemake run, finding the file missing, rebuilds it instead of failing on it again.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    xr.Dataset
        Loaded into memory.

    Raises
    ------
    UnreadableIntermediateError
        One line naming the file, the library's reason and where it was moved.
    FileNotFoundError, PermissionError
        Unchanged: the file is missing or may not be read (it is not moved).
    """
    import os

    path = Path(path)
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except (FileNotFoundError, PermissionError):
        raise
    except (OSError, RuntimeError) as e:
        if not path.is_file():
            raise
        reason = str(getattr(e, "strerror", None) or e).split(": '")[0]
        aside = path.with_name(path.name + ".unreadable")
        try:
            os.replace(path, aside)
        except OSError as move:
            raise UnreadableIntermediateError(
                f"{os.fspath(path)} is unreadable ({reason}) and could not be moved aside to {os.fspath(aside)} "
                f"({move.strerror or move}): delete it and run snakemake again to rebuild it.") from e
        raise UnreadableIntermediateError(
            f"{os.fspath(path)} is unreadable ({reason}) and has been moved aside to {os.fspath(aside)}: "
            "run snakemake again to rebuild it.") from e
