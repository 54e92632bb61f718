"""The MuJoCo settings a model is written and run with (derived per mechanism by
``linkgen.mujoco.settings``)."""

from __future__ import annotations

from dataclasses import asdict, dataclass

from linkgen.errors import SimulationError

# MuJoCo clamps the impedance at mjMAXIMP = 0.9999: the stiffest a soft constraint gets.
IMPEDANCE = 0.9999
# Newton iterations per step at tolerance 0: converged to rounding on every bundled model.
SOLVER_ITERATIONS = 50
# A run may take at most this many steps (per segment): 1e6 RK4 steps of a ten-link model are
# about 20 s here. Beyond it the settings are coarsened and the result says so. (Here, not in
# ``settings``, so that the command line's help reads it without importing MuJoCo.)
MAX_STEPS = 1_000_000


def within_budget(name: str, steps: int, timestep: float, max_steps: int) -> None:
    """Refuse, before any step, a run of ``steps`` steps past the budget ``max_steps``: for the
    families whose timestep cannot be coarsened without losing the contact or the loop (cams,
    spatial chains), a run over budget is not made at all rather than made worse."""
    if steps > max_steps:
        raise SimulationError(f"{name}: not run: one turn needs {steps:d} MuJoCo steps of {timestep:.3g} s, past the "
                              f"step budget of {max_steps:d} (max_steps); a budget of {steps:d} would run it")


def _fmt(x: float) -> str:
    return repr(float(x))


@dataclass(frozen=True)
class Settings:
    """What a MuJoCo run uses: timestep [s], loop time constant τ [s] and impedance,
    integrator, solver iterations and tolerance, rotor inertia on the driven joint [kg·m²]."""

    timestep: float
    timeconst: float
    impedance: float = IMPEDANCE
    integrator: str = "RK4"
    iterations: int = SOLVER_ITERATIONS
    tolerance: float = 0.0
    armature: float = 1e4
    solimp: tuple[float, ...] | None = None  # None: (impedance, impedance, 0.001)
    label: str = "derived"
    dampratio: float = 1.0  # solref's damping ratio

    @property
    def solref(self) -> str:
        return f"{_fmt(self.timeconst)} " + ("1" if self.dampratio == 1.0 else _fmt(self.dampratio))

    @property
    def solimp_text(self) -> str:
        imp = self.solimp if self.solimp is not None else (self.impedance, self.impedance, 0.001)
        return " ".join(_fmt(x) for x in imp)

    def to_json(self) -> dict:
        out = asdict(self)
        out["solimp"] = [float(x) for x in self.solimp_text.split()]
        return out



# What a model is compiled with before its own settings are known (to read its masses and loop
# Jacobians): the values that suit a metre-sized linkage at 10 rad/s.
PLACEHOLDER = Settings(timestep=5e-5, timeconst=1e-3, armature=1e4, label="placeholder")



# MuJoCo compiler limits that every MJCF writer respects (cam, planar and spatial geoms).
# Shortest capsule drawn [m]: MuJoCo's compiler refuses fromto points closer than 1e-7 m
# ("fromto points too close in geom"; measured on mujoco 4.0 for radii 1e-12..1 m); ten times that.
MUJOCO_MIN_BAR = 1e-6
MUJOCO_MIN_MESH_VOLUME = 1e-15  # m³
MESH_VOLUME_MARGIN = 10.0
# What MuJoCo does where the user gives no value (its XML reference): solimp of a constraint.
MUJOCO_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)
# MuJoCo's integrators linkgen's settings check models, and the evaluations of the dynamics each
# takes per step (RK4: four), the factor between steps and cost. (Here, not in ``accuracy``, so
# that the command line reads them without importing MuJoCo.)
EVALUATIONS = {"Euler": 1, "implicitfast": 1, "RK4": 4}
# Report progress for runs that last longer than this [s].
PROGRESS_AFTER = 2.0

__all__ = ["EVALUATIONS", "IMPEDANCE", "MUJOCO_SOLIMP", "MESH_VOLUME_MARGIN", "MUJOCO_MIN_BAR", "MUJOCO_MIN_MESH_VOLUME", "PLACEHOLDER", "PROGRESS_AFTER",
           "SOLVER_ITERATIONS", "Settings", "within_budget"]
