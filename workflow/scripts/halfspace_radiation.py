"""Im w0(0), radiated power and contact loss factor over the frequencies of Figs 5-6."""

import sys

from rail.setup import build, io
from rail.studies import datasets


def main(config, out_path):
    ds = datasets.radiation(build.elastic(config), build.halfspace_figures(config), build.halfspace_numerics(config))
    io.write_netcdf(io.finalize(ds, config, title="Half-space radiation", source="rail.studies.datasets.radiation"), out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.output[0])  # noqa: F821
