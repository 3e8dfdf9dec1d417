"""The traffic study's fleet spectra side by side: dataset, figure and summary (rail.studies.fleet)."""

import sys

from rail.plotting import studies as plots
from rail.setup import io
from rail.studies import fleet as fleet_study


def main(paths, cases, data_path, figure_path, summary_path):
    spectra = [io.open_intermediate(p).load() for p in paths]
    ds = fleet_study.traffic_study_dataset(spectra, [(d, s) for d, s in cases])
    io.write_netcdf(ds, data_path)
    plots.traffic_study_figure(ds).savefig(figure_path, dpi=150)
    with open(summary_path, "w") as fh:
        fh.write(fleet_study.traffic_summary_markdown(ds))


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(list(snakemake.input), snakemake.params.cases, snakemake.output.data, snakemake.output.figure,  # noqa: F821
         snakemake.output.summary)  # noqa: F821
