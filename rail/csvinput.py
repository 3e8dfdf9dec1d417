"""Reading the CSV input files of a scenario: one place for the decoding, the header and the line
numbers that every error message names (roughness coefficients, profiles, spectra)."""

from __future__ import annotations

import csv

__all__ = ["data_rows"]


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
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = list(csv.reader(fh))
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: is not a text (UTF-8) CSV file ({e.reason} at byte {e.start}).") from None
    if not rows or tuple(c.strip() for c in rows[0]) != tuple(header):
        got = ",".join(rows[0]) if rows else "an empty file"
        raise ValueError(f"{path}, line 1: the header must be '{','.join(header)}' (got {got}).")
    return [(n, row) for n, row in enumerate(rows[1:], start=2) if row and any(c.strip() for c in row)]
