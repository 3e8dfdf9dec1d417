"""The expected rail roughness under the wheels' roughness (wheel_source, rail.studies.wheel_source): the figure,
the band CSV and the summary from a scenario's growth-rate spectrum over its speeds, or from a fleet's spectrum
(rules settled_spectrum and fleet_settled_spectrum)."""

import sys

from rail.plotting.wheel_source import settled_figure
from rail.setup import io
from rail.studies import wheel_source


def main(data_path, figure_path, csv_path, summary_path, scenario):
    with io.open_intermediate(data_path) as ds:
        ds = ds.load()
    if "settled_band_level_dB" not in ds:
        raise SystemExit(f"scenario {scenario}: its spectrum has no wheels' source (wheel_source.roughness is none, and so is "
                         "every fleet vehicle's); set wheel_source.roughness (cast_iron, composite, disc or file; a fleet: or "
                         f"fleet.vehicles[*].wheel_source.roughness) to build {figure_path}.")
    settled_figure(ds).savefig(figure_path, dpi=150)
    with open(csv_path, "w") as fh:
        fh.write(wheel_source.settled_csv_text(ds))
    with open(summary_path, "w") as fh:
        fh.write(wheel_source.settled_summary_markdown(ds))


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.input[0], o.figure, o.csv, o.summary, snakemake.wildcards.scenario)  # noqa: F821
