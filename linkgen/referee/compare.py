"""The referee: a user's table of results against linkgen's closed form (and, asked, MuJoCo's
forward and inverse routes), column by column, with a diagnosis of every difference.

Errors are relative to a scale that cannot vanish: the largest magnitude, over the sampled
angles, of every closed-form quantity in the column's unit (a pivot's zero position is judged
against the mechanism's size, a reaction against the largest reaction), or the drive's own
scale of a kinematic unit where larger (the size or one radian times ω, ω², ω³)."""

from __future__ import annotations

import math
from typing import Any, Callable, Mapping

import numpy as np

from linkgen.referee.diagnose import Evidence, diagnose
from linkgen.referee.reference import Reference
from linkgen.referee.table import as_columns, build, split_header
from linkgen.referee.verdict import ColumnVerdict, RouteError, Verdict

# Default tolerance, as a fraction of the column's scale: a float64 solver converged to 1e-10
# and printed to 7 significant digits stays ~10× under it; the usual mistakes are ≥ 1e-4.
DEFAULT_TOLERANCE = 1e-6
# The crank-angle step of the closed form's own derivative of the jerk (the snap, the shape of a
# central difference's error in an acceleration) [rad]: truncation ~1e-8, rounding ~1e-12.
SNAP_STEP = 1e-4
_CHAIN = {"velocity": ("acceleration", "jerk"), "acceleration": ("jerk", None),
          "angular_velocity": ("angular_acceleration", "angular_jerk"), "angular_acceleration": ("angular_jerk", None)}


def referee(desc: Any, table: Any, *, mapping: Mapping[str, str] | None = None, omega: float | None = None,
            epsilon: float | None = None, tolerance: float = DEFAULT_TOLERANCE, mujoco: bool = False,
            progress: Callable[[str], None] | None = None) -> Verdict:
    """The verdict on ``table`` (a CSV path, a dict of columns or a data frame, headed as
    ``linkgen analyze``/``forces`` write: ``phi [deg]``, ``B.position.x [mm]``…; ``mapping``
    renames headers) for the description ``desc`` at ω, ε (None: the description's; a number
    in rad/s, rad/s² or a string with its unit, "120rpm"). ArgumentError for a bad option.
    ``progress`` is told (one line) when MuJoCo starts running."""
    from linkgen.errors import ArgumentError
    from linkgen.model.arguments import one_rate

    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not 0 < tolerance < 1:
        raise ArgumentError(f"tolerance: expected a fraction of the column's scale between 0 and 1 (e.g. 1e-6), "
                            f"got {tolerance!r}")
    if mapping is not None and not (isinstance(mapping, Mapping) and all(isinstance(v, str) for v in mapping.values())):
        raise ArgumentError(f"mapping: expected a dict of your header → linkgen's header (a string), got {mapping!r}")
    omega, epsilon = one_rate(omega, "omega", "rad/s"), one_rate(epsilon, "epsilon", "rad/s²")
    ref = Reference(desc, omega, epsilon)
    raw, source = as_columns(table)
    t = build(raw, source, ref.vocabulary, mapping)
    keys = list(t.columns)
    need_forces = any(k in ref.force_keys for k in keys)
    base = ref.evaluate(t.phi, ref.kinematic_keys + (ref.force_keys if need_forces else ()))
    scales = _scales(base, ref.omega, ref.epsilon)
    mj = _mujoco(ref, t.phi, keys, progress) if mujoco else {}
    diag = _Diagnoser(ref, t, base, scales, tolerance)
    verdicts = []
    for key, col in t.columns.items():
        r = base[key]
        ok = np.isfinite(r)
        angle = _is_angle(key)
        routes = {"closed_form": _route(col.values[ok], r[ok], t.phi[ok], scales[key], angle, tolerance)}
        for name, values in mj.get(key, {}).items():
            own = _route(values[ok], r[ok], t.phi[ok], scales[key], angle, tolerance).error
            routes[name] = _route(col.values[ok], values[ok], t.phi[ok], scales[key], angle, tolerance + own, own)
        d = diag.column(key, ok) if not routes["closed_form"].agrees and ok.any() else None
        curves = {"phi": t.phi, "user": col.values, "closed_form": r} | {n: v for n, v in mj.get(key, {}).items()}
        verdicts.append(ColumnVerdict(col.header, key, scales[key], routes, d, int(np.count_nonzero(~ok)), curves))
    mech = getattr(ref.desc, "mechanism", ref.desc)
    return Verdict(mech.name, source, ref.omega, ref.epsilon, len(t.phi), tolerance, tuple(verdicts), bool(mujoco))


