"""Wheel/rail contact (report sec. 3-4.3): a package named by model.

* ``hertz``: the contact material and its friction law, the one compliance, the Hertz patch (eqs 22-24).
* ``steady``: Carter's steady rolling solution (``carter``), the analytic limit of the march.
* ``normal``: the normal contact that sees the roughness in the patch (brute force, exact single
  zone, several zones) and its contact filters.
* ``models``: the contact's model choices as objects: the normal-contact models (``ReportNormal``,
  ``NonHertzianNormal``), each with its filter and its patch, the wear paths (``WheelPath``,
  ``PatchPath``); the friction law (``hertz.FrictionLaw``) is the material's; the scenario holds them
  (ContactNumerics.normal, ContactNumerics.path, ContactMaterial.friction_law).
* ``numerics``: the grid, the closures, ContactNumerics.
* ``basis``: the square-root-weighted traction basis and its log-kernel influence matrix.
* ``influence``: the influence matrix at a(t), rebuilt exactly or interpolated in a from a table.
* ``steps``: the steps of one time step (pressure, particle entry, stick solve, exit slip, step
  work), compiled; ``march`` runs them (solve_tangential) and ``tangent`` differentiates them
  (work_tangent).
* ``passage``: a wheel passage's inputs to the march (grid, force, half-length, pressure shape).

The names of the former rail.contact module are importable from here. ``passage`` and ``normal``
are imported on use (they import rail.interaction and its track models).
"""

from __future__ import annotations

from .basis import _basis_matrix, _basis_workspace, _closure_matrix, chebyshev_hat_moments  # noqa: F401 (kernels, as before)
from .steady import carter
from .hertz import (FRICTION_LAWS, ContactError, ContactMaterial, FrictionLaw, composite_modulus, compliance, equivalent_radius,
                    friction_law, friction_law_of, hertz_half_length, hertz_pressure, report_rigid_compliance)
from .march import (CHECKERBOARD_LIMIT, TangentialSolution, _march, checkerboard_measure,  # noqa: F401
                    perturbation_growth, solve_tangential)
from .models import (NORMAL_MODELS, WEAR_PATHS, NonHertzianNormal, NormalContact, PatchPath, ReportNormal, WearPath, WheelPath,
                     normal_contact, wear_path)
from .numerics import CLOSURES, MIN_NODES, THETA_EDGE, ContactNumerics, rolling_grid  # noqa: F401
from .tangent import work_tangent

__all__ = [
    "ContactMaterial",
    "ContactError",
    "composite_modulus",
    "compliance",
    "report_rigid_compliance",
    "hertz_half_length",
    "equivalent_radius",
    "hertz_pressure",
    "carter",
    "TangentialSolution",
    "ContactNumerics",
    "MIN_NODES",
    "solve_tangential",
    "work_tangent",
    "rolling_grid",
    "checkerboard_measure",
    "perturbation_growth",
    "NormalContact",
    "ReportNormal",
    "NonHertzianNormal",
    "normal_contact",
    "NORMAL_MODELS",
    "WearPath",
    "WheelPath",
    "PatchPath",
    "wear_path",
    "WEAR_PATHS",
    "FrictionLaw",
    "friction_law_of",
    "friction_law",
    "FRICTION_LAWS",
]
