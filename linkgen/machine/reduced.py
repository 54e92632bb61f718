"""The mechanism reduced to the crank over one turn, as smooth periodic functions of φ for an
ODE solver: J(φ) and dJ/dφ [kg·m²] by periodic cubic splines through the closed form on a grid,
and the reduced moment of the loads M(φ, ω) = M₀(φ) + c(φ)·ω [N·m] (gravity, forces, torques,
springs, the process load; dampers make it depend on the crank speed ω through the reduced
damping c(φ) = ∂M/∂ω ≤ 0, ``planar.kinetostatics.reduced_damping``).

M₀(φ) and c(φ) are piecewise linear between grid points, and M₀ jumps exactly where a
stroke-switched force switches (``tables``: the switch angles are in its grid twice)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from linkgen.machine.tables import PeriodicTable, jump_grid, switch_angles
from linkgen.errors import DescriptionError
from linkgen.model.machine import ProcessLoad
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinetostatics import forces

# Grid points over one turn. J(φ) of the bundled models is reproduced by the spline to < 1e-10
# relative between the grid points (checked in tests/test_dynamics.py against the closed form).
GRID = 4096
# Cells of the table of M₀ and C over one turn: linear between them, it errs by (2π/n)²/8·|M″|,
# 4.6e-9·|M″| here. At 4096 cells (2.9e-7·|M″|) a slider-crank's return spring (tests/test_springs.py,
# a 2000 N/m spring on a 0.1 m crank, M″ up to ~10³ N·m) moved the machine's ω by 3.0e-6 of its
# peak over 3 s — MuJoCo's full linkage, which has the spring itself, disagreed by as much (its
# tolerance is 1e-6); at 32768, by 3.1e-8. A table of 32768 angles costs ~0.05 s.
MOMENT_GRID = 32768


@dataclass(frozen=True)
class Reduced:
    """Periodic splines of J, dJ/dφ over [0, 2π) and the table of M (linear, with its jumps)."""

    phi: np.ndarray  # (GRID + 1,) [rad], from the drive's start over one turn
    inertia: CubicSpline
    inertia_derivative: CubicSpline
    moment_phi: np.ndarray  # (GRID + 1 + 2·switches,) [rad], non-decreasing; a switch angle twice
    moment_grid: np.ndarray  # M₀ at moment_phi [N·m] (at ω = 0)
    drive_omega: float = 0.0  # the drive's prescribed speed [rad/s]: a speed scale where a motor has none
    damping_grid: np.ndarray | None = None  # c = ∂M/∂ω at moment_phi [N·m·s/rad]; None: no dampers

    def j(self, phi):
        return self.inertia(self._wrap(phi))

    def dj(self, phi):
        return self.inertia_derivative(self._wrap(phi))

    def moment(self, phi, omega=0.0):
        """M(φ, ω) [N·m]: the loads' reduced moment at crank angle φ and speed ω (the one place
        the machine's equation reads it)."""
        m = self._table("moment_grid").at(phi)
        if self.damping_grid is not None:
            m = m + self._table("damping_grid").at(phi) * omega
        return m if np.ndim(m) else float(m)

    def _table(self, name: str) -> PeriodicTable:
        key = f"_cached_{name}"
        table = self.__dict__.get(key)
        if table is None:
            table = PeriodicTable(self.moment_phi, getattr(self, name))
            object.__setattr__(self, key, table)
        return table

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


def reduce(asm: Assembly, load: ProcessLoad | None = None, grid: int = GRID,
           moment_grid: int = MOMENT_GRID) -> Reduced:
    """J, dJ/dφ over one turn of the crank from the drive's start angle (splines through ``grid``
    angles) and M (a table of ``moment_grid`` cells)."""
    d = asm.mechanism.drive
    if asm.mechanism.frictions:  # its moment would depend on the reactions, so on φ̈: not modelled yet
        raise DescriptionError("friction", "the machine's equation of motion does not model friction in the pairs "
                                           "yet (the kinetostatics does: linkgen forces); remove [[friction]] to run "
                                           "the machine")
    if d.stop - d.start < 2 * math.pi - 1e-9:
        raise DescriptionError("drive.range", "a machine needs a crank that turns fully (range of 360°); this "
                               f"one spans {math.degrees(d.stop - d.start):.6g}°")
    phi = d.start + np.linspace(0.0, 2 * math.pi, grid + 1)
    f = forces(asm, phi[:-1], 0.0, 0.0)
    j = np.append(f.reduced.inertia, f.reduced.inertia[0])
    dj = np.append(f.reduced.inertia_derivative, f.reduced.inertia_derivative[0])
    table_phi, where = jump_grid(d.start, moment_grid, switch_angles(asm.mechanism, d.start))
    red = forces(asm, where, 0.0, 0.0).reduced
    m = red.moment - process_torque(load, where)
    m[-1] = m[0]  # one turn on: the same load
    c = None
    if any(s.damping for s in asm.mechanism.springs) or any(t.damping for t in asm.mechanism.torsion_springs):
        c = red.damping.copy()
        c[-1] = c[0]
    return Reduced(phi, CubicSpline(phi, j, bc_type="periodic"), CubicSpline(phi, dj, bc_type="periodic"),
                   table_phi, m, float(d.omega), c)


__all__ = ["GRID", "MOMENT_GRID", "Reduced", "process_torque", "process_torque_function", "reduce"]
