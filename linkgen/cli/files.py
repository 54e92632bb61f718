"""Writing output files safely, and running a command over several description files.

Outputs are written atomically: into a temporary file in the target's folder, then renamed
over the target with ``os.replace``. A reader never sees a half-written file, a failure leaves
the previous file (or none) in place, and a symlink planted at the output path is replaced
by the new file rather than followed into the file it points to.

    atomic_write_text(path, text)             # whole text at once
    atomic_write_bytes(path, data)
    with atomic_output(path) as tmp:          # for writers that take a path: np.savez,
        np.savez(tmp, **arrays)               # np.savetxt, matplotlib's savefig (keep the
                                              # suffix: tmp ends like path)
    with atomic_open(path, "w") as f:         # for writers that take a file object
        csv.writer(f).writerows(rows)

    outcomes = run_each(paths, build_one)     # goes on past a bad file, reports it on stderr
    return 0 if all(o.ok for o in outcomes) else 1
"""

from __future__ import annotations

import os
import sys
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, TextIO

from linkgen.errors import LinkgenError


class OutputError(LinkgenError, OSError):
    """An output path cannot be written (a folder, a missing folder, no permission)."""


def _target(path: str | Path) -> Path:
    path = Path(path)
    if path.is_dir() and not path.is_symlink():
        raise OutputError(f"{path}: is a folder; give a file name to write")
    folder = path.parent
    if not folder.is_dir():
        problem = "is not a folder" if folder.exists() else "does not exist"
        raise OutputError(f"{path}: the folder {str(folder)!r} {problem}")
    return path


@contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """A temporary path next to ``path`` (same suffix) to write; renamed onto ``path`` when the
    block ends without an exception, removed otherwise."""
    path = _target(path)
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix or ".tmp", dir=path.parent)
    except OSError as exc:
        raise OutputError(f"{path}: cannot write here: {exc.strerror or exc}") from None
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, _mode())
        os.replace(tmp, path)  # replaces a symlink at ``path`` itself, never its target
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        if isinstance(exc, OutputError):
            raise
        raise OutputError(f"{path}: cannot write: {exc.strerror or exc}") from exc
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


@contextmanager
def atomic_open(path: str | Path, mode: str = "w", **kwargs: Any) -> Iterator[TextIO]:
    """``open(tmp, mode, **kwargs)`` on a temporary file renamed onto ``path`` on success.
    Text mode defaults to UTF-8 and newline="" (csv writes its own line ends)."""
    if "b" not in mode:
        kwargs.setdefault("encoding", "utf-8")
        kwargs.setdefault("newline", "")
    with atomic_output(path) as tmp, open(tmp, mode, **kwargs) as f:
        yield f


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    with atomic_open(path, "wb") as f:
        f.write(data)


def atomic_write_text(path: str | Path, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` atomically (newlines as given)."""
    atomic_write_bytes(path, text.encode(encoding))


def _read_umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


# Read once at import: os.umask can only be read by setting it, which is not thread-safe.
_UMASK = _read_umask()


def _mode() -> int:
    """The permissions a plain ``open`` would give a new file (mkstemp makes it 0600)."""
    return 0o666 & ~_UMASK


@dataclass(frozen=True)
class Outcome:
    """The result of one file of a folder run: ``value`` if it succeeded, else ``error``."""

    path: Path
    value: Any = None
    error: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None


def message_for(path: str | Path, exc: BaseException) -> str:
    """``exc``'s message, starting with the file it concerns."""
    text = str(exc) or type(exc).__name__
    if isinstance(exc, OSError) and exc.strerror:
        text = f"{exc.strerror}" + (f": {exc.filename}" if exc.filename and str(exc.filename) != str(path) else "")
    prefix = f"{path}: "
    return text if text.startswith(prefix) else prefix + text


def run_each(paths: list[Path], fn: Callable[[Path], Any], stream: TextIO | None = None) -> list[Outcome]:
    """``fn(path)`` for every path in order. A LinkgenError or OSError is reported on
    ``stream`` (default stderr) as ``linkgen: error: FILE: message`` and the run goes on; other
    exceptions (bugs) propagate. The caller exits non-zero if any outcome is not ``ok``."""
    outcomes = []
    for path in paths:
        try:
            outcomes.append(Outcome(path, value=fn(path)))
        except (LinkgenError, OSError) as exc:
            msg = message_for(path, exc)
            print(f"linkgen: error: {msg}", file=stream or sys.stderr)
            outcomes.append(Outcome(path, error=msg))
    return outcomes


__all__ = ["OutputError", "Outcome", "atomic_open", "atomic_output", "atomic_write_bytes", "atomic_write_text",
           "message_for", "run_each"]
