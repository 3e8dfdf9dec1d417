"""Datasets behind the report's figures: physics from the modules below, units and names here.

Each function returns an xarray Dataset whose every variable carries ``units`` and
``long_name``; ``rail.setup.io.finalize`` adds the configuration and versions.
"""

from __future__ import annotations

import re

import numpy as np
import xarray as xr

from .. import halfspace
from ..halfspace import ElasticMaterial, HalfSpaceNumerics
from ..growth import band_growth, levels_dB
from ..interaction import Roughness, force_history
from ..moving import MovingReceptance
from ..setup.build import HalfSpaceFigureSettings
from ..setup.io import data_var
from ..contact import wear_path as _wear_path

__all__ = ["fig02", "fig03", "fig04", "radiation", "fig05", "fig06",
           "receptance_table", "read_receptance_table", "fig08", "fig22", "wear_case", "fig09", "fig10_11",
           "fig_wear", "fig_wear_spectrum", "growth", "growth_figure", "sweep"]



def _wavenumber_attrs(omega, material):
    b1, b2, bR = halfspace.wavenumbers(omega, material)
    return {
        "beta_P_rad_per_m": float(b1),
        "beta_S_rad_per_m": float(b2),
        "beta_R_rad_per_m": float(bR),
    }


def fig02(material: ElasticMaterial, fig: HalfSpaceFigureSettings, points: int = 600) -> xr.Dataset:
    """Fig. 2: real and imaginary parts of the folded integrand of eq (14), 0 < beta < beta_R.

    Parameters
    ----------
    material : ElasticMaterial
        Young's modulus [Pa], Poisson's ratio [-], density [kg/m^3].
    fig : HalfSpaceFigureSettings
        The figure's frequency [Hz] and radii [m] (figures.halfspace).
    points : int
        Wavenumbers [-].

    Returns
    -------
    xr.Dataset
        The integrand's real and imaginary parts over beta / beta_R [-].
    """
    omega = 2 * np.pi * fig.frequency
    _, _, bR = halfspace.wavenumbers(omega, material)
    beta = (np.arange(points) + 0.5) / points * bR  # midpoints: beta = 0 and beta_R excluded
    f = halfspace.folded_integrand(beta, omega, fig.radius, material)
    return xr.Dataset(
        {
            "integrand_real": data_var("wavenumber", f.real, "m^2/N", "real part of the integrand of the first integral of eq (14)"),
            "integrand_imag": data_var("wavenumber", f.imag, "m^2/N", "imaginary part of the integrand of the first integral of eq (14)"),
        },
        coords={"wavenumber": data_var("wavenumber", beta, "rad/m", "radial wavenumber beta")},
        attrs={"frequency_Hz": fig.frequency, "radius_m": fig.radius, **_wavenumber_attrs(omega, material)},
    )


def fig03(material: ElasticMaterial, fig: HalfSpaceFigureSettings, points: int = 400, upper: float = 20.0) -> xr.Dataset:
    """Fig. 3: beta G(beta, omega) for 2 beta_R <= beta <= ``upper`` beta_R and its limit, eq (15).

    Parameters
    ----------
    material : ElasticMaterial
        Young's modulus [Pa], Poisson's ratio [-], density [kg/m^3].
    fig : HalfSpaceFigureSettings
        The figure's frequency [Hz] and radii [m] (figures.halfspace).
    points : int
        Wavenumbers [-].
    upper : float
        Largest beta / beta_R [-].

    Returns
    -------
    xr.Dataset
        beta G and its limit over beta / beta_R [-].
    """
    omega = 2 * np.pi * fig.frequency
    _, _, bR = halfspace.wavenumbers(omega, material)
    beta = np.linspace(2 * bR, upper * bR, points)
    bG = (beta * halfspace.kernel_G(beta, omega, material)).real
    limit = np.full_like(beta, halfspace.static_limit_beta_G(material))
    return xr.Dataset(
        {
            "beta_G": data_var("wavenumber", bG, "m^2/N", "beta G(beta, omega), eq (9)"),
            "static_limit": data_var("wavenumber", limit, "m^2/N", "limit 2 (1 - nu^2) / E, eq (15)"),
        },
        coords={"wavenumber": data_var("wavenumber", beta, "rad/m", "radial wavenumber beta")},
        attrs={"frequency_Hz": fig.frequency, **_wavenumber_attrs(omega, material)},
    )


