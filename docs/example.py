"""Worked example: railgrowth from Python, without Snakemake (executed by tests/test_app.py).

A softer railpad (config/scenarios/soft_pad.yaml) at 40 m/s: grow roughness from the smooth rail
for 20,000 wheel passages, find the fastest-growing harmonic, then ask which wavelengths between
40 and 100 mm grow at all (the linearised growth-rate spectrum). Run it with

    python docs/example.py
"""

import numpy as np

from rail.app import api

study = api.load("soft_pad")  # validated like the workflow: a bad value names its key and range
print(f"scenario {study.name}: pad stiffness {study.scenario.track.pad.stiffness:.3g} N/m")

# 1. growth: levels (dB re 1 um) and profiles at every saved passage count
ds = api.growth(study, speed=40.0, passages=20000)
final = ds["level"].isel(passage=-1)
k = int(np.argmax(final.values))
wavelength = 2 * np.pi / float(ds["wavenumber"].values[k])
print(f"after {int(ds['passage'].values[-1])} passages the largest harmonic is k = {k + 1} "
      f"({1e3 * wavelength:.0f} mm) at {float(final[k]):.1f} dB re 1 um")

# 2. which wavelengths grow: growth rate per passage at 40-100 mm, 6 lines per octave at least,
# over a roughness period of 4 bays, on one contact grid (quick; the workflow uses 48 bays, 30
# lines per octave and two grids)
sp = api.spectrum(study, speeds=[40.0], shortest=0.04, longest=0.1, per_octave=6, bays=4, grid_phases=1)
g = sp["growth_dB_per_1e5_axles"].sel(speed=40.0)
grows = sp["wavelength"].values[g.values > 0]
print("wavelengths that grow (mm):", ", ".join(f"{1e3 * w:.1f}" for w in grows) or "none")
print(f"fastest: {1e3 * float(sp['fastest_wavelength'].values[0]):.1f} mm, "
      f"{float(sp['fastest_growth_dB_per_1e5_trains'].values[0]):+.2f} dB per 100,000 passages of the train")
