"""The validity of a result, stated where it is read: one line from a dataset's attributes for every
export's header, the run summary and the figures (issue 42; docs/contact.md)."""

from __future__ import annotations

import numpy as np

from ..wheelset import hz_text

__all__ = ["VALIDITY_ATTRS", "WEAR_PATH_TEXT", "NOT_USED", "model_attributes", "validity_text", "creepage_model_text"]

VALIDITY_ATTRS = ("wear_path", "wear_path_description", "contact_shift_warning", "normal_contact", "validity", "creepage_model")
# the attribute wear_path_description of every result, by its wear_path (contact.wear_path)
WEAR_PATH_TEXT = {"patch": "patch: the wear where the contact patch is, its centre c(x_w) from the wheel (docs/contact.md)",
                  "wheel": "wheel: the wear under the wheel centre (the report's); the move of the contact centre is neglected",
                  "none": "none: no wear is computed for this result"}
NOT_USED = "none"  # the value of wear_path or normal_contact where a result uses no wear or no wheel/rail contact model


def model_attributes(wear_path: str, normal) -> dict:
    """The model choices of a result as values (issue 57, item 8): ``wear_path`` ('patch', 'wheel', or
    'none' where no wear is computed) beside its description ``wear_path_description``, and
    ``normal_contact`` (the model's config value, 'report' or 'nonhertzian', or 'none' where no
    wheel/rail contact is modelled).

    Parameters
    ----------
    wear_path : str
        contact.wear_path, or NOT_USED.
    normal : str or rail.contact.NormalContact
        contact.normal (its name), or NOT_USED.

    Returns
    -------
    dict
        The three attributes.
    """
    path = str(wear_path)
    if path not in WEAR_PATH_TEXT:
        raise ValueError(f"wear_path = {path!r} is not allowed: it must be one of {list(WEAR_PATH_TEXT)}.")
    return {"wear_path": path, "wear_path_description": WEAR_PATH_TEXT[path], "normal_contact": str(normal)}


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
    path = str(attrs.get("wear_path", ""))
    if path.startswith("patch"):
        parts.append("wear on the contact patch's true path (its centre's move modelled)")
    elif path.startswith("wheel"):
        parts.append("wear under the wheel centre (the report's model): the contact centre's move, a wear term of about "
                     "1.8 w R_w beta^2 per unit roughness for long waves, is left out (contact.wear_path: patch models it)")
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
    the wheelset's modes (rail.wheelset), the rail's longitudinal flexibility (rail.longitudinal) and
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
        parts.append(f"dynamic creepage from the {head.label} ({'rail.cell_head' if hasattr(head, 'cell') else 'rail.longitudinal'})")
    if material.friction_decay > 0:
        parts.append(material.friction_law)
    return "; ".join(parts)

