"""One function per report figure: take the figure's dataset, return a matplotlib Figure.

Nothing here computes physics, saves or shows; the Agg backend is used so that figures are
made the same way on a laptop, in CI and on a cluster node.  Line styles follow the report's
captions.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402

__all__ = ["fig02", "fig03", "fig04", "fig05", "fig06", "fig08", "fig22"]

_SIZE = (6.0, 4.0)


def _new():
    fig, ax = plt.subplots(figsize=_SIZE, layout="constrained")
    ax.grid(True, alpha=0.3)
    return fig, ax


def fig02(ds: xr.Dataset):
    """Fig. 2: real (solid) and imaginary (dashed) parts of the folded integrand of eq (14)."""
    fig, ax = _new()
    beta = ds["wavenumber"]
    ax.plot(beta, ds["integrand_real"], "-", color="k", label="real part")
    ax.plot(beta, ds["integrand_imag"], "--", color="tab:red", label="imaginary part")
    for key, name in (("beta_P_rad_per_m", r"$\beta_1$"), ("beta_S_rad_per_m", r"$\beta_2$")):
        ax.axvline(ds.attrs[key], color="0.5", lw=0.8, ls=":")
        ax.annotate(name, (ds.attrs[key], 0.97), xycoords=("data", "axes fraction"), ha="right", va="top")
    ax.set_xlabel(r"wavenumber $\beta$ (rad/m)")
    ax.set_ylabel(r"integrand of eq (14) (m$^2$/N)")
    ax.set_title(f"f = {ds.attrs['frequency_Hz']:g} Hz, r = {1e3 * ds.attrs['radius_m']:g} mm", fontsize=9)
    ax.legend(loc="lower right")
    return fig


def fig03(ds: xr.Dataset):
    """Fig. 3: beta G against wavenumber for beta >= 2 beta_R, with the limit of eq (15)."""
    fig, ax = _new()
    ax.plot(ds["wavenumber"], ds["beta_G"], "-", color="k", label=r"$\beta G(\beta,\omega)$")
    ax.plot(ds["wavenumber"], ds["static_limit"], "--", color="tab:blue", label=r"$2(1-\nu^2)/E$, eq (15)")
    ax.set_xlabel(r"wavenumber $\beta$ (rad/m)")
    ax.set_ylabel(r"$\beta G$ (m$^2$/N)")
    ax.set_title(f"f = {ds.attrs['frequency_Hz']:g} Hz", fontsize=9)
    ax.legend()
    return fig


def fig04(ds: xr.Dataset):
    """Fig. 4: real part of eq (16) (solid) against Boussinesq's eq (17) (dashed)."""
    fig, ax = _new()
    r_mm = 1e3 * ds["radius"]
    ax.plot(r_mm, ds["displacement_real"], "-", color="k", label="real part, eq (16)")
    ax.plot(r_mm, ds["displacement_boussinesq"], "--", color="tab:red", label="eq (17), Boussinesq")
    ax.set_yscale("log")
    ax.set_xlabel("distance from the loading point r (mm)")
    ax.set_ylabel("vertical displacement amplitude (m)")
    ax.set_title(f"unit load, f = {ds.attrs['frequency_Hz']:g} Hz", fontsize=9)
    ax.legend()
    return fig


def fig05(ds: xr.Dataset):
    """Fig. 5: power radiated into the half-space by a unit harmonic load."""
    fig, ax = _new()
    ax.plot(ds["frequency"], ds["radiated_power"], "-", color="k")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("radiated power (W)")
    ax.set_title(f"vertical point load of amplitude {ds.attrs['load_N']:g} N", fontsize=9)
    return fig


def fig06(ds: xr.Dataset):
    """Fig. 6: loss factor of the contact spring against frequency."""
    fig, ax = _new()
    ax.plot(ds["frequency"], ds["loss_factor"], "-", color="k")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(r"contact-spring loss factor $\eta_H$ (-)")
    ax.set_title(f"$k_H$ = {ds.attrs['hertz_stiffness_N_per_m']:.3g} N/m", fontsize=9)
    return fig


def fig08(ds: xr.Dataset):
    """Fig. 8: position-history of the normal dynamic contact force (solid), roughness (dotted, not to scale)."""
    fig, ax = _new()
    x = ds["position"]
    ax.plot(x, ds["dynamic_force"] / 1e3, "-", color="k", label="dynamic contact force")
    ax.set_xlabel("wheel position in the sleeper bay (m)")
    ax.set_ylabel("normal dynamic contact force (kN)")
    ax2 = ax.twinx()
    ax2.plot(x, ds["roughness"] * 1e6, ":", color="tab:blue", label="roughness")
    ax2.set_ylabel("roughness (um)")
    lines = ax.get_lines() + ax2.get_lines()
    ax.legend(lines, [ln.get_label() for ln in lines], loc="upper right", fontsize=8)
    ax.set_title(
        f"V = {ds.attrs['speed_m_per_s']:g} m/s, {1e6 * ds.attrs['roughness_amplitude_m']:g} um at "
        f"{ds.attrs['roughness_frequency_Hz']:g} Hz",
        fontsize=9,
    )
    return fig


def fig22(ds: xr.Dataset):
    """Fig. 22: normal contact force over a smooth rail at each speed (solid, dashed, ...)."""
    fig, ax = _new()
    styles = ["-", "--", "-.", ":"]
    for i, name in enumerate(v for v in ds.data_vars if v.startswith("force_V")):
        V = name.removeprefix("force_V")
        ax.plot(ds["position"], ds[name] / 1e3, styles[i % 4], color="k", label=f"{V} m/s")
    ax.set_xlabel("wheel position in the sleeper bay (m)")
    ax.set_ylabel("normal contact force (kN)")
    ax.set_title("smooth rail", fontsize=9)
    ax.legend()
    return fig
