"""What a wrong column's difference from the closed form looks like: the usual mistakes of a
solver, each a model of the user's values built from linkgen's closed form and fitted to them.

- a factor: the user's values are k × linkgen's, k in FACTORS (a sign or on/by convention
  flipped, mm for m, degrees for radians), alone or on top of another model below;
- the other assembly mode of one Assur group over one arc of the sampled angles ("from some angle
  on"), the other mode computed by the closed form;
- a crank-angle column in degrees under a rad header (or the reverse);
- a crank-angle offset or time shift: user(φ) = linkgen(φ + δ), δ fitted (Gauss–Newton);
- a term missing, doubled or with its sign flipped: difference = c × term, c least squares near
  −1, +1 or −2, the term being linkgen's value less the value without it: the ε terms (a
  constant crank speed assumed where ε ≠ 0), the ω² terms (centripetal and Coriolis), gravity,
  one link's inertia torque (its moment of inertia about its centre of mass);
- numerical differentiation: difference = c × a higher derivative (central differences:
  (Δt²/6)·the derivative two orders up; forward or backward: (Δt/2)·the next one).

A model explains the difference when it leaves at most EXPLAINED of it and of the column's
scale (or less than the tolerance), judged in linkgen's units; it is the diagnosis when no other model explains it nearly as well (CLEAR).
Among several that explain, the one combining the fewest mistakes. Otherwise the column is
"unexplained", with the numbers. A column within the tolerance is never
diagnosed."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

# A model explains a difference when it leaves at most this fraction of the worst difference:
# a fitted model's own higher-order remainder (a finite difference's next term, ~(Δφ)² of its
# leading one for steps up to ~10°) stays well under it; a coincidence rarely does.
EXPLAINED = 0.05
# The diagnosis must leave at least this many times less than the next model that also explains.
CLEAR = 4.0
# A fitted coefficient counts as −1, +1 or −2 within this fraction (the term missing, doubled,
# sign flipped); further off, the column has some other error in that term.
COEFFICIENT = 0.03
# Steps of numerical differentiation the model accepts, as crank angle [rad]: up to 30°.
MAX_STEP = math.pi / 6
# A change over 2e-6 rad of crank larger than this fraction of the scale is a jump, not a slope
# (smooth quantities change by ~1e-5 of their scale there).
JUMP = 1e-3
# Unit factors and sign flips: the user's values are k × linkgen's.
FACTORS = {-1.0: "sign", 1000.0: "unit", 1e-3: "unit", 180 / math.pi: "unit", math.pi / 180: "unit"}


@dataclass(frozen=True)
class Diagnosis:
    """What the difference looks like: ``kind`` (``sign``, ``unit``, ``branch``, ``phi_unit``,
    ``offset``, ``constant_speed``, ``omega_squared``, ``gravity``, ``inertia``, ``finite_difference``,
    combinations joined by ``+``, or ``unexplained``), the evidence in words, the fraction of the
    worst difference the model leaves (``residual``) and its fitted parameters."""

    kind: str
    text: str
    residual: float
    parameters: Mapping[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "text": self.text, "residual": self.residual, "parameters": dict(self.parameters)}


@dataclass(frozen=True)
class Evidence:
    """What the diagnosis of one column works with, all (m,) over the compared samples: the
    user's values ``u``, linkgen's ``r``, the scale, the tolerance, whether the column is an angle
    (differences taken modulo 2π), the crank angles [rad] and speed; ``variants`` label → (values,
    words) from other models of the mechanism; ``terms`` label → (term, words for c = −1, +1,
    −2); ``derivatives``: (the next time derivative, the one after) or None; ``shifted``: δ →
    linkgen's values at φ + δ, or None."""

    u: np.ndarray
    r: np.ndarray
    scale: float
    tolerance: float
    angle: bool
    phi: np.ndarray
    omega: float
    quantity: str
    variants: Mapping[str, tuple[np.ndarray, str]]
    terms: Mapping[str, tuple[np.ndarray, tuple[str, str, str]]]
    derivatives: tuple[np.ndarray, np.ndarray] | None
    shifted: Callable[[float], np.ndarray] | None
    # offsets fitted to earlier columns of the same table (tried first: one evaluation each)
    deltas: list = field(default_factory=list, compare=False)


