"""The one way linkgen writes a file: atomically, never through a symlink, keeping the mode.

Every output (CSV, NPZ, MJCF, figures, reports, a description written back) goes through
``atomic_output``: the bytes go to a temporary file in the target's folder, which is renamed
over the target with ``os.replace`` once complete. So

- a reader never sees a half-written file, and a failure leaves the previous file (or none);
- a symlink planted at the output name is refused (``OutputError`` naming the path), never
  followed into the file it points to and never silently replaced;
- a file that is replaced keeps its permission bits (a 0600 file stays 0600); a new file gets
  what a plain ``open`` would give it (0666 less the umask);
- an interrupted write (an exception, Ctrl-C, SIGTERM or SIGHUP) removes the temporary file:
  while a temporary file exists, those signals raise ``Interrupted`` in the main thread.

    atomic_write_text(path, text)             # whole text at once
    atomic_write_bytes(path, data)
    with atomic_output(path) as tmp:          # for writers that take a path: np.savez,
        np.savez(tmp, **arrays)               # np.savetxt, matplotlib (tmp ends like path)
    with atomic_open(path, "w") as f:         # for writers that take a file object
        csv.writer(f).writerows(rows)
    save_figure(fig, path, dpi=90)            # a matplotlib figure, byte-identical across runs
    folder = output_folder(path)              # a report folder: created, never a symlink

A description updated in place (``assemble --write``) is the one output that follows a symlink,
on purpose: ``atomic_output(path, follow_symlink=True)`` writes the link's real target and
leaves the link a link. Every other output refuses a file read as a description in this run
(``note_input``, by device and inode: under any name or hard link), so that ``build M.toml -o
M.toml`` or ``analyze M.toml --csv M.toml`` never destroys the description.
"""

from __future__ import annotations

import os
import signal
import stat
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, TextIO

from linkgen.errors import LinkgenError

# The signals that end a command early; while a temporary file exists they raise Interrupted
# so that the temporary file is removed on the way out.
_SIGNALS = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))
# The figure metadata that would otherwise carry the creation date and the program version,
# per format (matplotlib: a key set to None is left out of the file).
_FIGURE_METADATA = {"svg": {"Date": None, "Creator": None}, "pdf": {"CreationDate": None, "Creator": None,
                                                                   "Producer": None}}
# SVG element ids are hashes salted with a random value unless svg.hashsalt is set.
_SVG_HASHSALT = "linkgen"


# The files read as descriptions in this run, by (device, inode): no output replaces them.
_INPUTS: set[tuple[int, int]] = set()


def note_input(info: os.stat_result) -> None:
    """Record a description file just read (its ``os.fstat``): outputs will not replace it."""
    _INPUTS.add((info.st_dev, info.st_ino))


def forget_inputs() -> None:
    """Forget the descriptions read so far (a new command starts)."""
    _INPUTS.clear()


class OutputError(LinkgenError, OSError):
    """An output path cannot be written (a folder, a missing folder, a symlink, no permission)."""


class Interrupted(BaseException):
    """SIGTERM or SIGHUP arrived during a write (raised like KeyboardInterrupt for Ctrl-C)."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"interrupted by {signal.Signals(signum).name}")
        self.signum = signum


def _refuse_symlink(path: Path) -> None:
    if path.is_symlink():
        raise OutputError(f"{path}: is a symbolic link (to {os.readlink(path)!r}); linkgen does not write "
                          "through links: remove it or give another output name")


def _target(path: str | Path, follow_symlink: bool) -> Path:
    path = Path(path)
    if follow_symlink:
        path = Path(os.path.realpath(path))
    else:
        _refuse_symlink(path)
    if path.is_dir():
        raise OutputError(f"{path}: is a folder; give a file name to write")
    if path.exists() and not path.is_file():
        raise OutputError(f"{path}: is not a regular file (a device, a pipe or a socket); give a file name to write")
    if not follow_symlink and path.exists() and _is_input(path):
        raise OutputError(f"{path}: is the description being read; linkgen does not write over it: give another "
                          "output name")
    folder = path.parent
    if not folder.is_dir():
        problem = "is not a folder" if folder.exists() else "does not exist"
        raise OutputError(f"{path}: the folder {str(folder)!r} {problem}")
    return path


def _is_input(path: Path) -> bool:
    try:
        info = path.stat()
    except OSError:
        return False
    return (info.st_dev, info.st_ino) in _INPUTS


def check_output(path: str | Path) -> Path:
    """Refuse ``path`` now, before a long run, for what ``atomic_output`` would refuse at the end
    (a symlink, a folder, a device, a missing folder)."""
    return _target(path, False)


def _mode_for(path: Path) -> int:
    """The permission bits the written file gets: those of the file it replaces, or what a
    plain ``open`` would give a new file (mkstemp makes it 0600)."""
    try:
        return stat.S_IMODE(path.stat().st_mode)
    except FileNotFoundError:
        return 0o666 & ~_UMASK


@contextmanager
def _signals_raise() -> Iterator[None]:
    """SIGTERM/SIGHUP raise Interrupted for the duration (main thread only: elsewhere Python
    cannot install handlers, and the default action is kept)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise Interrupted(signum)

    previous = {}
    for s in _SIGNALS:
        if signal.getsignal(s) in (signal.SIG_DFL, None):  # keep a handler the program installed itself
            previous[s] = signal.signal(s, handler)
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


