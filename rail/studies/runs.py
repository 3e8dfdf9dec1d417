"""A growth run as a dataset: the one place that turns a growth history into the result file's
content (used by the workflow's growth job and by rail.app.api.growth)."""

from __future__ import annotations

import xarray as xr

from .. import chain, interaction
from ..scenario import Scenario
from . import datasets

__all__ = ["growth_dataset"]


def growth_dataset(scn: Scenario, table, history, speed: float) -> xr.Dataset:
    """The growth dataset of a run (rail.studies.datasets.growth) with every wheel's contact force
    at each saved roughness.

    Parameters
    ----------
    scn : Scenario
    table : MovingReceptance or tuple of MovingReceptance
        The run's receptance table(s) at the speed.
    history : rail.growth.GrowthHistory
    speed : float
        Train speed [m/s].

    Returns
    -------
    xr.Dataset
    """
    bays = scn.roughness.bays

    def force(Z, x):  # every wheel's contact force at each saved roughness
        return interaction.force_history(chain.solve_forces(scn, table, interaction.Roughness(Z, bays)), x)

    ds = datasets.growth(history, scn.track, speed, len(scn.wheels.positions), bays=bays, force=force)
    ds.attrs["normal_contact"] = scn.contact_numerics.normal
    if history.stopped:  # a physical assumption broke: the states up to there, and why
        ds.attrs["stopped"] = history.stopped
    return ds
