"""Command-line interface: ``linkgen structure|analyze|forces|build|simulate|validate|check-settings|draw|page|animate|render|referee|suite``.

User mistakes (LinkgenError, missing files, bad arguments, conflicting options) print one
line to stderr naming the file concerned and exit with status 2; no traceback. A sampled run
(``analyze``/``forces`` with --samples or -o FILE.csv) writes singular samples marked (column
``singular`` = 1) and exits with status 3 unless --keep-singular is given. Output closed early
by the reader (``linkgen analyze ... | head``) ends quietly with status 141, as a process
stopped by SIGPIPE would.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys

from linkgen.cli import check_settings, closed_form, draw, dynamics, mujoco, optimize, referee, sketch, sweep
from linkgen.cli.common import OptionError
from linkgen.cli.files import message_for
from linkgen.outputs import Interrupted, OutputError
from linkgen.errors import LinkgenError, printable


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("linkgen")
    except PackageNotFoundError:  # run from a source tree that is not installed
        return "(not installed)"


class _VersionAction(argparse.Action):
    """``--version``, looked up only when asked for (importlib.metadata costs every other run
    a few milliseconds of its cold start)."""

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"linkgen {_version()}")
        parser.exit()


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (the usage is one ``--help`` away); subcommands inherit it."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def description() -> str:
    """What ``linkgen --help`` says first: every family with its commands, from the registry
    (``Family.commands``), so that it says what ``check_command`` accepts."""
    from linkgen.pipeline.registry import FAMILIES

    takes = "; ".join(f"{f.plural} ({f.doc}) take {', '.join(f.commands[:-1])} and {f.commands[-1]}" for f in FAMILIES)
    return ("Mechanisms from their descriptions (models/*.toml): closed-form kinematics and kinetostatics from "
            f"Assur groups, MuJoCo models and runs checked against them. {takes[0].upper()}{takes[1:]} "
            "(dynamics and flywheel: a planar linkage with a [machine] table, docs/machine.md).")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="linkgen", description=description())
    p.add_argument("--version", action=_VersionAction, nargs=0, help="show the program's version number and exit")
    sub = p.add_subparsers(dest="command", required=True)

    closed_form.add_commands(sub)
    mujoco.add_commands(sub)
    check_settings.add_command(sub)
    dynamics.add_command(sub)
    sketch.add_command(sub)
    draw.add_commands(sub)
    closed_form.add_profile(sub)
    referee.add_commands(sub)
    sweep.add_command(sub)
    optimize.add_command(sub)
    return p


# Options whose value may be negative with a unit ("-30deg"), which argparse would take for an option.
_SIGNED = ("--angle", "--angles", "--omega", "--epsilon")


def _join_signed(argv: list[str]) -> list[str]:
    """``--angle -30deg`` → ``--angle=-30deg``."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in _SIGNED and i + 1 < len(argv) and argv[i + 1][:1] == "-" and argv[i + 1][1:2] in "0123456789.":
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def _mujoco_imports() -> str | None:
    """None, or why MuJoCo cannot be imported (its OpenGL backend is chosen at import, from
    MUJOCO_GL, and a backend this machine lacks fails there)."""
    try:
        import mujoco  # noqa: F401
    except Exception as exc:  # noqa: BLE001 — any failure inside MuJoCo's import is reported as one line
        gl = os.environ.get("MUJOCO_GL")
        hint = (f"MUJOCO_GL={gl!r} names an OpenGL backend this machine cannot load; unset it or set it to "
                f"egl or osmesa where installed" if gl else "reinstall the mujoco package")
        return f"MuJoCo cannot be imported ({type(exc).__name__}: {exc}); {hint}"
    return None


# Commands that never touch MuJoCo: they skip its import (a fifth of a second, and a
# failure there says nothing about them). Every other command checks it first.
CLOSED_FORM_COMMANDS = frozenset({"structure", "analyze", "forces", "assemble"})
# Commands that are no family's (not in any ``Family.commands``): ``referee`` takes a description
# of any family and a table of results, ``suite`` writes mechanisms of every family.
EVERY_FAMILY_COMMANDS = frozenset({"referee", "suite"})


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(_join_signed(sys.argv[1:] if argv is None else list(argv)))
    problem = None if args.command in CLOSED_FORM_COMMANDS else _mujoco_imports()
    if problem:
        print(f"linkgen: error: {problem}", file=sys.stderr)
        return 2
    try:
        from linkgen.outputs import forget_inputs
        from linkgen.pipeline.family import FAMILY_OPTIONS
        from linkgen.pipeline.registry import check_command

        forget_inputs()  # the descriptions this command reads are the ones no output may replace
        with contextlib.ExitStack() as stack:
            if args.command not in CLOSED_FORM_COMMANDS:  # MuJoCo's warnings never become a file in the user's folder
                from linkgen.mujoco.log import no_log_file

                stack.enter_context(no_log_file())
            if getattr(args, "model", None) is not None:
                given = tuple(o for o in FAMILY_OPTIONS if getattr(args, o[2:].replace("-", "_"), False))
                check_command(args.command, args.model, given)  # a command or option the family does not take
            status = args.func(args)
        sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's exit
        return status
    except BrokenPipeError:
        _silence_stdout()
        return 141
    except (Interrupted, KeyboardInterrupt) as exc:  # Ctrl-C, or SIGTERM/SIGHUP during a write: no temporary file left
        signum = getattr(exc, "signum", signal.SIGINT)
        print(f"linkgen: interrupted by {signal.Signals(signum).name}; no output is left half-written", file=sys.stderr)
        return 128 + signum
    except OptionError as exc:
        print(f"linkgen {args.command}: error: {printable(str(exc))}", file=sys.stderr)
        return 2
    except (LinkgenError, OSError) as exc:
        model = getattr(args, "model", None)
        # an output's own error names the output, not the description
        text = message_for(model, exc) if model is not None and not isinstance(exc, OutputError) else printable(str(exc))
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
