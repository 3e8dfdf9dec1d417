"""Aggregate the closure sensitivity study: dataset, spectra figures and the conclusions table."""

import sys

from rail import track
from rail.plotting import studies as plots
from rail.setup import build, io
from rail.studies import closure, conclusions


def main(config, paths, meta, out):
    runs, soft, four, wear, wellposed = {}, {}, {}, {}, None
    for path, (kind, s, x) in zip(paths, meta):
        with io.open_intermediate(path) as ds:
            ds = ds.load()
        if kind == "run":
            runs[(s, x)] = ds
        elif kind == "soft":
            soft[s] = ds
        elif kind == "four":
            four[s] = ds
        elif kind == "wear":
            wear[(s, x)] = ds
        else:
            wellposed = ds
    tr = build.scenario(config).track
    ds = closure.closure_study(runs, soft, four, wear, wellposed, tr.L, track.pinned_pinned_frequency(tr),
                                k_max_rad_per_m=float(config["figures"]["wear"]["spectrum_max_wavenumber"]))
    io.write_netcdf(io.finalize(ds, config, title="Closure sensitivity study", source="rail.studies.closure.closure_study"), out["data"])
    plots.closure_spectra(ds).savefig(out["spectra"], dpi=150)
    plots.closure_wear_spectra(ds).savefig(out["wear"], dpi=150)
    conclusions.write_tables(conclusions.closure_table(ds), out["table"], out["html"], "Report conclusions (section 7) per closure value s")


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, list(snakemake.input), snakemake.params.meta, {k: o[k] for k in ("data", "spectra", "wear", "table", "html")})  # noqa: F821
