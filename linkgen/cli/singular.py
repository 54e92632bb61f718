"""Singular samples of a sampled run (``linkgen analyze|forces --samples/--csv``): which groups,
at which crank angles, and the command's exit status."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from linkgen.errors import angle_ranges, format_ranges
from linkgen.families.planar.kinematics import Kinematics, singular_cause

# Exit status of a sampled run (--samples, --csv) in which some samples are singular and
# --keep-singular was not given: the output is written, those rows marked (singular = 1), and
# the status tells a script that it holds rows without meaning. 2 stays for errors (nothing
# written); 1 is `linkgen validate`'s "the two sides disagree".
SINGULAR_STATUS = 3


def singular_groups(kin: Kinematics) -> list[str]:
    """One line per group with singular samples in ``kin`` (solved with
    ``on_singular="mark"``): the group, its crank-angle ranges, the count and the cause."""
    groups = {g.label: g for g in kin.assembly.structure.groups}
    return [f"group {label} is singular at crank angles {format_ranges(angle_ranges(kin.phi, mask))} "
            f"({int(np.count_nonzero(mask))} of {len(kin.phi)} samples: {singular_cause(groups[label])})"
            for label, mask in kin.near_singular.items() if np.any(mask)]


def report_singular(model: Path, kin: Kinematics | None, keep: bool) -> int:
    """Tell stderr which samples were marked singular (naming ``model``, the groups and the
    angles; ``kin`` None: none was); the command's exit status: 0 if none or ``keep``, else
    SINGULAR_STATUS."""
    lines = [] if kin is None else singular_groups(kin)
    if not lines:
        return 0
    kind, tail = (("warning", "kept: --keep-singular") if keep else
                  ("error", f"exit status {SINGULAR_STATUS}; --keep-singular accepts them"))
    for line in lines:
        print(f"linkgen: {kind}: {model}: {line}; marked singular = 1 in the output, every other value in "
              f"those rows set to 0 ({tail})", file=sys.stderr)
    return 0 if keep else SINGULAR_STATUS


__all__ = ["SINGULAR_STATUS", "report_singular", "singular_groups"]
