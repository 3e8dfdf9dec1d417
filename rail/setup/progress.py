"""Progress of a long job on the terminal as well as in its log (issue 23).

A Snakemake script job writes to its log file; its terminal is the Snakemake process's. ``Tee``
writes every line to the log unchanged and, when the terminal is a TTY, keeps a live progress bar
there (tqdm) that follows the "<done> of <total> passages" lines of rail.growth.run_growth; other
lines (warnings, resuming) are printed above the bar. Nothing is lost from the log."""

from __future__ import annotations

import re
import sys

from tqdm import tqdm

__all__ = ["Tee"]

_DONE = re.compile(r"^(\d+) of (\d+) passages")


class Tee:
    """A text stream that writes to a log file and shows progress on a second stream (the terminal).

    Parameters
    ----------
    log : file
        The job's log, which receives everything unchanged.
    label : str
        Name of the job on the terminal, e.g. "growth default V40".
    terminal : file, optional
        Default: the process's original stderr, used only if it is a TTY (no duplication into a
        cluster job's output file, where the log already holds it).
    """

    def __init__(self, log, label: str, terminal=None):
        self.log = log
        self.label = label
        term = sys.__stderr__ if terminal is None else terminal
        self.terminal = term if terminal is not None or (term is not None and term.isatty()) else None
        self.bar = None
        self._pending = ""

    def write(self, text: str) -> int:
        self.log.write(text)
        if self.terminal is not None:
            self._pending += text
            while "\n" in self._pending:
                line, self._pending = self._pending.split("\n", 1)
                self._show(line)
        return len(text)

    def _show(self, line: str) -> None:
        m = _DONE.match(line)
        if m:
            done, total = int(m.group(1)), int(m.group(2))
            if self.bar is None:
                self.bar = tqdm(total=total, desc=self.label, unit=" passages", file=self.terminal, dynamic_ncols=True,
                                mininterval=0.5)
            self.bar.update(done - self.bar.n)
            if done >= total:
                self.bar.close()
        elif line.strip():
            text = f"[{self.label}] {line}"
            if self.bar is not None and not self.bar.disable:
                self.bar.write(text, file=self.terminal)
            else:
                self.terminal.write(text + "\n")

    def flush(self) -> None:
        self.log.flush()
        if self.terminal is not None:
            self.terminal.flush()
