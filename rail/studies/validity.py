"""The validity of a result, stated where it is read: one line from a dataset's attributes for every
export's header, the run summary and the figures (issue 42; docs/contact.md)."""

from __future__ import annotations

import numpy as np

from .. import contact
from ..creepage.wheelset import hz_text

__all__ = ["VALIDITY_ATTRS", "NOT_USED", "NO_WEAR", "model_attributes", "stated_wear_path", "validity_text", "creepage_model_text"]

VALIDITY_ATTRS = ("wear_path", "wear_path_description", "contact_shift_modelled", "contact_shift_warning", "normal_contact",
                  "normal_contact_description", "validity", "creepage_model")
NOT_USED = "none"  # the value of wear_path or normal_contact where a result uses no wear or no wheel/rail contact model
# the attribute wear_path_description of a result that computes no wear (wear_path = NOT_USED)
NO_WEAR = "none: no wear is computed for this result"
NO_CONTACT = "none: no wheel/rail contact is modelled for this result"


def model_attributes(wear_path, normal) -> dict:
    """The model choices of a result as values (issue 57, item 8; issue 54): ``wear_path`` ('patch',
    'wheel', or 'none' where no wear is computed) beside its description ``wear_path_description``, and
    ``normal_contact`` (the model's config value, 'report' or 'nonhertzian', or 'none' where no
    wheel/rail contact is modelled) beside ``normal_contact_description``; each from its model object
    (rail.scenario.ModelChoices.attributes writes every choice of a scenario).

    Parameters
    ----------
    wear_path : str or rail.contact.WearPath
        contact.wear_path (the object or its name), or NOT_USED.
    normal : str or rail.contact.NormalContact
        contact.normal (the object or its name), or NOT_USED.

    Returns
    -------
    dict
        The five attributes.
    """
    path = None if str(wear_path) == NOT_USED else contact.wear_path(wear_path)
    model = None if str(normal) == NOT_USED else contact.normal_contact(normal)
    return {**({"wear_path": NOT_USED, "wear_path_description": NO_WEAR, "contact_shift_modelled": 0} if path is None else path.attributes()),
            "normal_contact": NOT_USED if model is None else model.name,
            "normal_contact_description": NO_CONTACT if model is None else model.description}


def stated_wear_path(attrs):
    """The wear path a result states (its attribute wear_path, a value), as its model object.

    Parameters
    ----------
    attrs : mapping
        A dataset's attributes.

    Returns
    -------
    rail.contact.WearPath or None
        None where the result states none, computes no wear ('none'), or predates the values (a
        sentence such as 'patch: the wear ...' is not parsed back: 'not stated').
    """
    try:
        return contact.wear_path(attrs.get("wear_path"))
    except ValueError:
        return None


def validity_text(attrs) -> str:
    """One line stating the validity of a result from its attributes (a growth, band or spectrum
    dataset's): where the wear is deposited, the contact-centre flag if raised, the normal contact's
    wavelength limit (docs/contact.md), and the dynamic creepage where modelled (docs/dynamic-creepage.md).
    Every export's header and the run summary carry it.

    Parameters
    ----------
    attrs : mapping
        The dataset's attributes (wear_path, contact_shift_warning, normal_contact, validity).

    Returns
    -------
    str
        '' where the attributes say nothing.
    """
    parts = []
    path = stated_wear_path(attrs)
    if path is not None:
        parts.append(path.validity)
    if attrs.get("contact_shift_warning"):
        parts.append("OUTSIDE VALIDITY: " + str(attrs["contact_shift_warning"]))
    if attrs.get("creepage_model"):
        parts.append(str(attrs["creepage_model"]))
    if attrs.get("validity"):
        parts.append(str(attrs["validity"]))
    elif attrs.get("normal_contact"):
        parts.append(f"normal contact {attrs['normal_contact']}")
    return "; ".join(parts)


def creepage_model_text(material) -> str:
    """What the contact's creepage and friction are beyond the report's (a fixed creepage, mu_s / mu_d step):
    the wheelset's modes (rail.creepage.wheelset), the rail's longitudinal flexibility (rail.creepage.rail_flexibility) and
    falling friction, with what is still left out.

    Parameters
    ----------
    material : rail.contact.ContactMaterial

    Returns
    -------
    str
        The creepage_model attribute of a result [-]; '' for the report's model.
    """
    parts = []
    head = material.rail_flexibility
    if material.longitudinal is not None:
        modes = material.longitudinal
        freqs = ", ".join(hz_text(o / (2 * np.pi)) for o in modes.omega)
        rail = "" if head is not None else "; the rail's longitudinal flexibility is not modelled"
        idle = getattr(modes, "unexcited", ())
        idle = f"; not excited at this wheel: {', '.join(hz_text(f) for f in idle)} Hz" if idle else ""
        parts.append(f"dynamic creepage from the {modes.label or 'wheelset'} (modes at {freqs} Hz{idle}{rail})")
    if head is not None:
        home = "rail.creepage.rail_flexibility_cell" if hasattr(head, "cell") else "rail.creepage.rail_flexibility"
        parts.append(f"dynamic creepage from the {head.label} ({home})")
    if material.friction_decay > 0:  # the falling law, or one made flat by mu_s = mu_d, said so
        parts.append(material.friction_law.description)
    return "; ".join(parts)

