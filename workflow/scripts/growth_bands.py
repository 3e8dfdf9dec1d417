"""One-third-octave band view of a growth run (one train or a fleet): dataset, band / narrow-band /
rolling-noise CSV exports, figure (rail.studies.exports.band_outputs, as the API and the command line)."""

import sys

from rail.plotting import report
from rail.setup import build, inputs, io
from rail.studies import exports


def main(config, name, growth_path, out):
    scn = build.scenario(config, name)
    with io.open_intermediate(growth_path) as g:
        growth = g.load()
    b = exports.band_outputs(growth, scn.L, config["figures"]["bands"], name, **inputs.band_inputs(config, scn))
    io.write_netcdf(io.finalize(b.data, config, title=f"One-third-octave roughness bands, scenario {name}", source="rail.studies.bands",
                                scenario=name), out["data"])
    for key, text in (("csv", b.bands_csv), ("narrow_csv", b.narrow_csv), ("rolling_noise_csv", b.rolling_noise_csv)):
        with open(out[key], "w") as f:
            f.write(text)
    report.band_spectra(b.data).savefig(out["figure"], dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.scenario, snakemake.input[0],  # noqa: F821
         {k: o[k] for k in ("data", "csv", "narrow_csv", "rolling_noise_csv", "figure")})
