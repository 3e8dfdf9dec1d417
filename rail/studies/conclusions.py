"""The report's conclusions (section 7) as measurable statements about model results.

Each function takes roughness or wear coefficients (eq 18: Z_k, k = -K..K, in m) and returns the
number that decides a conclusion; ``evaluate`` applies the decision rules that the tests of the
default model use (tests/test_growth.py), so that a study (the closure sensitivity study) can say,
for each of its parameter values, which conclusions hold.

1. parametric excitation by the supports initiates roughness on a smooth rail;
2. growth depends strongly on the excitation frequency; near pinned-pinned maximum wear occurs
   (2b); implied by it, and decided separately (2c): roughness at that frequency grows;
3. short-wavelength roughness starts just after the sleepers and spreads to mid-span with speed;
4. a softer railpad gives less roughness;
5. four wheels give less roughness than one (per wheel passage).
"""

from __future__ import annotations

import numpy as np

__all__ = ["overall_level_dB", "short_wavelength_ratio", "wear_at_roughness", "evaluate", "CONCLUSIONS"]

CONCLUSIONS = {
    1: "parametric excitation initiates roughness on a smooth rail",
    2: "growth depends strongly on the excitation frequency",
    "2b": "maximum wear near the pinned-pinned frequency",
    "2c": "roughness near the pinned-pinned frequency grows (is not worn away)",
    3: "short wavelengths start after the sleepers and spread to mid-span with speed",
    4: "a softer railpad gives less roughness",
    5: "four wheels give less roughness than one",
}


def overall_level_dB(Z) -> float:
    """Overall rms roughness level of all harmonics k >= 1, dB re 1 um (rms of a component pair
    Z_k, Z_{-k} is sqrt(2) abs(Z_k)).

    Parameters
    ----------
    Z : array_like of complex, shape (..., 2K + 1)
        Roughness coefficients Z_k, k = -K..K [m].

    Returns
    -------
    float
        The level [dB re 1 µm].
    """
    Z = np.asarray(Z)
    K = (Z.shape[-1] - 1) // 2
    return float(20 * np.log10(np.sqrt(2 * np.sum(np.abs(Z[..., K + 1 :]) ** 2, axis=-1)) / 1e-6))


def short_wavelength_ratio(Z, L: float, k_min: int = 5, points: int = 601) -> float:
    """rms of the roughness with wavelengths <= L / k_min over the first third of the bay (just
    after a sleeper, in the direction of travel) divided by its rms over the middle third
    (mid-span). Above 1: the short-wavelength roughness sits after the sleepers.

    Parameters
    ----------
    Z : array_like of complex, shape (2K + 1,)
        Roughness coefficients Z_k, k = -K..K [m].
    L : float
        Sleeper spacing [m].
    k_min : int
        Shortest harmonic counted: wavelengths <= L / k_min [-].
    points : int
        Positions over the bay [-].

    Returns
    -------
    float
        The ratio [-].
    """
    Z = np.asarray(Z)
    K = (len(Z) - 1) // 2
    k = np.arange(-K, K + 1)
    x = np.linspace(0, L, points)
    prof = np.real(np.exp(1j * np.outer(x, k * 2 * np.pi / L)) @ np.where(np.abs(k) >= k_min, Z, 0))

    def rms(sel):
        return np.sqrt(np.mean(prof[sel] ** 2))

    return float(rms(x < L / 3) / rms((x >= L / 3) & (x < 2 * L / 3)))


def wear_at_roughness(wear_Z, roughness_Z, harmonic: int, mean_wear: float):
    """Wear of one passage at the harmonic of a harmonic roughness: (amplitude, rate).

    Parameters
    ----------
    wear_Z : array_like of complex, shape (2K + 1,)
        Wear spectrum Delta Z_k, k = -K..K [m].
    roughness_Z : array_like of complex, shape (2K + 1,)
        The roughness Z_k [m].
    harmonic : int
        The roughness's harmonic m [-].
    mean_wear : float
        Mean wear depth of the passage [m].

    Returns
    -------
    amplitude : float
        2 abs(Delta Z_m) / mean wear depth [-] (how strongly the wear varies at the roughness wavelength).
    rate : float
        -Re(Delta Z_m / Z_m) [-] per passage: the in-phase part, > 0 when the wear makes the roughness grow
        (Z_m - Delta Z_m is larger), < 0 when it wears it away.
    """
    K = (len(wear_Z) - 1) // 2
    dz, z = wear_Z[K + harmonic], roughness_Z[K + harmonic]
    return float(2 * abs(dz) / mean_wear), float(-np.real(dz / z))


