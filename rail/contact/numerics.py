"""How the contact is discretised and closed: the rolling grid, the closures and the normal-contact
model and wear path chosen (config keys ``numerics.contact``, ``contact.closure``, ``contact.closure_scale``,
``contact.normal``, ``contact.wear_path``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .models import NORMAL_MODELS, WEAR_PATHS, NormalContact, WearPath, normal_contact, wear_path

__all__ = ["ContactNumerics", "MIN_NODES", "CLOSURES", "NORMAL_MODELS", "WEAR_PATHS", "THETA_EDGE", "rolling_grid"]


# A particle that reaches the leading edge within THETA_EDGE dt of the end of a step counts as
# entering in the next step (its pressure then is below sqrt(2 THETA_EDGE) p0 = 1.4e-5 p0), and one
# that leaves at the trailing edge within THETA_EDGE dt of the start of a step as gone with no work:
# otherwise the entry row (E_n - theta r_a) / (1 - theta) and the exit slip velocity
# (u_exit - u_old) / (phi dt) divide the rounding of a difference of nearly equal values by a
# vanishing time (a wear depth of 1e283 m was seen where the patch shrank as fast as the particles
# moved, |da/dx| = 1.2, under 45 mm corrugation).
THETA_EDGE = 1e-10
MIN_NODES = 11  # fewest grid nodes across the patch (the schema's bound on numerics.contact.nodes; tested equal)
CLOSURES = ("default", "report")


@dataclass(frozen=True)
class ContactNumerics:
    """How the contact is modelled, discretised and closed (config keys ``numerics.contact`` and
    ``contact.closure``, ``contact.closure_scale``, ``contact.normal``, ``contact.wear_path``). Every field is
    given: the defaults are the configuration's alone (config/config.yaml and its schema).

    Attributes
    ----------
    nodes : grid nodes across the largest patch [-], >= MIN_NODES
    closure : 'default' (well-posed log kernel) or 'report' (eqs 32-33)
    closure_scale : s, scale of the closure's rigid compliance [-], > 0
    normal : the normal-contact model, a rail.contact.models.NormalContact (given by its name, it is
                    looked up): 'report' (point spring on the roughness at the wheel centre, Hertz
                    patch with the local rail curvature, eqs 22-24) or 'nonhertzian' (the roughness
                    under the patch: the force through the contact filter J0(beta a), the exact
                    single-zone 2D pressure; rail.contact.normal, docs/contact.md)
    path : where the wear is deposited (config key contact.wear_path), a rail.contact.models.WearPath
                    (given by its name, it is looked up): 'wheel' (the report's: the patch under the
                    wheel centre, moving at V) or 'patch' (its true path, centred c(x_w) ahead of the
                    wheel: rail.contact.passage, docs/contact.md)
    """

    nodes: int
    closure: str
    closure_scale: float
    normal: NormalContact | str
    path: WearPath | str

    def __post_init__(self):
        if not isinstance(self.nodes, (int, np.integer)) or self.nodes < MIN_NODES:
            raise ValueError(f"numerics.contact.nodes = {self.nodes!r} is not allowed: it must be an integer >= {MIN_NODES}.")
        if self.closure not in CLOSURES:
            raise ValueError(f"contact.closure = {self.closure!r} is not allowed: it must be one of {list(CLOSURES)}.")
        if not (np.isfinite(self.closure_scale) and self.closure_scale > 0):
            raise ValueError(f"contact.closure_scale = {self.closure_scale!r} is not allowed: it must be > 0.")
        object.__setattr__(self, "path", wear_path(self.path))  # the model objects (a name is looked up)
        object.__setattr__(self, "normal", normal_contact(self.normal))

    def __repr__(self):
        # the wear path by its name, as when it was a string: the repr is hashed into the keys of class
        # spectra (rail.setup.study_files.class_key), which stay those of every earlier run
        return (f"ContactNumerics(nodes={self.nodes!r}, closure={self.closure!r}, closure_scale={self.closure_scale!r}, "
                f"normal={self.normal!r}, path={self.path.name!r})")


def rolling_grid(a_max: float, L: float, nodes: int):
    """Grid spacing Delta = L / N_x with N_x integer, at least ``nodes`` nodes across 2 a_max.

    Parameters
    ----------
    a_max : float
        Largest contact half-length [m].
    L : float
        Bay length [m]; the spacing divides it.
    nodes : int
        Grid nodes across 2 a_max [-], >= MIN_NODES.

    Returns
    -------
    delta : float
        Grid spacing [m].
    N_x : int
        Grid spacings per bay [-].
    M : int
        Index of the centre node; the grid has 2M + 1 nodes and (2M + 1) Delta > 2 a_max.
    """
    if nodes < MIN_NODES:
        raise ValueError(f"numerics.contact.nodes = {nodes} is not allowed: it must be >= {MIN_NODES}.")
    Nx = int(np.ceil(L * (nodes - 1) / (2 * a_max)))
    delta = L / Nx
    M = int(np.ceil(a_max / delta)) + 1
    return delta, Nx, M

