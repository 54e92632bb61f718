"""The ``[machine]`` table of a description: what drives the crank when its speed is not
prescribed — a motor (through a gearbox), the rotor's and a flywheel's inertia, an optional
elastic shaft between rotor and crank, and a process load over the crank angle.

    [machine]
    rotor_inertia = 0.5          # kg·m², on the motor shaft
    gear_ratio = 1.0             # motor speed / crank speed (> 0)
    gear_efficiency = 1.0        # (0, 1]: the crank gets ratio·efficiency·motor torque
    flywheel_inertia = 0.0       # kg·m², on the crank
    start_angle = "30deg"        # crank angle at t = 0 (default: the drive's start, drive.range[0])
    start_speed = 0.0            # crank speed at t = 0 [rad/s] (from rest by default; either sign)
    duration = 5.0               # s of machine time to integrate (default 10 s)
    turns = 10                   # optional: stop once the crank has turned this many turns either way
    rtol = 1e-10                 # the integration's relative tolerance (absolute: 1e-3 of it on the state)
    tables = true                # false: the equation reads the closed form at every step, not its tables

    [machine.motor]              # kind = "constant" | "linear" | "induction" | "dc" | "none";
                                 # no [machine.motor] table: "none", free motion under the loads
    kind = "linear"
    stall_torque = 2000.0        # N·m at standstill
    no_load_speed = 6.0          # rad/s where the torque falls to 0

    [machine.shaft]              # optional: rotor and crank joined by a torsion spring
    stiffness = 2000.0           # N·m/rad
    damping = 0.7                # N·m·s/rad
    backlash = 0.0               # rad, the total dead zone of the coupling

    [machine.process_load]       # optional: a resisting torque on the crank over φ
    angles = ["0deg", "90deg", "180deg", "270deg"]   # over one turn, increasing
    torque = [100.0, 150.0, 100.0, 50.0]             # N·m against the rotation

    [machine.schedule]           # optional: the motor switched on and off (linkgen.model.schedule)
    [machine.brake]              # optional: a brake that stops the crank (linkgen.model.schedule)

Motor kinds and their keys (SI): ``constant``: torque [N·m]; ``linear``: stall_torque [N·m],
no_load_speed [rad/s] (M = M0·(1 − ω/ω0)); ``induction`` (Kloss's formula from catalogue data):
rated_power [W], synchronous_speed [rad/s], rated_slip, breakdown_ratio (M_max/M_rated > 1);
``none``: no keys, no motor torque (free motion under gravity, springs and loads);
``dc`` (armature circuit L·di/dt = U − R·i − k_e·ω, M = k_t·i): voltage [V], resistance [Ω],
inductance [H], torque_constant [N·m/A], emf_constant [V·s/rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.errors import DescriptionError
from linkgen.model.schema import MACHINE as MACHINE_TYPES, check as check_types
from linkgen.model import limits
from linkgen.model.schedule import Brake, Schedule, brake_from_dict, schedule_from_dict
from linkgen.model.units import angular_speed, bounded, finite, parse_angle, shown

MOTOR_KEYS = {
    "none": (),
    "constant": ("torque",),
    "linear": ("stall_torque", "no_load_speed"),
    "induction": ("rated_power", "synchronous_speed", "rated_slip", "breakdown_ratio"),
    "dc": ("voltage", "resistance", "inductance", "torque_constant", "emf_constant"),
}
_MACHINE = {"rotor_inertia", "gear_ratio", "gear_efficiency", "flywheel_inertia", "start_angle", "start_speed", "duration",
            "turns", "rtol", "tables", "motor", "shaft", "process_load", "schedule", "brake"}
DEFAULT_DURATION = 10.0  # s
# The integration's relative tolerance by default (``machine.machine.run_machine``; absolute: 1e-3
# of it on every state), and the range a description may ask for: scipy's solvers raise any rtol
# below 100·eps = 2.2e-14 to that, silently, so 1e-13 is the tightest asked for here; above 1e-6
# the energy balance's check (1e-7 of the run's energy) would fail on the integration's own error.
DEFAULT_RTOL = 1e-10
RTOL_RANGE = (1e-13, 1e-6)
# No motor: free motion of the mechanism under its loads from the start state.
FREE = "none"


@dataclass(frozen=True)
class Motor:
    """A motor law: ``kind`` (see MOTOR_KEYS) and its parameters [SI]."""

    kind: str
    params: tuple[tuple[str, float], ...]

    def __getattr__(self, name: str) -> float:
        for k, v in self.params:
            if k == name:
                return v
        raise AttributeError(name)


@dataclass(frozen=True)
class Shaft:
    """Torsion spring and damper between the rotor (after the gearbox) and the crank."""

    stiffness: float  # N·m/rad
    damping: float  # N·m·s/rad
    backlash: float = 0.0  # rad, total dead zone


@dataclass(frozen=True)
class ProcessLoad:
    """A resisting torque on the crank [N·m] at crank angles [rad] over one turn (periodic)."""

    angles: tuple[float, ...]
    torque: tuple[float, ...]


@dataclass(frozen=True)
class Machine:
    motor: Motor
    rotor_inertia: float = 0.0
    gear_ratio: float = 1.0
    gear_efficiency: float = 1.0
    flywheel_inertia: float = 0.0
    start_speed: float = 0.0
    duration: float = DEFAULT_DURATION
    shaft: Shaft | None = None
    process_load: ProcessLoad | None = None
    start_angle: float | None = None  # rad; None: the drive's start angle
    turns: float | None = None  # the run stops after this many crank turns (either way); None: duration only
    schedule: Schedule | None = None  # when the motor runs; None: the whole run
    brake: Brake | None = None  # a brake on the crank; None: none
    rtol: float = DEFAULT_RTOL  # the integration's relative tolerance
    tables: bool = True  # the equation reads J, J′, M from tables over a turn (False: the closed form at each step)

    def start(self, drive_start: float) -> float:
        """The crank angle at t = 0 [rad]: ``start_angle``, or the drive's start angle if not given."""
        return drive_start if self.start_angle is None else self.start_angle

    @property
    def free(self) -> bool:
        """No motor: the mechanism moves under its loads alone."""
        return self.motor.kind == FREE

    def top_speed(self, drive_omega: float) -> float:
        """The largest crank speed the machine can reach [rad/s]: the motor's no-load or
        synchronous speed through the gearbox, or the start or prescribed speed if higher."""
        m, u = self.motor, self.gear_ratio
        w = max(drive_omega, abs(self.start_speed))
        if m.kind == "linear":
            w = max(w, m.no_load_speed / u)
        elif m.kind == "induction":
            w = max(w, m.synchronous_speed / u)
        elif m.kind == "dc":
            w = max(w, m.voltage / m.emf_constant / u)
        return w

    @property
    def added_inertia(self) -> float:
        """Rotor and flywheel reduced to the crank [kg·m²] (the rotor's through the gear ratio²)."""
        return self.rotor_inertia * self.gear_ratio**2 + self.flywheel_inertia


