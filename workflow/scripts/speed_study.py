"""The dynamic-creepage study over speed (issue 43): every dynspeed case's spectra in one dataset, a
figure and a table (rail.studies.speed_study)."""

import sys

from rail.setup import build, io
from rail.studies import speed_study
from rail.track import pinned_pinned_frequency


def main(paths, cfgs, out, log):
    from rail.plotting.speed_study import speed_study_figure

    cases = {}
    for name, files in paths.items():
        cases[name] = []
        for p in files:
            with io.open_intermediate(p) as g:
                cases[name].append(g.load())
    fpp = {name: pinned_pinned_frequency(build.track(cfgs[name])[0]) for name in paths}
    ds = speed_study.study_dataset(cases, fpp)
    io.write_netcdf(io.finalize(ds, cfgs, title="Dynamic creepage over speed: which lines grow, at which frequency",
                                source="rail.studies.speed_study.study_dataset"), out["data"])
    speed_study_figure(ds).savefig(out["figure"], dpi=110)
    table = speed_study.summary_table(ds)
    open(out["table"], "w").write(table)
    print(table, file=log, flush=True)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    p = snakemake.params  # noqa: F821
    main({n: list(f) for n, f in p.spectra.items()}, dict(p.cfg), {k: snakemake.output[k] for k in ("data", "figure", "table")}, log)  # noqa: F821
