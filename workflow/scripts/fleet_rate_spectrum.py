"""Growth-rate spectrum under a scenario's fleet (rail.growth_spectrum.fleet_rate_spectrum), from the shared
per-speed tables of the spectrum's period."""

import sys

from rail.growth_spectrum import fleet_rate_spectrum, spectrum_lines
from rail.plotting import studies as plots
from rail.setup import build, io
from rail.studies import datasets
from rail.studies import fleet as fleet_study
from rail.track import pinned_pinned_frequency



def read_tables(paths, speeds):
    """{speed: table} of the job's table files, each checked to be at its class speed."""
    tabs = []
    for path in paths:
        with io.open_intermediate(path) as t:
            tabs.append(datasets.read_receptance_table(t.load()))
    return fleet_study.tables_by_speed(tabs, speeds)


def main(config, name, table_paths, speeds, data_path, figure_path, log):
    s = config["figures"]["rate_spectrum"]
    scn = build.spectrum_scenario(config, name)  # smooth rail, the spectrum's N-bay period
    lines = spectrum_lines(scn.L, scn.roughness.bays, scn.harmonics, float(s["shortest"]), float(s["longest"]), int(s["per_octave"]))
    fl = build.fleet(config)
    classes = build.fleet_classes(config, scn)
    fs = fleet_rate_spectrum(classes, read_tables(table_paths, speeds), lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]))
    ds = fleet_study.fleet_spectrum_dataset(fs, fl)
    f_pp = pinned_pinned_frequency(scn.track)
    ds.attrs.update({"pinned_pinned_frequency_Hz": f_pp, "mean_speed_m_per_s": fl.speeds.mean,
                     "pinned_pinned_wavelength_m": fl.speeds.mean / f_pp})
    print(f"{len(lines)} lines of a {scn.roughness.bays}-bay period, {len(classes)} classes at {sorted({c.speed for c in classes})} m/s; "
          f"linearity {fs.total.linearity:.2e}", file=log, flush=True)
    ds = io.finalize(ds, config, title="Growth-rate spectrum under the fleet", source="rail.growth_spectrum.fleet_rate_spectrum",
                     scenario=name)
    io.write_netcdf(ds, data_path)
    plots.fleet_spectrum_figure(ds, f"growth-rate spectrum under the fleet of {name}").savefig(figure_path, dpi=150)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    main(snakemake.params.cfg, snakemake.wildcards.scenario, list(snakemake.input.tables), snakemake.params.speeds,  # noqa: F821
         snakemake.output.data, snakemake.output.figure, log)  # noqa: F821
