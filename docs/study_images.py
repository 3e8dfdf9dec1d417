"""Redraw the study figures of the documentation gallery (docs/reference/gallery.rst, "Study figures")
from the results of a workflow run, with the figure code of this checkout:

    snakemake -j2 irregular_track dynamic_creepage     # or any run that built the files below
    python docs/study_images.py [results directory, default results/]

Each image is drawn by the function the workflow's rule uses, from the dataset that rule reads, and
written to docs/images/study/ at a resolution fit for a web page.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import xarray as xr
import yaml

from rail.plotting import report, studies
from rail.setup import build
from rail.studies import irregular

DOCS = Path(__file__).resolve().parent
OUT = DOCS / "images" / "study"


def _open(path):
    with xr.open_dataset(path) as ds:
        return ds.load()


def _supports(ds):
    cell = build.track_cell(yaml.safe_load(ds.attrs["config"]))
    return None if cell is None else irregular.support_marks(cell)


def main(results: Path) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    run = _open(results / "growth/irregular_voided/V40.nc")
    default = _open(results / "growth/default/V40.nc")
    figures = {
        "overview.png": report.scenario_overview(run, default, "irregular_voided", "", _supports(run)),
        "bands.png": report.band_spectra(_open(results / "growth/irregular_voided/V40_bands.nc")),
        "growth_3d.png": report.growth_3d(run, "wavelength", "irregular_voided"),
        "narrowband.png": report.growth_narrowband(run, _supports(run)),
        "rate_spectrum.png": studies.rate_spectrum_figure(_open(results / "spectrum/dyn_trailer/rate_spectrum.nc")),
    }
    for name, fig in figures.items():
        fig.savefig(OUT / name, dpi=80)
        plt.close(fig)
        print(OUT / name)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else DOCS.parent / "results")
