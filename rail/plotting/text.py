"""Numbers in figure titles, labels and legends as a reader writes them.

``count(82345.6)`` is ``"82,300"``, never ``"8.23e+04"``; a state at 0 passages reads "initially",
never "after 0 passages"; a parameter value such as 3.5e8 N/m reads ``"3.5×10⁸"``. Every plotting
module formats passage counts and parameter values through these functions (docs/figures.md).
"""

from __future__ import annotations

import math
import numbers
import textwrap

__all__ = ["count", "passages", "after", "limit_reached", "number", "validity_notes", "validity_note"]

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def count(n, significant: int = 3) -> str:
    """A count with thousands separators: an integer exactly (``10000`` -> ``"10,000"``), any other
    number rounded to ``significant`` figures (``82345.6`` -> ``"82,300"``).

    Parameters
    ----------
    n : int or float
        A count of passages, days, members, ... [-] (finite).
    significant : int
        Significant figures kept for a non-integer, >= 1.

    Returns
    -------
    str
    """
    if isinstance(n, numbers.Integral):  # numpy integers too
        return f"{int(n):,}"
    x = float(n)
    if not math.isfinite(x):
        raise ValueError(f"count: n = {x} is not a finite number")
    if x == 0:
        return "0"
    digits = significant - 1 - math.floor(math.log10(abs(x)))
    r = round(x, digits)
    if digits <= 0:
        return f"{int(r):,}"
    return f"{r:,.{digits}f}".rstrip("0").rstrip(".")


def passages(n) -> str:
    """``"82,300 passages"`` (``"1 passage"``).

    Parameters
    ----------
    n : int or float
        Passages [-].

    Returns
    -------
    str
    """
    return f"{count(n)} passage{'' if n == 1 else 's'}"


def after(n) -> str:
    """The time of a saved state: ``"initially"`` at 0 passages, ``"after 82,300 passages"`` otherwise.

    Parameters
    ----------
    n : int or float
        Passages [-].

    Returns
    -------
    str
    """
    return "initially" if n == 0 else f"after {passages(n)}"


def limit_reached(n, days: float = float("nan"), band_mm: float | None = None) -> str:
    """The grinding interval in words: ``"limit reached after 82,300 passages (95 days) in the
    31.5 mm band"``, or ``"limit already exceeded initially (in the 31.5 mm band)"`` when the
    interval is 0 passages; ``days`` NaN when the traffic is not given.

    Parameters
    ----------
    n : int or float
        The grinding interval [passages].
    days : float
        The same in days [d] (NaN: no traffic given).
    band_mm : float, optional
        The band that reaches its limit first [mm].

    Returns
    -------
    str
    """
    band = f" in the {band_mm:g} mm band" if band_mm is not None else ""
    if n <= 0:
        return f"limit already exceeded initially{f' ({band.strip()})' if band else ''}"
    when = f" ({count(days)} days)" if math.isfinite(days) else ""
    return f"limit reached after {passages(n)}{when}{band}"


def number(x, significant: int = 3) -> str:
    """A parameter value for a title or tick: ``"40"``, ``"0.25"``, ``"3.5×10⁸"`` (powers of ten
    for magnitudes from 10⁵ and below 10⁻³, never ``"3.5e+08"``).

    Parameters
    ----------
    x : float
        The value, in the unit the caller writes beside it [-].
    significant : int
        Significant figures.

    Returns
    -------
    str
    """
    x = float(x)
    if x == 0 or not math.isfinite(x):
        return f"{x:g}"
    e = math.floor(math.log10(abs(x)))
    if -3 <= e < 5:
        return f"{x:.{significant}g}"
    m = f"{x / 10 ** e:.{significant}g}"
    if m == "10":  # rounding carried over
        m, e = "1", e + 1
    power = f"10{str(e).translate(_SUPERSCRIPT)}"
    return power if m == "1" else f"{m}×{power}"


def validity_notes(attrs) -> list:
    """The notes saying where a result leaves the model or how the wear was placed (issue 42), as
    (text, colour): red when the contact-centre flag is raised (attribute contact_shift_warning), grey
    when the wear is on the patch's true path; none for the report's model within its range.

    Parameters
    ----------
    attrs : mapping
        The plotted dataset's attributes (contact_shift_modelled, contact_shift_warning).

    Returns
    -------
    list of tuple of (str, str)
        (text, colour) per note.
    """
    warning = attrs.get("contact_shift_warning")
    if warning:
        return [("\n".join(textwrap.wrap("outside validity: " + " ".join(str(warning).split()), 150)), "firebrick")]
    if attrs.get("contact_shift_modelled"):  # the wear path's flag (rail.contact.WearPath.attributes), never its sentence parsed
        return [("wear on the contact patch's true path (docs/contact.md)", "0.4")]
    return []


def validity_note(fig, attrs, extra=()) -> None:
    """The notes of ``extra`` ((text, colour) pairs) and validity_notes(attrs) in one box below the axes
    (rail.plotting.axes.footer: never over a curve or a label); nothing when there are none, so that
    the report's figures are unchanged.

    Parameters
    ----------
    fig : matplotlib Figure (constrained layout)
    attrs : mapping
        The plotted dataset's attributes (wear_path, contact_shift_warning).
    extra : sequence of (str, colour)
        Notes of the figure itself, first.

    Returns
    -------
    None
    """
    from .axes import footer

    footer(fig, [*extra, *validity_notes(attrs)])
