"""Hostile input to every family (linkages, cam files, machines, spatial mechanisms), as a new
user and a hostile one would write it: each file loads, or every command that takes it fails
with one line naming the file, the field, the value and what is allowed — never a traceback,
a hang or a non-finite number in an output."""

import math
import os
import signal
import socket
from contextlib import contextmanager

import pytest

from conftest import ROOT
from linkgen import DescriptionError
from linkgen.cli.main import main

MODELS = ROOT / "models"
# Seconds a refused file may take: the refusal reads nothing; a command that waits on a pipe
# or reads a device to its end never returns, and the alarm ends it.
REFUSAL_SECONDS = 20


class _Hang(BaseException):
    """Raised by the alarm: not an OSError, which the code under test may catch."""


@contextmanager
def _deadline(seconds: int):
    def expired(signum, frame):
        raise _Hang(f"no answer in {seconds} s")

    old = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _mutant(tmp_path, model: str, old: str, new: str, name: str = "m.toml"):
    text = (MODELS / model).read_text(encoding="utf-8")
    assert old in text, (model, old)
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


def _special(tmp_path, kind: str) -> str:
    if kind == "fifo":
        path = tmp_path / "model.toml"
        os.mkfifo(path)
        return str(path)
    if kind == "socket":
        path = tmp_path / "model.toml"
        sock = socket.socket(socket.AF_UNIX)
        sock.bind(str(path))
        return str(path)
    return kind  # a device


@pytest.mark.parametrize("kind", ["fifo", "socket", "/dev/null"])
@pytest.mark.parametrize("command", [["analyze"], ["build"], ["validate"], ["structure"], ["forces"],
                                     ["profile"], ["dynamics"], ["draw", "-o", "{tmp}/x.svg"]])
def test_not_a_regular_file_is_refused_by_every_command(tmp_path, capsys, kind, command):
    model = _special(tmp_path, kind)
    with _deadline(REFUSAL_SECONDS):
        status = main([command[0], model, *(a.format(tmp=tmp_path) for a in command[1:])])
    assert status == 2
    assert capsys.readouterr().err == (f"linkgen: error: {model}: is not a regular file (a device, pipe or socket); "
                                       "give a description file\n")
