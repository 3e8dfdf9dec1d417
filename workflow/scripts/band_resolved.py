"""The band near the pinned-pinned frequency resolved (issue 54): the growth-rate spectrum of cases of
config/studies/spectrum_band.yaml, one speed at a time (each speed on its own band lines, not the union over
the case's speeds that the workflow's spectrum takes), and the band's peak, edges and width per speed
(rail.growth_spectrum.band.band_edges).

Run from the checkout (not a snakemake rule; the study file's target builds the same spectra on the union of
the speeds' lines):

    OMP_NUM_THREADS=1 python workflow/scripts/band_resolved.py tenhz_together 40 50 60 [--out results/band_resolved]

Writes results/band_resolved/<case>/<speed>.nc (the spectrum, as rail.app.api.spectrum) and appends one row
per speed to results/band_resolved/bands.csv (dB per 100,000 axles; per year at the scenario's traffic).
"""

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import yaml

from rail import chain, growth_spectrum
from rail.app import api
from rail.setup import build, io
from rail.studies import rate_spectrum
from rail.growth_spectrum.band import band_edges, class_pair_spectrum

FIELDS = ["case", "speed_m_s", "bays", "pad_N_m", "f_pp_Hz", "lines_in_1.00_1.15_fpp", "spacing_Hz", "peak_Hz", "peak_wavelength_mm",
          "peak_dB_per_1e5_axles", "peak_dB_per_year", "low_Hz", "high_Hz", "width_Hz", "half_low_Hz", "half_high_Hz", "half_width_Hz",
          "lines_growing", "linearity", "cpu_s"]


class Clock:
    """rate_spectrum's progress: each line of text stamped with the process's CPU time."""

    def __init__(self, out):
        self.out = out

    def __call__(self, text):
        print(f"[{time.process_time():7.1f} s CPU] {text}", file=self.out, flush=True)


def band_row(case: str, ds, cpu: float, bays: int) -> dict:
    """The band's row of one speed's spectrum (dataset of rail.app.api.spectrum, one speed)."""
    V = float(ds.speed.values[0])
    f = V / ds.wavelength.values
    g = ds.growth_dB_per_1e5_axles.values[0]
    fpp = float(ds.attrs["pinned_pinned_Hz"])
    b = band_edges(f, g, low=0.9 * fpp, high=1.3 * fpp)
    per_year = ds.growth_dB_per_year.values[0] if "growth_dB_per_year" in ds else None
    i = int(abs(f - b.peak_frequency).argmin())
    return {"case": case, "speed_m_s": V, "bays": bays, "pad_N_m": float(ds.attrs["pad_stiffness_N_per_m"]), "f_pp_Hz": round(fpp, 1),
            "lines_in_1.00_1.15_fpp": int(((f >= fpp) & (f <= 1.15 * fpp)).sum()), "spacing_Hz": round(b.spacing, 2),
            "peak_Hz": round(b.peak_frequency, 1), "peak_wavelength_mm": round(1e3 * V / b.peak_frequency, 2),
            "peak_dB_per_1e5_axles": round(b.peak_rate, 3), "peak_dB_per_year": None if per_year is None else round(float(per_year[i]), 1),
            **{f"{k}_Hz": round(getattr(b, k), 1) for k in ("low", "high", "width", "half_low", "half_high", "half_width")},
            "lines_growing": b.lines_growing, "linearity": float(ds.linearity.values[0]), "cpu_s": round(cpu, 1)}


