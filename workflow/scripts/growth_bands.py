"""One-third-octave band view of a growth run: dataset, band / narrow-band / rolling-noise CSV exports, figure."""

import sys

from rail.plotting import report
from rail.roughness import read_limit_spectrum, read_third_octave_spectrum
from rail.setup import build, io
from rail.studies import bands, exports
from rail.studies.validity import validity_text
from rail.traffic import traffic_of


def main(config, name, growth_path, out):
    scn = build.scenario(config, name)
    s = config["figures"]["bands"]
    with io.open_intermediate(growth_path) as g:
        growth = g.load()
    limit = read_limit_spectrum(s["limit"]) if s["limit"] else None
    tob = bands.third_octave_bands(float(s["longest"]), float(s["shortest"]))
    traffic = traffic_of(scn)
    ds = bands.bands_dataset(growth, scn.L, tob, int(s["min_lines"]), limit, traffic=traffic)
    io.write_netcdf(io.finalize(ds, config, title=f"One-third-octave roughness bands, scenario {name}", source="rail.studies.bands", scenario=name), out["data"])
    bands.write_band_csv(ds, out["csv"])
    with open(out["narrow_csv"], "w") as f:
        f.write(exports.narrow_band_csv_text(growth, scn.L, traffic, ds.attrs["grinding_interval_text"]))
    period = int(growth.attrs.get("bays", 1)) * scn.L
    Z = growth["Z_real"].values[-1] + 1j * growth["Z_imag"].values[-1]
    level, reasons = exports.rolling_noise_levels(Z, period, int(s["min_lines"]))
    wheel = s.get("wheel_roughness")
    wheel_dB = exports.wheel_levels_on_bands(*read_third_octave_spectrum(wheel), source=wheel) if wheel else None
    with open(out["rolling_noise_csv"], "w") as f:
        f.write(exports.rolling_noise_csv_text(level, reasons, period, period / ((Z.size - 1) // 2), float(ds.attrs["speed_m_per_s"]),
                                               f"scenario {name} after {bands.readable_count(growth['passage'].values[-1])} axle passages "
                                               "(the last save of the growth run)", wheel_dB=wheel_dB, wheel_source=wheel or "",
                                               grinding=ds.attrs["grinding_interval_text"], validity=validity_text(growth.attrs)))
    report.band_spectra(ds).savefig(out["figure"], dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    o = snakemake.output  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.scenario, snakemake.input[0],  # noqa: F821
         {k: o[k] for k in ("data", "csv", "narrow_csv", "rolling_noise_csv", "figure")})