def evaluate(*, levels_first, levels_final, argmax_harmonic, wear_amplitude, wear_rate, ratio_slow, ratio_fast,
             overall_default, overall_soft, overall_single, overall_four, pinned_pinned_Hz):
    """Decide each conclusion from its numbers; returns {id: (holds, evidence text)}.

    Rules (the same as tests/test_growth.py): 1 holds when the level of harmonic 1 grows past -40 dB and
    the strongest harmonic is one of the first three; 2 when the wear amplitude at the highest frequency is
    at least 5 times that at the lowest; 2b when the largest wear amplitude is at the frequency nearest
    pinned-pinned; 2c when the in-phase rate there is positive; 3 when ratio_slow > 3 and ratio_fast <
    0.6 ratio_slow; 4 and 5 when the level is lower.

    Parameters
    ----------
    levels_first, levels_final : float
        Level of harmonic 1 at the first save and at the end [dB re 1 µm].
    argmax_harmonic : int
        Harmonic with the highest final level (1-based) [-].
    wear_amplitude, wear_rate : dict
        {frequency [Hz]: value [-]} from wear_at_roughness.
    ratio_slow, ratio_fast : float
        short_wavelength_ratio at the lower and the higher speed [-].
    overall_default, overall_soft, overall_single, overall_four : float
        Overall levels [dB re 1 µm]: default and softer railpad, single wheel and four wheels.
    pinned_pinned_Hz : float
        The track's pinned-pinned frequency [Hz].

    Returns
    -------
    dict
        {conclusion id: (holds: bool, evidence: str)}.
    """
    f = sorted(wear_amplitude)
    out = {}
    out[1] = (bool(levels_final > levels_first > -40 and argmax_harmonic in (1, 2, 3)),
              f"harmonic 1: {levels_first:.1f} -> {levels_final:.1f} dB; strongest harmonic {argmax_harmonic}")
    amp_ratio = wear_amplitude[f[-1]] / wear_amplitude[f[0]]
    out[2] = (bool(amp_ratio >= 5), "wear at the roughness wavelength / mean: " + ", ".join(f"{wear_amplitude[x]:.3f} at {x:.0f} Hz" for x in f))
    nearest = min(f, key=lambda x: abs(x - pinned_pinned_Hz))
    largest = max(f, key=lambda x: wear_amplitude[x])
    out["2b"] = (bool(largest == nearest),
                 f"largest wear at {largest:.0f} Hz; pinned-pinned {pinned_pinned_Hz:.0f} Hz (nearest case {nearest:.0f} Hz)")
    out["2c"] = (bool(wear_rate[nearest] > 0), "in-phase rate per passage: " + ", ".join(f"{wear_rate[x]:.2e} at {x:.0f} Hz" for x in f))
    out[3] = (bool(ratio_slow > 3 and ratio_fast < 0.6 * ratio_slow), f"after-sleeper / mid-span: {ratio_slow:.2f} (slow), {ratio_fast:.2f} (fast)")
    out[4] = (bool(overall_soft < overall_default), f"{overall_soft:.2f} against {overall_default:.2f} dB")
    out[5] = (bool(overall_four < overall_single), f"{overall_four:.2f} against {overall_single:.2f} dB ({overall_four - overall_single:+.2f} dB)")
    return out


def closure_table(ds) -> list[list[str]]:
    """Rows of the closure study's conclusions table: conclusion, verdict over the well-posed
    closure values, then one cell per closure value with its number. The verdict is 'holds for
    every s', 'fails for every s' or 'depends on s'; closure values that are not well-posed are
    marked and left out of the verdict.

    Parameters
    ----------
    ds : xr.Dataset
        The closure study's dataset (rail.studies.closure.closure_study).

    Returns
    -------
    list of list of str
        The header first.
    """
    S = ds["closure_scale"].values
    ok = ds["well_posed"].values.astype(bool)
    header = ["conclusion (report section 7)", "verdict"] + [f"s = {s:g}" + ("" if w else " (not well-posed)") for s, w in zip(S, ok)]
    rows = [header]
    for j, key in enumerate(ds["conclusion"].values):
        h = ds["conclusion_holds"].values[:, j]
        decided = h[ok]
        verdict = "no well-posed value" if decided.size == 0 else (
            "holds for every s" if np.all(decided == 1) else "fails for every s" if np.all(decided == 0) else "depends on s")
        cells = [("yes" if v == 1 else "no" if v == 0 else "excluded") + ": " + str(e) for v, e in zip(h, ds["conclusion_evidence"].values[:, j])]
        rows.append([f"{key}. {ds['conclusion_text'].values[j]}", verdict] + cells)
    return rows


def markdown_table(rows) -> str:
    """A markdown table from rows (the first is the header).

    Parameters
    ----------
    rows : list of list of str
        The table's rows, the header first.

    Returns
    -------
    str
    """
    out = ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])]
    out += ["| " + " | ".join(r) + " |" for r in rows[1:]]
    return "\n".join(out) + "\n"


def html_table(rows, title: str) -> str:
    """A self-contained HTML page with the table (for the snakemake report).

    Parameters
    ----------
    rows : list of list of str
        The table's rows, the header first.
    title : str
        The page's title and heading.

    Returns
    -------
    str
    """
    from html import escape

    head = "".join(f"<th>{escape(c)}</th>" for c in rows[0])
    body = "".join("<tr>" + "".join(f"<td>{escape(c)}</td>" for c in r) + "</tr>" for r in rows[1:])
    return (f"<html><head><meta charset='utf-8'><title>{escape(title)}</title><style>td,th{{border:1px solid #999;"
            f"padding:4px;font-size:12px;vertical-align:top}}table{{border-collapse:collapse}}</style></head><body>"
            f"<h3>{escape(title)}</h3><table><tr>{head}</tr>{body}</table></body></html>\n")


def write_tables(rows, markdown_path, html_path, title: str, note: str = "") -> None:
    """Write a table (rows, header first) as markdown and as an HTML page, with an optional note
    above it.

    Parameters
    ----------
    rows : list of list of str
        The table's rows, the header first.
    markdown_path, html_path : str or Path
        The files written.
    title : str
        The HTML page's title.
    note : str
        Text above the table (markdown), or nothing.

    Returns
    -------
    None
    """
    with open(markdown_path, "w") as f:
        f.write((note + "\n\n" if note else "") + markdown_table(rows))
    with open(html_path, "w") as f:
        f.write(html_table(rows, f"{title}. {note}".strip() if note else title))