@contextmanager
def atomic_output(path: str | Path, *, follow_symlink: bool = False) -> Iterator[Path]:
    """A temporary path next to ``path`` (same suffix) to write; renamed onto ``path`` when the
    block ends without an exception, removed otherwise (also on Ctrl-C, SIGTERM, SIGHUP)."""
    path = _target(path, follow_symlink)
    with _signals_raise():
        try:
            fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix or ".tmp", dir=path.parent)
        except OSError as exc:
            raise OutputError(f"{path}: cannot write here: {exc.strerror or exc}") from None
        tmp = Path(name)
        try:
            os.close(fd)
            yield tmp
            os.chmod(tmp, _mode_for(path))
            if not follow_symlink:
                _refuse_symlink(path)  # planted while we wrote
            os.replace(tmp, path)
        except OutputError:
            tmp.unlink(missing_ok=True)
            raise
        except OSError as exc:
            tmp.unlink(missing_ok=True)
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


def atomic_write_bytes(path: str | Path, data: bytes, *, follow_symlink: bool = False) -> None:
    """Write ``data`` to ``path`` atomically."""
    with atomic_output(path, follow_symlink=follow_symlink) as tmp:
        tmp.write_bytes(data)


def atomic_write_text(path: str | Path, text: str, encoding: str = "utf-8", *, follow_symlink: bool = False) -> None:
    """Write ``text`` to ``path`` atomically (newlines as given)."""
    atomic_write_bytes(path, text.encode(encoding), follow_symlink=follow_symlink)


def output_folder(path: str | Path) -> Path:
    """``path`` as a folder to write a report into: created with its parents if missing;
    refused if it is a symlink or not a folder. The files inside go through ``atomic_output``."""
    path = Path(path)
    _refuse_symlink(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{path}: is not a folder; give a folder for the report")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{path}: cannot make this folder: {exc.strerror or exc}") from None
    return path


def figure_format(path: str | Path) -> str:
    """The matplotlib format a file name asks for (its suffix; png without one)."""
    return Path(path).suffix.lstrip(".").lower() or "png"


def figure_metadata(fmt: str) -> dict | None:
    """Metadata for ``savefig`` that keeps dates and versions out of the file (svg, pdf)."""
    return _FIGURE_METADATA.get(fmt)


def savefig_deterministic(fig, path: str | Path, **kwargs: Any) -> None:
    """``fig.savefig(path)`` with no creation date, no version and fixed SVG ids, so that the
    same figure gives the same bytes on every run (``path`` is written as it is: give it a
    temporary file from ``atomic_output``)."""
    import matplotlib

    fmt = kwargs.pop("format", None) or figure_format(path)
    with matplotlib.rc_context({"svg.hashsalt": _SVG_HASHSALT}):
        fig.savefig(path, format=fmt, metadata=figure_metadata(fmt), **kwargs)


def save_figure(fig, path: str | Path, **kwargs: Any) -> Path:
    """Write the matplotlib figure ``fig`` to ``path`` atomically and deterministically, in the
    format its suffix names; returns ``path``."""
    with atomic_output(path) as tmp:
        savefig_deterministic(fig, tmp, format=kwargs.pop("format", None) or figure_format(path), **kwargs)
    return Path(path)


def _read_umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


# Read once at import: os.umask can only be read by setting it, which is not thread-safe.
_UMASK = _read_umask()


__all__ = ["Interrupted", "OutputError", "atomic_open", "atomic_output", "atomic_write_bytes", "atomic_write_text",
           "check_output", "figure_format", "figure_metadata", "output_folder", "save_figure", "savefig_deterministic"]
