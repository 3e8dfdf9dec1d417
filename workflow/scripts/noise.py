"""Rolling noise over traffic of a growth run (one train, or a fleet: rules growth_noise, fleet_noise):
dataset, CSV, figure and the one-line change in the log (rail.studies.noise.noise_outputs, as the API
and the command line)."""

import sys

from rail.plotting.noise import noise_over_traffic
from rail.setup import build, inputs, io
from rail.studies import noise


def main(config, name, growth_path, out, log=sys.stderr):
    scn = build.scenario(config, name)
    with io.open_intermediate(growth_path) as g:
        growth = g.load()
    b = inputs.band_inputs(config, scn)
    o = noise.noise_outputs(growth, config, scn, name, build.noise_settings(config), initial_spectrum=b["initial_spectrum"],
                            traffic=b["traffic"], fleet=build.fleet(config))
    data = io.finalize(o.data, config, title=f"CNOSSOS-EU rolling noise, scenario {name}", source="rail.studies.noise", scenario=name)
    io.write_netcdf(data, out["data"])
    with open(out["csv"], "w") as f:
        f.write(o.csv)
    noise_over_traffic(data, name).savefig(out["figure"], dpi=150, bbox_inches="tight")
    print(noise.change_line(data), file=log)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.scenario, snakemake.input[0], {k: o[k] for k in ("data", "csv", "figure")})  # noqa: F821