def difference(e: Evidence, pred: np.ndarray, k: float = 1.0) -> np.ndarray:
    """(u − pred)/k in linkgen's units (pred = k × a model of linkgen's values), for an angle
    modulo 2π; NaN in pred counts as far off. Judged in linkgen's units, a model in degrees is
    held to the same closeness as one in radians."""
    d = (e.u - pred) / k
    if e.angle:
        d = (d + math.pi) % (2 * math.pi) - math.pi
    return np.where(np.isfinite(d), d, np.inf)


def worst(e: Evidence, pred: np.ndarray, k: float = 1.0) -> float:
    return float(np.max(np.abs(difference(e, pred, k)))) / e.scale


def _deg(x: float) -> str:
    return f"{math.degrees(x):.4g}°"


def _factor_words(k: float, quantity: str) -> str:
    if k == -1.0:
        if ".force" in quantity or "normal_force" in quantity or ".moment" in quantity:
            return ("−1 × linkgen's: the on/by convention flipped (linkgen gives what the pair's second link exerts "
                    "on its first, or the guide on the slider)")
        if "torque" in quantity:
            return "−1 × linkgen's: the sign flipped (linkgen's balancing torque is the one the drive applies to the crank)"
        return "−1 × linkgen's: the sign flipped"
    if abs(k - 180 / math.pi) < 1e-9:
        return "(180/π) × linkgen's: degrees where the header says radians"
    if abs(k - math.pi / 180) < 1e-12:
        return "(π/180) × linkgen's: radians where the header says degrees"
    unit = quantity[quantity.rfind("[") + 1:-1] if quantity.endswith("]") else "m"
    small = unit.replace("m", "mm", 1) if not unit.startswith("m") else "mm" + unit[1:]
    given, header = (small, unit) if k > 1 else (unit, small)
    return f"{k:g} × linkgen's: {given} where the header says {header}"


def _applies(k: float, key: str) -> bool:
    """Whether the factor ``k`` can be a unit mistake in a column of this header: ×1000 and
    ×0.001 where the unit has a length (mm for m, N·mm for N·m), degrees where it has an angle."""
    unit = key[key.rfind("[") + 1:-1] if key.endswith("]") else ""
    if k in (1000.0, 1e-3):  # a length to the first power: mm for m is ×1000 there only
        plain = unit.replace("rad", "")
        return "m" in plain and "m²" not in plain and "m³" not in plain
    if k != -1.0:
        return "rad" in unit
    return True


def _arc(e: Evidence, other: np.ndarray, k: float) -> np.ndarray | None:
    """The samples (a mask) where the user follows ``other`` rather than linkgen's values: one
    arc of the sampled order ("from some angle on"), or None when it is not one arc."""
    near_r = np.abs(difference(e, k * e.r, k))
    near_o = np.abs(difference(e, k * other, k))
    gap = e.r - other
    if e.angle:
        gap = (gap + math.pi) % (2 * math.pi) - math.pi
    apart = np.abs(gap) > 10 * e.tolerance * e.scale  # False where ``other`` is NaN
    on_other = apart & (near_o < near_r)
    on_ours = apart & ~on_other
    if np.count_nonzero(on_other) < 2:
        return None
    labels = [bool(x) for x, a in zip(on_other, apart) if a]
    changes = sum(a != b for a, b in zip(labels, labels[1:]))
    if changes > 2 or (changes == 2 and labels[0] != labels[-1] and np.any(on_ours)):
        return None
    return on_other


