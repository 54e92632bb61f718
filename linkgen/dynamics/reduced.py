"""The mechanism reduced to the crank over one turn, as smooth periodic functions of φ for an
ODE solver: J(φ) and dJ/dφ [kg·m²] by periodic cubic splines through the closed form on a grid,
and the reduced moment of the loads M(φ) [N·m] (gravity, forces, torques, the process load).

M(φ) jumps where a stroke-switched force switches; it is interpolated linearly between grid
points, so a jump is spread over one grid step (2π/GRID rad)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from linkgen.errors import DescriptionError
from linkgen.model.machine import ProcessLoad
from linkgen.planar.assembly import Assembly
from linkgen.planar.kinetostatics import forces

# Grid points over one turn. J(φ) of the bundled models is reproduced by the spline to < 1e-10
# relative between the grid points (checked in tests/test_dynamics.py against the closed form).
GRID = 4096


@dataclass(frozen=True)
class Reduced:
    """Periodic splines of J, dJ/dφ over [0, 2π) and the grid values of M (linear)."""

    phi: np.ndarray  # (GRID + 1,) [rad], from the drive's start over one turn
    inertia: CubicSpline
    inertia_derivative: CubicSpline
    moment_grid: np.ndarray  # (GRID + 1,) [N·m]

    def j(self, phi):
        return self.inertia(self._wrap(phi))

    def dj(self, phi):
        return self.inertia_derivative(self._wrap(phi))

    def moment(self, phi):
        return np.interp(self._wrap(phi), self.phi, self.moment_grid)

    def _wrap(self, phi):
        return self.phi[0] + np.mod(np.asarray(phi, dtype=float) - self.phi[0], 2 * math.pi)


def process_torque_function(load: ProcessLoad | None):
    """φ [rad] → the process load's resisting torque [N·m] (periodic cubic spline through the
    table; 0 without a process load)."""
    if load is None:
        return lambda phi: np.zeros_like(np.asarray(phi, dtype=float))
    a = np.array(load.angles + (load.angles[0] + 2 * math.pi,))
    spline = CubicSpline(a, np.array(load.torque + (load.torque[0],)), bc_type="periodic")
    return lambda phi: spline(a[0] + np.mod(np.asarray(phi, dtype=float) - a[0], 2 * math.pi))


def process_torque(load: ProcessLoad | None, phi: np.ndarray) -> np.ndarray:
    """The process load's resisting torque [N·m] at crank angles φ."""
    return process_torque_function(load)(phi)


def reduce(asm: Assembly, load: ProcessLoad | None = None, grid: int = GRID) -> Reduced:
    """J, dJ/dφ and M over one turn of the crank from the drive's start angle."""
    d = asm.mechanism.drive
    if d.stop - d.start < 2 * math.pi - 1e-9:
        raise DescriptionError("drive.range", "a machine needs a crank that turns fully (range of 360°); this "
                               f"one spans {math.degrees(d.stop - d.start):.6g}°")
    phi = d.start + np.linspace(0.0, 2 * math.pi, grid + 1)
    f = forces(asm, phi[:-1], 0.0, 0.0)
    j = np.append(f.reduced.inertia, f.reduced.inertia[0])
    dj = np.append(f.reduced.inertia_derivative, f.reduced.inertia_derivative[0])
    m = np.append(f.reduced.moment, f.reduced.moment[0]) - process_torque(load, phi)
    return Reduced(phi, CubicSpline(phi, j, bc_type="periodic"), CubicSpline(phi, dj, bc_type="periodic"), m)


__all__ = ["GRID", "Reduced", "process_torque", "process_torque_function", "reduce"]
