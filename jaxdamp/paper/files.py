"""Atomic file writes: every JSON, CSV, NPZ, PNG, Markdown and HTML file the study, the report and
the CLI write goes through here, so that an interrupted run (Ctrl-C, a full disk, a crash inside a
writer) leaves complete files or none, never a half-written one beside complete ones.

The data go to a temporary file in the target's own folder (same file system, so the rename is
atomic), which then replaces the target with os.replace. A failed write removes the temporary file
and leaves any previous version of the target untouched.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

__all__ = ["atomic_file", "save_figure", "write_bytes", "write_text"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_file(path, mode: str = "w", **open_kwargs):
    """Open a temporary file beside `path` for writing (mode "w" or "wb"); on a clean exit it
    replaces `path`, on an exception it is removed and `path` is left as it was."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        # mkstemp creates 0600; a written file gets the permissions open() would have given it.
        os.chmod(tmp, 0o666 & ~_umask())
        with os.fdopen(fd, mode, **open_kwargs) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text(path, text: str, encoding: str = "utf-8") -> Path:
    """Path.write_text, atomically."""
    with atomic_file(path, "w", encoding=encoding) as f:
        f.write(text)
    return Path(path)


def write_bytes(path, data: bytes) -> Path:
    """Path.write_bytes, atomically."""
    with atomic_file(path, "wb") as f:
        f.write(data)
    return Path(path)


def save_figure(fig, path, **savefig_kwargs) -> Path:
    """fig.savefig(path, ...), atomically; the format is the path's suffix (png, pdf, svg)."""
    path = Path(path)
    savefig_kwargs.setdefault("format", path.suffix.lstrip(".").lower() or None)
    with atomic_file(path, "wb") as f:
        fig.savefig(f, **savefig_kwargs)
    return path
