"""One irregular-track case beside the uniform track (rail.studies.irregular)."""

import sys

from rail.setup import build, io
from rail.studies import irregular


def main(case_config, uniform_config, speed, paths, out_data, out_figure, log):
    from rail.plotting.irregular import case_figure

    cell = build.track_cell(case_config)
    uniform = build.track(uniform_config)[0]
    with io.open_intermediate(paths["growth"]) as g, io.open_intermediate(paths["growth_uniform"]) as gu, \
            io.open_intermediate(paths["spectrum"]) as s, io.open_intermediate(paths["spectrum_uniform"]) as su:
        ds = irregular.case_dataset(cell, uniform, speed, g.load(), gu.load(), s.load(), su.load())
    print(f"cell of {cell.bays} bays, {len(cell.dampers)} rail dampers; pinned-pinned band {ds.attrs['pp_band_m'] * 1e3:g} mm: "
          f"{ds.attrs['pp_level_dB']:.1f} dB (uniform {ds.attrs['uniform_pp_level_dB']:.1f} dB)", file=log, flush=True)
    io.write_netcdf(io.finalize(ds, {"case": case_config, "uniform": uniform_config},
                                title=f"Irregular track beside the uniform track at {speed:g} m/s",
                                source="rail.studies.irregular.case_dataset"), out_data)
    fig = case_figure(ds, f"{paths['name']}: a track cell of {cell.bays} bays beside the uniform track, {speed:g} m/s")
    fig.savefig(out_figure, dpi=110)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    inp = snakemake.input  # noqa: F821
    paths = {k: inp[k] for k in ("growth", "growth_uniform", "spectrum", "spectrum_uniform")}
    paths["name"] = snakemake.wildcards.case  # noqa: F821
    p = snakemake.params  # noqa: F821
    main(p.cfg["case"], p.cfg["uniform"], p.speed, paths, snakemake.output.data, snakemake.output.figure, log)  # noqa: F821
