"""Reading the CSV input files of a scenario: one place for the decoding, the header and the line
numbers that every error message names (roughness coefficients, profiles, spectra).

Headers with units (``unit_rows``; docs/roughness-input.md). Each cell of line 1 names a quantity
and its unit, in one of three forms (blanks around the cell, the name and the unit are ignored; the
quantity name and the unit are read without regard to case)::

    <name>_<unit>        position_mm   wavelength_cm   level_dB
    <name> [<unit>]      position [mm]  roughness [µm]  level [dB re 1 µm]
    <name> (<unit>)      wavelength (cm)

Units: ``m``, ``cm``, ``mm``, ``µm`` (also written ``um`` or with the Greek mu ``μm``) and ``dB``
(also ``dB re 1 µm``): each column accepts the units its reader lists. A cell without a unit, or
with a unit its column does not accept, is an error naming the file, the column and the units
accepted.
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass

__all__ = ["data_rows", "Column", "split_header_cell", "canonical_unit", "unit_rows"]


def _read(path) -> list[list[str]]:
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            return list(csv.reader(fh))
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: is not a text (UTF-8) CSV file ({e.reason} at byte {e.start}).") from None


def _data(rows) -> list[tuple[int, list[str]]]:
    return [(n, row) for n, row in enumerate(rows[1:], start=2) if row and any(c.strip() for c in row)]


def data_rows(path, header: tuple[str, ...]) -> list[tuple[int, list[str]]]:
    """The data lines of a CSV file after its header, with their line numbers.

    Parameters
    ----------
    path : str or Path
        A UTF-8 text file; a byte-order mark is not part of the header.
    header : tuple of str
        The required column names of line 1 (surrounding blanks ignored).

    Returns
    -------
    list of (int, list of str)
        (line number from 1, cells) of every line after the header that is not blank.

    Raises
    ------
    ValueError
        Naming the file: not a UTF-8 text file; naming line 1: a wrong or missing header.
    """
    rows = _read(path)
    if not rows or tuple(c.strip() for c in rows[0]) != tuple(header):
        got = ",".join(rows[0]) if rows else "an empty file"
        raise ValueError(f"{path}, line 1: the header must be '{','.join(header)}' (got {got}).")
    return _data(rows)


@dataclass(frozen=True)
class Column:
    """One column of a CSV file whose header states the unit.

    quantity : the name written in the header (e.g. 'position')
    aliases  : other names accepted for it (e.g. ('distance',))
    units    : the units it accepts, canonical spelling (canonical_unit), e.g. ('m', 'cm', 'mm')
    """

    quantity: str
    aliases: tuple
    units: tuple

    def accepted(self) -> str:
        """The accepted units as a message writes them (µm also as um, dB as dB re 1 µm)."""
        spell = {"µm": "µm (or um)", "dB": "dB (re 1 µm)"}
        return ", ".join(spell.get(u, u) for u in self.units)


def split_header_cell(cell: str) -> tuple[str, str | None]:
    """A header cell as (name, unit): 'position [mm]', 'position (mm)', 'position_mm' -> ('position',
    'mm'); a cell without a unit -> (name, None).

    Parameters
    ----------
    cell : str
        One cell of line 1.

    Returns
    -------
    (str, str or None)
        The name and the unit as written (stripped).
    """
    s = cell.strip()
    m = re.fullmatch(r"(.*?)\s*[\[(]\s*(.*?)\s*[\])]", s)
    if m:
        return m.group(1).strip(), m.group(2)
    if "_" in s:
        name, unit = s.rsplit("_", 1)
        return name.strip(), unit.strip()
    return s, None


def canonical_unit(unit: str) -> str | None:
    """The canonical spelling of a unit written in a header, or None if it is not one of m, cm, mm,
    µm (um, μm), dB (dB re 1 µm).

    Parameters
    ----------
    unit : str
        As written, e.g. 'mm' or 'dB re 1 µm' [-] (case is ignored).

    Returns
    -------
    str or None
        'm', 'cm', 'mm', 'µm' or 'dB'.
    """
    u = " ".join(unit.replace("\u03bc", "\u00b5").split()).lower()
    if u in ("m", "cm", "mm"):
        return u
    if u in ("\u00b5m", "um"):
        return "µm"
    if re.fullmatch(r"db( re 1 ?[\u00b5u]m)?", u):
        return "dB"
    return None


def unit_rows(path, columns: tuple, example: str) -> tuple[tuple[str, ...], list[tuple[int, list[str]]]]:
    """The units a CSV file's header states for its columns, and its data lines with their numbers.

    Parameters
    ----------
    path : str or Path
        A UTF-8 text file (a byte-order mark is not part of the header).
    columns : tuple of Column
        The columns line 1 must name, in order, each with its unit (module docstring: the grammar).
    example : str
        A valid header, named in the messages (e.g. 'position_m,height_m').

    Returns
    -------
    units : tuple of str
        The canonical unit of each column (canonical_unit), e.g. ('mm', 'µm') [-].
    rows : list of (int, list of str)
        (line number from 1, cells) of every line after the header that is not blank.

    Raises
    ------
    ValueError
        Naming the file: not a UTF-8 text file; naming line 1: a missing header, a wrong number of
        columns or a wrong quantity; naming line 1, the column and the accepted units: a missing or
        unknown unit.
    """
    rows = _read(path)
    grammar = ("each column is <name>_<unit> or '<name> [<unit>]', "
               + "; ".join(f"{c.quantity} in {c.accepted()}" for c in columns))
    got = ",".join(rows[0]) if rows else "an empty file"
    cells = [c for c in rows[0]] if rows else []
    if len(cells) != len(columns):
        raise ValueError(f"{path}, line 1: the header must be '{example}' (got {got}): {len(columns)} columns, {grammar}.")
    units = []
    for i, (cell, col) in enumerate(zip(cells, columns), start=1):
        name, unit = split_header_cell(cell)
        if name.lower() not in (col.quantity, *col.aliases):
            names = " or ".join((col.quantity, *col.aliases))
            raise ValueError(f"{path}, line 1: the header must be '{example}' (got {got}): column {i} ({cell.strip()!r}) "
                             f"must be {names} with its unit; {grammar}.")
        if unit is None or unit == "":
            raise ValueError(f"{path}, line 1, column {i} ({cell.strip()!r}): no unit: write {name}_<unit> or '{name} [<unit>]' "
                             f"with <unit> one of {col.accepted()} (e.g. '{example}').")
        u = canonical_unit(unit)
        if u not in col.units:
            raise ValueError(f"{path}, line 1, column {i} ({cell.strip()!r}): the unit {unit!r} is not accepted for {col.quantity}: "
                             f"it must be one of {col.accepted()} (e.g. '{example}').")
        units.append(u)
    return tuple(units), _data(rows)
