"""The figure-regression comparison itself: it passes identical data and catches real changes."""

import sys
from pathlib import Path

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).parent / "regression"))
import figures as reg  # noqa: E402


def _write(path, values, units="N"):
    xr.Dataset({"force": ("x", np.asarray(values, float), {"units": units, "long_name": "f"})}).to_netcdf(path)


def test_identical_data_passes_and_a_visible_change_fails(tmp_path):
    base = np.linspace(1e5, 1.02e5, 50)
    _write(tmp_path / "old.nc", base)
    _write(tmp_path / "same.nc", base * (1 + 1e-9))
    _write(tmp_path / "changed.nc", base * 1.01)
    assert reg.compare_data(tmp_path / "same.nc", tmp_path / "old.nc") == []
    assert "differs by" in reg.compare_data(tmp_path / "changed.nc", tmp_path / "old.nc")[0]


def test_levels_in_dB_use_an_absolute_tolerance(tmp_path):
    _write(tmp_path / "old.nc", [-40.0, -20.0], units="dB re 1 um")
    _write(tmp_path / "new.nc", [-40.2, -20.0], units="dB re 1 um")
    assert reg.compare_data(tmp_path / "new.nc", tmp_path / "old.nc")


def test_an_image_with_a_different_line_fails(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for name, y in (("old.png", [0, 1]), ("new.png", [1, 0])):
        fig, ax = plt.subplots()
        ax.plot([0, 1], y, lw=5)
        fig.savefig(tmp_path / name)
        plt.close(fig)
    assert reg.compare_images(tmp_path / "new.png", tmp_path / "old.png")
    assert reg.compare_images(tmp_path / "old.png", tmp_path / "old.png") == []
