"""Result datasets that explain themselves: units, long names, configuration and versions.

Attributes do not survive xarray arithmetic, so they are attached here, at the boundary,
just before a dataset is written.
"""

from __future__ import annotations

import importlib.metadata
import platform

import xarray as xr
import yaml

from .. import __version__

__all__ = ["package_versions", "finalize", "write_netcdf"]

_PACKAGES = ("numpy", "scipy", "numba", "xarray", "netCDF4", "pandas", "matplotlib", "snakemake")


def package_versions() -> dict[str, str]:
    """Versions of railgrowth, Python and the scientific packages it runs on."""
    out = {"railgrowth": __version__, "python": platform.python_version()}
    for name in _PACKAGES:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def finalize(ds: xr.Dataset, config: dict, *, title: str, source: str) -> xr.Dataset:
    """Attach the resolved configuration, versions and provenance; insist on units and long names.

    Raises ValueError naming every variable or coordinate that lacks ``units`` or ``long_name``,
    so an unlabelled number can never reach a result file.
    """
    missing = [
        f"{name} ({attr})"
        for name, var in list(ds.data_vars.items()) + list(ds.coords.items())
        for attr in ("units", "long_name")
        if attr not in var.attrs
    ]
    if missing:
        raise ValueError(f"dataset '{title}' lacks attributes: {', '.join(missing)}")
    ds = ds.copy()
    ds.attrs.update(
        title=title,
        source=source,
        references="Sheng, Thompson & Jones, Modelling rail roughness growth on tangent tracks, ISVR",
        config=yaml.safe_dump(config, sort_keys=True),
        package_versions=yaml.safe_dump(package_versions(), sort_keys=True),
        Conventions="CF-1.10",
    )
    return ds


def write_netcdf(ds: xr.Dataset, path) -> None:
    """Write a dataset to netCDF4 (complex values must already be split into real parts).

    A failed write (the netCDF library says only "HDF error" when the disk is full) names the file,
    the free space left and the size of the data, and leaves no partial file behind.
    """
    import os
    import shutil
    from pathlib import Path

    path = Path(path)
    try:
        ds.to_netcdf(path, engine="netcdf4")
    except (OSError, RuntimeError) as e:
        if path.is_file():
            path.unlink()
        folder = path.parent if path.parent.exists() else Path(".")
        free = shutil.disk_usage(folder).free
        need = sum(v.nbytes for v in ds.variables.values())
        raise OSError(f"could not write {os.fspath(path)}: {e}. Free space there: {free / 2**20:.1f} MiB, data "
                      f"{need / 2**20:.1f} MiB (a full disk or a read-only folder gives this error).") from e
