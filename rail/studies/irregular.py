"""The irregular-track study (issue 34, named target irregular_track): each kind of support beside the
uniform track, and what the pinned-pinned band does as the irregularity grows.

Per case (a case of config/studies/irregular_track.yaml with a track cell): the point
receptance above each support of the cell and of the uniform track; the contact force of one wheel
over the smooth rail along the cell; the roughness grown after the run's passages; the growth-rate
spectrum.  Over the cases and the random-track ensemble: the level of the one-third-octave band that
holds the pinned-pinned wavelength V / f_pp, and the fastest-growing band, after the run.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..cell import TrackCell, cell_stationary_receptance
from ..track import Track, pinned_pinned_frequency, stationary_receptance
from ..bands import wavelength_bands
from .bands import band_levels
from ..setup.io import data_var

__all__ = ["support_differences", "support_labels", "support_marks", "support_receptances", "case_dataset", "band_summary", "FREQUENCIES_HZ"]

FREQUENCIES_HZ = np.geomspace(50.0, 3000.0, 80)


def support_differences(cell: TrackCell) -> list[str]:
    """How each support differs from the nominal one, "" for a nominal support ("ballast ×0.001" for a
    voided sleeper, "pad ×2, sleeper ×0.5", ...).

    Parameters
    ----------
    cell : TrackCell
        The track's cell of N bays (rail.cell).

    Returns
    -------
    list of str
        One per support, in the cell's order.
    """
    tr = cell.track
    out = []
    for s in cell.supports:
        diff = []
        if not np.isclose(s.pad.stiffness, tr.pad.stiffness, rtol=1e-9):
            diff.append(f"pad ×{s.pad.stiffness / tr.pad.stiffness:.3g}")
        if not np.isclose(s.ballast.stiffness, tr.ballast.stiffness, rtol=1e-9):
            diff.append(f"ballast ×{s.ballast.stiffness / tr.ballast.stiffness:.3g}")
        if not np.isclose(s.sleeper_mass, tr.sleeper.mass, rtol=1e-9):
            diff.append(f"sleeper ×{s.sleeper_mass / tr.sleeper.mass:.3g}")
        out.append(", ".join(diff))
    return out


def support_labels(cell: TrackCell) -> list[str]:
    """A short label per support: its position and how it differs from the nominal support.

    Parameters
    ----------
    cell : TrackCell
        The track's cell of N bays (rail.cell).

    Returns
    -------
    list of str
        One per support: its position [m] and difference.
    """
    return [f"support {j} at {s.position:.3f} m" + (f" ({d})" if d else "")
            for j, (s, d) in enumerate(zip(cell.supports, support_differences(cell)))]


def support_marks(cell: TrackCell) -> list[tuple[float, str]]:
    """The supports over one period of the cell for a figure along the rail (rail.plotting.axes.mark_supports):
    (position [m], how it differs from the nominal support, "" if it does not) per support, and the
    first support again at the period's end.

    Parameters
    ----------
    cell : TrackCell
        The track's cell of N bays (rail.cell).

    Returns
    -------
    list of tuple of (float, str)
        (position [m], difference) per support, and the period's end.
    """
    diff = support_differences(cell)
    return [(float(s.position), d) for s, d in zip(cell.supports, diff)] + [(float(cell.period), diff[0])]


def support_receptances(cell: TrackCell, uniform: Track, frequencies=FREQUENCIES_HZ):
    """Point receptances above every support and at every mid-bay of the cell, and of the uniform track.

    Parameters
    ----------
    cell : TrackCell
    uniform : Track
        The uniform track beside it.
    frequencies : array_like
        [Hz].

    Returns
    -------
    above, mid : complex ndarray, shape (frequencies, N) [m/N]
    uniform_above, uniform_mid : complex ndarray, shape (frequencies,) [m/N]
    """
    s = np.array([x.position for x in cell.supports])
    nxt = np.append(s[1:], cell.period)
    mid = 0.5 * (s + nxt)
    pts = np.concatenate([s, mid])
    above, middle, ua, um = [], [], [], []
    for f in np.asarray(frequencies, dtype=float):
        om = 2 * np.pi * f
        r = cell_stationary_receptance(pts, pts, om, cell)
        above.append(r[: len(s)])
        middle.append(r[len(s):])
        ua.append(stationary_receptance(0.0, 0.0, om, uniform))
        um.append(stationary_receptance(uniform.L / 2, uniform.L / 2, om, uniform))
    return np.array(above), np.array(middle), np.array(ua), np.array(um)


def _last_level(growth: xr.Dataset):
    """Wavelengths [m] and levels [dB re 1 µm] of the lines after the run's last saved passage."""
    lam = 2 * np.pi / growth["wavenumber"].values
    return lam, growth["level"].values[-1]