def fig04(material: ElasticMaterial, fig: HalfSpaceFigureSettings, numerics: HalfSpaceNumerics) -> xr.Dataset:
    """Fig. 4: displacement under a unit harmonic load from eq (16) and Boussinesq's eq (17).

    Parameters
    ----------
    material : ElasticMaterial
        Young's modulus [Pa], Poisson's ratio [-], density [kg/m^3].
    fig : HalfSpaceFigureSettings
        The figure's frequency [Hz] and radii [m] (figures.halfspace).
    numerics : HalfSpaceNumerics
        Quadrature tolerance [-] and subdivision limit.

    Returns
    -------
    xr.Dataset
        Real and imaginary displacement [m] per unit load [N] over radius [m], and Boussinesq's.
    """
    omega = 2 * np.pi * fig.frequency
    w = halfspace.surface_displacement(fig.radii, omega, material, 1.0, numerics)
    return xr.Dataset(
        {
            "displacement_real": data_var("radius", w.real, "m", "real part of the vertical displacement, eq (16), unit load"),
            "displacement_imag": data_var("radius", w.imag, "m",
                                          "imaginary part of the vertical displacement, eq (16) with the Rayleigh residue, unit load"),
            "displacement_boussinesq": data_var("radius", halfspace.boussinesq(fig.radii, material), "m",
                                                "static displacement, Boussinesq eq (17), unit load"),
        },
        coords={"radius": data_var("radius", fig.radii, "m", "distance r from the loading point")},
        attrs={"frequency_Hz": fig.frequency, "load_N": 1.0},
    )


def radiation(material: ElasticMaterial, fig: HalfSpaceFigureSettings, numerics: HalfSpaceNumerics) -> xr.Dataset:
    """Im w0(0), radiated power per unit load and the contact loss factor over frequency.

    Parameters
    ----------
    material : ElasticMaterial
        Young's modulus [Pa], Poisson's ratio [-], density [kg/m^3].
    fig : HalfSpaceFigureSettings
        Frequencies [Hz], contact radius [m] and contact stiffness [N/m] (figures.halfspace).
    numerics : HalfSpaceNumerics
        Quadrature tolerance [-] and subdivision limit.

    Returns
    -------
    xr.Dataset
        Im w0(0) [m/N], radiated power [W] and loss factor [-] over frequency [Hz].
    """
    f = fig.frequencies
    omega = 2 * np.pi * f
    im = halfspace.point_receptance_imag(omega, material, numerics)  # the quadrature, once for the three
    power = halfspace.radiated_power(omega, material, 1.0, numerics, receptance_imag=im)
    eta = halfspace.contact_loss_factor(omega, fig.hertz_stiffness, material, numerics, receptance_imag=im)
    return xr.Dataset(
        {
            "receptance_imag": data_var("frequency", im, "m/N", "imaginary part of the half-space driving-point receptance Im w0(0)"),
            "radiated_power": data_var("frequency", power, "W", "power radiated into the half-space by a 1 N harmonic load"),
            "loss_factor": data_var("frequency", eta, "1", "contact-spring loss factor eta_H = -2 k_H Im w0(0)"),
        },
        coords={"frequency": data_var("frequency", f, "Hz", "frequency")},
        attrs={"hertz_stiffness_N_per_m": fig.hertz_stiffness, "load_N": 1.0},
    )


def fig05(rad: xr.Dataset) -> xr.Dataset:
    """Fig. 5: radiated power for a unit load against frequency.

    Parameters
    ----------
    rad : xr.Dataset
        radiation's dataset.

    Returns
    -------
    xr.Dataset
        radiated_power [W] over frequency [Hz].
    """
    return rad[["radiated_power"]].assign_attrs(load_N=rad.attrs["load_N"])


def fig06(rad: xr.Dataset) -> xr.Dataset:
    """Fig. 6: contact-spring loss factor against frequency.

    Parameters
    ----------
    rad : xr.Dataset
        radiation's dataset.

    Returns
    -------
    xr.Dataset
        loss_factor [-] over frequency [Hz].
    """
    return rad[["loss_factor"]].assign_attrs(hertz_stiffness_N_per_m=rad.attrs["hertz_stiffness_N_per_m"])


