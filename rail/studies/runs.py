"""A growth run as a dataset: the one place that turns a growth history into the result file's
content (used by the workflow's growth job and by rail.app.api.growth)."""

from __future__ import annotations

import xarray as xr

from .. import chain, interaction
from ..scenario import Scenario
from . import datasets
from .validity import creepage_model_text

__all__ = ["growth_dataset"]


def growth_dataset(scn: Scenario, table, history, speed: float, warn=None) -> xr.Dataset:
    """The growth dataset of a run (rail.studies.datasets.growth) with every wheel's contact force
    and the neglected move of the contact centre (rail.chain.contact_shift) at each saved roughness.

    The initial roughness is stated in the attributes (rail.scenario.InitialRoughness.statement:
    for a measured profile the file, units, rows, segments averaged, remainder, spike removal and
    the longest resolved band) and in two lines to ``warn``.

    Where the move's sweep error abs(dc/dx) exceeds rail.chain.SWEEP_ERROR_LIMIT at a saved state, the
    attribute ``contact_shift_warning`` holds one line saying so (docs/contact.md), also written to
    ``warn``.

    Parameters
    ----------
    scn : Scenario
    table : MovingReceptance or tuple of MovingReceptance
        The run's receptance table(s) at the speed.
    history : rail.growth.GrowthHistory
    speed : float
        Train speed [m/s].
    warn : file, optional
        Where the one-line warning goes (default: nowhere).

    Returns
    -------
    xr.Dataset
    """
    bays = scn.roughness.bays

    def force(Z, x):  # every wheel's contact force at each saved roughness (a stopped run: as the linear model has it,
        # below zero where the contact was lost, so that the state it broke at is written with the others)
        return interaction.force_history(chain.solve_forces(scn, table, interaction.Roughness(Z, bays),
                                                            check_contact=not history.stopped), x)

    ds = datasets.growth(history, scn.track, speed, len(scn.wheels.positions), bays=bays, force=force)
    ds = datasets.with_contact_shift(ds, [chain.contact_shift(scn, table, Z) for Z in history.Z], chain.SWEEP_ERROR_LIMIT,
                                     scn.contact_numerics.path)
    if "contact_shift_warning" in ds.attrs and warn is not None:
        print("warning: " + ds.attrs["contact_shift_warning"], file=warn, flush=True)
    ds.attrs.update(scn.models.attributes())  # each model choice as a value beside its description
    if creepage_model_text(scn.material):
        ds.attrs["creepage_model"] = creepage_model_text(scn.material)
    stated = scn.roughness.statement(scn.L, scn.harmonics)  # what the initial roughness was read from, and how
    ds.attrs.update(stated)
    if warn is not None:
        for key in ("roughness_input", "roughness_processing"):
            if key in stated:
                print(f"initial roughness: {stated[key]}", file=warn, flush=True)
    if history.stopped:  # a physical assumption broke: the states up to there, and why
        ds.attrs["stopped"] = history.stopped
    return ds
