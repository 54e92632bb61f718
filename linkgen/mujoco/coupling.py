"""The loop-free export for robot learning (``linkgen build --loops coupling``): which joints the
model keeps, what each of them is as a function of the crank angle, and the quartic that stands
for it (``coupling_mjcf`` writes the file).

The tree. Every link keeps its body and its mass. The drive pair comes first; then every link
that a pair joins to the ground hangs on the ground by that pair (the outputs: a rocker's hinge
at its pivot, a slider's slide along a fixed guide); the other links (couplers, blocks, rods)
hang on a neighbour already placed, by one of their pairs (Kruskal's order, the description's
order of pairs). The pairs left out are the loop closures; instead of closing them, every joint
of the tree but the drive is tied by MuJoCo's joint equality to the crank or to another coupled
joint (a chain, ``_fits``), its ``polycoef`` the minimax quartic of the joint's coordinate over
the drive range (``families.planar.polyfit``). So the outputs (and the couplers, drawn and
carrying their inertia and weight) follow the closed form to the stated error, and nothing in
the model is a loop. Each joint coupled to the crank alone, the seven-link missed the bound over
its range (its rod by 3.1e-3 of its travel, the slotted link by 1.1e-3); along the chain every
joint holds 1.7e-4.

Coordinates, as the written joints read them: the crank's hinge reads the crank angle φ [rad]
(its ``ref`` is φ at the range's middle, where the bodies are placed); a hinge to the ground reads
its link's angle [rad] (``analyze``'s ``links.NAME.angle``, wrapped to (−π, π] at the middle); a
hinge between two moving links the child's angle less the parent's; a slide the slider's
displacement [m] along its guide line from the guide's base point (both as ``analyze`` gives them).

The bound: every coupled coordinate must keep its largest error within TOLERANCE of its travel
over the range (max − min). Where one does not, there is no model (``CouplingError`` with the
figure and the widest range about the middle that holds): a quartic cannot follow a periodic
function over a crank's full turn, and a model that silently misses by 10 % misleads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from typing import TYPE_CHECKING

import numpy as np

from linkgen.errors import CouplingError, StructureError
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.geometry import guide_shapes, link_shapes
from linkgen.families.planar.polyfit import MIDDLE, PolyFit, fit, grid, minimax
from linkgen.families.planar.structure import Pair, pairs_of
from linkgen.mujoco.tree import grow_tree

if TYPE_CHECKING:
    from linkgen.mujoco.coupling_torque import TorqueError

# The bound (issue 24, item 3): the largest position error of a coupled coordinate over
# the drive range, as a fraction of that coordinate's travel over the range.
TOLERANCE = 1e-3
# A range that holds is searched about the middle of the drive range to this fraction of it.
RANGE_STEPS = 12


@dataclass(frozen=True)
class CoupledJoint:
    """One joint of the loop-free tree: its pair's name, ``kind`` "hinge" or "slide", the parent
    and child links, ``output`` (hangs on the ground), ``ref`` (its value at the reference crank
    angle [rad or m]), the joint it is coupled to (``argument``: the crank's, or another coupled
    joint's), the fit of its value less ``ref`` in powers of the argument's less its ``ref``, its
    largest error over the range as the chain of couplings gives it, and the crank angle ``at``
    [rad] where that error is largest."""

    name: str
    kind: str
    parent: str
    child: str
    output: bool
    ref: float
    argument: str
    fit: PolyFit
    at: float

    @property
    def unit(self) -> str:
        return "rad" if self.kind == "hinge" else "m"

    def describe(self) -> str:
        """``JOINT (rocker angle): within 2.3e-05 rad, 2.7e-05 of its 0.86 rad travel``."""
        what = ("its link's angle" if self.kind == "hinge" and self.output else
                "relative angle" if self.kind == "hinge" else "slide")
        return (f"{self.name} ({self.child}, {what}, coupled to {self.argument}): within {self.fit.max_error:.2g} {self.unit}, "
                f"{self.fit.relative:.2g} of its {self.fit.travel:.3g} {self.unit} travel")


@dataclass(frozen=True)
class Coupling:
    """The loop-free tree of a mechanism over its drive range: the drive joint, φ_ref [rad] (the
    middle of ``drive_range``, where the bodies are placed), the tree (parent, child, pair), the
    coupled joints in tree order, the pairs left out (the loop closures) and the link poses at
    φ_ref {link: (origin (2,) [m], angle [rad])}; ``torque``: how near the written model's crank
    torque is to the closed form's (None where it is not known: no closed form)."""

    model: str
    drive: str
    phi_ref: float
    drive_range: tuple[float, float]
    tree: tuple[tuple[str, str, Pair], ...]
    joints: tuple[CoupledJoint, ...]
    left_out: tuple[str, ...]
    pose: dict
    timeconst: float | None = None  # the couplings' time constant τ [s] as written, None until written
    lags: dict | None = None  # each joint's lag [rad or m] at the drive's ω and τ (``coupling_torque.lag``)
    torque: TorqueError | None = None  # the written model's crank torque against the closed form (``coupling_torque``)

    @property
    def outputs(self) -> tuple[CoupledJoint, ...]:
        return tuple(j for j in self.joints if j.output)

    @property
    def worst(self) -> CoupledJoint:
        """The coupled joint with the largest error relative to its travel."""
        return max(self.joints, key=lambda j: j.fit.relative)

    def chain(self, phi) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Every joint's value [rad or m], d/dφ and d²/dφ² (n,) at crank angles φ (n,) [rad] as
        the couplings give them (each quartic of its argument's coupled value, chain rule)."""
        phi = np.asarray(phi, dtype=float)
        out = {self.drive: (phi, np.ones_like(phi), np.zeros_like(phi))}
        refs = {self.drive: self.phi_ref} | {j.name: j.ref for j in self.joints}
        P = np.polynomial.polynomial
        while len(out) <= len(self.joints):
            for j in self.joints:
                if j.name in out or j.argument not in out:
                    continue
                x, dx, ddx = out[j.argument]
                u, c = x - refs[j.argument], np.array(j.fit.coef)
                d1, d2 = P.polyval(u, P.polyder(c)), P.polyval(u, P.polyder(c, 2))
                out[j.name] = (j.ref + P.polyval(u, c), d1 * dx, d2 * dx * dx + d1 * ddx)
        return out

    def line(self) -> str:
        """What ``linkgen build --loops coupling`` prints: each output's largest error, the worst
        of every coupled joint, the crank torque's error; one line each."""
        lo, hi = (math.degrees(a) for a in self.drive_range)
        lines = [f"{self.model}: loops replaced by chained quartic couplings to the crank over {lo:.4g}..{hi:.4g}°"]
        lines += [f"    output {j.describe()}" for j in self.outputs]
        lines.append(f"    worst of all {len(self.joints)} coupled joints: {self.worst.describe()}")
        if self.lags and self.torque is not None:
            worst = max(self.lags, key=self.lags.get)
            unit = next(j.unit for j in self.joints if j.name == worst)
            lines.append(f"    MuJoCo's couplings lag by up to {self.lags[worst]:.2g} {unit} ({worst}) at {self.torque.omega:g} "
                         f"rad/s with τ = {self.timeconst:g} s (τ²·|p″|·ẋ²: it grows with ω² and τ²)")
        if self.torque is not None:
            lines.append(f"    {self.torque.text()}")
        return "\n".join(lines)


def coupled_tree(mech: Mechanism) -> tuple[tuple[tuple[str, str, Pair], ...], tuple[Pair, ...]]:
    """(parent, child, pair) of the loop-free tree, breadth first from the ground, and the pairs
    left out (module docstring)."""
    pairs = pairs_of(mech)
    drive = next(p for p in pairs if p.kind == "R" and p.name == mech.drive.joint)
    grounded = [p for p in pairs if p is not drive and GROUND in p.links]
    ordered = [drive] + grounded + [p for p in pairs if p is not drive and p not in grounded]
    return grow_tree(mech.link_names, ordered)


def link_poses(source: Mechanism | Assembly, phi: np.ndarray) -> tuple[dict, dict]:
    """Every link's frame origin {link: (n, 2)} [m] and angle {link: (n,)} [rad] at crank angles
    φ (n,): the closed form for an Assembly, the numeric pose (``pose.state``) otherwise."""
    if isinstance(source, Assembly):
        from linkgen.families.planar.kinematics import solve

        kin = solve(source, phi, on_singular="mark")  # positions only: a dead centre's rates do not enter
        names = source.mechanism.link_names
        return ({n: np.asarray(kin.links[n].origin.p) for n in names},
                {n: np.broadcast_to(kin.links[n].angle.v, phi.shape).astype(float) for n in names})
    from linkgen.families.planar.pose import state

    st = state(source, phi)
    return st.origin, st.angle


def _world(origin: np.ndarray, angle: np.ndarray, local) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return origin + np.column_stack([c * local[0] - s * local[1], s * local[0] + c * local[1]])


def coordinate(mech: Mechanism, pair: Pair, parent: str, child: str, origin: dict, angle: dict) -> np.ndarray:
    """The tree joint's value (n,) over the samples (module docstring), an angle unwrapped."""
    if pair.kind == "R":
        return np.unwrap(angle[child] - angle[parent])
    g = guide_shapes(mech, link_shapes(mech))[pair.name]
    th = angle[g.guide] + g.alpha
    d = _world(origin[g.slider], angle[g.slider], g.point) - _world(origin[g.guide], angle[g.guide], g.base)
    return d[:, 0] * np.cos(th) + d[:, 1] * np.sin(th)


def _fits(source, mech, tree, start: float, stop: float):
    """φ_ref, the coupled joints (in tree order) and the poses at φ_ref for the drive range
    [start, stop].

    The chain: a joint may be coupled to the crank or to any joint already coupled, whichever
    gives the least error relative to its travel; the joint coupled next is the one that can be
    coupled best (each pair of joint and argument is fitted once). A link of a group that an
    output drives follows that output more nearly as a quartic than the crank (the seven-link's
    rod, coupler and lever follow the slotted link 3), and fitting against the argument's
    coupled, not its exact, value makes each stated error that of the whole chain."""
    phi = grid(start, stop)
    origin, angle = link_poses(source, phi)
    coupled = {tree[0][2].name: (phi, float(phi[MIDDLE]))}  # joint → (its value as the couplings give it (n,), ref)
    pending = {}
    for parent, child, pair in tree[1:]:
        y = coordinate(mech, pair, parent, child, origin, angle)
        ref = y[MIDDLE] if pair.kind == "P" else math.remainder(y[MIDDLE], 2 * math.pi)
        pending[pair.name] = (y - (y[MIDDLE] - ref), float(ref))  # the value the joint reads (turns taken off)
    fits, chosen = {}, {}
    while pending:
        for name, (y, ref) in pending.items():
            for arg, (x, x0) in coupled.items():
                if (name, arg) not in fits:
                    fits[name, arg] = fit(x, y, x0, ref, minimax)
        name, arg = min(((n, a) for n in pending for a in coupled), key=lambda k: fits[k].relative)
        f, (x, x0), (y, ref) = fits[name, arg], coupled[arg], pending.pop(name)
        coupled[name] = (ref + f(x - x0), ref)
        chosen[name] = (arg, f, ref)
    out = []
    for parent, child, pair in tree[1:]:
        arg, f, ref = chosen[pair.name]
        out.append(CoupledJoint(pair.name, "hinge" if pair.kind == "R" else "slide", parent, child,
                                parent == GROUND, ref, arg, f, float(phi[f.at])))
    pose = {n: (origin[n][MIDDLE].copy(), float(angle[n][MIDDLE])) for n in mech.link_names}
    return float(phi[MIDDLE]), tuple(out), pose


def couple(source: Mechanism | Assembly) -> Coupling:
    """The loop-free tree and its fits over the drive range.

    Raises:
        CouplingError: some coupled coordinate misses TOLERANCE of its travel (names it, the
            figure, and the widest range about the middle where every one holds).
        StructureError: the mechanism has cams or gears (not exported loop-free).
    """
    mech = source if isinstance(source, Mechanism) else source.mechanism
    if mech.cams or mech.gears:
        what = "a cam" if mech.cams else "gears"
        raise StructureError(f"{mech.name}: a linkage with {what} has no loop-free export (--loops coupling is for "
                             f"linkages of revolute and prismatic pairs); build it with its loops closed")
    tree, left = coupled_tree(mech)
    if not left:
        raise CouplingError(f"{mech.name}: it has no loops to replace (the crank is its only moving link); build it without --loops coupling, which writes it loop-free")
    d = mech.drive
    phi_ref, joints, pose = _fits(source, mech, tree, d.start, d.stop)
    worst = max(joints, key=lambda j: j.fit.relative, default=None)
    if worst is not None and worst.fit.relative > TOLERANCE:
        raise CouplingError(_refusal(source, mech, tree, worst))
    return Coupling(mech.name, d.joint, phi_ref, (d.start, d.stop), tree, joints, tuple(p.name for p in left), pose)


def _holds(source, mech, tree, start: float, stop: float) -> bool:
    return all(j.fit.relative <= TOLERANCE for j in _fits(source, mech, tree, start, stop)[1])


def holding_range(source, mech, tree) -> tuple[float, float] | None:
    """The widest range [rad] about the drive range's middle (to 1/2^RANGE_STEPS of its
    half-width) on which every coupled coordinate holds TOLERANCE, or None."""
    d = mech.drive
    mid, half = 0.5 * (d.start + d.stop), 0.5 * (d.stop - d.start)
    lo, hi = 0.0, 1.0  # fractions of the half-width: lo holds, hi does not
    for _ in range(RANGE_STEPS):
        f = 0.5 * (lo + hi)
        if _holds(source, mech, tree, mid - f * half, mid + f * half):
            lo = f
        else:
            hi = f
    return (mid - lo * half, mid + lo * half) if lo > 0.0 else None


def _refusal(source, mech, tree, worst: CoupledJoint) -> str:
    d = mech.drive
    span = f"{math.degrees(d.start):.4g}..{math.degrees(d.stop):.4g}°"
    text = (f"{mech.name}: no chain of quartic couplings to the crank holds {TOLERANCE:g} of the travel over the drive range "
            f"{span}: {worst.describe()} (worst at φ = {math.degrees(worst.at):.4g}°), "
            f"{worst.fit.relative / TOLERANCE:.3g}× the bound")
    found = holding_range(source, mech, tree)
    if found is None:
        return text + "; no range about its middle holds; build it with its loops closed (--loops closed)"
    lo, hi = (math.degrees(a) for a in found)
    return (text + f"; it holds over {lo:.4g}..{hi:.4g}° ([drive] range = [\"{lo:.4g}deg\", \"{hi:.4g}deg\"]), "
            "or build it with its loops closed (--loops closed)")


__all__ = ["CoupledJoint", "Coupling", "TOLERANCE", "coordinate", "coupled_tree", "couple", "holding_range",
           "link_poses"]