# Keys that are angular speeds: a number in rad/s or a string with its unit ("1500rpm", "10rad/s").
SPEED_KEYS = {"no_load_speed", "synchronous_speed", "start_speed"}
# Keys bounded by linkgen's limits (linkgen.model.limits), so that the reduced moments and the
# energies of a turn stay within float64's range like the mechanism's own loads: (limit, unit).
LIMITS = {"torque": (limits.MAX_TORQUE, "N·m"), "stall_torque": (limits.MAX_TORQUE, "N·m"),
          "no_load_speed": (limits.MAX_OMEGA, "rad/s"), "synchronous_speed": (limits.MAX_OMEGA, "rad/s"),
          "start_speed": (limits.MAX_OMEGA, "rad/s"), "rotor_inertia": (limits.MAX_INERTIA, "kg·m²"),
          "flywheel_inertia": (limits.MAX_INERTIA, "kg·m²"),
          "rated_power": (limits.MAX_TORQUE * limits.MAX_OMEGA, "W"),
          # motor speed / crank speed: a ratio of two speeds within linkgen's range, so that
          # u²·rotor_inertia stays within MAX_OMEGA²·MAX_INERTIA = 1e114 (and 1/u likewise)
          "gear_ratio": (limits.MAX_OMEGA, "as a ratio")}
