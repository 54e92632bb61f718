"""The referee's result: per column of the user's table, the worst error against linkgen's
closed form (and MuJoCo's routes when asked), where it occurs, who the user agrees with, and
the diagnosis of a difference. ``to_dict()`` (JSON), ``text()`` (the terminal)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from linkgen.referee.diagnose import Diagnosis

# Who the user's column agrees with.
AGREES = ("both", "closed form", "MuJoCo", "neither")


@dataclass(frozen=True)
class RouteError:
    """The user's worst difference from one route (relative to the column's scale) and the crank
    angle [rad] where it occurs; the route's own difference from the closed form on that column
    (``route_error``, None for the closed form itself) and the tolerance applied."""

    error: float
    at_phi: float
    tolerance: float
    route_error: float | None = None

    @property
    def agrees(self) -> bool:
        return self.error <= self.tolerance

    def to_dict(self) -> dict:
        return {"relative_error": _finite(self.error), "at_phi": _finite(self.at_phi), "tolerance": self.tolerance,
                "route_error": _finite(self.route_error), "agrees": self.agrees}


def _finite(x: float | None) -> float | None:
    """JSON's value of a figure: None where there is none (every sample of the column singular)."""
    return x if x is not None and math.isfinite(x) else None


@dataclass(frozen=True)
class ColumnVerdict:
    """One column: the user's header, linkgen's header (``key``), the scale [SI unit] the errors
    are relative to, the routes' errors (``closed_form``, and ``mujoco_forward``,
    ``mujoco_inverse`` when run), who it agrees with, the diagnosis (None when it agrees with the
    closed form), the samples left out (singular) and the curves."""

    header: str
    key: str
    scale: float
    routes: Mapping[str, RouteError]
    diagnosis: Diagnosis | None
    left_out: int = 0
    # the curves for the report: "phi" [rad], "user" and each route's values (n,), SI units
    curves: Mapping[str, np.ndarray] = field(default_factory=dict, repr=False, compare=False)

    @property
    def agrees(self) -> str:
        cf = self.routes["closed_form"].agrees
        mj = [r.agrees for name, r in self.routes.items() if name != "closed_form"]
        if not mj:
            return "closed form" if cf else "neither"
        return AGREES[0 if cf and all(mj) else 1 if cf else 2 if any(mj) else 3]

    def to_dict(self) -> dict:
        return {"header": self.header, "key": self.key, "scale": self.scale, "agrees": self.agrees,
                "routes": {k: r.to_dict() for k, r in self.routes.items()},
                "diagnosis": self.diagnosis.to_dict() if self.diagnosis else None, "left_out_singular": self.left_out}


@dataclass(frozen=True)
class Verdict:
    """The referee's verdict on a table: the mechanism, the table's file, ω [rad/s], ε [rad/s²],
    the samples, the tolerance (relative) and every column's verdict, in the table's order."""

    model: str
    source: str
    omega: float
    epsilon: float
    samples: int
    tolerance: float
    columns: tuple[ColumnVerdict, ...]
    mujoco: bool = False
    notes: tuple[str, ...] = field(default=())

    @property
    def ok(self) -> bool:
        """Every column agrees with the closed form."""
        return all(c.routes["closed_form"].agrees for c in self.columns)

    def to_dict(self) -> dict:
        return {"model": self.model, "table": self.source, "omega": self.omega, "epsilon": self.epsilon,
                "samples": self.samples, "tolerance": self.tolerance, "ok": self.ok, "mujoco": self.mujoco,
                "notes": list(self.notes), "columns": [c.to_dict() for c in self.columns]}

    def text(self) -> str:
        bad = [c for c in self.columns if not c.routes["closed_form"].agrees]
        head = (f"{self.source}: {len(self.columns)} columns at {self.samples} crank angles against {self.model} "
                f"(ω = {self.omega:g} rad/s, ε = {self.epsilon:g} rad/s², tolerance {self.tolerance:g} of each "
                f"column's scale): {len(self.columns) - len(bad)} agree, {len(bad)} differ")
        lines = [head, *self.notes]
        width = max(len(c.header) for c in self.columns)
        for c in self.columns:
            cf = c.routes["closed_form"]
            routes = "  ".join(f"{name.replace('_', ' ')} {r.error:.2e}" for name, r in c.routes.items())
            where = f" worst at φ = {math.degrees(cf.at_phi):.4g}°" if not cf.agrees else ""
            lines.append(f"  {c.header:<{width}}  {routes}  agrees with: {c.agrees}{where}")
            if c.diagnosis is not None:
                lines.append(f"  {'':<{width}}  → {c.diagnosis.text}")
            if c.left_out:
                lines.append(f"  {'':<{width}}  ({c.left_out} samples left out: the closed form is singular there, or the "
                             "mechanism does not assemble)")
        return "\n".join(lines)
