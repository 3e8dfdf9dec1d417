"""Closure sensitivity study (contact.closure_scale): its dataset (named target closure_study)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .conclusions import CONCLUSIONS, evaluate, overall_level_dB, short_wavelength_ratio
from ..setup.io import data_var

__all__ = ["closure_study"]


def closure_study(runs: dict, soft: dict, four: dict, wear_cases: dict, wellposed: xr.Dataset, L: float,
                  pinned_pinned_Hz: float, k_max_rad_per_m: float = 525.0) -> xr.Dataset:
    """The closure sensitivity study (contact.closure_scale s) in one dataset.

    A closure value whose perturbations grow (growth per transit >= 1 on any grid) is marked
    well_posed = 0 and its conclusions are not decided (conclusion_holds = -1).

    Parameters
    ----------
    runs : dict
        {(s, speed [m/s]): growth dataset} single wheel, default track.
    soft, four : dict
        {s: growth dataset} softer railpad and four wheels at the higher speed.
    wear_cases : dict
        {(s, frequency [Hz]): wear-case dataset} one passage over a harmonic roughness.
    wellposed : xr.Dataset
        growth_per_transit(closure_scale, nodes) [-] from rail.contact.perturbation_growth.
    L : float
        Sleeper spacing [m].
    pinned_pinned_Hz : float
        The track's pinned-pinned frequency [Hz].
    k_max_rad_per_m : float
        Largest wavenumber of the wear spectra [rad/m].

    Returns
    -------
    xr.Dataset
        Per closure value: levels [dB re 1 µm] over speed and passage, overall levels, the
        short-wavelength ratio [-], wear amplitude [-] and rate [-] per frequency, well_posed, and each
        conclusion's verdict and evidence.
    """
    S = sorted({s for s, _ in runs})
    V = sorted({v for _, v in runs})
    F = sorted({f for _, f in wear_cases})
    first = runs[(S[0], V[0])]
    Kh = first.sizes["harmonic"]
    passages = first["passage"].values

    def Z(ds, i=-1):
        return ds["Z_real"].values[i] + 1j * ds["Z_imag"].values[i]

    level = np.array([[runs[(s, v)]["level"].values for v in V] for s in S])
    overall = np.array([[overall_level_dB(Z(runs[(s, v)])) for v in V] for s in S])
    ratio = np.array([[short_wavelength_ratio(Z(runs[(s, v)]), L) for v in V] for s in S])
    o_soft = np.array([overall_level_dB(Z(soft[s])) for s in S])
    o_four = np.array([overall_level_dB(Z(four[s])) for s in S])
    wear_spec = np.array([[wear_cases[(s, f)]["wear_spectrum"].values for f in F] for s in S])
    amp = np.zeros((len(S), len(F)))
    rate = np.zeros((len(S), len(F)))
    for i, s in enumerate(S):
        for j, f in enumerate(F):
            c = wear_cases[(s, f)]
            m = int(round(L / c.attrs["roughness_wavelength_m"]))
            dz = c["wear_spectrum_real"].values[m - 1] + 1j * c["wear_spectrum_imag"].values[m - 1]
            z = c.attrs["roughness_amplitude_m"] / 2  # Z_m of A cos(2 pi x / lambda)
            amp[i, j] = 2 * abs(dz) / c.attrs["mean_wear_m"]
            rate[i, j] = -np.real(dz / z)
    gpt = wellposed["growth_per_transit"].sel(closure_scale=S).values
    ok = np.all(gpt < 1.0, axis=1)
    keys = list(CONCLUSIONS)
    holds = np.full((len(S), len(keys)), -1, dtype=int)
    evidence = np.empty((len(S), len(keys)), dtype=object)
    slow, fast = 0, len(V) - 1
    for i, s in enumerate(S):
        res = evaluate(
            levels_first=float(level[i, fast, 1, 0]),
            levels_final=float(level[i, fast, -1, 0]), argmax_harmonic=int(np.argmax(level[i, fast, -1])) + 1,
            wear_amplitude=dict(zip(F, amp[i])), wear_rate=dict(zip(F, rate[i])),
            ratio_slow=float(ratio[i, slow]), ratio_fast=float(ratio[i, fast]),
            overall_default=float(overall[i, fast]), overall_soft=float(o_soft[i]),
            overall_single=float(overall[i, fast]), overall_four=float(o_four[i]), pinned_pinned_Hz=pinned_pinned_Hz,
        )
        for j, key in enumerate(keys):
            evidence[i, j] = res[key][1]
            if ok[i]:
                holds[i, j] = int(res[key][0])
    return xr.Dataset(
        {
            "level": data_var(("closure_scale", "speed", "passage", "harmonic"), level, "dB re 1 um",
                              "rms roughness level of each harmonic, single wheel, smooth initial rail"),
            "overall_level": data_var(("closure_scale", "speed"), overall, "dB re 1 um", "overall rms roughness level at the end, single wheel"),
            "overall_level_soft_pad": data_var("closure_scale", o_soft, "dB re 1 um", f"overall level at the end, softer railpad, {V[fast]:g} m/s"),
            "overall_level_four_wheels": data_var("closure_scale", o_four, "dB re 1 um", f"overall level at the end, four wheels, {V[fast]:g} m/s"),
            "short_wavelength_ratio": data_var(("closure_scale", "speed"), ratio, "1",
                                               "rms of wavelengths <= L/5 after the sleepers over that at mid-span"),
            "wear_spectrum": data_var(("closure_scale", "frequency", "harmonic"), wear_spec, "m",
                                      "amplitude 2|Delta Z_k| of the wear of one passage over a harmonic roughness"),
            "wear_amplitude": data_var(("closure_scale", "frequency"), amp, "1", "wear at the roughness wavelength over the mean wear, one passage"),
            "wear_rate": data_var(("closure_scale", "frequency"), rate, "1",
                                  "in-phase growth per passage -Re(Delta Z_m / Z_m) (> 0: the roughness grows)"),
            "growth_per_transit": data_var(("closure_scale", "nodes"), gpt, "1",
                                           "growth factor per patch transit of a perturbation of steady rolling (< 1: well-posed)"),
            "well_posed": data_var("closure_scale", ok.astype(int), "1", "1 when perturbations decay on every grid tested, else 0"),
            "conclusion_holds": data_var(("closure_scale", "conclusion"), holds, "1", "1 holds, 0 does not, -1 not decided (closure not well-posed)"),
            "conclusion_evidence": data_var(("closure_scale", "conclusion"), evidence.astype(str), "1", "the numbers that decide each conclusion"),
        },
        coords={
            "closure_scale": data_var("closure_scale", np.array(S), "1", "closure scale s: l = (a/2) exp(2 s / pi)"),
            "speed": data_var("speed", np.array(V), "m/s", "train speed"),
            "passage": data_var("passage", passages, "1", "wheel passages"),
            "harmonic": data_var("harmonic", first["harmonic"].values, "1", "harmonic k of the sleeper bay"),
            "wavenumber": data_var("harmonic", first["wavenumber"].values, "rad/m", "wavenumber k beta0"),
            "frequency": data_var("frequency", np.array(F), "Hz", "excitation frequency of the harmonic roughness (wear cases)"),
            "nodes": wellposed["nodes"],
            "conclusion": data_var("conclusion", np.array([str(k) for k in keys]), "1", "conclusion of section 7 of the report"),
            "conclusion_text": data_var("conclusion", np.array([CONCLUSIONS[k] for k in keys]), "1", "statement of the conclusion"),
        },
        attrs={"pinned_pinned_Hz": pinned_pinned_Hz, "spectrum_max_wavenumber_rad_per_m": k_max_rad_per_m, "harmonics": int(Kh),
               "wear_speed_m_per_s": float(next(iter(wear_cases.values())).attrs["speed_m_per_s"])},
    )
