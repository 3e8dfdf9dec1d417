"""Band growth over the grid of a sweep study: dataset and map (band wavelength against swept key)."""

import sys

from rail.bands import wavelength_bands
from rail.plotting import report
from rail.setup import build, io
from rail.studies import bands


def main(config, study, keys, values, indices, units, run_paths, data_path, figure_path):
    runs = []
    for path in run_paths:
        with io.open_intermediate(path) as ds:
            runs.append(ds.load())
    s = config["figures"]["bands"]
    tob = wavelength_bands(float(s["longest"]), float(s["shortest"]))
    ds = bands.sweep_band_map(runs, keys, values, indices, units, build.track(config)[0].L, tob, int(s["min_lines"]))
    io.write_netcdf(io.finalize(ds, config, title=f"Band growth over the sweep {study}",
                                source="rail.studies.bands.sweep_band_map", scenario=f"sweep study {study}"), data_path)
    report.sweep_band_map(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.study, snakemake.params.swept, snakemake.params.grid, snakemake.params.indices,  # noqa: F821
         snakemake.params.units, list(snakemake.input), snakemake.output.data, snakemake.output.figure)  # noqa: F821
