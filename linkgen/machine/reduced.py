"""The mechanism reduced to the crank over one turn (or over the drive's range where the crank
cannot turn fully: then the tables end there and ``stop`` says where), as smooth functions of φ
for an ODE solver, periodic over a full turn: J(φ) [kg·m²] by a cubic Hermite spline through the
closed form's J and dJ/dφ on a grid, and dJ/dφ as its derivative,
and the reduced moment of the loads M(φ, ω) = M₀(φ) + c(φ)·ω [N·m] (gravity, forces, torques,
springs, the process load; dampers make it depend on the crank speed ω through the reduced
damping c(φ) = ∂M/∂ω ≤ 0, ``planar.kinetostatics.reduced_damping``). Friction in the pairs is
not a table: its moment depends on the acceleration too (``machine.friction``, ``Reduced.friction``).

M₀(φ) and c(φ) are cubic splines through a fine grid (``tables.SmoothTable``), and M₀ jumps
exactly where a stroke-switched force switches (``tables``: the switch angles are in its grid
twice). The tables err by ~1e-10 of J between their angles (the Hermite spline's h⁴·J⁗/384 at
4096 angles a turn) and their derivatives have kinks at every angle, which bounds what a tighter
integration can reach: ``[machine] tables = false`` (``reduce(..., exact=True)``) evaluates the
closed form itself at every call of the equation instead (``ClosedForm``: the kinematics and the
reduced dynamics at each φ, ~1 ms a call), so that only the integration's tolerance is left.
MuJoCo's side of the comparison applies the same grid's values as a linear table
(``tables.PeriodicTable``: its step means), which differs from the spline by
(2π/n)²/8·|M″| ≈ 4.6e-9·|M″|, far inside that comparison's tolerance."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicHermiteSpline, CubicSpline

from linkgen.machine.tables import SmoothTable, jump_grid, switch_angles
from linkgen.errors import DescriptionError
from linkgen.model.machine import ProcessLoad
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinematics import Kinematics, raise_failure, solve_block
from linkgen.families.planar.kinetostatics import forces, reduced_dynamics

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
    """J (a Hermite spline) and dJ/dφ (its derivative) over a turn from the drive's start (or the
    drive's range) and the grid of M₀ and C (read through ``table``: cubic, with its jumps)."""

    phi: np.ndarray  # (GRID + 1,) [rad], from the drive's start over one turn
    inertia: CubicHermiteSpline  # J(φ) [kg·m²]
    inertia_derivative: object  # its derivative dJ/dφ (a PPoly) [kg·m²/rad]
    moment_phi: np.ndarray  # (GRID + 1 + 2·switches,) [rad], non-decreasing; a switch angle twice
    moment_grid: np.ndarray  # M₀ at moment_phi [N·m] (at ω = 0)
    drive_omega: float = 0.0  # the drive's prescribed speed [rad/s]: a speed scale where a motor has none
    damping_grid: np.ndarray | None = None  # c = ∂M/∂ω at moment_phi [N·m·s/rad]; None: no dampers
    stop: float | None = None  # the drive range's end [rad] where the crank does not turn fully; None: it does
    friction: object = None  # ``machine.friction.PairFriction`` with [[friction]]: M_f(φ, ω, ε); None without
    closed_form: object = None  # ``ClosedForm``: J, J′, M₀, C evaluated at each φ instead of the tables; None: tables

    @property
    def exact(self) -> bool:
        """Whether J, J′, M₀ and C come from the closed form at each angle (no tables)."""
        return self.closed_form is not None

    @property
    def full_turn(self) -> bool:
        """Whether the tables cover a full turn (periodic in φ)."""
        return self.stop is None

    def j(self, phi):
        if self.closed_form is not None:
            return self.closed_form.at(phi)[0]
        return self.inertia(self._wrap(phi))

    def dj(self, phi):
        """dJ/dφ: the derivative of the very function ``j`` is (so that ½·J·ω² is the equation's
        kinetic energy to the last digit: ``machine.energy``)."""
        if self.closed_form is not None:
            return self.closed_form.at(phi)[1]
        return self.inertia_derivative(self._wrap(phi))

    def moment(self, phi, omega=0.0):
        """M(φ, ω) [N·m]: the loads' reduced moment at crank angle φ and speed ω (the one place
        the machine's equation reads it)."""
        if self.closed_form is not None:
            m = self.closed_form.at(phi)[2] + self.damping(phi) * omega
            return m if np.ndim(m) else float(m)
        m = self.table("moment_grid").at(phi)
        if self.damping_grid is not None:
            m = m + self.table("damping_grid").at(phi) * omega
        return m if np.ndim(m) else float(m)

    def load_moment(self, phi):
        """M₀(φ) [N·m]: the reduced moment of the loads that depend on φ alone (at ω = 0)."""
        if self.closed_form is not None:
            return self.closed_form.at(phi)[2]
        m = self.table("moment_grid").at(phi)
        return m if np.ndim(m) else float(m)

    def damping(self, phi):
        """C(φ) = ∂M/∂ω [N·m·s/rad] (≤ 0; 0 without dampers)."""
        if self.damping_grid is None:
            return np.zeros_like(np.asarray(phi, dtype=float)) if np.ndim(phi) else 0.0
        if self.closed_form is not None:
            return self.closed_form.at(phi)[3]
        c = self.table("damping_grid").at(phi)
        return c if np.ndim(c) else float(c)

    def table(self, name: str) -> SmoothTable:
        """The smooth table (``tables.SmoothTable``) of ``moment_grid`` or ``damping_grid``."""
        key = f"_cached_{name}"
        table = self.__dict__.get(key)
        if table is None:
            table = SmoothTable(self.moment_phi, getattr(self, name), periodic=self.full_turn)
            object.__setattr__(self, key, table)
        return table


    def _wrap(self, phi):
        x = np.asarray(phi, dtype=float)
        return self.phi[0] + np.mod(x - self.phi[0], 2 * math.pi) if self.full_turn else x


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


