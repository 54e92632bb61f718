"""Assembly modes from the whole sketch and structure independent of how a mechanism is written:
equivalent descriptions of one physical mechanism give the same physics."""

import copy
import itertools
import math

import numpy as np
import pytest

from conftest import ROOT
from linkgen import assemble, decompose, from_dict, solve
from linkgen.families.planar.kinetostatics import forces

G = 9.81
# Equivalent descriptions go through different arithmetic (other local frames, guide lines through
# other points, other pair orientations): rounding of ~1e2 operations on values of order one,
# ~1e-14 of each quantity's peak, amplified at most 1e4-fold near a dead centre (denominators stay
# above linkgen.families.planar.kinematics.SINGULAR_TOL = 1e-4). A wrong branch differs by order one.
EQUIV_TOL = 1e-10
# The hand solution against linkgen: positions by the formula below to rounding (~1e-16 m);
# the static torque as a central difference of the potential energy with step H: truncation
# H²/6·|V‴| ≈ 1e-13 N·m, rounding eps·|V|/H ≈ 1e-10 N·m, so 1e-8 N·m.
HAND_ANGLE_TOL = 1e-12
H = 1e-6
HAND_TORQUE_TOL = 1e-8

# A coulisse (RPR group) whose two links each carry one point: the block pinned to the crank at A
# slides in a slot of the rocker, which is pinned to ground at C. The slot runs at SLOT_ANGLE to the
# rocker's x axis (the world x axis in the sketch), at OFFSET to the left of C.
SLOT_ANGLE, OFFSET, ALONG = math.radians(60.0), 0.05, 0.25
C = np.array([0.0, -0.3])
_U = np.array([math.cos(SLOT_ANGLE), math.sin(SLOT_ANGLE)])
A = C + ALONG * _U + OFFSET * np.array([-_U[1], _U[0]])
CRANK = float(np.hypot(*A))
ROCKER_COM, ROCKER_MASS, CRANK_COM, CRANK_MASS, BLOCK_MASS = (0.1, 0.04), 1.0, (0.05, 0.0), 0.3, 0.5


def coulisse(reversed_slot: bool = False) -> dict:
    """The coulisse; ``reversed_slot`` describes the same slot by the opposite direction (angle
    + 180°), which flips its left normal and so the offset's sign."""
    return {
        "mechanism": {"name": "coulisse", "gravity": [0.0, -G]},
        "points": {"O": [0.0, 0.0], "C": C.tolist(), "A": A.tolist()},
        "links": {
            "ground": {"points": ["O", "C"]},
            "crank": {"points": ["O", "A"], "length": CRANK,
                      "inertial": {"mass": CRANK_MASS, "com": list(CRANK_COM), "inertia": 1e-3}},
            "block": {"points": ["A"], "inertial": {"mass": BLOCK_MASS, "com": [0.0, 0.0], "inertia": 2e-3}},
            "rocker": {"points": ["C"], "inertial": {"mass": ROCKER_MASS, "com": list(ROCKER_COM), "inertia": 0.01}},
        },
        "prismatic": {"slot": {"slider": "block", "guide": "rocker", "point": "A", "through": "C",
                               "angle": SLOT_ANGLE + (math.pi if reversed_slot else 0.0),
                               "offset": -OFFSET if reversed_slot else OFFSET}},
        "drive": {"joint": "O", "omega": 1.0},
    }


def _rocker_by_hand(phi: np.ndarray) -> np.ndarray:
    """The rocker's angle [rad]: A - C = s·u + OFFSET·n with u the slot's world direction
    ψ + SLOT_ANGLE, so |A - C|·sin(β - ψ - SLOT_ANGLE) = OFFSET with β the direction of A - C,
    on the sketch's side s > 0."""
    a = CRANK * np.stack((np.cos(phi), np.sin(phi)), axis=1)
    d = a - C
    beta, dist = np.arctan2(d[:, 1], d[:, 0]), np.hypot(d[:, 0], d[:, 1])
    return beta - np.arcsin(OFFSET / dist) - SLOT_ANGLE


def _potential_by_hand(phi: np.ndarray) -> np.ndarray:
    """Σ m·g·y of the centres of mass [J]."""
    psi = _rocker_by_hand(phi)
    y_crank = CRANK_COM[0] * np.sin(phi) + CRANK_COM[1] * np.cos(phi)
    y_block = CRANK * np.sin(phi)
    y_rocker = C[1] + ROCKER_COM[0] * np.sin(psi) + ROCKER_COM[1] * np.cos(psi)
    return G * (CRANK_MASS * y_crank + BLOCK_MASS * y_block + ROCKER_MASS * y_rocker)


