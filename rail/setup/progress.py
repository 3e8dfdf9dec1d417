"""Progress of a long job on the terminal as well as in its log (issues 23 and 36).

A Snakemake script job writes to its log file; its terminal is the Snakemake process's. ``Tee``
writes every line to the log unchanged and, when there is a terminal, keeps a live progress bar
there (tqdm) that follows the "<done> of <total> <unit>" lines of the long jobs (growth: "passages",
receptance tables: "tables" or "node blocks", growth-rate spectrum: "probe batches"); other lines
(warnings, resuming) are printed above the bar. Nothing is lost from the log. A count's lines in the
log say the time used and the time left (``progress_lines``: "3 of 10 probe batches, 6 min elapsed,
about 14 min left"; the growth loop writes its own "s left").

The terminal is the process's stderr if that is a TTY, else the controlling terminal /dev/tty if
the process has one (Snakemake run as ``snakemake ... 2>&1 | tee run.txt`` or with its stderr in a
file: the bar still shows where the user sees it). A cluster job has none and writes the log only.
A terminal that reports no size (0 columns or 0 lines: a pseudo-terminal without a window size, as
under ``script``, ``ssh -t`` from a script or some IDE and agent consoles) gets a bar of 80 columns:
tqdm's own size there is 0 columns or -1 lines, with which it drew an empty line (issue 36: "under
a terminal the growth bar did not show").
"""

from __future__ import annotations

import os
import re
import sys
import time

from tqdm import tqdm

__all__ = ["Tee", "controlling_terminal", "time_left", "duration", "Progress", "progress_lines"]

_DONE = re.compile(r"^(\d+) of (\d+) ([^,(\n]+)")
_FALLBACK_COLUMNS = 80
_FALLBACK_LINES = 24


def controlling_terminal():
    """The terminal a job's progress bar is drawn on, or None.

    Returns
    -------
    file or None
        ``sys.__stderr__`` if it is a TTY; else /dev/tty opened for writing if the process has a
        controlling terminal; else None (a cluster job, a daemon, a test without a terminal).
    """
    err = sys.__stderr__
    try:
        if err is not None and err.isatty():
            return err
    except ValueError:  # closed
        pass
    try:
        return open("/dev/tty", "w", encoding="utf-8", errors="replace")  # noqa: SIM115 - closed by Tee.close
    except OSError:  # ENXIO: no controlling terminal
        return None


def _size(stream) -> tuple[int, int]:
    """(columns, lines) of a terminal stream; each 0 where it reports none."""
    try:
        size = os.get_terminal_size(stream.fileno())
        return size.columns, size.lines
    except (OSError, ValueError, AttributeError):
        return 0, 0


class Tee:
    """A text stream that writes to a log file and shows progress on a second stream (the terminal).

    Parameters
    ----------
    log : file
        The job's log, which receives everything unchanged.
    label : str
        Name of the job on the terminal, e.g. "growth default V40".
    terminal : file, optional
        Default: ``controlling_terminal()`` (stderr if a TTY, else /dev/tty, else none: then only
        the log is written, with no duplication into a cluster job's output file).
    """

    def __init__(self, log, label: str, terminal=None):
        self.log = log
        self.label = label
        self._own = terminal is None
        self.terminal = controlling_terminal() if terminal is None else terminal
        self._own = self._own and self.terminal is not None and self.terminal is not sys.__stderr__
        self.bar = None
        self._unit = None
        self._pending = ""

    def write(self, text: str) -> int:
        self.log.write(text)
        if self.terminal is not None:
            self._pending += text
            while "\n" in self._pending:
                line, self._pending = self._pending.split("\n", 1)
                self._show(line)
        return len(text)

    def _new_bar(self, total: int, unit: str):
        # the size is given, not left to tqdm: where the terminal reports 0 columns or 0 lines tqdm's
        # own size is 0 columns or -1 lines, and it draws nothing
        columns, lines = _size(self.terminal)
        return tqdm(total=total, desc=self.label, unit=f" {unit}", file=self.terminal, mininterval=0.5,
                    ncols=columns if columns > 0 else _FALLBACK_COLUMNS, nrows=lines if lines > 0 else _FALLBACK_LINES)

    def _show(self, line: str) -> None:
        m = _DONE.match(line)
        if m:
            done, total, unit = int(m.group(1)), int(m.group(2)), m.group(3).strip()
            if self.bar is None or unit != self._unit or done < self.bar.n or total != self.bar.total:
                if self.bar is not None:
                    self.bar.close()
                self.bar, self._unit = self._new_bar(total, unit), unit
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

    def close(self) -> None:
        """Close the bar, and the terminal if this Tee opened it (/dev/tty); the log stays open."""
        if self.bar is not None:
            self.bar.close()
        if self._own:
            self.terminal.close()
            self.terminal = None


