"""Im w0(0), radiated power and contact loss factor over the frequencies of Figs 5-6."""

import sys

from rail import datasets, io, params


def main(config, out_path):
    ds = datasets.radiation(params.material(config), params.halfspace_figures(config), params.halfspace_numerics(config))
    io.write_netcdf(io.finalize(ds, config, title="Half-space radiation", source="rail.datasets.radiation"), out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.config, snakemake.output[0])  # noqa: F821