def _is_angle(key: str) -> bool:
    name, unit = split_header(key)
    return unit == "rad" and name.endswith("angle")


def _scales(base: Mapping[str, np.ndarray], omega: float, epsilon: float) -> dict[str, float]:
    """Per header, the largest magnitude of every closed-form column in its unit, or the drive's
    own scale of that unit where larger (``natural``): a mechanism whose links all turn evenly
    has angular accelerations of rounding size, not a scale to judge them by."""
    by_unit: dict[str, float] = {}
    for k, v in base.items():
        u = split_header(k)[1]
        m = float(np.nanmax(np.abs(v))) if np.isfinite(v).any() else 0.0
        by_unit[u] = max(by_unit.get(u, 0.0), m)
    size = by_unit.get("m", 0.0)
    return {k: max(by_unit[u], natural(u, size, omega, epsilon)) or 1.0 for k in base
            for u in (split_header(k)[1],)}


def natural(unit: str, size: float, omega: float, epsilon: float) -> float:
    """The drive's scale of a kinematic unit: the mechanism's size [m] (its largest coordinate)
    or one radian, times |ω|, max(ω², |ε|) or max(|ω|³, |ω·ε|) per time derivative; 0 for a
    unit without one (forces: their own largest is the scale)."""
    rates = {"": 1.0, "/s": abs(omega), "/s²": max(omega**2, abs(epsilon)),
             "/s³": max(abs(omega) ** 3, abs(omega * epsilon))}
    for base, length in (("m", size), ("rad", 1.0)):
        if unit.startswith(base) and unit[len(base):] in rates:
            return length * rates[unit[len(base):]]
    return 0.0


def _route(u: np.ndarray, r: np.ndarray, phi: np.ndarray, scale: float, angle: bool, tol: float,
           own: float | None = None) -> RouteError:
    if not len(u):
        return RouteError(math.nan, math.nan, tol, own)
    d = u - r
    if angle:
        d = (d + math.pi) % (2 * math.pi) - math.pi
    i = int(np.argmax(np.abs(d)))
    return RouteError(float(abs(d[i]) / scale), float(phi[i]), tol, own)