def receptance_table(tab, track) -> xr.Dataset:
    """Moving-load receptance matrices A_d[p, k] = a_{p-k}(k Omega_0, d) of rail.moving.receptance_table.

    Parameters
    ----------
    tab : rail.moving.MovingReceptance
        The table (speed [m/s], harmonics K, wheel offsets d [m]).
    track : Track
        Its track (attributes: sleeper spacing [m], ...).

    Returns
    -------
    xr.Dataset
        A_real and A_imag [m/N] over offset, harmonic p and harmonic k.
    """
    K = tab.harmonics
    h = np.arange(-K, K + 1)
    dims = ("offset", "response_harmonic", "force_harmonic")
    ds = xr.Dataset(
        {
            "receptance_real": data_var(dims, tab.A.real, "m/N",
                                        "real part of a_{p-k}(k Omega_0, d): response harmonic p at offset d per unit force harmonic k"),
            "receptance_imag": data_var(dims, tab.A.imag, "m/N", "imaginary part of a_{p-k}(k Omega_0, d)"),
            "quadrature_error": data_var(dims, tab.error, "m/N", "estimated absolute error of the wavenumber quadrature"),
        },
        coords={
            "offset": data_var("offset", tab.offsets, "m", "offset d of the receiving point ahead of the load"),
            "response_harmonic": data_var("response_harmonic", h, "1", "harmonic p of the sleeper-passing frequency in the response"),
            "force_harmonic": data_var("force_harmonic", h, "1", "harmonic k of the sleeper-passing frequency in the force"),
        },
        attrs={
            "speed_m_per_s": tab.speed,
            "sleeper_passing_frequency_Hz": tab.speed / track.L,
            "damping_model": track.damping,
            "quadrature_nodes": tab.nodes,
            "convention": "harmonic p of the rail displacement at offset d equals sum_k A[d, p, k] P_k for force harmonics P_k; "
            "time factor exp(+i p Omega_0 t); displacement and force positive downwards",
        },
    )
    if tab.supports is not None:  # a track periodic over a cell of N bays (rail.moving.cell_receptance_table)
        ds.attrs.update({
            "cell_bays": int(tab.bays),
            "cell_attachment_positions_m": np.asarray(tab.supports, dtype=float),
            "cell_frequency_Hz": tab.speed / (track.L * tab.bays),
            "convention": ds.attrs["convention"].replace("Omega_0", "Omega_P")
            + "; Omega_P = 2 pi V / P, the frequency of the track's cell of N bays (P = N L)",
        })
        for c in ("response_harmonic", "force_harmonic"):
            ds[c].attrs["long_name"] = ds[c].attrs["long_name"].replace("of the sleeper-passing frequency", "of the cell frequency V / (N L)")
    return ds


def bloch_tables(tabs, track) -> xr.Dataset:
    """The receptance tables of a roughness periodic over N bays (rail.moving.bloch_tables) in one
    dataset, along the dimension 'fraction' (nu = r / N); the tables with nu > 0 have no harmonic K
    (their entries there are NaN).

    Parameters
    ----------
    tabs : sequence of rail.moving.MovingReceptance
        The N tables, nu = r / N for r = 0..N-1.
    track : Track

    Returns
    -------
    xr.Dataset
        As receptance_table, along 'fraction' [-] too.
    """
    K = tabs[0].harmonics
    shape = (len(tabs), len(tabs[0].offsets), 2 * K + 1, 2 * K + 1)
    A = np.full(shape, np.nan + 0j)
    err = np.full(shape, np.nan)
    for i, t in enumerate(tabs):
        n = len(t.indices)
        A[i, :, :n, :n] = t.A
        err[i, :, :n, :n] = t.error
    one = receptance_table(tabs[0], track)
    dims = ("fraction", "offset", "response_harmonic", "force_harmonic")
    return xr.Dataset(
        {
            "receptance_real": data_var(dims, A.real, "m/N",
                                        "real part of a_{p-k}((k + nu) Omega_0, d): response at (p + nu) Omega_0 per unit force at (k + nu) Omega_0"),
            "receptance_imag": data_var(dims, A.imag, "m/N", "imaginary part of a_{p-k}((k + nu) Omega_0, d)"),
            "quadrature_error": data_var(dims, err, "m/N", "estimated absolute error of the wavenumber quadrature"),
            "quadrature_nodes": data_var("fraction", np.array([t.nodes for t in tabs]), "1", "wavenumber quadrature nodes"),
        },
        coords={**{k: v for k, v in one.coords.items()},
                "fraction": data_var("fraction", np.array([t.fraction for t in tabs]), "1",
                                     "Bloch fraction nu = r / N of the base frequency nu Omega_0")},
        attrs={**one.attrs, "bays": int(round(1 / tabs[1].fraction)) if len(tabs) > 1 else 1},
    )


def read_receptance_table(ds: xr.Dataset):
    """The MovingReceptance stored by receptance_table, or the tuple of them stored by bloch_tables
    (inverse of them).

    Parameters
    ----------
    ds : xr.Dataset
        A dataset written by receptance_table or bloch_tables.

    Returns
    -------
    MovingReceptance or tuple of MovingReceptance
    """
    if "fraction" in ds.dims:
        out = []
        K = (ds.sizes["response_harmonic"] - 1) // 2
        for i, nu in enumerate(ds["fraction"].values):
            n = 2 * K + 1 if nu == 0 else 2 * K
            A = ds["receptance_real"].values[i, :, :n, :n] + 1j * ds["receptance_imag"].values[i, :, :n, :n]
            out.append(MovingReceptance(float(ds.attrs["speed_m_per_s"]), K, ds["offset"].values, A,
                                        ds["quadrature_error"].values[i, :, :n, :n], int(ds["quadrature_nodes"].values[i]), float(nu)))
        return tuple(out)
    A = ds["receptance_real"].values + 1j * ds["receptance_imag"].values
    K = (A.shape[1] - 1) // 2
    if "cell_bays" in ds.attrs:
        sup = tuple(float(x) for x in np.atleast_1d(ds.attrs["cell_attachment_positions_m"]))
        return MovingReceptance(float(ds.attrs["speed_m_per_s"]), K, ds["offset"].values, A, ds["quadrature_error"].values,
                                int(ds.attrs["quadrature_nodes"]), 0.0, int(ds.attrs["cell_bays"]), sup)
    return MovingReceptance(
        float(ds.attrs["speed_m_per_s"]), K, ds["offset"].values, A, ds["quadrature_error"].values, int(ds.attrs["quadrature_nodes"])
    )