@pytest.mark.parametrize("reversed_slot", [False, True], ids=["slot", "reversed_slot"])
def test_one_point_coulisse_takes_the_sketched_mode(reversed_slot):
    asm = assemble(from_dict(coulisse(reversed_slot)))
    phi0 = math.atan2(A[1], A[0])
    phi = phi0 + np.radians(np.arange(0.0, 360.0, 15.0))
    kin = solve(asm, phi)
    # at the sketch a one-point link's angle is 0: the rocker must stay there, not turn 150° away
    assert abs(kin.links["rocker"].angle.v[0]) < HAND_ANGLE_TOL
    wrapped = np.angle(np.exp(1j * (kin.links["rocker"].angle.v - _rocker_by_hand(phi))))
    assert np.abs(wrapped).max() < HAND_ANGLE_TOL
    # static balancing torque = dV/dφ (virtual work of gravity), by hand
    torque = forces(asm, phi, 0.0, 0.0).balancing_torque
    fd = (_potential_by_hand(phi + H) - _potential_by_hand(phi - H)) / (2 * H)
    assert np.abs(torque - fd).max() < HAND_TORQUE_TOL


def _physics(data: dict, phi: np.ndarray, omega: float = 3.0, epsilon: float = -2.0) -> dict:
    """Everything a description's wording must not change: point positions, velocities and
    accelerations, the balancing torque, and the force and moment each link receives from
    each other link at each pair, keyed by (receiving link, giving link, point or pair)."""
    mech = from_dict(data)
    asm = assemble(mech)
    kin = solve(asm, phi)
    mo = kin.motion(omega, epsilon)
    f = forces(asm, phi, omega, epsilon)
    out = {"torque": f.balancing_torque}
    for name, (p, v, a) in mo.points.items():
        out[f"point {name}"] = np.concatenate([p, v, a], axis=1)
    for j in mech.revolutes:
        first, second = j.links
        out[f"{first}<-{second}@{j.point}"] = f.reactions[j.name]
        out[f"{second}<-{first}@{j.point}"] = -f.reactions[j.name]
    for pj in mech.prismatics:
        g = asm.guides[pj.name]
        u = kin.links[pj.guide].direction(g.alpha).p
        normal = f.normal_force[pj.name][:, None] * np.stack((-u[:, 1], u[:, 0]), axis=1)
        # the slot's couple is taken about the slider's point: the same point in both wordings
        out[f"{pj.slider}<-{pj.guide}"] = np.concatenate([normal, f.moment[pj.name][:, None]], axis=1)
        out[f"{pj.guide}<-{pj.slider}"] = -out[f"{pj.slider}<-{pj.guide}"]
    return out


def _assert_same(a: dict, b: dict) -> None:
    assert set(a) == set(b) - {"point Q"}  # Q: an extra point on ground that one wording names
    for key in a:
        peak = max(np.abs(a[key]).max(), 1e-300)
        assert np.abs(a[key] - b[key]).max() <= EQUIV_TOL * peak, key


def _reordered(data: dict) -> dict:
    """The same description with its link and point tables and each link's points reversed."""
    out = copy.deepcopy(data)
    out["links"] = dict(reversed(list(out["links"].items())))
    out["points"] = dict(reversed(list(out["points"].items())))
    for name, link in out["links"].items():
        if name != "ground" and "length" not in link and "inertial" not in link:
            link["points"] = list(reversed(link["points"]))
    return out


def test_coulisse_descriptions_give_the_same_physics():
    phi = math.atan2(A[1], A[0]) + np.radians(np.arange(0.0, 360.0, 7.5))
    ref = _physics(coulisse(), phi)
    _assert_same(ref, _physics(coulisse(reversed_slot=True), phi))
    _assert_same(ref, _physics(_reordered(coulisse(reversed_slot=True)), phi))


def _slider_crank(variant: str) -> dict:
    """The offset slider-crank of models/slider_crank_offset.toml (no masses: default bars)."""
    import tomllib

    data = tomllib.loads((ROOT / "models" / "slider_crank_offset.toml").read_text())
    data["mechanism"]["gravity"] = [0.0, -G]
    if variant == "other_point":  # the same line y = 0.005 m through another point of ground
        data["points"]["Q"] = [0.07, 0.005]
        data["links"]["ground"]["points"] = ["O", "Q"]
        data["prismatic"]["slider"] |= {"through": "Q", "offset": 0.0}
    elif variant == "reversed":  # the same line, direction reversed: the left normal flips
        data["prismatic"]["slider"] |= {"angle": "180deg", "offset": -0.005}
    elif variant == "rod_points_reversed":  # the rod's frame from B towards A
        data["links"]["rod"]["points"] = ["B", "A"]
    return data


def test_slider_crank_descriptions_give_the_same_physics():
    phi = np.radians(np.arange(0.5, 360.0, 5.0))
    ref = _physics(_slider_crank(""), phi)
    for variant in ("other_point", "reversed", "rod_points_reversed"):
        _assert_same(ref, _physics(_slider_crank(variant), phi))
    _assert_same(ref, _physics(_reordered(_slider_crank("reversed")), phi))


# A six-bar whose point B is a compound hinge of three links: the four-bar O-A-B-C, and a second
# RRR group (link4 from B to D, link5 from D to ground at E).
SIX_BAR = {
    "mechanism": {"name": "compound", "gravity": [0.0, -G]},
    "points": {"O": [0.0, 0.0], "A": [0.0, 0.3], "B": [0.8, 0.6], "C": [1.0, 0.0],
               "D": [1.5, 0.9], "E": [1.9, 0.2]},
    "links": {
        "ground": {"points": ["O", "C", "E"]},
        "crank": {"points": ["O", "A"]},
        "coupler": {"points": ["A", "B"]},
        "rocker": {"points": ["C", "B"]},
        "link4": {"points": ["B", "D"]},
        "link5": {"points": ["E", "D"]},
    },
    "drive": {"joint": "O", "omega": 1.0},
}


