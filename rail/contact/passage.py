"""The inputs of one wheel's passage over the period for the tangential march: the contact grid, and
the normal contact (force, half-length, pressure shape) at every step, from the wheel/rail force and
the roughness (report eqs 22-24, or rail.contact.normal through the scenario's normal-contact model).

Positions: the wheel centre at step i is x = (i - spin) Delta; the rail points x_k = k Delta of the
period are the wear's (rail.wear.bay_wear).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..interaction import ForceResult, Roughness, force_on_grid
from .hertz import ContactError, ContactMaterial
from .numerics import ContactNumerics, rolling_grid

__all__ = ["MarchInputs", "march_inputs", "SPIN_UP_TRANSITS"]

# spin-up from zero traction over this many patch transits (at most a bay) before the bay: a
# perturbation of the traction decays by 0.1-0.5 per transit (rail.wear)
SPIN_UP_TRANSITS = 20


@dataclass(frozen=True)
class MarchInputs:
    """What bay_wear hands the tangential march (solve_tangential) for one wheel over the period.

    Attributes
    ----------
    P, a : (steps,) normal force [N] and half-length [m] at each step of the march
    shape : (steps, 2M + 1) pressure shape factor (normal contact 'nonhertzian'), else None
    delta : grid spacing [m]; Nx: spacings over the period; M: centre node; spin: spin-up steps
             (step spin + k has the wheel at x_k = k delta)
    min_shape, shift : as WearResult
    dt : (steps,) the time of each step [s] on the patch's true path (the wheel travels V dt while the
         patch moves delta over the rail), else None (delta / V)
    x_wheel : (steps,) the wheel centre at each step [m] (the patch centre is at (i - spin) delta)
    """

    P: np.ndarray
    a: np.ndarray
    shape: np.ndarray | None
    delta: float
    Nx: int
    M: int
    spin: int
    min_shape: float
    shift: float
    dt: np.ndarray | None = None
    x_wheel: np.ndarray | None = None


def march_inputs(forces: ForceResult, wheel_index: int, roughness: Roughness, material: ContactMaterial,
                 numerics: ContactNumerics, grid_phase: float = 0.0, a_max: float | None = None,
                 grid: tuple | None = None) -> MarchInputs:
    """The contact grid and the normal contact (force, half-length, pressure shape) of every step of
    bay_wear's march (eqs 22-24 or rail.contact.normal.patch_contact).

    Parameters
    ----------
    forces, wheel_index, roughness, material, numerics, grid_phase, a_max
        As bay_wear (forces [N], roughness [m], a_max [m]; bay_wear checks them).
    grid : tuple, optional
        (delta [m], spacings per bay, centre node M, spin-up steps) of a one-bay march to use as is,
        repeated over the N bays (the linearised spectrum holds the smooth rail's grid for its
        probes: a probe must not move the grid). Default: chosen from the patch as bay_wear does.

    Returns
    -------
    MarchInputs
        Force [N], half-length [m] and pressure shape [-] at each step, grid spacing [m] and sizes.
    """
    L = forces.period  # the period N L of roughness and force
    nodes = numerics.nodes
    model = numerics.normal
    P_s = force_on_grid(forces, 512 * forces.bays)[wheel_index]  # at x = k L / (512 N)
    a_s = model.half_lengths(P_s, roughness, L, material)
    a_est = float(np.max(a_s)) * 1.02 if a_max is None else a_max
    # The grid holds the largest patch, estimated from 512 N samples; where the patch at the grid's
    # own points is larger (a half-length that changes fast between samples: a rail nearly as concave
    # as the wheel, or a force that peaks between them), the grid is rebuilt for it.
    for _attempt in range(3):
        # the grid of one bay, repeated over the N bays of the period (so that a one-bay-periodic
        # roughness gives the same wear with any N)
        if grid is not None:
            delta, Nx, M, spin = float(grid[0]), int(grid[1]) * forces.bays, int(grid[2]), int(grid[3])
        else:
            delta, Nx, M = rolling_grid(a_est, forces.L, nodes)
            if grid_phase:
                Nx += int(round(grid_phase * forces.L / max(float(np.mean(a_s)), 1e-300)))
            if grid_phase or forces.bays > 1:
                Nx *= forces.bays
                delta = L / Nx
                M = int(np.ceil(a_est / delta)) + 1
            # spin-up from zero traction over SPIN_UP_TRANSITS patch transits (at most a bay) before the bay
            spin = min(Nx, int(np.ceil(SPIN_UP_TRANSITS * 2 * a_est / delta)))
        steps = spin + Nx + 2 * M + 1
        x_wheel = (np.arange(steps) - spin) * delta  # wheel centre at each step; x = 0 at step `spin`
        on_grid = (np.arange(steps) - spin) % Nx  # x_wheel mod L = on_grid L / Nx: exact grid points
        P = force_on_grid(forces, Nx)[wheel_index][on_grid]
        xi = (np.arange(2 * M + 1) - M) * delta
        patch = model.patches(P, x_wheel, on_grid, Nx, roughness, L, material, xi)
        dt = None
        if numerics.path.modelled_shift:
            P, x_wheel, patch, dt = true_path(forces, wheel_index, roughness, material, model, x_wheel, on_grid, Nx, P, patch, xi)
        a = patch.a
        if a_max is not None or grid is not None or float(np.max(a)) < (M - 0.5) * delta:
            break
        a_est = 1.02 * float(np.max(a))
    else:
        raise ContactError(f"the patch half-length {float(np.max(a)) * 1e3:.3g} mm of wheel {wheel_index} keeps outgrowing its "
                           "contact grid (the rail is nearly as concave as the wheel: multiple contact is near).")
    if float(np.min(a)) < 2.5 * delta:  # the patch changes length by more than one grid can hold along the period
        raise model.multiple_contact(wheel_index, float(np.min(a)), float(np.max(a)))
    return MarchInputs(P=P, a=a, shape=patch.shape, delta=delta, Nx=Nx, M=M, spin=spin, min_shape=patch.min_shape, shift=patch.shift,
                       dt=dt, x_wheel=x_wheel)


def true_path(forces: ForceResult, wheel_index: int, roughness: Roughness, material: ContactMaterial, model, x_patch, on_grid,
              Nx: int, P_patch, patch, xi):
    """The passage on the patch's true path: the patch centre steps uniformly over the rail (x_p = i delta),
    the wheel centre is where its patch is centred there, x_w + c(x_w) = x_p, and each step lasts the
    wheel's travel over V.

    The centre c is the normal contact's own (rail.contact.models: R_w r' for the report's model, the
    single- or multi-zone 2D solution's for the non-Hertzian one). x_w follows by two evaluations of c
    (x_w = x_p - c(x_p - c(x_p)): an error of second order in the roughness). The force is the wheel's
    at x_w, P(x_p) - c P'(x_p) (the force's slope from its harmonics; the shift c is microns, the
    spacing a fraction of a millimetre); the half-length and pressure shape are the contact's with the
    wheel at x_w (the report's curvature is taken at the patch, x_p: the difference is of second order).
    The step time is dt_i = (x_w,i - x_w,i-1) / V = delta (1 - dc/dx) / V to first order: the patch lingers
    where c decreases (on crests) and hurries where it increases.

    Parameters
    ----------
    forces, wheel_index, roughness, material, model
        As march_inputs (model: the normal-contact model).
    x_patch, on_grid, Nx : the patch centre's positions [m] at the steps, their grid index, spacings per period
    P_patch, patch : the force [N] and the contact (rail.contact.models.Patches) with the wheel at x_patch
    xi : the contact grid's nodes [m]

    Returns
    -------
    P : (steps,) [N]; x_wheel : (steps,) [m]; patch : Patches with the wheel at x_wheel; dt : (steps,) [s]

    Raises
    ------
    ContactError
        Where the patch's path folds back (dc/dx <= -1: the wheel would move its patch backwards).
    """
    L, delta = forces.period, float(x_patch[1] - x_patch[0])
    slope = force_on_grid(forces, Nx, derivative=1)[wheel_index][on_grid]  # dP/dx at x_p [N/m]
    x_w = x_patch - patch.centre  # the first estimate
    P = P_patch - patch.centre * slope
    patch = model.patches(P, x_w, on_grid, Nx, roughness, L, material, xi)
    x_w = x_patch - patch.centre
    # the wheel one step before the first: its patch one grid point back, where the passage (longer than
    # the period) has the contact's centre already (c is periodic over the period)
    c_before = patch.centre[np.flatnonzero(on_grid == (on_grid[0] - 1) % Nx)[0]]
    travel = np.diff(np.concatenate([x_patch[:1] - delta - c_before, x_w]))
    if np.any(travel <= 0):
        i = int(np.argmin(travel))
        raise ContactError(f"the contact patch of wheel {wheel_index} moves backwards over the rail at x = {x_patch[i]:.4f} m "
                           f"(its centre moves {1 - travel[i] / delta:.3g} of the wheel's step the other way: dc/dx <= -1): "
                           "the roughness is far too large for one contact patch.")
    return P, x_w, patch, travel / forces.speed