def _force_history_vars(results, track, x, labels):
    """Force histories over the bay, one variable per result, N."""

    out = {}
    for key, (res, long_name) in zip(labels, results):
        out[key] = data_var("position", force_history(res, x)[0], "N", long_name)
    return out


def fig08(result, track, roughness, settings: dict, points: int = 601) -> xr.Dataset:
    """Fig. 8: normal contact force of one wheel over a bay with harmonic roughness, and that roughness.

    Parameters
    ----------
    result : rail.chain.ForceResult
        The forces of the passage.
    track : Track
    roughness : Roughness
        The harmonic roughness Z_k [m].
    settings : dict
        figures.fig08: speed [m/s], frequency [Hz], amplitude [m].
    points : int
        Positions over the bay [-].

    Returns
    -------
    xr.Dataset
        Normal contact force [N] and roughness [m] over position [m].
    """
    x = np.linspace(0.0, track.L, points)
    data = _force_history_vars([(result, "normal contact force")], track, x, ["force"])
    data["dynamic_force"] = data_var("position", data["force"][1] - result.P[0, result.harmonics].real,
                                     "N", "normal dynamic contact force (force minus static load)")
    data["roughness"] = data_var("position", roughness.profile(x, track.L), "m", "rail-head roughness (upwards positive)")
    return xr.Dataset(
        data,
        coords={"position": data_var("position", x, "m", "wheel position in the sleeper bay (0 = above a sleeper)")},
        attrs={"speed_m_per_s": settings["speed"], "roughness_frequency_Hz": settings["frequency"],
               "roughness_amplitude_m": settings["amplitude"], "damping_model": track.damping},
    )


def fig22(results: dict, track, points: int = 601) -> xr.Dataset:
    """Fig. 22: normal contact force of one wheel over a smooth rail, one variable per speed.

    Parameters
    ----------
    results : dict
        {speed [m/s]: the forces of the passage}.
    track : Track
    points : int
        Positions over the bay [-].

    Returns
    -------
    xr.Dataset
        Normal contact force [N] per speed over position [m].
    """
    x = np.linspace(0.0, track.L, points)
    data = {}
    for V, res in results.items():
        data.update(_force_history_vars([(res, f"normal contact force at {V:g} m/s, smooth rail")], track, x, [f"force_V{V:g}"]))
    return xr.Dataset(
        data,
        coords={"position": data_var("position", x, "m", "wheel position in the sleeper bay (0 = above a sleeper)")},
        attrs={"speeds_m_per_s": list(results), "damping_model": track.damping},
    )


def wear_case(result, forces, roughness, track, settings: dict, frequency: float) -> xr.Dataset:
    """One wheel passage over a harmonic roughness: contact and wear along the bay (Figs 9-19).

    Parameters
    ----------
    result : rail.chain.PassageWear
        Contact and wear of the passage along the bay.
    forces : rail.chain.ForceResult
        Its forces.
    roughness : Roughness
        The harmonic roughness Z_k [m].
    track : Track
    settings : dict
        figures.wear: speed [m/s], amplitude [m].
    frequency : float
        The roughness's excitation frequency [Hz] (its wavelength: speed / frequency).

    Returns
    -------
    xr.Dataset
        Forces [N], traction [Pa], slip velocity [m/s], wear depth [m] and its spectrum [m] along the bay [m].
    """
    x = result.x
    K = roughness.harmonics
    k = np.arange(1, K + 1)
    P0 = forces.P[0, forces.harmonics].real
    return xr.Dataset(
        {
            "wear_depth": data_var("position", result.depth, "m", "height of rail removed by one wheel passage (eq 51)"),
            "normal_force": data_var("position", result.P, "N", "normal contact force with the wheel at the position"),
            "dynamic_normal_force": data_var("position", result.P - P0, "N", "normal dynamic contact force (minus the static load)"),
            "tangential_force": data_var("position", result.Q, "N", "tangential contact force 2b int q"),
            "half_length": data_var("position", result.a, "m", "contact patch half-length a (eq 23)"),
            "roughness": data_var("position", roughness.profile(x, track.L), "m", "initial rail-head roughness (upwards positive)"),
            "traction": data_var(("position", "patch"), result.q, "Pa", "tangential traction q(xi) with the wheel at the position"),
            "slip_velocity": data_var(("position", "patch"), result.s, "m/s", "slip velocity s(xi) (step average, eq 26)"),
            "wear_spectrum": data_var("harmonic", 2 * np.abs(result.Z[K + 1 :]), "m", "amplitude of the wear's Fourier components, 2 |Delta Z_k|"),
            "wear_spectrum_real": data_var("harmonic", result.Z[K + 1 :].real, "m", "real part of Delta Z_k"),
            "wear_spectrum_imag": data_var("harmonic", result.Z[K + 1 :].imag, "m", "imaginary part of Delta Z_k"),
        },
        coords={
            "position": data_var("position", x, "m", "wheel (contact centre) position in the sleeper bay, 0 above a sleeper"),
            "patch": data_var("patch", result.xi, "m", "position xi in the contact patch (leading edge positive)"),
            "harmonic": data_var("harmonic", k, "1", "harmonic k of the sleeper bay"),
            "wavenumber": data_var("harmonic", k * track.beta0, "rad/m", "wavenumber k beta0"),
        },
        attrs={
            "speed_m_per_s": settings["speed"],
            "roughness_frequency_Hz": frequency,
            "roughness_wavelength_m": settings["speed"] / frequency,
            "roughness_amplitude_m": settings["amplitude"],
            "mean_wear_m": float(result.depth.mean()),
            "periodicity_error": result.periodicity,
            "damping_model": track.damping,
        },
    )