# The smallest gear ratio: 1/MAX_OMEGA (the reciprocal bound of the same ratio).
MIN_GEAR_RATIO = 1.0 / limits.MAX_OMEGA


def _number(t: dict, key: str, where: str, *, low: float = -math.inf, strict: bool = False, default=None) -> float:
    if key not in t:
        if default is None:
            raise DescriptionError(f"{where}.{key}", "is required")
        return default
    x = angular_speed(t[key], f"{where}.{key}") if key in SPEED_KEYS else finite(t[key], f"{where}.{key}")
    if key in LIMITS:
        bounded(x, f"{where}.{key}", *LIMITS[key])
    if x < low or (strict and x == low):
        raise DescriptionError(f"{where}.{key}", f"must be {'>' if strict else '>='} {low:g}, got {shown(t[key])}")
    return x


def _table(x, where: str) -> dict:
    if not isinstance(x, dict):
        raise DescriptionError(where, f"must be a table, got {shown(x)}")
    return x


def _only(t: dict, allowed, where: str) -> None:
    for k in t:
        if k not in allowed:
            raise DescriptionError(f"{where}.{k}", f"unknown key; allowed keys: {sorted(allowed)}")


def _motor(t: dict) -> Motor:
    where = "machine.motor"
    kind = t.get("kind")
    if kind not in MOTOR_KEYS:
        raise DescriptionError(f"{where}.kind", f"must be one of {sorted(MOTOR_KEYS)}, got {shown(kind)}")
    keys = MOTOR_KEYS[kind]
    _only(t, {"kind", *keys}, where)
    strict_positive = {"no_load_speed", "rated_power", "synchronous_speed", "resistance", "torque_constant",
                       "emf_constant"}
    params = []
    for k in keys:
        low = 0.0 if (k in strict_positive or k in ("stall_torque", "inductance")) else -math.inf
        params.append((k, _number(t, k, where, low=low, strict=k in strict_positive)))
    m = Motor(kind, tuple(params))
    if kind == "induction":
        if not 0.0 < m.rated_slip < 1.0:
            raise DescriptionError(f"{where}.rated_slip", f"must be in (0, 1), got {m.rated_slip!r}")
        if not m.breakdown_ratio > 1.0:
            raise DescriptionError(f"{where}.breakdown_ratio", f"must be > 1 (M_max / M_rated), got {m.breakdown_ratio!r}")
    return m


def _rtol(t: dict) -> float:
    x = _number(t, "rtol", "machine", default=DEFAULT_RTOL)
    lo, hi = RTOL_RANGE
    if not lo <= x <= hi:
        raise DescriptionError("machine.rtol", f"must be between {lo:g} and {hi:g} (the integration's relative "
                               f"tolerance), got {shown(t['rtol'])}")
    return x


