"""The growth-rate spectra of one scenario over its speeds: one dataset and the speed x wavelength map
(with one speed the line alone, rail.plotting.studies.rate_spectrum_figure)."""

import sys

import xarray as xr

from rail.plotting import rate_map
from rail.plotting import studies as plots
from rail.setup import io
from rail.studies import exports, rate_spectrum


def main(paths, data_path, figure_path, summary_path, csv_path, map_path=None):
    parts = [io.open_intermediate(p) for p in paths]
    ds = xr.concat(parts, dim="speed", data_vars="minimal", coords="minimal", compat="override", combine_attrs="override")
    ds = ds.sortby("speed")
    io.write_netcdf(ds, data_path)
    plots.rate_spectrum_figure(ds).savefig(figure_path, dpi=150)
    if map_path is not None:  # growth over frequency and speed: does a band keep its frequency?
        fig = rate_map.rate_map_figure(ds) if ds.sizes["wavelength"] >= 2 else rate_map.placeholder_figure("one line: no map")
        fig.savefig(map_path, dpi=150)
    with open(summary_path, "w") as fh:
        fh.write(rate_spectrum.summary_markdown(ds))
    with open(csv_path, "w") as fh:
        fh.write(exports.spectrum_csv_text(ds))


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(list(snakemake.input), snakemake.output.data, snakemake.output.figure, snakemake.output.summary, snakemake.output.csv,  # noqa: F821
         snakemake.output.frequency_map)  # noqa: F821