def write_table(out: Path):
    """bands.csv afresh from the spectra saved under ``out`` (one row per file, by case and speed)."""
    rows = []
    for f in sorted(out.glob("*/*_N*.nc")):
        with io.open_intermediate(f) as ds:
            nodes = f.stem.split("_")[2] if f.stem.count("_") >= 2 else ""
            case = ds.attrs["scenario"] + (f" ({nodes.replace('nodes', ' nodes')})" if nodes else "")
            rows.append(band_row(case, ds.load(), float("nan"), int(f.stem.split("_N")[1].split("_")[0])))
    with (out / "bands.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(sorted(rows, key=lambda r: (r["case"], r["speed_m_s"])))
    for r in rows:
        print(r)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", nargs="?")
    ap.add_argument("speeds", type=float, nargs="*")
    ap.add_argument("--table", action="store_true", help="only write bands.csv afresh from every <case>/<speed>_N<bays>*.nc under --out")
    ap.add_argument("--out", default="results/band_resolved")
    ap.add_argument("--bays", type=int, default=0, help="the lines' period N [bays] (0: the fewest that space the band's lines "
                    "at most its spacing apart at the speed, N = ceil(V / (spacing L)), so every line of the period in the band is taken)")
    ap.add_argument("--wavelengths", type=float, nargs=2, metavar=("SHORTEST", "LONGEST"),
                    help="every line of the period (--bays, required) from SHORTEST to LONGEST [m] instead of the band's lines")
    ap.add_argument("--lines", type=int, nargs="+", help="these lines j of the period (--bays, required) instead of the band's")
    ap.add_argument("--nodes", type=int, default=0, help="contact grid nodes (0: the case's)")
    ap.add_argument("--check-lines", type=int, default=1, help="free lines of the linearity check (probes of 2 eps by the nonlinear "
                    "march over the N bays: most of a speed's CPU with the rail's flexibility, which needs the head's tables of every "
                    "class; 0: none, the spectrum's linearity NaN)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a configuration change on top of the case, a dotted key and a YAML value (track.pad.rotational_stiffness=9.45e5); "
                         "the files are named by a --label")
    ap.add_argument("--label", default="", help="appended to the case's name in the files and bands.csv (with --set)")
    a = ap.parse_args()
    if a.table:
        return write_table(Path(a.out))
    if not (a.case and a.speeds):
        ap.error("give a case and its speeds (or --table)")
    if (a.wavelengths or a.lines) and not a.bays:
        ap.error("--wavelengths and --lines need --bays")
    out = Path(a.out)
    (out / a.case).mkdir(parents=True, exist_ok=True)
    table = out / "bands.csv"
    for V in a.speeds:
        c = time.process_time()
        study = api.load(a.case)
        band = study.config["figures"]["rate_spectrum"]["band"]
        N = a.bays or int(math.ceil(V / (band["spacing"] * study.scenario.L) * (1 - 1e-12)))
        changes = {"figures": {"rate_spectrum": {"speeds": [V], "bays": N}}}
        if a.lines:  # the band's check of its spacing does not apply to lines given
            changes["figures"]["rate_spectrum"]["band"] = None
        if a.wavelengths:  # every line of the period in the range: the log-spaced lines at 300 per octave, no band
            changes["figures"]["rate_spectrum"].update(shortest=a.wavelengths[0], longest=a.wavelengths[1], per_octave=300, band=None)
        if a.nodes:
            changes["numerics"] = {"contact": {"nodes": a.nodes}}
        for item in a.set:
            key, _, value = item.partition("=")
            d = changes
            *path, last = key.split(".")
            for k in path:
                d = d.setdefault(k, {})
            d[last] = yaml.safe_load(value)
        study = api.load(a.case, changes=changes)
        scn = build.spectrum_scenario(study.config, study.name)  # as rail.app.api.spectrum, one class pair at a time
        tables = chain.receptance_table(scn, V)
        t_tables = time.process_time() - c
        s = study.config["figures"]["rate_spectrum"]
        lines = a.lines or growth_spectrum.settings_lines(scn.L, N, scn.harmonics, s)
        sp = class_pair_spectrum(scn, tables, lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]),
                                 check_lines=a.check_lines if a.check_lines > 0 else None,
                                 progress=Clock(sys.stderr))
        ds = io.finalize(rate_spectrum.spectrum_dataset_of({V: sp}, scn), study.config, title="Growth-rate spectrum",
                         source="workflow/scripts/band_resolved.py", scenario=study.name)
        cpu = time.process_time() - c
        print(f"{a.case} {V:g} m/s, {N} bays: tables {t_tables:.0f} s CPU, all {cpu:.0f} s CPU", file=sys.stderr, flush=True)
        if a.set and not a.label:
            ap.error("--set needs a --label naming the change in the files")
        label = f"_{a.label}" if a.label else ""
        ds.attrs["band_resolved_changes"] = "; ".join(a.set) or "none"
        ds.to_netcdf(out / a.case / (f"{V:g}_N{N}" + (f"_{a.nodes}nodes" if a.nodes else "") + label + ".nc"))
        row = band_row(a.case + (f" ({a.nodes} nodes)" if a.nodes else "") + (f" [{a.label}]" if a.label else ""), ds, cpu, N)
        new = not table.exists()
        with table.open("a", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=FIELDS)
            if new:
                w.writeheader()
            w.writerow(row)
        print(row, flush=True)


if __name__ == "__main__":
    main()
