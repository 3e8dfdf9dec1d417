"""Growth-rate spectrum of one member of the uncertainty ensemble (its own tables: the pad stiffness is drawn)."""

import sys

from rail import chain
from rail.setup import build, io
from rail.setup.progress import Tee, progress_lines
from rail.studies import rate_spectrum


def main(config, member, speed, out_path, log):
    scn = build.spectrum_scenario(config, f"uncertainty-m{member}")
    tabs = chain.receptance_table(scn, speed)
    sp = rate_spectrum.spectrum_with_settings(scn, tabs, config["figures"]["rate_spectrum"],
                                                  progress=progress_lines(log))
    print(f"member {member}: {len(sp.line)} lines, linearity {sp.linearity:.2e}, method {sp.method}", file=log, flush=True)
    ds = rate_spectrum.spectrum_dataset_of({speed: sp}, scn)
    io.write_netcdf(io.finalize(ds, config, title=f"Growth-rate spectrum of ensemble member {member}",
                                source="rail.growth_spectrum.rate_spectrum", scenario=f"uncertainty-m{member}"), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    tee = Tee(log, f"uncertainty member {snakemake.wildcards.member}")  # noqa: F821 - the log, and the terminal if there is one
    main(snakemake.params.cfg, int(snakemake.wildcards.member), float(snakemake.params.speed), snakemake.output[0], tee)  # noqa: F821
    tee.close()
