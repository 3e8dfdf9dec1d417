"""Figure datasets of section 3: each asserts the feature the report's figure shows."""

import numpy as np
import pytest
import xarray as xr

from rail import halfspace
from rail.plotting import report as figures
from rail.setup import build, io
from rail.studies import datasets
from rail.setup.config import load_yaml


@pytest.fixture(scope="module")
def cfg(root):
    return load_yaml(root / "config/config.yaml")


@pytest.fixture(scope="module")
def settings(cfg):
    return build.halfspace_figures(cfg)


def test_fig02_integrand_is_real_between_s_and_rayleigh_wavenumbers(steel, settings):
    ds = datasets.fig02(steel, settings)
    beyond_s = ds["wavenumber"] > ds.attrs["beta_S_rad_per_m"]
    assert np.all(ds["integrand_imag"].where(beyond_s, drop=True) == 0)
    below_s = ds["wavenumber"] < ds.attrs["beta_S_rad_per_m"]
    assert np.all(ds["integrand_imag"].where(below_s, drop=True) <= 0)
    assert np.all(np.isfinite(ds["integrand_real"]))  # the folded pole singularity cancels (Fig. 2)


def test_fig03_beta_G_approaches_the_eq15_limit(steel, settings):
    ds = datasets.fig03(steel, settings)
    rel = np.abs(ds["beta_G"] / ds["static_limit"] - 1).values
    assert rel[-1] < 0.01 * rel[0]
    assert rel[-1] < 5e-3


@pytest.mark.slow
def test_fig04_eq16_follows_boussinesq_near_the_load(steel, settings):
    ds = datasets.fig04(steel, settings, halfspace.HalfSpaceNumerics())
    rel = np.abs(ds["displacement_real"] / ds["displacement_boussinesq"] - 1)
    assert float(rel.sel(radius=slice(None, 0.01)).max()) < 5e-3  # beta_R r < 0.085


def test_finalize_refuses_a_variable_without_units(cfg):
    ds = xr.Dataset({"x": ("i", [1.0], {"long_name": "x"})})
    with pytest.raises(ValueError, match=r"lacks attributes: x \(units\)"):
        io.finalize(ds, cfg, title="t", source="s")


def test_every_halfspace_figure_draws(steel, settings, cfg):
    num = halfspace.HalfSpaceNumerics(epsrel=1e-6)
    small = build.HalfSpaceFigureSettings(
        settings.frequency, settings.radius, settings.radii[:3], settings.frequencies[:3], settings.hertz_stiffness
    )
    rad = datasets.radiation(steel, small, num)
    built = {
        "fig02": datasets.fig02(steel, small, points=50),
        "fig03": datasets.fig03(steel, small, points=50),
        "fig04": datasets.fig04(steel, small, num),
        "fig05": datasets.fig05(rad),
        "fig06": datasets.fig06(rad),
    }
    for name, ds in built.items():
        fig = getattr(figures, name)(io.finalize(ds, cfg, title=name, source="test"))
        ax = fig.axes[0]
        assert ax.get_xlabel() and ax.get_ylabel() and "(" in ax.get_ylabel()  # labels carry units
