"""The mitigation study's summary (issue 55, rail.studies.mitigation): the band near pinned-pinned per mitigation,
speed spread and driven share, and the time from a ground rail to the limit, from the cases' spectra."""

import sys

from rail.plotting.mitigation import mitigation_figure
from rail.setup import inputs, io
from rail.studies import mitigation as M


def main(paths: dict, roles: dict, speeds: dict, cfg: dict, out, log):
    spectra = {}
    for name, path in paths.items():
        with io.open_intermediate(path) as ds:
            spectra[name] = ds.load()
    spread = {}
    for name in roles.get("spread", []):
        V = sorted(speeds[name])
        if len(V) != 3:
            raise SystemExit(f"mitigation: the spread case {name} needs three speeds (V (1 - 8 %), V, V (1 + 8 %)), has {V}.")
        spread[V[1]] = spectra[name]
    cases = {}
    for role, kind in M.KINDS.items():
        for name in roles.get(role, []):
            (V,) = speeds[name]
            cases[(float(V), kind)] = M.at_speed(spectra[name], V)
    sources = inputs.wheel_source_spectra(cfg)
    axles_per_day = M.traffic_axles_per_day(cfg)
    rows = M.mitigation_rows(spread, cases, sources, axles_per_day)
    header = M.header_text(cfg)
    print(header, file=log)
    curves = {}
    for V in spread:
        curves[V] = []
        base = M.at_speed(spread[V], V)
        parts = [("default track, every train at V", base)] + [(k, cases[(V, k)]) for k in M.KINDS.values() if (V, k) in cases]
        parts.append((f"speed spread +-{100 * M.SPREAD:g} %", M.mixture([M.at_speed(spread[V], v) for v in sorted(spread[V].speed.values)],
                                                                       M.SPREAD_WEIGHTS)))
        for label, part in parts:
            curves[V].append((label, V / part.wavelength.values, part.growth_dB_per_1e5_axles.values[0]))
    mitigation_figure(curves, rows).savefig(out.figure, dpi=150)
    with open(out.csv, "w") as fh:
        fh.write(M.rows_csv_text(rows, header))
    with open(out.summary, "w") as fh:
        fh.write(M.rows_markdown(rows, "# " + header.replace("\n", "\n\n")))
    ds = io.finalize(M.rows_dataset(rows), cfg, title="Mitigation study", source="rail.studies.mitigation", scenario="mitigation")
    io.write_netcdf(ds, out.data)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    names = [n for role in snakemake.params.roles.values() for n in role]  # noqa: F821
    main(dict(zip(names, snakemake.input)), snakemake.params.roles, snakemake.params.speeds, snakemake.params.cfg,  # noqa: F821
         snakemake.output, log)  # noqa: F821
