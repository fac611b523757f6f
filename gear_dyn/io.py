"""Files written whole or not at all.

- :func:`write_text` / :func:`write_bytes`: write to a temporary file in the same folder, flush,
  fsync, then ``os.replace`` onto the target (atomic on POSIX).
- :func:`staged_output`: a context manager for a whole output folder. Everything is written into
  a fresh temporary sibling folder; only when the block succeeds is it swapped in place of the
  target (the previous folder is kept until the swap is done, then removed). A failure or a kill
  leaves the previous output intact and no partial files in it.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError


def write_bytes(path: str | Path, data: bytes) -> Path:
    """Atomically write ``data`` to ``path``."""
    p = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, p)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
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


def write_csv(path: str | Path, columns: Mapping[str, Sequence[float] | np.ndarray]) -> Path:
    """Atomically write equal-length columns as CSV with a header row."""
    names = list(columns)
    arrays = [np.asarray(columns[n]) for n in names]
    if len({a.shape for a in arrays}) > 1:
        raise InputError("write_csv: columns have different lengths")
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(names)
    for row in zip(*arrays, strict=True):
        w.writerow([f"{float(v):.10g}" for v in row])
    return write_text(path, buf.getvalue())


def save_figure(fig: Any, path: str | Path, **kwargs: Any) -> Path:
    """Render a matplotlib figure to bytes and write it atomically."""
    buf = io.BytesIO()
    fmt = Path(path).suffix.lstrip(".") or "png"
    fig.savefig(buf, format=fmt, **kwargs)
    return write_bytes(path, buf.getvalue())


@contextlib.contextmanager
def staged_output(out_dir: str | Path) -> Iterator[Path]:
    """Yield a temporary folder; on success it replaces ``out_dir`` as a whole.

    Raises
    ------
    InputError
        ``out_dir`` exists and is not a folder, or its parent cannot be created.
    """
    target = Path(out_dir)
    if target.exists() and not target.is_dir():
        raise InputError(f"--out {target}: exists and is not a folder")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {target}: cannot create parent folder ({exc.strerror})") from None
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".partial", dir=target.parent))
    try:
        yield tmp
        old = None
        if target.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old",
                                        dir=target.parent))
            os.rmdir(old)
            os.replace(target, old)
        os.replace(tmp, target)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
