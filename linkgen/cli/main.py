"""Command-line interface: ``linkgen structure|analyze|forces|build|simulate|validate``.

User mistakes (LinkgenError, missing files, bad arguments, conflicting options) print one
line to stderr naming the file concerned and exit with status 2; no traceback. A sampled run
(``analyze``/``forces`` with --samples/--csv) writes singular samples marked (column
``singular`` = 1) and exits with status 3 unless --keep-singular is given. Output closed early
by the reader (``linkgen analyze ... | head``) ends quietly with status 141, as a process
stopped by SIGPIPE would.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from linkgen.cli import closed_form, dynamics, forces, mujoco
from linkgen.cli.common import OptionError, add_crank_arguments
from linkgen.cli.files import message_for
from linkgen.errors import LinkgenError


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (the usage is one ``--help`` away); subcommands inherit it."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="linkgen", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("structure", help="mobility, Assur groups and the structure formula")
    s.add_argument("model", type=Path)
    s.set_defaults(func=closed_form.cmd_structure)

    a = sub.add_parser("analyze", help="closed-form positions, velocities and accelerations")
    add_crank_arguments(a, "38.117deg")
    a.set_defaults(func=closed_form.cmd_analyze)

    forces.add_command(sub)
    mujoco.add_commands(sub)
    dynamics.add_command(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status = args.func(args)
        sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's exit
        return status
    except BrokenPipeError:
        _silence_stdout()
        return 141
    except OptionError as exc:
        print(f"linkgen {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except (LinkgenError, OSError) as exc:
        model = getattr(args, "model", None)
        text = message_for(model, exc) if model is not None else str(exc)
        print(f"linkgen: error: {text}", file=sys.stderr)
        return 2


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush of what is left in
    its buffer does not report the closed pipe again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # stdout without a file descriptor (captured)
        pass


if __name__ == "__main__":
    sys.exit(main())
