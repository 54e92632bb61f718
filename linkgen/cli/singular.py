"""Singular samples of a sampled run (``linkgen analyze|forces --samples``): the lines naming the
singular groups and the command's exit status."""

from __future__ import annotations

import sys
from pathlib import Path

# Exit status of a sampled run (--samples, --csv) in which some samples are singular and
# --keep-singular was not given: the output is written, those rows marked (singular = 1), and
# the status tells a script that it holds rows without meaning. 2 stays for errors (nothing
# written); 1 is `linkgen validate`'s "the two sides disagree".
SINGULAR_STATUS = 3


def report_singular(model: Path, lines: list[str], keep: bool) -> int:
    """Tell stderr which samples were marked singular (naming ``model``; ``lines``: one per group,
    with its angles, as the result's ``singular_lines()`` gives them); the command's exit status:
    0 if none or ``keep``, else SINGULAR_STATUS."""
    if not lines:
        return 0
    kind, tail = (("warning", "kept: --keep-singular") if keep else
                  ("error", f"exit status {SINGULAR_STATUS}; --keep-singular accepts them"))
    for line in lines:
        print(f"linkgen: {kind}: {model}: {line}; marked singular = 1 in the output, every other value in "
              f"those rows set to 0 ({tail})", file=sys.stderr)
    return 0 if keep else SINGULAR_STATUS


__all__ = ["SINGULAR_STATUS", "report_singular"]