def _candidates(e: Evidence):
    """(residual as a fraction of the scale, kind, words, parameters) of every model that applies."""
    bases = [("", e.r, "", {})]
    for label, (values, words) in e.variants.items():
        if label.startswith("branch:"):
            bases.append((label, values, words, {}))
        else:
            yield worst(e, values), label, f"your values are linkgen's {words}", {}
    for k in [1.0, *(k for k in FACTORS if _applies(k, e.quantity))]:
        for label, other, words, params in bases:
            if label == "" and k == 1.0:
                continue
            if label == "":
                yield worst(e, k * e.r, k), FACTORS[k], f"your values are {_factor_words(k, e.quantity)}", {"factor": k}
                continue
            mask = _arc(e, other, k)
            if mask is None:
                continue
            pred = k * np.where(mask, other, e.r)
            idx = np.flatnonzero(mask)
            where = (f"from φ = {_deg(e.phi[idx[0]])} on" if idx[-1] == len(mask) - 1 and idx[0] > 0 else
                     "over the whole range" if len(idx) == len(mask) else
                     f"from φ = {_deg(e.phi[idx[0]])} to {_deg(e.phi[idx[-1]])}")
            text = f"{where} your values follow {words}"
            kind = "branch"
            if k != 1.0:
                text = f"your values are {_factor_words(k, e.quantity)}, and {text}"
                kind = f"{FACTORS[k]}+branch"
            yield worst(e, pred, k), kind, text, {"factor": k, "from_phi": float(e.phi[idx[0]]),
                                                  "to_phi": float(e.phi[idx[-1]])}
    d = np.nan_to_num(difference(e, e.r), posinf=0.0)
    for label, (term, words) in e.terms.items():
        tt = float(term @ term)
        if not np.all(np.isfinite(term)) or not np.max(np.abs(term)) > 0.1 * np.max(np.abs(d)):
            continue  # a term much smaller than the difference cannot be what is missing
        c = float(d @ term) / tt
        for c0, w in zip((-1.0, 1.0, -2.0), words):
            if abs(c / c0 - 1) <= COEFFICIENT:
                kind, _, link = label.partition(":")
                yield (worst(e, e.r + c * term), kind, f"the difference is {c:.3g} × {w}",
                       {"coefficient": c} | ({"link": link} if link else {}))
    yield from _finite_differences(e, d)
    if e.shifted is not None:
        yield from _offset(e)


def _finite_differences(e: Evidence, d: np.ndarray):
    if e.derivatives is None or e.omega == 0:
        return
    for order, term in ((1, e.derivatives[0]), (2, e.derivatives[1])):
        tt = float(term @ term)
        if not np.all(np.isfinite(term)) or not tt > 0:
            continue
        c = float(d @ term) / tt
        dt = 2 * abs(c) if order == 1 else math.sqrt(6 * abs(c))
        if (order == 2 and c <= 0) or not 0 < dt * abs(e.omega) <= MAX_STEP:
            continue
        how = (("forward" if c > 0 else "backward") + f" differences (Δt/2 × the next derivative)" if order == 1 else
               "central differences (Δt²/6 × the derivative two orders up; a second difference of positions: "
               f"Δt ≈ {dt * math.sqrt(2):.3g} s)")
        yield (worst(e, e.r + c * term), "finite_difference",
               f"the difference is numerical differentiation by {how}, step Δt ≈ {dt:.3g} s "
               f"(Δφ ≈ {_deg(dt * abs(e.omega))})", {"step_s": dt, "order": order})


