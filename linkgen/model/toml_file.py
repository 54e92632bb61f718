"""The one reader of description files, for every family (linkages, cams, machines, spatial
mechanisms): a regular file of at most MAX_FILE_BYTES, UTF-8 text (with or without a byte-order
mark), without NUL bytes, valid TOML of a sane depth. Anything else is a DescriptionError naming
the file; a device (``/dev/zero``), a pipe or a socket is refused before a byte is read, so that
no command hangs on it or fills the memory."""

from __future__ import annotations

import os
import stat
import tomllib
from pathlib import Path

from linkgen.errors import DescriptionError
from linkgen.outputs import note_input

_BOM = b"\xef\xbb\xbf"
# Largest description file [bytes]: a 5000-group chain takes about 1 MB (some 200 bytes a group);
# beyond 64 MiB a file is not a description, and reading it whole would only spend memory.
MAX_FILE_BYTES = 64 * 2**20


def read_bytes(path: str | Path) -> bytes:
    """The bytes of the description file ``path``: refused (DescriptionError naming it) if it is
    missing, a folder, not a regular file or larger than MAX_FILE_BYTES."""
    path = Path(path)
    source = str(path)
    if path.is_dir():
        raise DescriptionError("", "is a folder; give one description file", source)
    not_regular = DescriptionError("", "is not a regular file (a device, pipe or socket); give a description file",
                                   source)
    if path.exists() and not path.is_file():  # a socket cannot even be opened
        raise not_regular
    try:
        # O_NONBLOCK: opening a FIFO without a writer would otherwise wait for one
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise DescriptionError("", "no such description file", source) from None
    except OSError as exc:
        raise DescriptionError("", f"cannot be read: {exc.strerror or exc}", source) from None
    try:
        info = os.fstat(fd)  # the file opened, not what the name points to by now
        if not stat.S_ISREG(info.st_mode):
            raise not_regular
        if info.st_size > MAX_FILE_BYTES:
            raise DescriptionError("", f"is {info.st_size} bytes; a description is at most {MAX_FILE_BYTES} bytes",
                                   source)
        with os.fdopen(fd, "rb", closefd=False) as f:
            raw = f.read(MAX_FILE_BYTES + 1)  # a file growing while read stops here
        note_input(info)  # no output of this run replaces it
    except OSError as exc:
        raise DescriptionError("", f"cannot be read: {exc.strerror or exc}", source) from None
    finally:
        os.close(fd)
    if len(raw) > MAX_FILE_BYTES:
        raise DescriptionError("", f"is more than {MAX_FILE_BYTES} bytes; a description is at most {MAX_FILE_BYTES} "
                               "bytes", source)
    return raw


def parse_toml(raw: bytes | str, source: str) -> dict:
    """The TOML structure of a description's bytes (or text); DescriptionError naming ``source``
    for text that is not UTF-8, holds NUL bytes, is not TOML or is nested too deeply."""
    if isinstance(raw, bytes):
        if raw.startswith(_BOM):
            raw = raw[len(_BOM):]
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            line = raw[:exc.start].count(b"\n") + 1
            raise DescriptionError(
                "", f"is not UTF-8 text (byte {raw[exc.start]:#04x} at line {line}, offset {exc.start}); "
                "a description is a UTF-8 TOML file", source) from None
    else:
        text = raw.removeprefix("\ufeff")
    if "\x00" in text:
        raise DescriptionError("", "contains NUL bytes: a description is a UTF-8 TOML text file", source)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DescriptionError("", f"not valid TOML: {exc}", source) from None
    except RecursionError:
        # tomllib parses nested arrays and inline tables recursively
        raise DescriptionError("", "nested too deeply to parse: a description needs at most a few "
                               "levels of tables and arrays", source) from None


def read_toml(path: str | Path) -> dict:
    """The TOML structure of the description file ``path`` (``read_bytes`` then ``parse_toml``)."""
    return parse_toml(read_bytes(path), str(path))


__all__ = ["MAX_FILE_BYTES", "parse_toml", "read_bytes", "read_toml"]