def time_left(done: float, total: float, elapsed: float) -> float | None:
    """Seconds left of a count, extrapolated from the fraction done: elapsed (total - done) / done.

    Parameters
    ----------
    done, total : float
        Steps done and steps in all [-] (0 <= done <= total).
    elapsed : float
        Seconds since the count started [s], >= 0.

    Returns
    -------
    float or None
        None before the first step is done (nothing to extrapolate from), or for an empty count.
    """
    if done <= 0 or total <= 0:
        return None
    return max(elapsed, 0.0) * max(total - done, 0.0) / done


def duration(seconds: float) -> str:
    """A time span as a reader takes it in: "45 s", "12 min", "2.3 h" (seconds below 2 minutes, minutes
    below 2 hours).

    Parameters
    ----------
    seconds : float
        The time span [s].

    Returns
    -------
    str
    """
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class Progress:
    """The lines of a progress callback with the time used and the time left.

    A "<done> of <total> <unit>" line gets ", <elapsed> elapsed, about <left> left": elapsed since the
    callback was made, left extrapolated from the fraction done of that count (time_left). Each count
    (unit and total) is timed on its own, so that a job counting tables, and node blocks within each
    table, states both: a count's clock starts at its "0 of" line, or when it has none at the
    callback's making (its first run) or at the line before (a count that starts again). Any other line
    gets the elapsed time.

    Parameters
    ----------
    clock : callable
        Seconds, monotonic (default time.perf_counter; a test passes a fake one).
    """

    def __init__(self, clock=time.perf_counter):
        self.clock = clock
        self.t0 = self.last = clock()
        self._counts = {}  # (unit, total) -> (last done, start time)

    def line(self, text: str) -> str:
        """The line to write for ``text``."""
        now = self.clock()
        elapsed = now - self.t0
        m = _DONE.match(text)
        if m is None:
            self.last = now
            return f"{text}, {duration(elapsed)} elapsed"
        done, total, unit = int(m.group(1)), int(m.group(2)), m.group(3).strip()
        key = (unit, total)
        if key not in self._counts:
            start = now if done == 0 else self.t0
        elif done < self._counts[key][0]:
            start = now if done == 0 else self.last
        else:
            start = self._counts[key][1]
        self._counts[key] = (done, start)
        self.last = now
        left = time_left(done, total, now - start)
        return f"{text}, {duration(elapsed)} elapsed" + ("" if left is None else f", about {duration(left)} left")


def progress_lines(stream, prefix: str = "", clock=time.perf_counter):
    """A progress callback for rail's long computations (``progress=`` of rail.chain.track_table,
    rail.growth_spectrum.rate_spectrum): each line it is given is written to ``stream`` (a log or a
    Tee) with the time since the callback was made and, on a "<done> of <total>" line, the time left
    (Progress), and flushed.

    Parameters
    ----------
    stream : file
    prefix : str
        Put before each line (e.g. "receptance V40: "); a "<done> of <total>" line keeps its start
        so that a Tee draws it as a bar, the prefix is then appended in brackets.
    clock : callable
        Seconds, monotonic (a test passes a fake one).

    Returns
    -------
    callable
        ``callback(text)``.
    """
    timer = Progress(clock)

    def callback(text: str) -> None:
        line = timer.line(text)
        if _DONE.match(text):
            line += f" [{prefix.rstrip(': ')}]" if prefix else ""
        else:
            line = prefix + line
        print(line, file=stream, flush=True)

    return callback
