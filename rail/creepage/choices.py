"""The sources of dynamic creepage as model choices (docs/dynamic-creepage.md): the wheelset's model
(config key ``wheelset.model``, rail.creepage.wheelset) and the rail head's longitudinal flexibility
(``rail_flexibility.model``, rail.creepage.rail_flexibility).

Each choice is a small frozen object with ``name`` (the configuration's value, which results store
as a value: ``wheelset_model = "torsional"``, ``rail_flexibility = "rod_and_bending"``),
``description`` (stored beside it, never parsed back) and the flags the rest of the package asks
instead of comparing the name (``modelled``, ``bending``). ``wheelset_model(name)`` and
``rail_flexibility(name)`` look a configured or stored value up; ``wheelset_model_of`` and
``rail_flexibility_of`` name what a contact material holds (rail.contact.ContactMaterial.longitudinal,
.rail_flexibility). The defaults are the schema's (config/schema/config.schema.yaml): an absent
``wheelset`` section is its ``wheelset.model`` default, an absent ``rail_flexibility`` its
``rail_flexibility.model`` default.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["WheelsetModel", "RailFlexibility", "WHEELSET_CHOICES", "RAIL_FLEXIBILITIES", "wheelset_model", "rail_flexibility",
           "wheelset_model_of", "rail_flexibility_of"]


@dataclass(frozen=True)
class WheelsetModel:
    """The wheelset's model (config key wheelset.model; rail.creepage.wheelset).

    Attributes
    ----------
    name : 'fixed_creepage' (the report's rigid wheel at the fixed creepage), 'rigid' (a rigid
        wheelset spinning under the drive torque) or 'torsional' (the elastic axle and the drive);
        'modes' for modes given directly (rail.creepage.modes.LongitudinalModes built without a wheelset)
    description : what it is, in words (a result's wheelset_model_description)
    modelled : whether the wheelset's rotation drives a dynamic creepage (False: the report's)
    """

    name: str
    description: str
    modelled: bool

    def __str__(self) -> str:
        return self.name

    def mechanism(self, driven: bool) -> str:
        """The wheelset as a mechanism of u_bar in a study's words: '' for the report's fixed creepage,
        'trailer wheelset' or 'motored wheelset' for the torsional one, '<name> wheelset' otherwise.

        Parameters
        ----------
        driven : bool
            Whether a motor hangs on the axle (wheelset.motor_inertia > 0) [-].

        Returns
        -------
        str
        """
        if not self.modelled:
            return ""
        if self.name == "torsional":
            return "motored wheelset" if driven else "trailer wheelset"
        return f"{self.name} wheelset"

    def unread_keys(self, driven: bool) -> tuple:
        """The wheelset section's keys this model does not read (rail.creepage.wheelset.wheelset_modes), left out of a
        job's rerun trigger (rail.setup.targets.read_part): the rigid wheelset reads only its inertias, a
        torsional one without a drive no coupling.

        Parameters
        ----------
        driven : bool
            Whether a motor hangs on the axle (wheelset.motor_inertia > 0) [-].

        Returns
        -------
        tuple of str
            Keys of the wheelset section [-].
        """
        if self.name == "rigid":
            return ("axle_stiffness", "coupling_stiffness", "damping")
        if self.name == "torsional" and not driven:
            return ("coupling_stiffness",)
        return ()


_WHEELSETS = {
    "fixed_creepage": WheelsetModel("fixed_creepage", "fixed_creepage: the report's rigid wheel at the fixed creepage contact.creepage "
                                    "(no dynamic creepage from the wheelset)", False),
    "rigid": WheelsetModel("rigid", "rigid: a rigid wheelset spinning under the drive or brake torque, which holds the steady traction "
                           "(its rigid spin alone; rail.creepage.wheelset)", True),
    "torsional": WheelsetModel("torsional", "torsional: two wheels on an elastic axle, the inertia between them and the drive through "
                               "its coupling (rail.creepage.wheelset)", True),
}
GIVEN_MODES = WheelsetModel("modes", "modes: the wheelset's modes given directly (rail.creepage.modes.LongitudinalModes)", True)
WHEELSET_CHOICES = tuple(_WHEELSETS)  # rail.creepage.wheelset.WHEELSET_MODELS and the schema's enum (tests/test_model_choices.py)


@dataclass(frozen=True)
class RailFlexibility:
    """The rail head's longitudinal flexibility (config key rail_flexibility.model; rail.creepage.rail_flexibility).

    Attributes
    ----------
    name : 'none' (the report's rail, without longitudinal flexibility), 'rod' (the axial rod on the
        pads' shear springs alone) or 'rod_and_bending' (the rod and the head's motion from the bending
        rotation)
    description : what it is, in words (a result's rail_flexibility_description)
    modelled : whether the rail's flexibility drives a dynamic creepage
    bending : whether the head's motion from the bending rotation is included (rail.creepage.rail_flexibility.RailHead.bending)
    """

    name: str
    description: str
    modelled: bool
    bending: bool

    def __str__(self) -> str:
        return self.name


_FLEXIBILITIES = {
    "none": RailFlexibility("none", "none: the report's rail, without longitudinal flexibility", False, False),
    "rod": RailFlexibility("rod", "rod: the rail as an axial rod on the pads' shear springs (rail.creepage.rail_flexibility)", True, False),
    "rod_and_bending": RailFlexibility("rod_and_bending", "rod_and_bending: the axial rod and the head's motion e psi from the bending "
                                       "rotation, driven by the tangential force's moment and the vertical force (rail.creepage.rail_flexibility)",
                                       True, True),
}
RAIL_FLEXIBILITIES = tuple(_FLEXIBILITIES)


def wheelset_model(name) -> WheelsetModel:
    """The wheelset model named ``name`` (config key wheelset.model, or a result's wheelset_model), or ``name`` itself.

    Parameters
    ----------
    name : str or WheelsetModel
        One of WHEELSET_CHOICES [-].

    Returns
    -------
    WheelsetModel
    """
    if isinstance(name, WheelsetModel):
        return name
    if not isinstance(name, str) or name not in _WHEELSETS:
        raise ValueError(f"wheelset.model = {name!r} is not allowed: it must be one of {list(WHEELSET_CHOICES)}.")
    return _WHEELSETS[name]


def rail_flexibility(name) -> RailFlexibility:
    """The rail flexibility named ``name`` (config key rail_flexibility.model, or a result's rail_flexibility), or ``name`` itself.

    Parameters
    ----------
    name : str or RailFlexibility
        One of RAIL_FLEXIBILITIES [-].

    Returns
    -------
    RailFlexibility
    """
    if isinstance(name, RailFlexibility):
        return name
    if not isinstance(name, str) or name not in _FLEXIBILITIES:
        raise ValueError(f"rail_flexibility.model = {name!r} is not allowed: it must be one of {list(RAIL_FLEXIBILITIES)}.")
    return _FLEXIBILITIES[name]


def wheelset_model_of(modes) -> WheelsetModel:
    """The wheelset model a contact material holds.

    Parameters
    ----------
    modes : rail.creepage.modes.LongitudinalModes or None
        ContactMaterial.longitudinal: None for the report's fixed creepage; modes built by
        rail.creepage.wheelset.wheelset_modes carry their model's name (``model``).

    Returns
    -------
    WheelsetModel
        Its name [-]; 'modes' (GIVEN_MODES) for modes built without a wheelset.
    """
    if modes is None:
        return _WHEELSETS["fixed_creepage"]
    return _WHEELSETS.get(getattr(modes, "model", ""), GIVEN_MODES)


def rail_flexibility_of(head) -> RailFlexibility:
    """The rail flexibility a contact material holds.

    Parameters
    ----------
    head : rail.creepage.rail_flexibility.RailHead or None
        ContactMaterial.rail_flexibility: None for the report's rail.

    Returns
    -------
    RailFlexibility
        Its name [-], from the head's bending flag.
    """
    if head is None:
        return _FLEXIBILITIES["none"]
    return next(c for c in _FLEXIBILITIES.values() if c.modelled and c.bending == bool(head.bending))
