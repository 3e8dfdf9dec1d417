"""Figs 20, 21, 23-27 (one job for the seven), the 3-D growth plot, the narrow-band figure and a
scenario's overview, from growth datasets."""

import sys

import matplotlib.pyplot as plt
import yaml

from rail.plotting import report
from rail.setup import build, io
from rail.studies import datasets, irregular


def _load(path):
    with io.open_intermediate(path) as ds:
        return ds.load()


def _save(fig, path, dpi):
    fig.savefig(path, dpi=dpi)
    plt.close(fig)


def supports(ds):
    """The supports of the run's track over its period for the figures along the rail, from the resolved
    configuration the dataset carries: the cell's (a voided sleeper described), or None for uniform
    track (every sleeper, drawn by the figure itself)."""
    cfg = yaml.safe_load(ds.attrs["config"]) if "config" in ds.attrs else None
    cell = build.track_cell(cfg) if isinstance(cfg, dict) and "track" in cfg else None
    return None if cell is None else irregular.support_marks(cell)


def report_figures(runs, config, data_paths, figure_paths):
    """Figs 20, 21, 23-27: runs is {nn: {label: growth run file}}; the output paths in its order.
    Each run file is read once."""
    loaded = {}
    for nn, data_path, figure_path in zip(runs, data_paths, figure_paths, strict=True):
        for path in runs[nn].values():
            if path not in loaded:
                loaded[path] = _load(path)
        n = int(nn)
        kind = {20: "profiles", 21: "profiles", 24: "final_profiles"}.get(n, "spectra")
        ds = datasets.growth_figure({label: loaded[path] for label, path in runs[nn].items()}, kind,
                                    float(config["figures"]["wear"]["spectrum_max_wavenumber"]))
        ds = io.finalize(ds, config, title=f"Figure {n}", source="rail.studies.datasets.growth_figure")
        io.write_netcdf(ds, data_path)
        draw = {"profiles": report.growth_profiles, "final_profiles": report.growth_final_profiles}.get(kind, report.growth_spectra)
        _save(draw(ds), figure_path, dpi=150)


def main(rule, name, inputs, outputs, params):
    if rule == "growth_3d":
        axis = params.get("axis", "wavenumber")
        _save(report.growth_3d(_load(inputs[0]), axis, "" if axis == "wavenumber" else name), outputs[0], dpi=130)
    elif rule == "growth_narrowband":
        ds = _load(inputs[0])
        _save(report.growth_narrowband(ds, supports(ds)), outputs[0], dpi=150)
    elif rule in ("scenario_overview", "fleet_overview"):
        default = _load(inputs.default) if "default" in inputs.keys() else None
        note = params.get("default_note", "")
        if default is None and note:
            print(f"{name}: {note}", file=sys.stderr)  # the log says it too, not only the figure
        run = _load(inputs.run)
        _save(report.scenario_overview(run, default, name, note, supports(run)), outputs[0], dpi=130)
    else:
        raise ValueError(f"growth_figure.py: unknown rule {rule!r}")


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    if snakemake.rule == "growth_figures":  # noqa: F821
        report_figures(snakemake.params.runs, snakemake.params.cfg, snakemake.output.data, snakemake.output.figure)  # noqa: F821
    else:
        main(snakemake.rule, snakemake.wildcards.get("scenario", ""), snakemake.input, snakemake.output, dict(snakemake.params.items()))  # noqa: F821