def _attrs(ds):
    return {k: ds.attrs[k] for k in ("speed_m_per_s", "roughness_frequency_Hz", "roughness_amplitude_m", "mean_wear_m") if k in ds.attrs}


def fig09(case: xr.Dataset) -> xr.Dataset:
    """Fig. 9: tangential contact force against wheel position.

    Parameters
    ----------
    case : xr.Dataset
        A wear case (wear_case).

    Returns
    -------
    xr.Dataset
        Tangential and normal force [N] over position [m].
    """
    return case[["tangential_force", "normal_force"]].assign_attrs(_attrs(case))


def fig10_11(case: xr.Dataset, variable: str, instants_s=(0.0, 0.25e-3, 0.5e-3, 0.75e-3, 1.0e-3)) -> xr.Dataset:
    """Figs 10 and 11: traction or slip velocity across the patch at instants of one excitation period.

    Parameters
    ----------
    case : xr.Dataset
        A wear case (wear_case).
    variable : str
        'traction' or 'slip_velocity'.
    instants_s : sequence of float
        Times within the excitation period [s].

    Returns
    -------
    xr.Dataset
        The variable across the patch [m] at each instant [s].
    """
    V = case.attrs["speed_m_per_s"]
    x = case["position"].values
    out = {}
    for t in instants_s:
        i = int(np.argmin(np.abs(x - V * t)))
        out[f"t{1e3 * t:.2f}ms".replace(".", "_")] = data_var(
            "patch", case[variable].values[i], case[variable].attrs["units"],
            f"{case[variable].attrs['long_name']} at t = {1e3 * t:.2f} ms (x = {x[i]:.4f} m)"
        )
    return xr.Dataset(out, coords={"patch": case["patch"]}, attrs=_attrs(case))


def fig_wear(case: xr.Dataset) -> xr.Dataset:
    """Figs 12, 14, 16, 18: wear after one passage with the initial roughness and the dynamic force.

    Parameters
    ----------
    case : xr.Dataset
        A wear case (wear_case).

    Returns
    -------
    xr.Dataset
        Wear depth [m], roughness [m] and dynamic normal force [N] over position [m].
    """
    return case[["wear_depth", "roughness", "dynamic_normal_force"]].assign_attrs(_attrs(case))


def fig_wear_spectrum(case: xr.Dataset, k_max: float) -> xr.Dataset:
    """Figs 13, 15, 17, 19: amplitude spectrum of the wear up to k_max rad/m.

    Parameters
    ----------
    case : xr.Dataset
        A wear case (wear_case).
    k_max : float
        Largest wavenumber shown [rad/m].

    Returns
    -------
    xr.Dataset
        wear_spectrum [m] over wavenumber [rad/m].
    """
    sel = case["wavenumber"].values <= k_max + 1e-9
    return case[["wear_spectrum"]].isel(harmonic=np.where(sel)[0]).assign_attrs(_attrs(case))


