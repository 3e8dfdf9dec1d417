"""Outcome table of the stability suite: netCDF, markdown and HTML (for the report)."""

import json
import sys

from rail import moving
from rail.setup import build, io
from rail.studies import conclusions, stability


def main(config, paths, expect, out):
    records = []
    for p in paths:
        with open(p) as f:
            records.append(json.load(f))
    vc = moving.critical_speed(build.scenario(config).track)
    ds = stability.stability_dataset(records, expect, vc)
    io.write_netcdf(io.finalize(ds, config, title="Stability suite", source="rail.studies.stability.run_case"), out["data"])
    note = f"Critical speed of the default track (largest mean deflection under a moving load): {vc:.0f} m/s."
    conclusions.write_tables(stability.stability_rows(ds), out["table"], out["html"], "Stability suite", note)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, list(snakemake.input), snakemake.params.expect, {k: o[k] for k in ("data", "table", "html")})  # noqa: F821
