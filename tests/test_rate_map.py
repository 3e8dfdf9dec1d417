"""The growth-rate map over frequency and speed (rail.plotting.rate_map): its cells hold each line at
its own frequency, and a synthetic band at a fixed frequency lands in the same frequency column at
every speed (the property the map is read for)."""

import numpy as np
import pytest
import xarray as xr

from rail.plotting.rate_map import frequency_speed_cells, rate_map_figure

L = 0.6


def _dataset(speeds, lines, bays, band_Hz=1120.0, width_Hz=25.0):
    lam = bays * L / np.asarray(lines, dtype=float)
    f = np.asarray(speeds)[:, None] / lam[None, :]
    g = -3.0 + 5.0 * np.exp(-0.5 * ((f - band_Hz) / width_Hz) ** 2)  # a band at a fixed frequency
    return xr.Dataset({"growth_dB_per_1e5_axles": (("speed", "wavelength"), g)},
                      coords={"speed": ("speed", np.asarray(speeds, float)), "wavelength": ("wavelength", lam),
                              "frequency": (("speed", "wavelength"), f)},
                      attrs={"sleeper_spacing_m": L, "pinned_pinned_Hz": 1067.0})


def test_every_line_lies_inside_its_own_cell_and_the_cells_tile_the_row():
    speeds = np.array([20.0, 40.0, 60.0, 80.0])
    ds = _dataset(speeds, np.arange(30, 80), 24)
    f = ds["frequency"].values
    edges, v_edges = frequency_speed_cells(f, speeds)
    fs = np.sort(f, axis=1)
    assert np.all(edges[:, :-1] < fs) and np.all(fs < edges[:, 1:])
    assert np.all(np.diff(edges, axis=1) > 0)
    assert np.all(np.diff(v_edges) > 0) and np.all((v_edges[:-1] < speeds) & (speeds < v_edges[1:]))
    # neighbouring cells meet at the midpoint between their lines
    assert np.allclose(edges[:, 1:-1], 0.5 * (fs[:, 1:] + fs[:, :-1]))


def test_a_band_at_a_fixed_frequency_peaks_in_the_same_frequency_cell_at_every_speed():
    # lines 15 Hz or closer over 900-1,400 Hz at every speed: the peak cell holds 1,120 Hz within a cell
    speeds = np.array([40.0, 50.0, 60.0])
    ds = _dataset(speeds, np.arange(1, 1500), 24)
    edges, _ = frequency_speed_cells(ds["frequency"].values, speeds)
    g = ds["growth_dB_per_1e5_axles"].values
    for k in range(speeds.size):
        i = int(np.argmax(g[k]))
        order = np.argsort(ds["frequency"].values[k])
        cell = int(np.nonzero(order == i)[0][0])
        assert edges[k, cell] <= 1120.0 + 15.0 and edges[k, cell + 1] >= 1120.0 - 15.0


def test_the_map_draws_one_row_per_speed_with_the_pinned_pinned_frequency_marked():
    speeds = np.array([40.0, 60.0])
    fig = rate_map_figure(_dataset(speeds, np.arange(30, 80), 24), f_range=(900.0, 1400.0), title="default track")
    ax = fig.axes[0]
    assert len(ax.collections) == speeds.size
    assert any(abs(t.get_position()[0] - 1067.0) < 1e-9 for t in ax.texts)
    assert ax.get_xlim() == (900.0, 1400.0)
    assert "Hz" in ax.get_xlabel() and "m/s" in ax.get_ylabel()


def test_bad_shapes_are_refused():
    with pytest.raises(ValueError, match="rows"):
        frequency_speed_cells(np.ones((2, 5)), np.array([40.0]))
    with pytest.raises(ValueError, match="two lines"):
        frequency_speed_cells(np.ones((1, 1)), np.array([40.0]))