def _with_order(data: dict, order) -> dict:
    out = copy.deepcopy(data)
    out["links"] = {name: data["links"][name] for name in order}
    return out


def test_compound_hinge_decomposes_in_every_table_order():
    names = list(SIX_BAR["links"])
    seen = set()
    for order in itertools.permutations(names):
        mech = from_dict(_with_order(SIX_BAR, order))
        s = decompose(mech)
        assert s.formula == "I(0,1) → II(2,3) → II(4,5)"
        groups = frozenset(frozenset(g.links) for g in s.groups)
        assert groups == {frozenset({"coupler", "rocker"}), frozenset({"link4", "link5"})}
        seen.add(frozenset((j.point, frozenset(j.links)) for j in mech.revolutes))
        for j in mech.revolutes:  # names follow the documented rule POINT:FIRST-OTHER
            if j.point == "B":
                assert j.name == f"B:{j.links[0]}-{j.links[1]}"
                assert order.index(j.links[0]) < order.index(j.links[1])
    # the pairs joined at B do not depend on the order: the inner pair of the first group, and
    # link4 to the first of the two that the decomposition knows
    assert len(seen) == 1


def test_compound_hinge_physics_in_any_table_order():
    phi = np.radians(np.arange(60.0, 120.0, 5.0))
    ref = _physics(SIX_BAR, phi)
    for order in (("link4", "link5", "rocker", "coupler", "crank", "ground"),
                  ("ground", "link5", "rocker", "link4", "crank", "coupler")):
        _assert_same(ref, _physics(_with_order(SIX_BAR, order), phi))


def test_compound_hinge_at_the_drive_pivot_keeps_its_name():
    # O carries ground, crank and a second rocker (an RRR group with a coupler from A): the drive is
    # O:ground-crank in either table order, and the rocker is joined to ground at O (the carrier
    # known first), named with the two links in description order.
    data = {
        "mechanism": {"name": "pivot"},
        "points": {"O": [0.0, 0.0], "A": [0.2, 0.0], "B": [0.5, 0.4]},
        "links": {"ground": {"points": ["O"]}, "crank": {"points": ["O", "A"]},
                  "coupler": {"points": ["A", "B"]}, "rocker": {"points": ["O", "B"]}},
        "drive": {"joint": "O:ground-crank", "omega": 1.0},
    }
    for order in (("ground", "crank", "coupler", "rocker"), ("rocker", "ground", "coupler", "crank")):
        mech = from_dict(_with_order(data, order))
        names = {j.name: set(j.links) for j in mech.revolutes if j.point == "O"}
        rocker = "O:ground-rocker" if order.index("ground") < order.index("rocker") else "O:rocker-ground"
        assert names == {"O:ground-crank": {"ground", "crank"}, rocker: {"ground", "rocker"}}
        assert decompose(mech).formula == "I(0,1) → II(2,3)"


def test_reversed_slot_coulisse_agrees_with_mujoco():
    # MuJoCo integrates the model built from the same assembly, so it cannot tell the mode (the hand
    # solution above does); it checks the reversed slot's kinematics and forces in that mode by an
    # independent route (tolerances of linkgen.mujoco.tolerances)
    from linkgen.crosscheck.compare import compare
    from linkgen.mujoco.simulate import simulate

    asm = assemble(from_dict(coulisse(reversed_slot=True)))
    cmp = compare(asm, simulate(asm))
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad


@pytest.mark.parametrize("reversed_slot", [False, True], ids=["slot", "reversed_slot"])
def test_mujoco_is_started_in_the_sketched_mode(reversed_slot):
    # `linkgen validate` once reported agreement for the wrong mode: MuJoCo is started from the
    # closed form's pose, so both sides shared it. The pose MuJoCo is given must hold the rocker
    # at the angle by hand, and MuJoCo's own loop-closure residuals must vanish there.
    import mujoco

    from linkgen.mujoco.simulate import build_model, joint_state

    asm = assemble(from_dict(coulisse(reversed_slot)))
    model = build_model(asm)
    data = mujoco.MjData(model)
    phi = math.atan2(A[1], A[0]) + np.radians(np.arange(0.0, 360.0, 45.0))
    rocker = model.body("rocker").id
    for p, hand in zip(phi, _rocker_by_hand(phi)):
        data.qpos[:] = joint_state(asm, model, float(p), 0.0, 0.0)[0]
        mujoco.mj_forward(model, data)
        angle = math.atan2(data.xmat[rocker][3], data.xmat[rocker][0])
        assert abs(np.angle(np.exp(1j * (angle - hand)))) < HAND_ANGLE_TOL
        closure = data.efc_pos[data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY]
        assert closure.size and np.abs(closure).max() < HAND_ANGLE_TOL * CRANK
