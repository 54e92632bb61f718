"""The ``[drive]`` of a spatial mechanism: a crank's revolute with the ground (``omega``,
``epsilon``), or a prismatic pair between the ground and an input slider (``velocity`` [m/s],
``acceleration`` [m/s²], the range ``start``, ``stop`` [m]: displacements of the slider's point
from its sketch position along its line) — the names a planar slider drive uses."""

from __future__ import annotations

from dataclasses import dataclass

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.names import GROUND
from linkgen.model.units import angular_acceleration, angular_speed, bounded, finite, length, shown

_DRIVE = {"joint", "omega", "epsilon"}
_SLIDE_DRIVE = {"joint", "velocity", "acceleration", "start", "stop"}


@dataclass(frozen=True)
class Drive3:
    """The driven pair and the input's rate ``omega`` and its constant derivative ``epsilon``:
    a crank's ω [rad/s] and ε [rad/s²], or for a prismatic input (``slides``) the slider's
    velocity [m/s] and acceleration [m/s²] ([drive] velocity, acceleration) over ``range``
    (start, stop) [m]."""

    joint: str
    omega: float
    epsilon: float = 0.0
    slides: bool = False
    range: tuple[float, float] | None = None

    @property
    def start(self) -> float:
        """The range's start: a slider input's [m], a crank's 0 rad (it turns full circles)."""
        return self.range[0] if self.range is not None else 0.0

    @property
    def stop(self) -> float:
        """The range's end: a slider input's [m], a crank's 2π rad."""
        import math

        return self.range[1] if self.range is not None else 2 * math.pi


def _keys(table: dict, allowed: set, where: str) -> None:
    for k in table:
        if k not in allowed:
            raise DescriptionError(f"{where}.{k}", f"unknown key; allowed: {', '.join(sorted(allowed))}")


def read_drive(drive_t: dict, joints: list, slides: list) -> Drive3:
    """[drive]: a revolute between ground and the crank, or a prismatic pair between ground and
    the input slider with its range."""
    dj = drive_t.get("joint")
    inputs = [s for s in slides if s.guide == GROUND]
    if dj in [s.name for s in inputs]:
        _keys(drive_t, _SLIDE_DRIVE, "drive")
        for key in ("velocity", "start", "stop"):
            if key not in drive_t:
                raise DescriptionError(f"drive.{key}", "missing: a prismatic input needs " + {
                    "velocity": "the slider's velocity [m/s]",
                    "start": "the start of its range [m] (the slider's displacement from its sketch position)",
                    "stop": "the end of its range [m] (the slider's displacement from its sketch position)"}[key])
        v = bounded(finite(drive_t["velocity"], "drive.velocity"), "drive.velocity", limits.MAX_OMEGA, "m/s")
        a = bounded(finite(drive_t.get("acceleration", 0.0), "drive.acceleration"), "drive.acceleration",
                    limits.MAX_EPSILON, "m/s²")
        lo = bounded(length(drive_t["start"], "drive.start"), "drive.start", limits.MAX_LENGTH, "m")
        hi = bounded(length(drive_t["stop"], "drive.stop"), "drive.stop", limits.MAX_LENGTH, "m")
        if not hi > lo:
            raise DescriptionError("drive.stop", f"must be greater than drive.start ({lo:g} m), got {shown(drive_t['stop'])}")
        return Drive3(dj, v, a, True, (lo, hi))
    _keys(drive_t, _DRIVE, "drive")
    revolutes = [j.name for j in joints if j.kind == "revolute" and GROUND in j.links]
    if dj not in revolutes:
        other = next((j for j in joints if j.name == dj), None)
        if other is not None and other.kind != "revolute" and GROUND in other.links:
            raise DescriptionError(f"joints.{dj}.kind", f"the driven pair {dj!r} must be a revolute with its axis (the "
                                                        f"crank turns about it), got {other.kind!r}")
        pairs = revolutes + [s.name for s in inputs]
        raise DescriptionError("drive.joint", f"must be a revolute or prismatic pair with the ground "
                                              f"({', '.join(pairs) or 'none'}), got {shown(dj)}")
    if "omega" not in drive_t:
        raise DescriptionError("drive.omega", "missing: the crank speed (rad/s, or '120rpm')")
    omega = bounded(angular_speed(drive_t["omega"], "drive.omega"), "drive.omega", limits.MAX_OMEGA, "rad/s")
    epsilon = bounded(angular_acceleration(drive_t.get("epsilon", 0.0), "drive.epsilon"), "drive.epsilon",
                      limits.MAX_EPSILON, "rad/s²")
    return Drive3(dj, omega, epsilon)


__all__ = ["Drive3", "read_drive"]