def _offset(e: Evidence):
    """user(φ) = linkgen(φ + δ): δ by Newton iterations on the closed form's own values at φ + δ
    (slopes by central differences of step 1e-6 rad); tried only where the first, linear step
    explains the difference to half. Samples where φ + δ leaves the drive range are not judged
    (at most a tenth of them)."""
    h = 1e-6
    e0 = worst(e, e.r)
    for delta in e.deltas:  # a table shifted as a whole: the offset of an earlier column
        r0 = e.shifted(delta)
        ok = np.isfinite(r0)
        if ok.sum() >= 0.9 * len(ok):
            resid = float(np.max(np.abs(difference(e, r0)[ok]))) / e.scale
            if resid <= max(EXPLAINED * min(e0, 1.0), e.tolerance):
                yield resid, "offset", _offset_words(e, delta), {"delta_rad": delta}
                return

    def rate(at: float) -> np.ndarray:
        """d/dφ of linkgen's values at φ + at (an angle's across ±π); NaN across a jump (a load's
        stroke that starts or ends there), which no slope describes."""
        step = e.shifted(at + h) - e.shifted(at - h)
        if e.angle:
            step = (step + math.pi) % (2 * math.pi) - math.pi
        return np.where(np.abs(step) < JUMP * e.scale, step / (2 * h), np.nan)

    slope = rate(0.0)
    ok = np.isfinite(slope) & np.isfinite(e.r)
    ss = float(slope[ok] @ slope[ok])
    if not ok.any() or ss == 0:
        return
    d = np.nan_to_num(difference(e, e.r), posinf=0.0)[ok]
    delta = float(d @ slope[ok]) / ss
    if np.max(np.abs(d - delta * slope[ok])) > 0.5 * np.max(np.abs(d)):
        return
    for _ in range(8):
        r0 = e.shifted(delta)
        slope = rate(delta)
        ok = np.isfinite(r0) & np.isfinite(slope)
        ss = float(slope[ok] @ slope[ok])
        if ok.sum() < 0.9 * len(ok) or ss == 0:
            return
        step = float(difference(e, r0)[ok] @ slope[ok]) / ss
        delta += float(np.clip(step, -0.1, 0.1))
        if abs(step) < 1e-13:
            break
    r0 = e.shifted(delta)
    ok = np.isfinite(r0)
    if not 0 < abs(delta) <= math.pi or ok.sum() < 0.9 * len(ok):
        return
    resid = float(np.max(np.abs(difference(e, r0)[ok]))) / e.scale
    if resid <= max(EXPLAINED * min(e0, 1.0), e.tolerance):
        e.deltas.append(delta)
    yield resid, "offset", _offset_words(e, delta), {"delta_rad": delta}


def _offset_words(e: Evidence, delta: float) -> str:
    shift = f", or a time shift of {delta / e.omega:.4g} s at ω = {e.omega:.4g} rad/s" if e.omega else ""
    return f"your values are linkgen's at φ + δ with δ = {_deg(delta)}: a crank-angle offset{shift}"


def diagnose(e: Evidence) -> Diagnosis | None:
    """The diagnosis of one column, None when it agrees (worst difference within the tolerance)."""
    e0 = worst(e, e.r)
    if e0 <= e.tolerance:
        return None
    found = sorted(_candidates(e), key=lambda c: c[0])
    # a model's residual is in linkgen's units (a unit factor's divided out), so it is held to a
    # fraction of the difference or of the scale, whichever is smaller
    good = max(EXPLAINED * min(e0, 1.0), e.tolerance)
    # among the models that explain, the simplest (fewest mistakes combined) first: a centred
    # slider-crank's other mode is exactly −1 × its rod's angular velocity, one mistake, not two
    explaining = sorted((c for c in found if c[0] <= good), key=lambda c: (c[1].count("+"), c[0]))
    if explaining:
        best = explaining[0]
        rival = next((c for c in explaining[1:] if c[1].count("+") == best[1].count("+")
                      and (c[1] != best[1] or c[2] != best[2])), None)
        if rival is None or rival[0] >= CLEAR * best[0]:
            return Diagnosis(best[1], best[2], best[0] / e0, best[3])
        return Diagnosis("unexplained", f"unexplained: two models fit alike — {best[2]} (leaves "
                         f"{best[0] / e0:.1%}) and {rival[2]} (leaves {rival[0] / e0:.1%})", best[0] / e0)
    close = "; ".join(f"{c[1]} leaves {min(c[0] / e0, 9.99):.0%}" for c in found[:3])
    return Diagnosis("unexplained", f"unexplained: the difference fits none of the usual mistakes (closest: "
                     f"{close or 'none applies'})", found[0][0] / e0 if found else 1.0)
