"""The linearised growth-rate spectrum of one scenario at one speed (rail.growth_spectrum)."""

import sys

from rail.setup import build, inputs, io
from rail.setup.progress import Tee, progress_lines
from rail.studies import datasets, rate_spectrum, wheel_source


def main(config, name, table_path, speed, out_path, log):
    """``log``: the job's log (a Tee: also a progress bar on the terminal)."""
    s = config["figures"]["rate_spectrum"]
    scn = build.spectrum_scenario(config, name)  # smooth rail, the spectrum's N-bay period
    with io.open_intermediate(table_path) as t:
        tabs = datasets.read_receptance_table(t.load())
    sp = rate_spectrum.spectrum_with_settings(scn, tabs, s, progress=progress_lines(log))
    print(f"{len(sp.line)} lines of a {scn.roughness.bays}-bay period, {sp.wavelength.min():.4g}-{sp.wavelength.max():.4g} m, "
          f"V = {speed:g} m/s, normal contact {scn.contact_numerics.normal}",
          file=log, flush=True)
    print(f"linearity (2 eps against eps): {sp.linearity:.2e}; grid spread of the growth rate: at most "
          f"{(sp.grid_spread / abs(sp.growth_rate).max()).max():.2e} of the largest rate", file=log, flush=True)
    ds = rate_spectrum.spectrum_dataset_of({speed: sp}, scn)
    # the wheels' roughness as a source (wheel_source; none: ds as it is)
    ds = wheel_source.with_wheel_source(ds, scn, tabs, s, inputs.wheel_source_spectra(config), progress=progress_lines(log))
    io.write_netcdf(io.finalize(ds, config, title=f"Growth-rate spectrum at {speed:g} m/s",
                                source="rail.growth_spectrum.rate_spectrum", scenario=name), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    w = snakemake.wildcards  # noqa: F821
    tee = Tee(log, f"spectrum {w.scenario} V{w.speed}")  # the log, and the terminal if there is one
    main(snakemake.params.cfg, w.scenario, snakemake.input.table, snakemake.params.speed, snakemake.output[0], tee)  # noqa: F821
    tee.close()
