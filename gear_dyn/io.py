"""Files written whole or not at all.

- :func:`write_text` / :func:`write_bytes`: write a temporary file in the same folder, fsync, then
  ``os.replace`` it onto the target (atomic on POSIX).
- :func:`staged_output`: a whole output folder, written into a temporary sibling and swapped in
  place of the target only when the block succeeds. A failure, Ctrl-C or SIGTERM leaves the
  previous output intact; a ``.NAME.PID.*.partial`` sibling left by SIGKILL is removed by the
  next ``staged_output`` of the same target once process PID is gone.

Files and folders get the usual permissions (0666 / 0777 minus the umask), like ``open()``.
"""

from __future__ import annotations

import contextlib
import csv
import glob
import io
import json
import math
import os
import shutil
import signal
import sys
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from gear_dyn.errors import InputError


def _read_umask() -> int:
    try:  # Linux: read it without changing it
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _read_umask()


def write_bytes(path: str | Path, data: bytes) -> Path:
    """Atomically write ``data`` to ``path`` (temporary file in the same folder, then rename).

    Raises
    ------
    InputError
        The folder does not exist or is not writable, the path is a folder, or the write failed
        (disk full, ...); the message names the path and the target is unchanged.
    """
    p = Path(path)
    if not p.name or p.is_dir():
        raise InputError(f"{str(path)!r}: is a folder, expected a file name")
    tmp: str | None = None
    try:
        with _signals_deferred():  # a signal cannot land between creating and naming it
            try:
                fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
            except OSError as exc:
                raise InputError(f"{p}: cannot write here ({exc.strerror})") from None
        with os.fdopen(fd, "wb") as fh:
            os.fchmod(fh.fileno(), 0o666 & ~_UMASK)
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, p)
    except BaseException as exc:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        if isinstance(exc, OSError):  # disk full, permission denied, ...: say where
            raise InputError(f"{p}: cannot write ({exc.strerror or exc}); nothing was "
                             "changed") from None
        raise
    return p


def write_text(path: str | Path, text: str) -> Path:
    """Atomically write UTF-8 ``text`` to ``path``."""
    return write_bytes(path, text.encode("utf-8"))


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, Mapping):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, float | np.floating):
        f = float(obj)
        return f if math.isfinite(f) else None
    return obj


def write_json(path: str | Path, data: Any) -> Path:
    """Atomically write ``data`` as indented JSON (numpy values converted, NaN -> null)."""
    return write_text(path, json.dumps(_jsonable(data), indent=2) + "\n")


def write_csv(path: str | Path, columns: Mapping[str, Sequence[float] | np.ndarray],
              comments: Sequence[str] = ()) -> Path:
    """Atomically write equal-length columns as CSV with a header row, after ``comments``
    (lines written as they are, e.g. ``# units ...``)."""
    names = list(columns)
    arrays = [np.asarray(columns[n]) for n in names]
    if len({a.shape for a in arrays}) > 1:
        raise InputError("write_csv: columns have different lengths")
    buf = io.StringIO()
    buf.writelines(f"{line}\n" for line in comments)
    csv.writer(buf, lineterminator="\n").writerow(names)
    # shortest text that reads back exactly (repr of each float), a column at a time: ~5x
    # faster than a csv.writer row loop, the same text
    texts = [map(repr, a.astype(float).ravel().tolist()) for a in arrays]
    buf.write("".join(",".join(row) + "\n" for row in zip(*texts, strict=True)))
    return write_text(path, buf.getvalue())


def column_rows(columns: Mapping[str, Sequence[float] | np.ndarray]) -> list[dict[str, float]]:
    """Equal-length columns (as :func:`write_csv` takes them) as one dict of plain floats per
    row: the rows of their CSV, for a result's ``rows()``."""
    names = list(columns)
    values = [np.asarray(columns[n], dtype=float).ravel().tolist() for n in names]
    return [dict(zip(names, row, strict=True)) for row in zip(*values, strict=True)]


