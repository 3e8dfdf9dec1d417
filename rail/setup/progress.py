"""Progress of a long job on the terminal as well as in its log (issue 23).

A Snakemake script job writes to its log file; its terminal is the Snakemake process's. ``Tee``
writes every line to the log unchanged and also to the terminal, prefixed with the job's name,
when the terminal is a TTY (one line per message; nothing is lost from the log)."""

from __future__ import annotations

import sys

__all__ = ["Tee"]


class Tee:
    """A text stream that writes to a log file and, prefixed, to a second stream (the terminal).

    Parameters
    ----------
    log : file
        The job's log, which receives everything unchanged.
    label : str
        Prefix of the terminal lines, e.g. "growth default V40".
    terminal : file, optional
        Default: the process's original stderr, used only if it is a TTY (no duplication into a
        cluster job's output file, where the log already holds it).
    """

    def __init__(self, log, label: str, terminal=None):
        self.log = log
        self.label = label
        term = sys.__stderr__ if terminal is None else terminal
        self.terminal = term if terminal is not None or (term is not None and term.isatty()) else None
        self._pending = ""

    def write(self, text: str) -> int:
        self.log.write(text)
        if self.terminal is not None:
            self._pending += text
            while "\n" in self._pending:
                line, self._pending = self._pending.split("\n", 1)
                if line.strip():
                    self.terminal.write(f"[{self.label}] {line}\n")
        return len(text)

    def flush(self) -> None:
        self.log.flush()
        if self.terminal is not None:
            self.terminal.flush()
