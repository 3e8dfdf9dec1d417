"""Growth-rate spectrum of one (vehicle, speed) class of a fleet (rail.growth_spectrum.rate_spectrum)."""

import sys
from pathlib import Path

import numpy as np

from rail import chain
from rail.setup import build, inputs, io
from rail.setup.progress import Tee, progress_lines
from rail.studies import datasets, rate_spectrum, wheel_source
from rail.studies import fleet as fleet_study


def main(config, name, index, speed, table_path, out_path, log, label=""):
    if label:
        print(f"class spectrum {Path(out_path).stem}: {label}", file=log, flush=True)  # the fleets holding it
    scn = build.spectrum_scenario(config, name)  # smooth rail, the spectrum's N-bay period
    c = build.fleet_classes(config, scn)[index]
    with io.open_intermediate(table_path) as t:
        tab = datasets.read_receptance_table(t.load())
    if c.speed != speed or chain.table_speed(tab) != speed:
        raise ValueError(f"class {c.label}: table at {chain.table_speed(tab)!r} m/s, class speed {c.speed!r}, job speed {speed!r} m/s.")
    sp = rate_spectrum.spectrum_with_settings(c.scenario, tab, config["figures"]["rate_spectrum"],
                                                  progress=progress_lines(log))
    print(f"{name}, class {index} ({c.label}): {len(sp.line)} lines, linearity {sp.linearity:.2e}, method {sp.method}",
          file=log, flush=True)
    # the wheels' source (wheel_source: each axle's own rate and the vehicle's wheel roughness; none: nothing added)
    wheels = (inputs.wheel_source_spectra(config) or {}).get("vehicles", {})
    extra = wheel_source.class_source_arrays(c.scenario, tab, config["figures"]["rate_spectrum"], sp, wheels.get(c.vehicle),
                                             progress=progress_lines(log))
    with open(out_path, "wb") as fh:
        np.savez(fh, **fleet_study.spectrum_arrays(sp), **extra)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    name, index, speed = snakemake.params.job  # noqa: F821
    tee = Tee(log, f"fleet class spectrum {name} {index}")  # the log, and the terminal if there is one
    main(snakemake.params.cfg, name, int(index), float(speed), snakemake.input.table, snakemake.output[0], tee,  # noqa: F821
         snakemake.params.label)  # noqa: F821
    tee.close()