def machine_from_dict(data: dict) -> Machine | None:
    """The ``[machine]`` table of a parsed description, or None if it has none."""
    if "machine" not in data:
        return None
    check_types(data["machine"], MACHINE_TYPES, "machine")
    t = _table(data["machine"], "machine")
    _only(t, _MACHINE, "machine")
    shaft = None
    if "shaft" in t:
        s = _table(t["shaft"], "machine.shaft")
        _only(s, {"stiffness", "damping", "backlash"}, "machine.shaft")
        shaft = Shaft(_number(s, "stiffness", "machine.shaft", low=0.0, strict=True),
                      _number(s, "damping", "machine.shaft", low=0.0, default=0.0),
                      _number(s, "backlash", "machine.shaft", low=0.0, default=0.0))
    load = None
    if "process_load" in t:
        p = _table(t["process_load"], "machine.process_load")
        _only(p, {"angles", "torque"}, "machine.process_load")
        for k in ("angles", "torque"):
            if not isinstance(p.get(k), list) or len(p[k]) < 3:
                raise DescriptionError(f"machine.process_load.{k}", f"must be a list of at least 3 values, got {shown(p.get(k))}")
        ang = [parse_angle(a, f"machine.process_load.angles[{i}]") for i, a in enumerate(p["angles"])]
        tq = [bounded(finite(x, f"machine.process_load.torque[{i}]"), f"machine.process_load.torque[{i}]",
                      limits.MAX_TORQUE, "N·m") for i, x in enumerate(p["torque"])]
        if len(ang) != len(tq):
            raise DescriptionError("machine.process_load", f"angles ({len(ang)}) and torque ({len(tq)}) differ in length")
        if not (np.all(np.diff(ang) > 0) and ang[-1] - ang[0] < 2 * math.pi):
            raise DescriptionError("machine.process_load.angles", "must increase and span less than one turn")
        load = ProcessLoad(tuple(ang), tuple(tq))
    duration = _number(t, "duration", "machine", low=0.0, strict=True, default=DEFAULT_DURATION)
    schedule = schedule_from_dict(t["schedule"], duration) if "schedule" in t else None
    brake = brake_from_dict(t["brake"], duration) if "brake" in t else None
    if brake is not None and "shaft" in t:
        raise DescriptionError("machine.brake", "cannot be combined with [machine.shaft]: the brake holds the crank "
                               "at rest, while an elastic shaft would keep the rotor moving; brake a rigid machine")
    eff = _number(t, "gear_efficiency", "machine", low=0.0, strict=True, default=1.0)
    if eff > 1.0:
        raise DescriptionError("machine.gear_efficiency", f"must be in (0, 1], got {eff!r}")
    machine = Machine(
        motor=_motor(_table(t["motor"], "machine.motor")) if "motor" in t else Motor(FREE, ()),
        rotor_inertia=_number(t, "rotor_inertia", "machine", low=0.0, default=0.0),
        gear_ratio=_number(t, "gear_ratio", "machine", low=MIN_GEAR_RATIO, default=1.0),
        gear_efficiency=eff,
        flywheel_inertia=_number(t, "flywheel_inertia", "machine", low=0.0, default=0.0),
        start_speed=_number(t, "start_speed", "machine", default=0.0),
        start_angle=bounded(parse_angle(t["start_angle"], "machine.start_angle"), "machine.start_angle",
                            limits.MAX_ANGLE, "rad") if "start_angle" in t else None,
        turns=_number(t, "turns", "machine", low=0.0, strict=True) if "turns" in t else None,
        duration=duration,
        shaft=shaft,
        process_load=load,
        schedule=schedule,
        brake=brake,
        rtol=_rtol(t),
        tables=t.get("tables", True),
    )
    # The motor's own top speed at the crank (a DC motor's U/(k_e·u), say) within linkgen's
    # speeds, like every other speed of the description: past it the machine's time constants
    # leave what a step can resolve (a voltage of 1e100 V: 7e-98 s).
    top = machine.top_speed(0.0)
    if not top <= limits.MAX_OMEGA:
        raise DescriptionError("machine.motor", f"gives a top speed at the crank of {top:.3g} rad/s (its no-load or "
                               f"synchronous speed through the gear ratio), beyond linkgen's limit of "
                               f"{limits.MAX_OMEGA:g} rad/s (see the README); check the motor's parameters")
    return machine


__all__ = ["DEFAULT_RTOL", "FREE", "MOTOR_KEYS", "Machine", "Motor", "ProcessLoad", "Shaft", "machine_from_dict"]
