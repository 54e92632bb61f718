"""CLI commands that need MuJoCo: build, simulate, validate."""

from __future__ import annotations


def add_commands(sub) -> None:
    return None
