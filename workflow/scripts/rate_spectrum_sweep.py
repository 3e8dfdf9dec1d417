"""The growth-rate spectra of a sweep study's points on its grid: one dataset and a map figure."""

import sys

from rail.plotting import studies as plots
from rail.setup import io
from rail.studies import rate_spectrum


def main(config, study, keys, values, indices, units, paths, data_path, figure_path):
    points = [io.open_intermediate(p) for p in paths]
    ds = rate_spectrum.sweep_rate_spectrum(points, keys, values, indices, units)
    ds = io.finalize(ds, config, title=f"Growth-rate spectrum over the sweep {study}",
                     source="rail.studies.rate_spectrum.sweep_rate_spectrum", scenario=f"sweep study {study}")
    io.write_netcdf(ds, data_path)
    plots.rate_spectrum_sweep_figure(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    p = snakemake.params  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.study, p.swept, p.grid, p.indices, p.units, list(snakemake.input),  # noqa: F821
         snakemake.output.data, snakemake.output.figure)  # noqa: F821
