"""One-third-octave band view of a growth run: dataset, CSV export for rolling-noise tools, figure."""

import sys

from rail.plotting import report
from rail.roughness import read_limit_spectrum
from rail.setup import build, io
from rail.studies import bands


def main(config, name, growth_path, out):
    scn = build.scenario(config, name)
    s = config["figures"]["bands"]
    with io.open_intermediate(growth_path) as g:
        growth = g.load()
    limit = read_limit_spectrum(s["limit"]) if s["limit"] else None
    tob = bands.third_octave_bands(float(s["longest"]), float(s["shortest"]))
    ds = bands.bands_dataset(growth, scn.L, tob, int(s["min_lines"]), limit, scn.axles_per_day)
    io.write_netcdf(io.finalize(ds, config, title=f"One-third-octave roughness bands, scenario {name}", source="rail.studies.bands", scenario=name), out["data"])
    bands.write_band_csv(ds, out["csv"])
    report.band_spectra(ds).savefig(out["figure"], dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.scenario, snakemake.input[0], {k: o[k] for k in ("data", "csv", "figure")})  # noqa: F821
