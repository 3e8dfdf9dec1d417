"""Aggregate the convergence study: dataset, error-against-time figure and summary table."""

import sys

from rail.plotting import studies as plots
from rail.setup import build, io
from rail.studies import conclusions, convergence


def main(config, study, paths, out):
    points = {}
    for p in paths:
        with io.open_intermediate(p) as ds:
            ds = ds.load()
        points[(ds.attrs["setting"], float(ds.attrs["value"]))] = ds
    ds = convergence.convergence_dataset(points, study, convergence.default_settings(build.scenario(config)))
    io.write_netcdf(io.finalize(ds, config, title="Convergence study", source="rail.studies.convergence"), out["data"])
    plots.convergence_figure(ds).savefig(out["figure"], dpi=150)
    conclusions.write_tables(convergence.convergence_rows(ds), out["table"], out["html"],
                             "Convergence study: error of the defaults against a 4-times refined reference")


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, snakemake.params.study, list(snakemake.input), {k: o[k] for k in ("data", "figure", "table", "html")})  # noqa: F821