def growth(history, track, speed: float, n_wheels: int, points: int = 601, bays: int = 1, force=None) -> xr.Dataset:
    """Roughness growth: levels per harmonic and profiles at every saved passage count. For a
    roughness periodic over N = bays bays the harmonics are j = 1..N K at the wavenumbers
    2 pi j / (N L) and the profiles span the N bays. force : optional function of the roughness
    coefficients Z giving every wheel's contact force [N] at the profile positions, shape
    (wheels, positions); stored per saved passage count.

    Parameters
    ----------
    history : rail.growth.GrowthHistory
        Z at every saved passage count [m].
    track : Track
    speed : float
        Train speed [m/s].
    n_wheels : int
        Wheels of the train [-].
    points : int
        Profile positions over the period [-].
    bays : int
        Roughness period N [-].
    force : callable, optional
        Z -> contact force [N], shape (wheels, positions).

    Returns
    -------
    xr.Dataset
        Level per harmonic [dB re 1 µm], Z [m], profiles [m] over position [m], growth rates [-] per passage,
        [µm per 100000 axle passages] and [dB per 100000 axle passages] and, with ``force``, the force [N] at
        every save.
    """

    Z = history.Z
    K = (Z.shape[1] - 1) // 2  # J = N K for a roughness periodic over N bays
    k = np.arange(1, K + 1)
    x = np.linspace(0.0, track.L * bays, points if bays == 1 else points * bays)
    profiles = np.array([Roughness(z, bays).profile(x, track.L) for z in Z])
    rms = np.sqrt(2) * np.abs(Z[:, K + 1 :])
    levels = np.where(rms > 0, levels_dB(Z), np.nan)  # a harmonic that is exactly 0 (the smooth rail) has no level
    n = history.passages
    half = n >= n[-1] / 2
    if half.sum() >= 2:
        # the e-folding rate d ln(amplitude) / dn where the amplitude stays positive (growth about a
        # roughness that is there; from a smooth rail the amplitude grows linearly and this rate is
        # not a property of the track)
        positive = np.all(rms[half] > 0, axis=0)
        log_rms = np.log(np.where(rms[half] > 0, rms[half], 1.0))
        exp_rate = np.where(positive, np.polyfit(n[half], log_rms, 1)[0], np.nan)
    else:
        exp_rate = np.full(K, np.nan)
    # amplitude and level growth of each line as of a band (rail.growth.band_growth over every save):
    # the straight-line amplitude rate and the level rate at the last save from the law that fits
    if n.size >= 3:
        g = band_growth(n, rms**2)
        amp_rate, dB_rate = g.linear_rate * 1e6, g.dB_rate
    else:
        amp_rate = dB_rate = np.full(K, np.nan)
    return xr.Dataset(
        {
            "level": data_var(("passage", "harmonic"), levels, "dB re 1 um",
                              "rms roughness level of each harmonic of the bay (NaN where the harmonic is exactly 0)"),
            "profile": data_var(("passage", "position"), profiles, "m", "rail-head roughness profile over the bay (upwards positive)"),
            "Z_real": data_var(("passage", "harmonic_all"), Z.real, "m", "real part of the roughness coefficients Z_k, k = -K..K"),
            "Z_imag": data_var(("passage", "harmonic_all"), Z.imag, "m", "imaginary part of the roughness coefficients Z_k"),
            "exponential_rate": data_var("harmonic", exp_rate, "1", "e-folding rate of the rms amplitude per wheel passage over the second half "
                                     "of the run (d ln A / dn; from a smooth rail the growth is linear in the amplitude, "
                                     "see amplitude_growth_um_per_1e5_axles)"),
            "amplitude_growth_um_per_1e5_axles": data_var("harmonic", amp_rate, "um per 100000 axle passages",
                                                      "growth rate of the rms amplitude (straight-line fit over every save, as for a band)"),
            "growth_dB_per_1e5_axles": data_var("harmonic", dB_rate, "dB per 100000 axle passages",
                                            "level growth rate at the last save from the law (straight line or exponential in amplitude) "
                                            "that fits the line, as for a band (rail.growth.band_growth)"),
            "step_error": data_var("update", history.step_error, "1",
                                   "estimated local error of each update relative to the roughness (rail.growth.step_error)"),
            "full_slip": data_var("update", history.full_slip, "1", "largest fraction of the bay with no stick zone in the contact, per update"),
            **({} if force is None else {"force": data_var(("passage", "wheel", "position"), np.array([force(z, x) for z in Z]), "N",
                                                        "contact force of each wheel with the wheel at the position (eq 21)")}),
        },
        coords={
            "passage": data_var("passage", n, "1", "axle passages: wheel passages on the rail (a train of n wheels counts n)"),
            "harmonic": data_var("harmonic", k, "1",
                                 "harmonic k of the sleeper bay" if bays == 1 else f"index j of the wavenumber 2 pi j / ({bays} L)"),
            "wavenumber": data_var("harmonic", k / bays * track.beta0, "rad/m",
                                   "wavenumber k beta0" if bays == 1 else f"wavenumber j beta0 / {bays}"),
            "harmonic_all": data_var("harmonic_all", np.arange(-K, K + 1), "1", "harmonic index k of Z_k"),
            "position": data_var("position", x, "m",
                                 "position in the sleeper bay, 0 above a sleeper" if bays == 1
                                 else f"position over the {bays}-bay period, 0 above a sleeper"),
        },
        attrs={"speed_m_per_s": speed, "wheels": n_wheels, "damping_model": track.damping, "pad_stiffness_N_per_m": track.pad.stiffness,
               **({} if bays == 1 else {"bays": bays})},
    )


