"""Figs 20, 21, 23-27 and the 3-D growth plot from growth datasets."""

import sys

from rail.plotting import report
from rail.setup import io
from rail.studies import datasets


def _load(path):
    with io.open_intermediate(path) as ds:
        return ds.load()


def main(rule, nn, config, inputs, outputs):
    if rule == "growth_3d":
        report.growth_3d(_load(inputs[0])).savefig(outputs[0], dpi=130)
        return
    if rule == "growth_narrowband":
        report.growth_narrowband(_load(inputs[0])).savefig(outputs[0], dpi=150)
        return
    if rule == "scenario_overview":
        default = _load(inputs.default) if "default" in inputs.keys() else None
        report.scenario_overview(_load(inputs.run), default, nn).savefig(outputs[0], dpi=130)
        return
    runs = {label: _load(path) for label, path in inputs.items()}
    n = int(nn)
    kind = {20: "profiles", 21: "profiles", 24: "final_profiles"}.get(n, "spectra")
    ds = datasets.growth_figure(runs, kind, float(config["figures"]["wear"]["spectrum_max_wavenumber"]))
    ds = io.finalize(ds, config, title=f"Figure {n}", source="rail.studies.datasets.growth_figure")
    io.write_netcdf(ds, outputs.data)
    draw = {"profiles": report.growth_profiles, "final_profiles": report.growth_final_profiles}.get(kind, report.growth_spectra)
    draw(ds).savefig(outputs.figure, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    w = snakemake.wildcards  # noqa: F821
    main(snakemake.rule, w.get("nn", w.get("scenario", "")), getattr(snakemake.params, "cfg", None), snakemake.input, snakemake.output)  # noqa: F821
