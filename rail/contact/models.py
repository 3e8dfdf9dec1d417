"""The contact's model choices as objects: the normal-contact models, which know their filter and
their patch (config key ``contact.normal``), the wear path (``contact.wear_path``) and the friction
law's name (rail.contact.hertz.FrictionLaw, held by the material: ContactMaterial.friction_law).

* ``ReportNormal`` ('report', sec. 4.2-4.3, eqs 22-24): a point spring on the roughness at the wheel
  centre (the force sees the roughness unfiltered) and a Hertz patch whose radius follows the local
  rail curvature, 1/R = 1/R_w + kappa.
* ``NonHertzianNormal`` ('nonhertzian', rail.contact.normal): the roughness under the patch. The
  force sees the roughness through the contact filter J0(beta a_0); the patch is the exact
  single-zone 2D solution (or several zones by the brute force where one does not hold), its
  pressure the Hertz ellipse times a shape factor.

The wear path (``WearPath``: ``WheelPath`` 'wheel', ``PatchPath`` 'patch') says whether the patch's
true path is marched (``modelled_shift``, rail.contact.passage) and, as ``validity``, what a result
leaves out; the friction law (rail.contact.hertz.FrictionLaw: 'step', 'falling' or 'constant') is
read from the material's friction coefficients. Each choice has ``name`` (the
configuration's value, which results store as a value) and ``description`` (stored beside it, never
parsed back); ``wear_path(name)`` looks a stored value up again.

The rest of the package asks the model, never its name: ``filter`` (what the contact spring sees),
``half_lengths`` (the patch along the period, to size the grid), ``patches`` (half-length, pressure
shape and centre shift at each step of a passage) and ``multiple_contact`` (the error where one grid
cannot hold the contact).

Conventions: x along the rail in the direction of travel [m]; roughness r(x) positive upwards, given
by its complex Fourier coefficients Z_j over the period N L (rail.interaction.Roughness); curvature
kappa = -z'' [1/m]; forces in N.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._lazyjit import njit
from .hertz import ContactError, ContactMaterial, equivalent_radius, hertz_half_length

__all__ = ["NormalContact", "ReportNormal", "NonHertzianNormal", "Patches", "NORMAL_MODELS", "normal_contact",
           "WearPath", "WheelPath", "PatchPath", "WEAR_PATHS", "wear_path", "roughness_slope", "curvature_on_grid"]


def roughness_slope(roughness, period: float):
    """The slope r'(x) of the roughness as a function of position (rail.contact.normal.patch_contact).

    r' is sampled by one inverse FFT on a grid of at least 64 points per shortest wavelength and
    interpolated linearly (periodically): relative error at most (2 pi / 64)^2 / 8 = 1.2e-3 of the
    shortest harmonic's slope, less for the longer ones.

    Parameters
    ----------
    roughness : rail.interaction.Roughness
        Z_j, j = -J..J over the period [m].
    period : float
        N L [m].

    Returns
    -------
    callable
        x [m] (any shape) -> r'(x) [-].
    """
    J = roughness.harmonics
    n = 1 << int(np.ceil(np.log2(max(64 * J, 64))))
    j = np.arange(-J, J + 1)
    acc = np.zeros(n, dtype=complex)
    np.add.at(acc, j % n, 1j * j * (2 * np.pi / period) * roughness.Z)
    values = np.real(np.fft.ifft(acc)) * n
    grid = np.arange(n) * period / n
    return _periodic_interpolant(grid, values, period)


def _periodic_interpolant(xp, fp, period: float):
    """x -> np.interp(x, xp, fp, period=period), the same numbers, by a compiled loop on the wrapped table.

    Parameters
    ----------
    xp : ndarray, shape (n,)
        Increasing sample positions in [0, period) [m], about equally spaced (each point's interval is
        first guessed from the mean spacing).
    fp : ndarray, shape (n,)
        The values there [any unit].
    period : float
        The period [m], > 0.

    Returns
    -------
    callable
        x [m] (any shape) -> the periodic linear interpolant at x [unit of fp], as numpy.interp with
        ``period``: x wrapped to [0, period), the table padded with one sample at each end.
    """
    xp_wrapped = np.concatenate((xp[-1:] - period, xp, xp[:1] + period))
    fp_wrapped = np.concatenate((fp[-1:], fp, fp[:1]))
    slopes = np.diff(fp_wrapped) / np.diff(xp_wrapped)  # as numpy.interp: (f_{j+1} - f_j) / (x_{j+1} - x_j)

    def interpolant(x):
        x = np.asarray(x, dtype=float)
        out = np.empty(x.shape)
        _interp_wrapped(np.ascontiguousarray(x).reshape(-1), xp_wrapped, fp_wrapped, slopes, float(period),
                        out.reshape(-1))
        return out

    return interpolant


@njit(cache=True)
def _wrap(x, period):
    """x % period [m] (Python's and numpy's: fmod, plus the period where the sign differs), the same number
    (-0 kept): x itself in [0, period), x - period (exact) in [period, 2 period), x + period in [-period, 0)."""
    if 0.0 <= x < period:
        return x
    if period <= x < 2.0 * period:
        return x - period
    if -period <= x < 0.0:
        return x + period
    return x % period


@njit(cache=True)
def _interp_wrapped(x, xp, fp, slopes, period, out):
    """out = numpy.interp(x % period, xp, fp) for an increasing table xp covering [0, period] [unit of fp].

    The interval j (the largest with xp_j <= x) is guessed from the mean spacing and walked to, which is
    numpy's binary search's answer; the value is numpy's, slopes_j (x - xp_j) + fp_j, fp_j where
    x = xp_j or at the table's last point, and NaN for NaN x. x [m], period [m]; out: shape of x.
    """
    n = xp.size
    h = (xp[n - 1] - xp[0]) / (n - 1)
    for i in range(x.size):
        y = _wrap(x[i], period)
        if y != y:
            out[i] = y
            continue
        j = min(max(int((y - xp[0]) / h), 0), n - 1)
        while j > 0 and xp[j] > y:
            j -= 1
        while j < n - 1 and xp[j + 1] <= y:
            j += 1
        if j == n - 1 or xp[j] == y:
            out[i] = fp[j]
        else:
            out[i] = slopes[j] * (y - xp[j]) + fp[j]


def curvature_on_grid(roughness, n: int, period: float):
    """kappa = -z'' (eq 20) [1/m] at x_k = k P / n over the roughness period P [m], by one inverse
    FFT (the coefficients folded into n bins: exact at these points, the same values as the direct sum
    to rounding).

    Parameters
    ----------
    roughness : rail.interaction.Roughness
        The roughness coefficients Z_j [m], j = -J..J, periodic over P.
    n : int
        Number of grid points over the period [-], >= 1.
    period : float
        The roughness period P [m], > 0.

    Returns
    -------
    ndarray, (n,)
        The curvature kappa [1/m] at x_k = k P / n.
    """
    J = roughness.harmonics
    j = np.arange(-J, J + 1)
    beta = 2 * np.pi / period
    acc = np.zeros(n, dtype=complex)
    np.add.at(acc, j % n, (j * beta) ** 2 * roughness.Z)
    return np.real(np.fft.ifft(acc)) * n


@dataclass(frozen=True)
class Patches:
    """The normal contact at the steps of a passage.

    Attributes
    ----------
    a : (steps,) half-length [m]
    shape : (steps, nodes) pressure shape factor [-] (pressure = Hertz ellipse x shape), or None for
            the Hertz ellipse itself
    min_shape : smallest shape factor over the steps [-] (1 for Hertz; 0 where several zones)
    shift : largest abs(c) / a, the patch centre's move relative to the wheel over its half-length [-]
    centre : (steps,) c, the patch centre relative to the wheel centre, positive ahead [m] (the
            report's model: the rigid wheel's tangent point R_w r'(x); the 2D patch: R_w <r'>)
    """

    a: np.ndarray
    shape: np.ndarray | None
    min_shape: float
    shift: float
    centre: np.ndarray


class NormalContact:
    """A normal-contact model (a frozen dataclass in each subclass). ``name`` is its config value,
    ``description`` what it is, in words (a result's attribute normal_contact_description)."""

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    # the model holds for wavelengths above this many static patch lengths 2 a_0 (0: no such limit)
    valid_patch_lengths: ClassVar[float] = 0

    def __str__(self) -> str:
        return self.name

    def filter(self, beta, a0):
        """What the contact spring sees of a roughness harmonic of wavenumber beta [rad/m] about the
        static half-length a0 [m] [-]."""
        raise NotImplementedError

    def half_lengths(self, P, roughness, period: float, material: ContactMaterial):
        """The half-length [m] at P.size equally spaced points x_k = k period / P.size of the period
        (P [N] there), to size the contact grid."""
        raise NotImplementedError

    def patches(self, P, x_wheel, on_grid, Nx: int, roughness, period: float, material: ContactMaterial, xi) -> Patches:
        """The contact at each step of a passage: P [N] and x_wheel [m] per step, on_grid the wheel's
        grid point (x_wheel mod period = on_grid period / Nx), xi [m] the contact grid's nodes."""
        raise NotImplementedError

    def multiple_contact(self, wheel: int, a_min: float, a_max: float) -> ContactError:
        """The error where the half-length along the period ranges too far for one grid."""
        raise NotImplementedError


@dataclass(frozen=True)
class ReportNormal(NormalContact):
    """The report's normal contact (eqs 22-24): the roughness at the wheel centre drives the spring;
    a Hertz patch with the local curvature. Valid for wavelengths much longer than the patch."""

    name: ClassVar[str] = "report"
    description: ClassVar[str] = ("report: the report's point spring on the roughness at the wheel centre and a Hertz patch with the "
                                  "local rail curvature (eqs 22-24); valid for wavelengths above about ten patch lengths")
    # above ten patch lengths its filter 1 is within 0.22 dB of the 2D patch's J0(beta a_0) (docs/contact.md)
    valid_patch_lengths: ClassVar[float] = 10

    def filter(self, beta, a0):
        return np.ones(np.shape(beta))

    def half_lengths(self, P, roughness, period, material):
        kappa = curvature_on_grid(roughness, np.size(P), period)
        return hertz_half_length(P, equivalent_radius(kappa, material), material)

    def patches(self, P, x_wheel, on_grid, Nx, roughness, period, material, xi):
        kappa = curvature_on_grid(roughness, Nx, period)[on_grid]
        a = hertz_half_length(P, equivalent_radius(kappa, material), material)
        centre = material.wheel_radius * roughness_slope(roughness, period)(x_wheel)  # the tangent point (eqs 22-24 keep it at 0)
        return Patches(a=a, shape=None, min_shape=1.0, shift=0.0, centre=centre)

    def multiple_contact(self, wheel, a_min, a_max):
        return ContactError(f"multiple contact is near: the patch half-length of wheel {wheel} ranges from "
                            f"{a_min * 1e3:.3g} to {a_max * 1e3:.3g} mm along the period (the rail nearly as "
                            "concave as the wheel); the report's local-curvature Hertz patch is far outside its validity there "
                            "(contact.normal: nonhertzian sees the roughness under the patch).")


@dataclass(frozen=True)
class NonHertzianNormal(NormalContact):
    """The roughness under the patch (rail.contact.normal): the force through J0(beta a_0), the
    exact single-zone 2D pressure, several zones by the brute force where one does not hold."""

    name: ClassVar[str] = "nonhertzian"
    description: ClassVar[str] = ("nonhertzian: the roughness under the patch, the force through the contact filter J0(beta a_0), "
                                  "the exact single-zone 2D pressure (several zones by the brute force; docs/contact.md)")

    def filter(self, beta, a0):
        from .normal import approach_filter
        return approach_filter(beta, a0)

    def half_lengths(self, P, roughness, period, material):
        from .normal import patch_contact
        hertz_half_length(P, material.wheel_radius, material)  # refuses a negative (lost) contact force
        slope = roughness_slope(roughness, period)
        a = patch_contact(P, np.arange(np.size(P)) * period / np.size(P), slope, material, np.zeros(1), strict=False).a
        # NaN where one zone does not hold: the grid is rebuilt if the zones' hull outgrows it
        return np.where(np.isfinite(a), a, np.nanmax(np.append(a, hertz_half_length(np.max(P), material.wheel_radius, material))))

    def patches(self, P, x_wheel, on_grid, Nx, roughness, period, material, xi):
        from .normal import passage_contact
        # one zone (exact), or several where the pressure would turn negative inside the patch (brute force)
        pc = passage_contact(P, x_wheel, roughness_slope(roughness, period), material, xi)
        return Patches(a=pc.a, shape=pc.shape, min_shape=float(pc.min_shape.min()), shift=float(np.max(np.abs(pc.shift) / pc.a)),
                       centre=pc.shift)

    def multiple_contact(self, wheel, a_min, a_max):
        return ContactError(f"multiple contact: the contact of wheel {wheel} ranges from one zone of half-length "
                            f"{a_min * 1e3:.3g} mm to zones over +-{a_max * 1e3:.3g} mm along the period (the "
                            "wheel rides on separate roughness crests); one contact grid cannot resolve both (fewer than 2.5 "
                            "spacings across the smallest).")


_MODELS = {cls.name: cls for cls in (ReportNormal, NonHertzianNormal)}
NORMAL_MODELS = tuple(_MODELS)


def normal_contact(model) -> NormalContact:
    """The normal-contact model named ``model`` (config key contact.normal), or ``model`` itself.

    Parameters
    ----------
    model : str or NormalContact
        'report' or 'nonhertzian' [-].

    Returns
    -------
    NormalContact
    """
    if isinstance(model, NormalContact):
        return model
    if not isinstance(model, str) or model not in _MODELS:
        raise ValueError(f"contact.normal = {model!r} is not allowed: it must be one of {list(NORMAL_MODELS)}.")
    return _MODELS[model]()


class WearPath:
    """Where the wear is deposited (config key contact.wear_path; a frozen dataclass in each subclass).

    ``name`` is its config value, ``description`` the result attribute wear_path_description,
    ``modelled_shift`` whether the move of the contact centre c(x_w) is in the model (the patch's true
    path is marched, rail.contact.passage.true_path), and ``validity`` what a result's validity line
    says of it (rail.studies.validity.validity_text).
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    modelled_shift: ClassVar[bool] = False
    validity: ClassVar[str] = ""

    def __str__(self) -> str:
        return self.name

    def attributes(self) -> dict:
        """The wear path as a result's attributes: ``wear_path`` (the value) beside ``wear_path_description``,
        and ``contact_shift_modelled`` (1 where the move of the contact centre is in the model, else 0), the
        flag a figure's note reads from the dataset alone.

        Returns
        -------
        dict
            Attribute name -> str or int [-].
        """
        return {"wear_path": self.name, "wear_path_description": self.description, "contact_shift_modelled": int(self.modelled_shift)}


@dataclass(frozen=True)
class WheelPath(WearPath):
    """The report's wear under the wheel centre: the patch centred under the wheel, moving at its speed V."""

    name: ClassVar[str] = "wheel"
    description: ClassVar[str] = "wheel: the wear under the wheel centre (the report's); the move of the contact centre is neglected"
    validity: ClassVar[str] = ("wear under the wheel centre (the report's model): the contact centre's move, a wear term of about "
                               "1.8 w R_w beta^2 per unit roughness for long waves, is left out (contact.wear_path: patch models it)")


@dataclass(frozen=True)
class PatchPath(WearPath):
    """The patch's true path: centred c(x_w) from the wheel, sweeping the rail at V (1 + dc/dx) (docs/contact.md)."""

    name: ClassVar[str] = "patch"
    description: ClassVar[str] = "patch: the wear where the contact patch is, its centre c(x_w) from the wheel (docs/contact.md)"
    modelled_shift: ClassVar[bool] = True
    validity: ClassVar[str] = "wear on the contact patch's true path (its centre's move modelled)"


_PATHS = {cls.name: cls for cls in (WheelPath, PatchPath)}
WEAR_PATHS = tuple(_PATHS)


def wear_path(path) -> WearPath:
    """The wear path named ``path`` (config key contact.wear_path, or a result's attribute wear_path), or ``path`` itself.

    Parameters
    ----------
    path : str or WearPath
        'wheel' or 'patch' [-].

    Returns
    -------
    WearPath
    """
    if isinstance(path, WearPath):
        return path
    if not isinstance(path, str) or path not in _PATHS:
        raise ValueError(f"contact.wear_path = {path!r} is not allowed: it must be one of {list(WEAR_PATHS)}.")
    return _PATHS[path]()
