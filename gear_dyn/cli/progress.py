"""Progress of the long commands on stderr: a tqdm bar on a terminal, plain lines elsewhere.

Off a terminal (a log, CI, a pipe) :func:`counter` writes a line when the work has run for one
second (``gear-dyn: 0% (0/361 speeds, 1.0 s)``, from a timer: the first block may take much
longer than that), then one per 10 % of the items (``gear-dyn: 30% (108/361 speeds, 2.4
s)``); :class:`Stages` a line naming the stage under way at one second, then one as each later
stage starts. Runs shorter than a second stay silent. ``--quiet`` silences both. tqdm is
imported only when a bar is drawn.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO


def add_quiet_flag(p: Any, *aliases: str) -> None:
    """``--quiet`` (and its ``aliases``): no progress bar (there is none when stderr is not a
    terminal)."""
    p.add_argument(*aliases, "--quiet", dest="quiet", action="store_true",
                   help="no progress on stderr (a bar on a terminal, else a line after one "
                   "second and per 10 %% or per stage)")


def shown(quiet: bool, stream: TextIO | None = None) -> bool:
    """Whether a bar is drawn: not ``quiet`` and ``stream`` (default stderr) is a terminal."""
    s = sys.stderr if stream is None else stream
    return not quiet and bool(getattr(s, "isatty", lambda: False)())


def _bar(stream: TextIO, **kw: Any) -> Any:
    """A tqdm bar on ``stream``, removed when closed, as wide and high as the terminal, at
    least 40 x 2 (a fresh pseudo-terminal says 0 x 0, and tqdm hides a bar below row 0)."""
    import shutil

    from tqdm import tqdm

    size = shutil.get_terminal_size()
    return tqdm(file=stream, leave=False, ncols=max(size.columns, 40), nrows=max(size.lines, 2),
                **kw)


def counter(unit: str, quiet: bool = False, stream: TextIO | None = None
            ) -> Callable[[int, int], None] | None:
    """A ``progress(done, total)`` callback drawing a bar of ``unit`` items, or None (silent).

    The bar closes itself when ``done`` reaches ``total``.
    """
    s = sys.stderr if stream is None else stream
    if quiet:
        return None
    if not shown(quiet, s):
        return _lines(unit, s)
    state: dict[str, Any] = {}

    def show(done: int, total: int) -> None:
        bar = state.get("bar")
        if bar is None:
            bar = state["bar"] = _bar(s, total=total, unit=unit)
        bar.update(done - bar.n)
        if done >= total:
            bar.close()
    return show


def _after(delay: float, fn: Callable[[], None]) -> threading.Timer:
    """``fn()`` in ``delay`` seconds on a daemon timer thread (cancel it when done)."""
    timer = threading.Timer(delay, fn)
    timer.daemon = True
    timer.start()
    return timer


def _lines(unit: str, stream: TextIO, step: float = 0.1, after: float = 1.0
           ) -> Callable[[int, int], None]:
    """``progress(done, total)`` writing a line once ``after`` seconds have passed (from a
    timer started on the first call, whether or not a step was reached), then at each
    ``step`` of the total (off a terminal: no redrawing)."""
    t0 = time.perf_counter()
    state: dict[str, Any] = {"next": step, "done": 0, "total": 0, "written": False,
                             "timer": None}
    lock = threading.Lock()

    def write(done: int, total: int) -> None:
        elapsed = time.perf_counter() - t0
        stream.write(f"gear-dyn: {done / max(total, 1):.0%} ({done}/{total} {unit}s, "
                     f"{elapsed:.1f} s)\n")
        stream.flush()
        state["written"] = True

    def heartbeat() -> None:
        with lock:
            if not state["written"] and state["done"] < state["total"]:
                write(state["done"], state["total"])

    def show(done: int, total: int) -> None:
        with lock:
            state["done"], state["total"] = done, total
            if state["timer"] is None and done < total:
                state["timer"] = _after(max(after - (time.perf_counter() - t0), 0.0),
                                        heartbeat)
            if done >= total and state["timer"] is not None:
                state["timer"].cancel()
            share = done / max(total, 1)
            if share + 1e-12 < state["next"]:
                return
            while state["next"] <= share + 1e-12:
                state["next"] += step
            if time.perf_counter() - t0 >= after:
                write(done, total)
    return show


class Stages:
    """A bar over named stages: ``with Stages(["load", "solve", "write"], quiet) as st:``
    then ``st.next()`` as each stage starts (the bar shows the stage's name)."""

    def __init__(self, names: Sequence[str], quiet: bool = False,
                 stream: TextIO | None = None, after: float = 1.0) -> None:
        self.names = list(names)
        self.i = -1
        self.bar: Any = None
        self.stream: TextIO | None = None  # off a terminal: lines on it
        self.t0, self.after = time.perf_counter(), after
        self.timer: threading.Timer | None = None
        self.lock = threading.Lock()
        s = sys.stderr if stream is None else stream
        if shown(quiet, s):
            self.bar = _bar(s, total=len(self.names), unit="stage",
                            bar_format="{l_bar}{bar}| {n}/{total} stages")
        elif not quiet:
            self.stream = s
            self.timer = _after(after, self._line)

    def _line(self) -> None:
        """``gear-dyn: stage 2/3, solve (1.0 s)``: the stage under way."""
        with self.lock:
            if self.stream is not None and 0 <= self.i < len(self.names):
                self.stream.write(f"gear-dyn: stage {self.i + 1}/{len(self.names)}, "
                                  f"{self.names[self.i]} ({time.perf_counter() - self.t0:.1f}"
                                  " s)\n")
                self.stream.flush()

    def next(self) -> None:
        """Start the next stage (the previous one is counted done)."""
        if self.i >= 0 and self.bar is not None:
            self.bar.update(1)
        self.i += 1
        if self.bar is not None and self.i < len(self.names):
            self.bar.set_description_str(self.names[self.i])
        if self.stream is not None and time.perf_counter() - self.t0 >= self.after:
            self._line()

    def __enter__(self) -> Stages:
        self.next()
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.timer is not None:
            self.timer.cancel()
        self.stream = None
        if self.bar is not None:
            if exc[0] is None:
                self.bar.update(len(self.names) - self.bar.n)
            self.bar.close()


__all__ = ["Stages", "add_quiet_flag", "counter", "shown"]
