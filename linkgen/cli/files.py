"""Writing output files safely, and running a command over several description files.

Outputs go through ``linkgen.outputs`` (atomic, never through a symlink, mode kept, no
temporary file left when interrupted); its writers are re-exported here for the commands.

    outcomes = run_each(paths, build_one)     # goes on past a bad file, reports it on stderr
    return 0 if all(o.ok for o in outcomes) else 1
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, TextIO

from linkgen.errors import LinkgenError, printable
from linkgen.outputs import (OutputError, atomic_open, atomic_output, atomic_write_bytes, atomic_write_text,
                             output_folder, save_figure)


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
    return printable(text if text.startswith(prefix) else prefix + text)


def run_each(paths: list[Path], fn: Callable[[Path], Any], stream: TextIO | None = None) -> list[Outcome]:
    """``fn(path)`` for every path in order. A LinkgenError or OSError is reported on
    ``stream`` (default stderr) as ``linkgen: error: FILE: message``, any other exception (a
    bug) as ``FILE: internal error (Type: message)``, and the run goes on to the next file: one
    bad file never keeps the others from being processed. The caller exits non-zero if any
    outcome is not ``ok``. Ctrl-C and SIGTERM still end the run."""
    outcomes = []
    for path in paths:
        try:
            outcomes.append(Outcome(path, value=fn(path)))
        except (LinkgenError, OSError) as exc:
            msg = message_for(path, exc)
            print(f"linkgen: error: {msg}", file=stream or sys.stderr)
            outcomes.append(Outcome(path, error=msg))
        except Exception as exc:  # noqa: BLE001 - reported with its type, and the other files still run
            msg = f"{path}: internal error ({type(exc).__name__}: {str(exc).strip()}); please report it with this file"
            print(f"linkgen: error: {msg}", file=stream or sys.stderr)
            outcomes.append(Outcome(path, error=msg))
    return outcomes


def same_name(paths: list[Path]) -> tuple[str, Path, Path] | None:
    """The first two files naming their mechanism alike, as (name, first, second), or None. A
    file that cannot be read is skipped: its own run reports it."""
    from linkgen.model.toml_file import read_toml

    seen: dict[str, Path] = {}
    for path in paths:
        try:
            data = read_toml(path)
        except (LinkgenError, OSError):
            continue
        name = data.get("mechanism", {}).get("name") if isinstance(data.get("mechanism"), dict) else None
        if not isinstance(name, str):
            continue
        if name in seen:
            return name, seen[name], path
        seen[name] = path
    return None


__all__ = ["OutputError", "Outcome", "atomic_open", "atomic_output", "atomic_write_bytes", "atomic_write_text",
           "message_for", "output_folder", "run_each", "same_name", "save_figure"]