def band_summary(growth: xr.Dataset, speed: float, track: Track) -> dict:
    """Level of the pinned-pinned band and the loudest band after the run.

    Parameters
    ----------
    growth : xr.Dataset
        A growth result (results/growth/<scenario>/V<speed>.nc).
    speed : float
        [m/s].
    track : Track
        Its nominal track (for the pinned-pinned frequency).

    Returns
    -------
    dict
        pinned_pinned_wavelength_m, pp_band_m (nominal centre), pp_level_dB, loudest_band_m,
        loudest_level_dB, passages.
    """
    Z = growth["Z_real"].values[-1] + 1j * growth["Z_imag"].values[-1]
    N = int(growth.attrs.get("bays", 1))
    period = N * track.L
    bands = wavelength_bands(1.0, 0.02)
    lev, resolved = band_levels(Z, period, bands)
    lam_pp = speed / pinned_pinned_frequency(track)
    b = int(np.argmin(np.abs(np.log(bands.centre / lam_pp))))
    ok = resolved & np.isfinite(lev)
    loud = int(np.nanargmax(np.where(ok, lev, -np.inf))) if ok.any() else b
    return {"pinned_pinned_wavelength_m": float(lam_pp), "pp_band_m": float(bands.nominal[b]), "pp_level_dB": float(lev[b]),
            "loudest_band_m": float(bands.nominal[loud]), "loudest_level_dB": float(lev[loud]),
            "passages": int(growth["passage"].values[-1])}