class ClosedForm:
    """J, dJ/dφ, M₀ (at ω = 0, less the process load) and C at crank angles φ from the closed form
    itself: the kinematics and ``kinetostatics.reduced_dynamics``, the same functions the tables
    are made of, without the reactions. ``at`` keeps its last angles' values, since the equation
    reads J, J′ and M at the same φ one after the other."""

    def __init__(self, asm: Assembly, load: ProcessLoad | None):
        self.asm, self.process = asm, process_torque_function(load)
        self._key, self._values = None, None

    def at(self, phi) -> tuple:
        """(J [kg·m²], dJ/dφ [kg·m²/rad], M₀ [N·m], C [N·m·s/rad]) at φ [rad], each shaped as φ.
        AssemblyError or SingularityError where the mechanism does not assemble or is singular."""
        x = np.asarray(phi, dtype=float)
        key = (x.shape, x.tobytes())
        if key != self._key:
            flat = np.atleast_1d(x).ravel()
            (poses, points, sliders, near, marked), ok = solve_block(self.asm, flat)
            if not ok:
                raise_failure(self.asm, flat)
            red = reduced_dynamics(self.asm, Kinematics(self.asm, flat, poses, points, sliders, near, marked))
            values = (red.inertia, red.inertia_derivative, red.moment - self.process(flat), red.damping)
            shaped = tuple(v.reshape(x.shape) if x.ndim else float(v[0]) for v in values)
            self._key, self._values = key, shaped
        return self._values


def reduce(asm: Assembly, load: ProcessLoad | None = None, grid: int = GRID,
           moment_grid: int = MOMENT_GRID, *, exact: bool = False) -> Reduced:
    """J, dJ/dφ over one turn of the crank from the drive's start angle (splines through ``grid``
    angles) and M (a table of ``moment_grid`` cells); over the drive's range only where it spans
    less than a turn (``Reduced.stop``: a motion that leaves it is stopped there). ``exact``: the
    equation reads J, J′, M₀ and C from the closed form at each angle (``ClosedForm``) rather
    than from the tables (which are still made: the speed scale and the flywheel read them)."""
    d = asm.mechanism.drive
    full = d.stop - d.start >= 2 * math.pi - 1e-9
    span = 2 * math.pi if full else d.stop - d.start
    phi = d.start + np.linspace(0.0, span, grid + 1)
    # J, J′ and M₀ at ω = 0, where the closed form's friction is zero: the friction enters the
    # equation as its own moment M_f(φ, ω, ε) (``machine.friction``).
    f = forces(asm, phi[:-1] if full else phi, 0.0, 0.0)
    j, dj = f.reduced.inertia, f.reduced.inertia_derivative
    if full:
        j, dj = np.append(j, j[0]), np.append(dj, dj[0])
    table_phi, where = jump_grid(d.start, moment_grid, switch_angles(asm.mechanism, d.start), span)
    red = forces(asm, where, 0.0, 0.0).reduced
    m = red.moment - process_torque(load, where)
    c = None
    if any(s.damping for s in asm.mechanism.springs) or any(t.damping for t in asm.mechanism.torsion_springs):
        c = red.damping.copy()
    if full:  # one turn on: the same load
        m[-1] = m[0]
        if c is not None:
            c[-1] = c[0]
    inertia = CubicHermiteSpline(phi, j, dj)  # J and dJ/dφ at each grid angle, one function
    friction = None
    if asm.mechanism.frictions:
        from linkgen.machine.friction import PairFriction

        friction = PairFriction(asm)
    return Reduced(phi, inertia, inertia.derivative(), table_phi, m, float(d.omega), c, None if full else float(d.stop),
                   friction, ClosedForm(asm, load) if exact else None)


def require_full_turn(red: Reduced, what: str) -> None:
    """DescriptionError unless the crank turns fully: ``what`` needs a periodic machine."""
    if not red.full_turn:
        raise DescriptionError("drive.range", f"{what} needs a crank that turns fully (range of 360°); this one "
                               f"spans {math.degrees(red.stop - red.phi[0]):.6g}°")


__all__ = ["ClosedForm", "GRID", "MOMENT_GRID", "Reduced", "process_torque", "process_torque_function", "reduce", "require_full_turn"]
