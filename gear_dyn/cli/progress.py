"""Progress of the long commands on stderr: a tqdm bar on a terminal, plain lines elsewhere.

Off a terminal :func:`counter` writes one line per 10 % of the items
(``gear-dyn: sweep 30% (108/361 speeds, 2.4 s)``), from the first step reached after one
second, so short runs stay silent. ``--quiet`` silences both. tqdm is imported only when a bar
is drawn.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from typing import Any, TextIO


def add_quiet_flag(p: Any, *aliases: str) -> None:
    """``--quiet`` (and its ``aliases``): no progress bar (there is none when stderr is not a
    terminal)."""
    p.add_argument(*aliases, "--quiet", dest="quiet", action="store_true",
                   help="no progress bar on stderr (there is none when stderr is not a "
                   "terminal)")


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


def _lines(unit: str, stream: TextIO, step: float = 0.1, after: float = 1.0
           ) -> Callable[[int, int], None]:
    """``progress(done, total)`` writing a line at each ``step`` of the total, once ``after``
    seconds have passed (off a terminal: no redrawing)."""
    import time

    t0 = time.perf_counter()
    state = {"next": step}

    def show(done: int, total: int) -> None:
        share = done / max(total, 1)
        if share + 1e-12 < state["next"]:
            return
        while state["next"] <= share + 1e-12:
            state["next"] += step
        elapsed = time.perf_counter() - t0
        if elapsed >= after:
            stream.write(f"gear-dyn: {share:.0%} ({done}/{total} {unit}s, {elapsed:.1f} s)\n")
            stream.flush()
    return show


class Stages:
    """A bar over named stages: ``with Stages(["load", "solve", "write"], quiet) as st:``
    then ``st.next()`` as each stage starts (the bar shows the stage's name)."""

    def __init__(self, names: Sequence[str], quiet: bool = False,
                 stream: TextIO | None = None) -> None:
        self.names = list(names)
        self.i = -1
        self.bar: Any = None
        s = sys.stderr if stream is None else stream
        if shown(quiet, s):
            self.bar = _bar(s, total=len(self.names), unit="stage",
                            bar_format="{l_bar}{bar}| {n}/{total} stages")

    def next(self) -> None:
        """Start the next stage (the previous one is counted done)."""
        if self.i >= 0 and self.bar is not None:
            self.bar.update(1)
        self.i += 1
        if self.bar is not None and self.i < len(self.names):
            self.bar.set_description_str(self.names[self.i])

    def __enter__(self) -> Stages:
        self.next()
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.bar is not None:
            if exc[0] is None:
                self.bar.update(len(self.names) - self.bar.n)
            self.bar.close()


__all__ = ["Stages", "add_quiet_flag", "counter", "shown"]
