"""Seeded mistakes for the referee's diagnosis, made from linkgen's closed form (the referee's
own code is not used): tables of results as a solver with one usual mistake would write them.

``seeded(desc, phi, omega, epsilon, rng)`` yields ``Seed``s: the mistake's kind, the column it
was put in, the table (the crank angle and that column, in SI, with linkgen's headers) and the
diagnosis kind the referee should give. ``correct(...)`` yields tables without a mistake, only
printed to a finite number of digits, which must never be diagnosed.

Kinds (the diagnosis expected):
    branch          the other assembly mode of a group from a random angle on       (branch)
    sign            the sign flipped (a reaction's on/by convention)                 (sign)
    unit_mm         millimetres under a metre header                                 (unit)
    unit_deg        degrees under a radian header                                    (unit)
    phi_deg         the crank-angle column in degrees under a radian header          (phi_unit)
    offset          the results of φ + δ written at φ, δ 0.5°..3°                    (offset)
    constant_speed  accelerations and forces at ε = 0 where ε ≠ 0                    (constant_speed)
    centripetal     accelerations and forces without their ω² terms                  (omega_squared)
    gravity         forces without gravity                                           (gravity)
    inertia         forces without one link's moment of inertia about its centre     (inertia)
    finite_diff     velocities by central differences of positions in time, and
                    accelerations by second differences (Δt: 0.2°..3° of crank)      (finite_difference)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Iterator

import numpy as np

import linkgen
from linkgen.families.planar.assembly import Assembly, assemble

EXPECTED = {"branch": "branch", "sign": "sign", "unit_mm": "unit", "unit_deg": "unit", "phi_deg": "phi_unit",
            "offset": "offset", "constant_speed": "constant_speed", "centripetal": "omega_squared",
            "gravity": "gravity", "inertia": "inertia", "finite_diff": "finite_difference"}


@dataclass(frozen=True)
class Seed:
    kind: str
    key: str
    table: dict
    expected: str


def _cols(asm, phi, omega, epsilon, forces: bool = True) -> dict[str, np.ndarray]:
    out = linkgen.kinematics(asm, phi, omega, epsilon).columns()
    if forces:
        out |= linkgen.forces(asm, phi, omega, epsilon).columns()
    return out


def _pick(cols: dict, rng: np.random.Generator, test, count: int) -> list[str]:
    keys = [k for k in cols if k not in ("phi [rad]", "singular") and test(k) and np.ptp(cols[k]) > 0]
    rng.shuffle(keys)
    return keys[:count]


def _is(kind: str):
    return {
        "position": lambda k: ".position." in k,
        "angle": lambda k: k.endswith(".angle [rad]"),
        "velocity": lambda k: "velocity" in k and "[" in k,
        "acceleration": lambda k: "acceleration" in k,
        "force": lambda k: k.endswith("[N]") or k.endswith("[N·m]") and "reduced" not in k,
        "any": lambda k: ".d" not in k and "reduced" not in k and "power" not in k,
    }[kind]


def seeded(asm: Assembly, phi: np.ndarray, omega: float, epsilon: float, rng: np.random.Generator,
           per_kind: int = 3) -> Iterator[Seed]:
    """Seeded mistakes in ``per_kind`` columns each, of the assembled mechanism at φ (n,), ω, ε."""
    ref = _cols(asm, phi, omega, epsilon)
    table = lambda key, values, phi_col=("phi [rad]", phi): {phi_col[0]: phi_col[1], key: values}  # noqa: E731
    for k in _pick(ref, rng, _is("any"), per_kind):
        yield Seed("sign", k, table(k, -ref[k]), "sign")
    for k in _pick(ref, rng, lambda k: k.endswith("[m]") and ".position." in k, per_kind):
        yield Seed("unit_mm", k, table(k, 1000 * ref[k]), "unit")
    for k in _pick(ref, rng, lambda k: k.endswith("[rad]"), per_kind):
        yield Seed("unit_deg", k, table(k, np.degrees(ref[k])), "unit")
    for k in _pick(ref, rng, _is("any"), per_kind):
        yield Seed("phi_deg", k, table(k, ref[k], ("phi [rad]", np.degrees(phi))), "phi_unit")
    delta = math.radians(rng.uniform(0.5, 3.0)) * rng.choice([-1, 1])
    shifted = _cols(asm, phi + delta, omega, epsilon)
    for k in _pick(ref, rng, _is("any"), per_kind):
        yield Seed("offset", k, table(k, shifted[k]), "offset")
    if epsilon != 0:
        steady = _cols(asm, phi, omega, 0.0)
        for k in _pick(ref, rng, lambda k: _is("acceleration")(k) or _is("force")(k), per_kind):
            yield Seed("constant_speed", k, table(k, steady[k]), "constant_speed")
    if omega != 0:
        still = _cols(asm, phi, 0.0, epsilon)
        for k in _pick(ref, rng, lambda k: _is("acceleration")(k) or _is("force")(k), per_kind):
            yield Seed("centripetal", k, table(k, still[k]), "omega_squared")
    if any(asm.mechanism.gravity):
        weightless = replace(asm, mechanism=replace(asm.mechanism, gravity=(0.0, 0.0)))
        light = _cols(weightless, phi, omega, epsilon)
        for k in _pick(ref, rng, _is("force"), per_kind):
            yield Seed("gravity", k, table(k, light[k]), "gravity")
    from linkgen.families.planar.description import MassProperties
    from linkgen.families.planar.loads import mass_table

    spinning = [n for n, mp in mass_table(asm).items() if mp.inertia > 0]
    if spinning:
        link = spinning[int(rng.integers(len(spinning)))]
        mp = mass_table(asm)[link]
        links = tuple(replace(k, inertial=MassProperties(mp.mass, mp.com, 0.0), density=None, areal_density=None)
                      if k.name == link else k for k in asm.mechanism.links)
        flat = _cols(replace(asm, mechanism=replace(asm.mechanism, links=links)), phi, omega, epsilon)
        for k in _pick(ref, rng, _is("force"), per_kind):
            yield Seed("inertia", k, table(k, flat[k]), "inertia")
    yield from _branches(asm, phi, omega, epsilon, ref, rng, per_kind)
    if epsilon == 0 and omega != 0:
        yield from _finite_differences(asm, phi, omega, ref, rng, per_kind)


def _branches(asm, phi, omega, epsilon, ref, rng, per_kind) -> Iterator[Seed]:
    for i, g in enumerate(asm.structure.groups):
        if asm.branches[i] not in (1, -1):
            continue
        modes = list(asm.branches)
        modes[i] = -modes[i]
        try:
            other = _cols(replace(asm, branches=tuple(modes)), phi, omega, epsilon)
        except linkgen.LinkgenError:
            continue  # the other mode does not assemble over the range
        start = int(rng.integers(len(phi) // 4, 3 * len(phi) // 4))
        for k in _pick(ref, rng, lambda k: (_is("position")(k) or _is("angle")(k) or _is("velocity")(k))
                       and np.max(np.abs(other[k] - ref[k])) > 1e-3 * np.max(np.abs(ref[k])), per_kind):
            values = np.where(np.arange(len(phi)) >= start, other[k], ref[k])
            yield Seed("branch", k, {"phi [rad]": phi, k: values}, "branch")


def _finite_differences(asm, phi, omega, ref, rng, per_kind) -> Iterator[Seed]:
    h = math.radians(rng.uniform(0.2, 3.0))  # crank step; Δt = h/ω
    dt = h / omega
    up, down = _cols(asm, phi + h, omega, 0.0, False), _cols(asm, phi - h, omega, 0.0, False)
    def step(a, b, key):  # a − b, an angle's across ±π
        d = a[key] - b[key]
        return (d + math.pi) % (2 * math.pi) - math.pi if key.endswith("[rad]") else d

    for k in _pick(ref, rng, lambda k: (".velocity." in k or "angular_velocity" in k), per_kind):
        pos = k.replace("angular_velocity", "angle").replace("velocity", "position").replace("[m/s]", "[m]") \
            .replace("[rad/s]", "[rad]")
        yield Seed("finite_diff", k, {"phi [rad]": phi, k: step(up, down, pos) / (2 * dt)}, "finite_difference")
    for k in _pick(ref, rng, lambda k: (".acceleration." in k or "angular_acceleration" in k), per_kind):
        pos = k.replace("angular_acceleration", "angle").replace("acceleration", "position") \
            .replace("[m/s²]", "[m]").replace("[rad/s²]", "[rad]")
        values = (step(up, ref, pos) - step(ref, down, pos)) / dt**2
        yield Seed("finite_diff", k, {"phi [rad]": phi, k: values}, "finite_difference")


def packed(seeds) -> Iterator[tuple[dict, list[Seed]]]:
    """The seeds gathered into as few tables as their columns allow (one referee call each): seeds
    share a table when they share its crank-angle column and none gives the same column."""
    tables: list[tuple[dict, list[Seed]]] = []
    for s in seeds:
        (phi_key, phi), (key, values) = list(s.table.items())
        for table, members in tables:
            if phi_key in table and np.array_equal(table[phi_key], phi) and key not in table:
                table[key] = values
                members.append(s)
                break
        else:
            tables.append(({phi_key: phi, key: values}, [s]))
    return iter(tables)


def correct(asm: Assembly, phi: np.ndarray, omega: float, epsilon: float, digits: int = 10) -> dict:
    """Every column of the closed form, printed to ``digits`` significant digits (as a solver's
    CSV would carry them)."""
    ref = _cols(asm, phi, omega, epsilon)
    out = {"phi [rad]": phi}
    for k, v in ref.items():
        if k not in ("phi [rad]", "singular"):
            out[k] = np.array([float(f"{x:.{digits - 1}e}") for x in v])
    return out


def mechanism(path) -> Assembly:
    return assemble(linkgen.load(path))