class _Diagnoser:
    """The variants of the closed form the diagnosis needs, computed once for every column that
    differs (on first use) and kept."""

    def __init__(self, ref: Reference, t, base, scales, tolerance: float) -> None:
        self.ref, self.t, self.base, self.scales, self.tol = ref, t, base, scales, tolerance
        self._variants: dict | None = None
        self._shifted: dict[float, dict] = {}
        self._deltas: list[float] = []  # offsets fitted so far (a whole table is usually shifted alike)

    def variants(self) -> dict:
        if self._variants is not None:
            return self._variants
        ref, phi, keys = self.ref, self.t.phi, list(self.t.columns)
        out: dict[str, tuple[dict, str]] = {}
        for g in ref.groups():
            out[f"branch:{g}"] = (ref.evaluate(phi, keys, desc=ref.other_mode(g)), f"the other assembly mode of group {g}")
        if self.t.phi_unit.strip() in ("rad", ""):
            out["phi_unit"] = (ref.evaluate(phi * math.pi / 180, keys), "at your crank angles read as degrees: your "
                               "crank-angle column is in degrees though its header says rad")
        else:
            out["phi_unit"] = (ref.evaluate(phi * 180 / math.pi, keys), "at your crank angles read as radians: your "
                               f"crank-angle column is in radians though its header says {self.t.phi_unit}")
        terms: dict[str, tuple[dict, tuple[str, str, str]]] = {}
        if ref.epsilon != 0:
            e0 = ref.evaluate(phi, keys, epsilon=0.0)
            terms["constant_speed"] = ({k: self.base[k] - e0[k] for k in keys}, (
                f"linkgen's ε terms: a constant crank speed assumed though ε = {ref.epsilon:g} rad/s²",
                "linkgen's ε terms: the ε terms counted twice", "linkgen's ε terms: ε with its sign flipped"))
        if ref.omega != 0:
            w0 = ref.evaluate(phi, [k for k in keys if _omega_squared(k)], omega=0.0)
            terms["omega_squared"] = ({k: self.base[k] - w0[k] for k in w0}, (
                "linkgen's ω² terms (the centripetal and Coriolis accelerations, and their inertia forces): "
                "they are missing", "linkgen's ω² terms: counted twice", "linkgen's ω² terms: with their sign flipped"))
        plain = ref.without_gravity()
        if plain is not None:
            g0 = ref.evaluate(phi, [k for k in keys if k in ref.force_keys], desc=plain)
            terms["gravity"] = ({k: self.base[k] - g0[k] for k in g0}, (
                "the weights' share (linkgen's value less its value without gravity): gravity left out",
                "the weights' share: gravity counted twice", "the weights' share: gravity pointing the wrong way"))
        force_keys = [k for k in keys if k in ref.force_keys]
        for link in ref.inertias() if force_keys else ():
            i0 = ref.evaluate(phi, force_keys, desc=ref.without_inertia(link))
            terms[f"inertia:{link}"] = ({k: self.base[k] - i0[k] for k in i0}, (
                f"the inertia torque of link {link} (its moment of inertia about its centre of mass times its angular "
                "acceleration): it is left out", f"the inertia torque of link {link}: counted twice",
                f"the inertia torque of link {link}: with its sign flipped"))
        self._variants = {"variants": out, "terms": terms}
        return self._variants

    def shifted(self, key: str, delta: float) -> np.ndarray:
        if delta not in self._shifted:
            keys = list(self.t.columns)
            self._shifted[delta] = self.ref.evaluate(self.t.phi + delta, keys)
        return self._shifted[delta][key]

    def derivatives(self, key: str) -> tuple[np.ndarray, np.ndarray] | None:
        name, _ = split_header(key)
        parts = name.split(".")
        q = next((i for i, p in enumerate(parts) if p in _CHAIN), None)
        if q is None:
            return None
        by_name = {split_header(k)[0]: k for k in self.ref.kinematic_keys}
        first, second = _CHAIN[parts[q]]
        k1 = by_name.get(".".join(parts[:q] + [first] + parts[q + 1:]))
        if k1 is None:
            return None
        if second is not None:
            k2 = by_name.get(".".join(parts[:q] + [second] + parts[q + 1:]))
            return (self.base[k1], self.base[k2]) if k2 else None
        up = self.ref.evaluate(self.t.phi + SNAP_STEP, [k1])[k1]
        down = self.ref.evaluate(self.t.phi - SNAP_STEP, [k1])[k1]
        return self.base[k1], self.ref.omega * (up - down) / (2 * SNAP_STEP)

    def column(self, key: str, ok: np.ndarray):
        v = self.variants()
        sel = lambda x: np.asarray(x)[ok]  # noqa: E731
        variants = {label: (sel(cols[key]), words) for label, (cols, words) in v["variants"].items() if key in cols}
        terms = {label: (sel(cols[key]), words) for label, (cols, words) in v["terms"].items() if key in cols}
        der = self.derivatives(key)
        e = Evidence(sel(self.t.columns[key].values), sel(self.base[key]), self.scales[key], self.tol,
                     _is_angle(key), sel(self.t.phi), self.ref.omega, key, variants, terms,
                     None if der is None else (sel(der[0]), sel(der[1])),
                     lambda delta: sel(self.shifted(key, delta)), self._deltas)
        return diagnose(e)


def _stem(key: str) -> str:
    return split_header(key)[0].split(".")[0] + "."


def _omega_squared(key: str) -> bool:
    name, unit = split_header(key)
    return "acceleration" in name or unit in ("N", "N·m")


def _mujoco(ref: Reference, phi: np.ndarray, keys: list[str], progress) -> dict[str, dict[str, np.ndarray]]:
    from linkgen.referee.mujoco_routes import routes

    return routes(ref, phi, keys, progress)