def with_contact_shift(ds: xr.Dataset, shifts, limit: float, path) -> xr.Dataset:
    """The growth dataset ``ds`` with the move of the contact centre at each saved state
    (rail.chain.ContactShift, one per passage), its wear path as a value (wear_path beside
    wear_path_description) and, where the move is neglected (the wear under the wheel centre,
    contact.wear_path: wheel) and its sweep error exceeds ``limit`` [-], the attribute
    ``contact_shift_warning`` (docs/contact.md, "The move of the contact centre"). Where the path
    models the move (contact.wear_path: patch, ``path.modelled_shift``) it is reported, not flagged.

    Parameters
    ----------
    ds : xr.Dataset
        A growth dataset (growth).
    shifts : sequence of rail.chain.ContactShift
        The move of the contact centre [m] and its ratio [-] at each saved state.
    limit : float
        Sweep error above which it is flagged [-].
    path : rail.contact.WearPath or str
        The run's wear path (contact.wear_path), or its name.

    Returns
    -------
    xr.Dataset
        ``ds`` with contact_shift [m] and contact_shift_ratio [-] per save.
    """
    c = np.array([s.shift for s in shifts])
    ratio = np.array([s.ratio for s in shifts])
    sweep = np.array([s.sweep for s in shifts])
    ds = ds.assign(
        contact_shift=data_var("passage", c, "m", "largest |c| over the wheels and the period, c the neglected move of the contact "
                           "patch centre relative to the wheel centre (R_w times the patch-weighted roughness slope)"),
        contact_shift_ratio=data_var("passage", ratio, "1", "largest |c| / a, the neglected move of the contact centre relative to "
                                 "the patch half-length"),
        contact_shift_sweep=data_var("passage", sweep, "1", "largest |dc/dx|: the wear depth the neglected move of the contact centre "
                                 "leaves out, relative to the mean wear (beta |c| for a harmonic)"),
    )
    path = _wear_path(path)
    ds.attrs.update(path.attributes())
    if path.modelled_shift:
        for name in ("contact_shift", "contact_shift_ratio", "contact_shift_sweep"):
            ds[name].attrs["long_name"] = ds[name].attrs["long_name"].replace("the neglected move", "the move") + (
                " (in the model: the wear on the patch's true path)")
        return ds
    ds.attrs["contact_shift_sweep_limit"] = float(limit)
    over = np.flatnonzero(sweep > limit)
    if over.size:
        i = int(over[0])
        ds.attrs["contact_shift_warning"] = (
            f"the neglected move of the contact centre leaves out {100 * sweep[i]:.2g} % of the mean wear from "
            f"{int(ds['passage'].values[i])} passages on (|dc/dx| > {limit:g}; largest |c| = {1e6 * c[i]:.3g} µm, "
            f"{100 * ratio[i]:.2g} % of the half-length): comparable with the wear modulation that drives growth, "
            "the growth beyond is outside the model's validity (docs/contact.md)")
    return ds


def _slug(prefix: str, label: str) -> str:
    """A netCDF-safe variable name for a plotted line: 'level' + '20 m/s' -> 'level_20_m_per_s'."""
    return prefix + "_" + re.sub(r"[^0-9A-Za-z.+-]+", "_", label.replace("/", " per ")).strip("_")


# the model choices of a run that its figure's data states (rail.studies.validity.model_attributes)
_MODEL_ATTRS = ("wear_path", "wear_path_description", "normal_contact", "normal_contact_description")


def _run_models(ds) -> dict:
    """The model attributes of one growth run ('not stated' where an older file lacks one)."""
    return {k: str(ds.attrs.get(k, "not stated")) for k in _MODEL_ATTRS}


def _figure_models(runs: dict) -> dict:
    """The model attributes of a figure drawn from several runs: each run's where they all agree, else
    'mixed' (each variable then states its own run's)."""
    each = [_run_models(ds) for ds in runs.values()]
    out = {k: each[0][k] if all(e[k] == each[0][k] for e in each) else "mixed: see the attribute of each variable"
           for k in _MODEL_ATTRS}
    # the figure's note on the patch's true path (rail.plotting.text.validity_notes) where every run has it
    out["contact_shift_modelled"] = int(all(int(ds.attrs.get("contact_shift_modelled", 0)) for ds in runs.values()))
    return out