def write_rows(path: str | Path, rows: Sequence[Mapping[str, Any]],
               empty: Sequence[str] = ()) -> Path:
    """Atomically write dict rows as CSV, the first row's keys as header (``empty``: the header
    when there are no rows)."""
    buf = io.StringIO()
    fields = list(rows[0]) if rows else list(empty)
    if fields:
        w = csv.DictWriter(buf, fieldnames=fields, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    return write_text(path, buf.getvalue())


def save_figure(fig: Any, path: str | Path, **kwargs: Any) -> Path:
    """Render a matplotlib figure to bytes, write it atomically and close the figure.

    Works for a plain :class:`matplotlib.figure.Figure` (no pyplot, no backend: ``savefig``
    renders off-screen). A figure that pyplot manages is closed even when rendering fails, so
    commands that draw many figures do not accumulate them in pyplot's registry; saving never
    imports pyplot itself.
    """
    buf = io.BytesIO()
    fmt = Path(path).suffix.lstrip(".") or "png"
    try:
        fig.savefig(buf, format=fmt, **kwargs)
    finally:
        plt = sys.modules.get("matplotlib.pyplot")
        if plt is not None:
            plt.close(fig)
    return write_bytes(path, buf.getvalue())


@contextlib.contextmanager
def staged_output(out_dir: str | Path) -> Iterator[Path]:
    """Yield a temporary folder; on success it replaces ``out_dir`` as a whole.

    Raises
    ------
    InputError
        ``out_dir`` exists and is not a folder, or its parent cannot be created; or it is a
        folder holding anything but files with the suffixes in :data:`OUTPUT_SUFFIXES` (a
        scene, notes, subfolders: replacing the folder would delete them), or the current
        folder, one of its parents or the home folder.
    """
    target = Path(out_dir)
    if target.exists() and not target.is_dir():
        raise InputError(f"--out {target}: exists and is not a folder")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {target}: cannot create parent folder ({exc.strerror})") from None
    _remove_stale(target)
    _check_replaceable(target)
    prefix = f".{target.name}.{os.getpid()}."
    tmp: Path | None = None
    try:
        # SIGINT/SIGTERM are held while the folder is created and named, so that the cleanup
        # below always knows it; they are delivered right after
        with _signals_deferred():
            try:
                tmp = Path(tempfile.mkdtemp(prefix=prefix, suffix=".partial", dir=target.parent))
                os.chmod(tmp, 0o777 & ~_UMASK)
            except OSError as exc:
                raise InputError(f"--out {target}: cannot write here ({exc.strerror})") from None
        yield tmp
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    # the swap: a few renames, with SIGINT/SIGTERM held so that it completes either way
    with _signals_deferred():
        old = None
        try:
            if target.exists():
                old = Path(tempfile.mkdtemp(prefix=prefix, suffix=".old", dir=target.parent))
                os.rmdir(old)
                os.replace(target, old)
            os.replace(tmp, target)
        except BaseException:
            if old is not None and not target.exists():  # put the previous output back
                with contextlib.suppress(OSError):
                    os.replace(old, target)
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM for the block: their handlers only note a signal, and the first
    one noted is handed to the previous handler when the block ends.

    Python runs signal handlers in the main thread whichever thread the kernel hands the signal
    to (a BLAS worker, a progress bar's monitor), so a mask of the main thread alone does not
    hold them; swapping the Python-level handlers does. Outside the main thread, where handlers
    cannot be set (and do not run), the block runs as it is.
    """
    import threading

    held = (signal.SIGINT, signal.SIGTERM)
    previous = {s: signal.getsignal(s) for s in held}
    if threading.current_thread() is not threading.main_thread() or None in previous.values():
        yield  # None: a handler not set from Python, which cannot be put back
        return
    noted: list[tuple[int, Any]] = []
    for s in held:
        signal.signal(s, lambda signum, frame: noted.append((signum, frame)))
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        if noted:
            signum, frame = noted[0]
            handler = previous[signal.Signals(signum)]
            if callable(handler):
                handler(signum, frame)
            elif handler == signal.SIG_DFL:  # the default action: end the process by it
                os.kill(os.getpid(), signum)


#: what gear_dyn commands write into an output folder; a folder holding anything else (a scene,
#: notes, a subfolder) is not replaced, since replacing it would delete those
OUTPUT_SUFFIXES = (".png", ".svg", ".pdf", ".csv", ".json", ".md")
_IGNORED = (".DS_Store", "Thumbs.db", "desktop.ini")


def _check_replaceable(target: Path) -> None:
    """Refuse to replace a folder that is not a previous output (it would be deleted whole)."""
    if not target.is_dir():
        return
    res = target.resolve()
    cwd = Path.cwd().resolve()
    try:
        home: Path | None = Path.home().resolve()
    except (RuntimeError, KeyError, OSError):  # no HOME and no passwd entry
        home = None
    if res == cwd or res in cwd.parents or res == home:
        raise InputError(
            f"--out {target}: is the current folder, one of its parents or the home folder; "
            "the output folder is replaced as a whole, so give a new folder"
        )
    foreign = sorted(
        q.name for q in target.iterdir()
        if q.name not in _IGNORED
        and not (q.is_file() and not q.is_symlink() and q.suffix.lower() in OUTPUT_SUFFIXES)
    )
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise InputError(
            f"--out {target}: the folder holds {len(foreign)} item(s) gear_dyn does not write "
            f"({shown}); the output folder is replaced as a whole, so give a new or empty "
            "folder, or a previous output folder"
        )


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # e.g. EPERM: it exists, owned by someone else
        return True
    return True


def _remove_stale(target: Path) -> None:
    """Clean ``.NAME.PID.*.partial`` / ``.old`` siblings left by processes killed with SIGKILL.

    A stale ``.old`` folder whose target is missing (killed inside the swap) is the complete
    previous output: it is put back. Folders of processes still alive are left alone.
    """
    with contextlib.suppress(OSError):
        for sib in sorted(target.parent.glob(f".{glob.escape(target.name)}.*")):
            parts = sib.name[len(target.name) + 2:].split(".")
            if len(parts) < 3 or parts[-1] not in ("partial", "old") or not parts[0].isdigit():
                continue
            if _pid_alive(int(parts[0])) or not sib.is_dir():
                continue
            if parts[-1] == "old" and not target.exists():
                os.replace(sib, target)
            else:
                shutil.rmtree(sib, ignore_errors=True)