def case_dataset(cell: TrackCell, uniform: Track, speed: float, growth: xr.Dataset, growth_uniform: xr.Dataset,
                 spectrum: xr.Dataset, spectrum_uniform: xr.Dataset, frequencies=FREQUENCIES_HZ) -> xr.Dataset:
    """Everything the case's figure shows, in one dataset (units and long names).

    Parameters
    ----------
    cell : TrackCell
        The case's track.
    uniform : Track
        The uniform track beside it.
    speed : float
        [m/s].
    growth, growth_uniform : xr.Dataset
        Growth results of the case and of the uniform track at the speed.
    spectrum, spectrum_uniform : xr.Dataset
        Their growth-rate spectra at the speed.

    Returns
    -------
    xr.Dataset
    """
    above, mid, ua, um = support_receptances(cell, uniform, frequencies)
    lam, lev = _last_level(growth)
    lam_u, lev_u = _last_level(growth_uniform)
    x = growth["position"].values
    force = growth["force"].values[0, 0]
    xu = growth_uniform["position"].values
    fu = growth_uniform["force"].values[0, 0]
    sp, su = spectrum.sel(speed=speed), spectrum_uniform.sel(speed=speed)
    labels = support_labels(cell)
    s_case, s_uni = band_summary(growth, speed, cell.track), band_summary(growth_uniform, speed, uniform)

    def db(a):
        return 20 * np.log10(np.abs(a))

    return xr.Dataset(
        {
            "receptance_above_support_dB": data_var(("frequency", "support"), db(above), "dB re 1 m/N",
                                                    "point receptance magnitude above each support"),
            "receptance_mid_bay_dB": data_var(("frequency", "support"), db(mid), "dB re 1 m/N",
                                              "point receptance magnitude mid-way to the next support"),
            "uniform_receptance_above_support_dB": data_var("frequency", db(ua), "dB re 1 m/N", "uniform track: point receptance above a support"),
            "uniform_receptance_mid_bay_dB": data_var("frequency", db(um), "dB re 1 m/N", "uniform track: point receptance at mid-span"),
            "force": data_var("position", force, "N", "contact force of the wheel over the smooth rail along the cell"),
            "uniform_force": data_var("position_uniform", fu, "N", "uniform track: contact force over the smooth rail along one bay"),
            "level": data_var("wavelength", lev, "dB re 1 um", f"roughness level per line after {int(growth['passage'].values[-1])} passages"),
            "uniform_level": data_var("wavelength_uniform", lev_u, "dB re 1 um", "uniform track: roughness level per line after the same run"),
            "growth_dB_per_1e5_trains": data_var("spectrum_wavelength", sp["growth_dB_per_1e5_trains"].values, "dB per 100000 train passages",
                                             "growth-rate spectrum: level change per 100,000 passages of the whole train"),
            "growth_dB_per_1e5_axles": data_var("spectrum_wavelength", sp["growth_dB_per_1e5_axles"].values, "dB per 100000 axle passages",
                                            "growth-rate spectrum: level change per 100,000 axle (wheel) passages"),
            "uniform_growth_dB_per_1e5_trains": data_var("spectrum_wavelength_uniform", su["growth_dB_per_1e5_trains"].values,
                                                     "dB per 100000 train passages",
                                                     "uniform track: growth-rate spectrum per 100,000 passages of the whole train"),
            "uniform_growth_dB_per_1e5_axles": data_var("spectrum_wavelength_uniform", su["growth_dB_per_1e5_axles"].values,
                                                    "dB per 100000 axle passages",
                                                    "uniform track: growth-rate spectrum per 100,000 axle (wheel) passages"),
        },
        coords={
            "frequency": data_var("frequency", np.asarray(frequencies, dtype=float), "Hz", "frequency"),
            "support": data_var("support", np.arange(cell.bays), "1", "support index in the cell"),
            "support_label": data_var("support", np.array(labels), "1", "support position and how it differs from the nominal"),
            "support_position": data_var("support", np.array([x.position for x in cell.supports], dtype=float), "m",
                                         "position of the support in the cell"),
            "support_difference": data_var("support", np.array(support_differences(cell)), "1",
                                           "how the support differs from the nominal one (empty: it does not)"),
            "position": data_var("position", x, "m", "wheel position along the cell"),
            "position_uniform": data_var("position_uniform", xu, "m", "wheel position along the uniform track's period"),
            "wavelength": data_var("wavelength", lam, "m", "roughness wavelength of the line"),
            "wavelength_uniform": data_var("wavelength_uniform", lam_u, "m", "roughness wavelength of the line (uniform track)"),
            "spectrum_wavelength": data_var("spectrum_wavelength", sp["wavelength"].values, "m", "growth-rate spectrum wavelength"),
            "spectrum_wavelength_uniform": data_var("spectrum_wavelength_uniform", su["wavelength"].values, "m",
                                                    "growth-rate spectrum wavelength (uniform track)"),
        },
        attrs={"speed_m_per_s": float(speed), "cell_bays": cell.bays, "cell_period_m": cell.period,
               "rail_dampers": len(cell.dampers),
               "pinned_pinned_wavelength_m": s_case["pinned_pinned_wavelength_m"],
               "pp_band_m": s_case["pp_band_m"], "pp_level_dB": s_case["pp_level_dB"], "uniform_pp_level_dB": s_uni["pp_level_dB"],
               "loudest_band_m": s_case["loudest_band_m"], "loudest_level_dB": s_case["loudest_level_dB"],
               "uniform_loudest_band_m": s_uni["loudest_band_m"], "uniform_loudest_level_dB": s_uni["loudest_level_dB"],
               "validity": "linear track model: a voided sleeper is a very soft ballast whose gap never closes under load"},
    )