def growth_figure(runs: dict, kind: str, k_max_rad_per_m: float = 525.0) -> xr.Dataset:
    """Data of Figs 20-27 from growth datasets: kind 'profiles' (every save of one run),
    'spectra' (final levels of each run) or 'final_profiles' (final profile of each run). Every
    dataset states its wear path and normal contact as values (the runs' wear_path, normal_contact,
    and on each variable its own run's where several runs are drawn).

    Parameters
    ----------
    runs : dict
        {label: growth dataset}.
    kind : str
        'profiles', 'spectra' or 'final_profiles'.
    k_max_rad_per_m : float
        Largest wavenumber of the spectra [rad/m].

    Returns
    -------
    xr.Dataset
        Profiles [m] over position [m], or levels [dB re 1 µm] over wavenumber [rad/m].
    """
    first = next(iter(runs.values()))
    if kind == "profiles":
        ds = first
        out = {f"profile_{int(n)}": data_var("position", ds["profile"].values[i], "m", f"roughness profile after {int(n)} passages")
               for i, n in enumerate(ds["passage"].values)}
        return xr.Dataset(out, coords={"position": ds["position"]}, attrs={**dict(ds.attrs), **_figure_models(runs)})
    if kind == "final_profiles":
        out = {
            _slug("profile", label): data_var("position", ds["profile"].values[-1], "m",
                                              f"roughness profile after {int(ds['passage'].values[-1])} passages, {label}",
                                              label=label, **_run_models(ds))
            for label, ds in runs.items()
        }
        return xr.Dataset(out, coords={"position": first["position"]}, attrs=_figure_models(runs))
    sel = first["wavenumber"].values <= k_max_rad_per_m
    out = {
        _slug("level", label): data_var("harmonic", ds["level"].values[-1][sel], "dB re 1 um",
                                        f"roughness level after {int(ds['passage'].values[-1])} passages, {label}",
                                        label=label, **_run_models(ds))
        for label, ds in runs.items()
    }
    return xr.Dataset(
        out,
        coords={
            "harmonic": data_var("harmonic", first["harmonic"].values[sel], "1", "harmonic k of the sleeper bay"),
            "wavenumber": data_var("harmonic", first["wavenumber"].values[sel], "rad/m", "wavenumber k beta0"),
        },
        attrs=_figure_models(runs),
    )


def sweep_coords(keys, values, units) -> tuple[tuple, dict]:
    """The grid of a sweep study: one dimension per swept key (dots become underscores) and its
    coordinate, with the key's unit as the schema states it (rail.setup.config.schema_unit).

    Parameters
    ----------
    keys : sequence of str
        Swept keys (dotted config keys or 'speed').
    values : sequence of sequence
        Values of each key [the key's unit].
    units : sequence of str
        The unit of each key.

    Returns
    -------
    (dims, coords)
        Dimension names and {dim: (dim, values, attrs)}.
    """
    dims = tuple(k.replace(".", "_") for k in keys)
    return dims, {d: (d, np.asarray(v), {"units": u, "long_name": f"swept parameter {k}"}) for d, k, v, u in zip(dims, keys, values, units)}


def sweep(runs, keys, values, indices, units) -> xr.Dataset:
    """A sweep study: growth results on the grid of swept keys (one dimension per key, in the units
    of ``units``, one per key).

    Parameters
    ----------
    runs : sequence of xr.Dataset
        The points' growth datasets, in grid order.
    keys : list of str
        The swept keys.
    values : list of list
        Their values, in each key's unit.
    indices : list of list of int
        Each point's grid index.
    units : list of str
        Each key's unit (rail.setup.config.schema_unit).

    Returns
    -------
    xr.Dataset
        Final levels per harmonic and overall [dB re 1 µm], the fastest amplitude growth [µm per 100000 axle
        passages] and its wavelength [m] on the grid.
    """
    dims, coords = sweep_coords(keys, values, units)
    shape = tuple(len(v) for v in values)
    first = runs[0]
    K = first.sizes["harmonic"]
    level = np.full(shape + (K,), np.nan)
    rate = np.full(shape + (K,), np.nan)
    for run, idx in zip(runs, indices):
        level[tuple(idx)] = run["level"].values[-1]
        rate[tuple(idx)] = run["amplitude_growth_um_per_1e5_axles"].values
    overall = 10 * np.log10(np.sum(10 ** (level / 10), axis=-1))
    fastest = np.nanargmax(rate, axis=-1)
    wavelength = 2 * np.pi / first["wavenumber"].values[fastest]
    coords["harmonic"] = data_var("harmonic", first["harmonic"].values, "1",
                                  first["harmonic"].attrs.get("long_name", "harmonic k of the sleeper bay"))
    coords["wavenumber"] = data_var("harmonic", first["wavenumber"].values, "rad/m", first["wavenumber"].attrs.get("long_name", "wavenumber k beta0"))
    return xr.Dataset(
        {
            "level": data_var(dims + ("harmonic",), level, "dB re 1 um", "rms roughness level of each harmonic at the end of the run"),
            "overall_level": data_var(dims, overall, "dB re 1 um", "overall rms roughness level at the end of the run"),
            "max_amplitude_growth_um_per_1e5_axles": data_var(dims, np.nanmax(rate, axis=-1), "um per 100000 axle passages",
                                                          "rms amplitude growth rate of the fastest-growing wavelength"),
            "fastest_wavelength": data_var(dims, wavelength, "m", "wavelength that grows fastest"),
        },
        coords=coords,
        attrs={"swept_keys": list(keys), "passages": int(first["passage"].values[-1])},
    )
