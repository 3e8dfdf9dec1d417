"""Growth-rate spectrum under a scenario's fleet from its classes' spectra (each a job of its own, shared by
the fleets holding the class): rail.growth_spectrum.fleet_spectrum_of, per fleet passage and per year."""

import sys

import numpy as np

from rail.growth_spectrum import fleet_spectrum_of
from rail.plotting import studies as plots
from rail.setup import build, inputs, io
from rail.studies import fleet as fleet_study
from rail.studies import wheel_source
from rail.track import pinned_pinned_frequency


def main(config, name, class_paths, data_path, figure_path, log):
    scn = build.spectrum_scenario(config, name)  # smooth rail, the spectrum's N-bay period
    fl = build.fleet(config)
    classes = build.fleet_classes(config, scn)
    spectra, sources = [], []
    for path in class_paths:
        with np.load(path) as arrays:
            spectra.append(fleet_study.spectrum_from_arrays(arrays))
            sources.append(wheel_source.source_arrays_of(arrays))  # the wheels' source's arrays ({}: none)
    for c, path in zip(classes, class_paths, strict=True):  # which hash-named class file holds which class
        print(f"class {c.label}, weight {c.weight:.4g}: {path}", file=log, flush=True)
    fs = fleet_spectrum_of(classes, spectra)
    ds = fleet_study.fleet_spectrum_dataset(fs, fl, classes)
    f_pp = pinned_pinned_frequency(scn.track)
    ds.attrs.update({"pinned_pinned_frequency_Hz": f_pp, "mean_speed_m_per_s": fl.speeds.mean,
                     "pinned_pinned_wavelength_m": fl.speeds.mean / f_pp})
    source = inputs.wheel_source_spectra(config)  # the wheels' roughness as a source (None: ds as it is)
    if source is not None:
        limit = source["limit"]
        ds = wheel_source.fleet_source_dataset(ds, fs, fl, classes, scn.roughness.bays * scn.L, sources,
                                               source["ground"] if limit is not None else None, limit)
    print(f"{len(fs.total.line)} lines of a {scn.roughness.bays}-bay period, {len(classes)} classes at "
          f"{sorted({c.speed for c in classes})} m/s; linearity {fs.total.linearity:.2e}", file=log, flush=True)
    ds = io.finalize(ds, config, title="Growth-rate spectrum under the fleet", source="rail.growth_spectrum.fleet_spectrum_of",
                     scenario=name)
    io.write_netcdf(ds, data_path)
    plots.fleet_spectrum_figure(ds, f"growth-rate spectrum under the fleet of {name}").savefig(figure_path, dpi=150)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    main(snakemake.params.cfg, snakemake.wildcards.scenario, list(snakemake.input), snakemake.output.data,  # noqa: F821
         snakemake.output.figure, log)  # noqa: F821
