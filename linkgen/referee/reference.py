"""linkgen's closed form at the user's crank angles, and the variants the diagnosis compares
with: the same mechanism with the drive's acceleration ε or its speed's ω² terms removed,
without gravity, with one Assur group on its other assembly mode, at shifted crank angles.

Every value is keyed by the header ``linkgen analyze``/``forces`` write (``"B.position.x [m]"``),
through the registry's ``kinematics`` and ``forces`` stages: the referee computes nothing of
its own. A sample where the closed form is singular (or a variant does not assemble) is NaN."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable, Mapping

import numpy as np

from linkgen.errors import LinkgenError
from linkgen.pipeline.registry import family_of, stage

# Headers that are not quantities (the angle itself, the singular flag).
NOT_QUANTITIES = ("phi [rad]", "singular")


def _has(desc, name: str) -> bool:
    return name in family_of(desc).stages


def _mechanism(desc):
    return getattr(desc, "mechanism", desc)


class Reference:
    """The closed form of ``desc`` (any description; planar ones assembled once) at one drive
    speed ω [rad/s] and acceleration ε [rad/s²] (None: the description's)."""

    def __init__(self, desc: Any, omega: float | None = None, epsilon: float | None = None) -> None:
        if family_of(desc).name == "planar" and not hasattr(desc, "structure"):
            from linkgen.families.planar.assembly import assemble

            desc = assemble(desc)
        self.desc = desc
        probe = stage(desc, "kinematics")(desc, stage(desc, "angles")(desc), omega, epsilon)
        self.omega = float(probe.omega) if omega is None else float(omega)
        self.epsilon = float(probe.epsilon) if epsilon is None else float(epsilon)
        self.kinematic_keys = tuple(k for k in probe.columns(transfer=True) if k not in NOT_QUANTITIES)
        self.force_keys: tuple[str, ...] = ()
        if _has(desc, "forces"):
            f = stage(desc, "forces")(desc, stage(desc, "angles")(desc), omega, epsilon)
            self.force_keys = tuple(k for k in f.columns(transfer=True) if k not in NOT_QUANTITIES)

    @property
    def vocabulary(self) -> tuple[str, ...]:
        """Every header the closed form writes (kinematics with transfer functions, then forces)."""
        return self.kinematic_keys + self.force_keys

    def evaluate(self, phi: np.ndarray, keys, *, desc=None, omega: float | None = None,
                 epsilon: float | None = None) -> dict[str, np.ndarray]:
        """The columns ``keys`` at crank angles φ (n,) [rad], of ``desc`` (default the mechanism)
        at ω and ε (default the reference's); NaN where singular or not assembled."""
        desc = self.desc if desc is None else desc
        omega = self.omega if omega is None else omega
        epsilon = self.epsilon if epsilon is None else epsilon
        keys = list(keys)
        out: dict[str, np.ndarray] = {}
        for name, wanted in (("kinematics", set(self.kinematic_keys)), ("forces", set(self.force_keys))):
            mine = [k for k in keys if k in wanted]
            if mine:
                out |= _columns(stage(desc, name), desc, np.asarray(phi, dtype=float), omega, epsilon, mine)
        return out

    def groups(self) -> tuple[str, ...]:
        """The labels of the Assur groups that have two assembly modes (planar linkages), in
        order; other families: none."""
        branches = getattr(self.desc, "branches", None)
        if branches is None:
            return ()
        return tuple(g.label for g, m in zip(self.desc.structure.groups, branches) if m in (1, -1))

    def other_mode(self, group: str):
        """The assembled mechanism with ``group`` (a label of ``groups()``) on its other mode."""
        labels = [g.label for g in self.desc.structure.groups]
        i = labels.index(group)
        flipped = list(self.desc.branches)
        flipped[i] = -flipped[i]
        return replace(self.desc, branches=tuple(flipped))

    def inertias(self) -> tuple[str, ...]:
        """The moving links with a moment of inertia about their centre of mass (planar linkages;
        other families: none): each one a term a solver may leave out."""
        if not hasattr(self.desc, "shapes"):
            return ()
        from linkgen.families.planar.loads import mass_table

        return tuple(n for n, mp in mass_table(self.desc).items() if mp.inertia > 0)

    def without_inertia(self, link: str):
        """The assembled mechanism with ``link``'s moment of inertia about its centre of mass
        zero, its mass and centre of mass kept."""
        from linkgen.families.planar.description import MassProperties
        from linkgen.families.planar.loads import mass_table

        mp = mass_table(self.desc)[link]
        plain = MassProperties(mp.mass, mp.com, 0.0)
        mech = self.desc.mechanism
        links = tuple(replace(k, inertial=plain, density=None, areal_density=None) if k.name == link else k
                      for k in mech.links)
        return replace(self.desc, mechanism=replace(mech, links=links))

    def without_gravity(self):
        """The description with no gravity, or None when it has none (or the family carries none)."""
        mech = _mechanism(self.desc)
        g = getattr(mech, "gravity", None)
        if g is None or not any(g):
            return None
        plain = replace(mech, gravity=tuple(0.0 for _ in g))
        return replace(self.desc, mechanism=plain) if hasattr(self.desc, "structure") else plain


def _columns(fn: Callable, desc, phi: np.ndarray, omega: float, epsilon: float, keys: list[str]) -> Mapping:
    """``keys`` of ``fn(desc, φ, ω, ε)``'s columns; a variant that does not assemble somewhere is
    evaluated angle by angle and NaN where it fails."""
    try:
        cols = fn(desc, phi, omega, epsilon, on_singular="mark").columns(transfer=True)
        return {k: _marked(cols, k) for k in keys}
    except LinkgenError:
        out = {k: np.full(phi.shape, np.nan) for k in keys}
        for i, p in enumerate(phi):
            try:
                cols = fn(desc, phi[i:i + 1], omega, epsilon, on_singular="mark").columns(transfer=True)
            except LinkgenError:
                continue
            for k in keys:
                out[k][i] = _marked(cols, k)[0]
        return out


def _marked(cols: Mapping, key: str) -> np.ndarray:
    x = np.array(cols[key], dtype=float)
    singular = np.asarray(cols.get("singular", np.zeros(x.shape, bool)), dtype=bool)
    x[singular] = np.nan
    return x
