"""Kinetostatics and reduced dynamics: every number checked by an independent route."""

import json
import math

import mujoco
import numpy as np
import pytest

from conftest import MODELS, ROOT
from linkgen import assemble, from_dict, load
from linkgen.cli.common import crank_grid
from linkgen.cli.main import main
from linkgen.crosscheck.compare import compare
from linkgen.families.planar.kinetostatics import forces
from linkgen.mujoco.forces import inverse_forces
from linkgen.mujoco.simulate import build_model, joint_state, simulate

# Group-by-group solution against virtual work (Σ F·v′ + M·θ′ + T = 0): both are sums of a few
# dozen products, the former through up to four chained 6×6 solves; measured ≤ 1.5e-15 of the
# peak torque on every bundled model, so 1e-12 leaves room for conditioning but not for a wrong term.
POWER_BALANCE_TOL = 1e-12
# dJ/dφ against a central difference of J with step H: truncation H²/6·|J‴| ~ 1e-11 and
# rounding eps·|J|/H ~ 2e-11 relative, so 1e-8 of the peak.
H = 1e-5
FD_TOL = 1e-8
# Hand-computed static equilibria: exact arithmetic on g = 9.81, so rounding only [N], [N·m].
HAND_TOL = 1e-9
G = 9.81


def _angles(mech, n=361):
    return crank_grid(mech, n)


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_balancing_torque_equals_power_balance_and_reduced_dynamics(path):
    mech = load(path)
    phi = _angles(mech)
    for omega, eps in ((mech.drive.omega, 0.0), (2.0, -3.0), (0.0, 0.0)):
        f = forces(mech, phi, omega, eps)
        peak = max(np.abs(f.balancing_torque).max(), 1e-300)
        assert np.abs(f.balancing_torque - f.power_balance_torque).max() <= POWER_BALANCE_TOL * peak
        # T = J·ε + ½·J′·ω² − M_red (+ the friction's lost power over ω, [[friction]]): the
        # reduced-dynamics route (kinetic energy) to the same torque
        r = f.reduced
        t_red = r.inertia * eps + 0.5 * r.inertia_derivative * omega**2 - r.moment
        if omega:
            t_red = t_red + f.friction_power / omega
        assert np.abs(f.balancing_torque - t_red).max() <= POWER_BALANCE_TOL * peak


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_reduced_inertia_derivative_matches_finite_differences(path):
    mech = load(path)
    asm = assemble(mech)
    phi = _angles(mech, 90)
    phi = np.clip(phi, mech.drive.start + 2 * H, mech.drive.stop - 2 * H)
    j = forces(asm, phi, 1.0).reduced
    jp, jm = forces(asm, phi + H, 1.0).reduced.inertia, forces(asm, phi - H, 1.0).reduced.inertia
    fd = (jp - jm) / (2 * H)
    assert np.abs(fd - j.inertia_derivative).max() <= FD_TOL * np.abs(j.inertia).max()
    assert np.all(j.inertia > 0)


PARALLELOGRAM = {
    "mechanism": {"name": "parallelogram", "gravity": [0.0, -G]},
    "points": {"O": [0, 0], "A": [0, 0.5], "B": [1, 0.5], "C": [1, 0]},
    "links": {
        "ground": {"points": ["O", "C"]},
        "crank": {"points": ["O", "A"], "length": 0.5, "inertial": {"mass": 1.0, "com": [0.25, 0], "inertia": 0.02}},
        "coupler": {"points": ["A", "B"], "length": 1.0, "inertial": {"mass": 2.0, "com": [0.5, 0], "inertia": 0.2}},
        "rocker": {"points": ["C", "B"], "length": 0.5, "inertial": {"mass": 1.0, "com": [0.25, 0], "inertia": 0.02}},
    },
    "drive": {"joint": "O", "omega": 1.0},
}
# Crank and rocker upright, coupler level at φ = 90°: the coupler only translates, so gravity does
# no virtual work and T = 0; with no torque the crank and rocker carry the coupler's weight along
# their axes, half at A and half at B.
PARALLELOGRAM_HAND = {
    "balancing_torque": 0.0,
    "A": (0.0, -G),           # coupler on crank: half the coupler's 2 kg
    "B": (0.0, G),            # rocker on coupler
    "O": (0.0, -2 * G),       # crank on ground: its own 1 kg + half the coupler
    "C": (0.0, -2 * G),       # rocker on ground
}

SLIDER_CRANK = {
    "mechanism": {"name": "dead_centre", "gravity": [0.0, -G]},
    "points": {"O": [0, 0], "A": [0.1, 0], "B": [0.4, 0]},
    "links": {
        "ground": {"points": ["O"]},
        "crank": {"points": ["O", "A"], "length": 0.1, "inertial": {"mass": 1.0, "com": [0.05, 0], "inertia": 1e-3}},
        "rod": {"points": ["A", "B"], "length": 0.3, "inertial": {"mass": 2.0, "com": [0.15, 0], "inertia": 0.015}},
        "slider": {"points": ["B"], "inertial": {"mass": 3.0, "com": [0, 0], "inertia": 0.0}},
    },
    "prismatic": {"slider": {"slider": "slider", "guide": "ground", "point": "B", "through": "O", "angle": 0.0}},
    "drive": {"joint": "O", "omega": 1.0},
}
# Everything level at φ = 0: the rod's weight splits in half between A and B (moments about B);
# the guide carries the slider and half the rod, N = (3 + 1)·g; the crank holds its own weight at
# 0.05 m and half the rod's at 0.1 m: T = g·(1·0.05 + 1·0.1) = 0.15·g.
SLIDER_CRANK_HAND = {
    "balancing_torque": 0.15 * G,
    "A": (0.0, -G),           # rod on crank
    "B": (0.0, G),            # slider on rod
    "O": (0.0, -2 * G),       # crank on ground
    "normal_force": 4 * G,
    "moment": 0.0,
}


@pytest.mark.parametrize("data, phi, hand", [
    (PARALLELOGRAM, math.pi / 2, PARALLELOGRAM_HAND),
    (SLIDER_CRANK, 0.0, SLIDER_CRANK_HAND),
], ids=["parallelogram", "slider_crank"])
def test_static_equilibrium_by_hand(data, phi, hand):
    asm = assemble(from_dict(data))
    f = forces(asm, np.array([phi]), 0.0, 0.0)
    model = build_model(asm)
    q, v, a = joint_state(asm, model, phi, 0.0, 0.0)
    mj = inverse_forces(asm, model, mujoco.MjData(model), phi, q, v, a)
    for got_t, got_r, got_n, got_m in (
        (f.balancing_torque[0], {k: r[0] for k, r in f.reactions.items()},
         {k: n[0] for k, n in f.normal_force.items()}, {k: m[0] for k, m in f.moment.items()}),
        (mj.balancing_torque, mj.reactions, mj.normal_force, mj.moment),
    ):
        assert got_t == pytest.approx(hand["balancing_torque"], abs=HAND_TOL)
        for joint in ("A", "B", "O"):
            assert got_r[joint] == pytest.approx(hand[joint], abs=HAND_TOL), joint
        if "normal_force" in hand:
            assert got_n["slider"] == pytest.approx(hand["normal_force"], abs=HAND_TOL)
            assert got_m["slider"] == pytest.approx(hand["moment"], abs=HAND_TOL)


def _fourbar_with_loads(force: bool = True):
    import tomllib

    data = tomllib.loads((ROOT / "models" / "fourbar.toml").read_text())
    data["torque"] = [{"link": "rocker", "torque": 12.0}]
    if force:
        data["force"] = [{"link": "coupler", "point": "B", "force": [30.0, -50.0], "stroke": ["90deg", "200deg"]}]
    return from_dict(data)


def test_process_load_acts_only_inside_its_stroke():
    from linkgen import solve

    mech = _fourbar_with_loads()
    phi = crank_grid(mech, 720)
    bare = forces(_fourbar_with_loads(force=False), phi, 3.0).balancing_torque
    loaded = forces(mech, phi, 3.0).balancing_torque
    b1 = solve(mech, phi).points["B"].d1
    inside = (phi >= math.radians(90)) & (phi <= math.radians(200))
    # virtual work of the force alone: ΔT = −F·B′ inside the stroke, nothing outside
    expected = -(30.0 * b1[:, 0] - 50.0 * b1[:, 1]) * inside
    assert np.abs(loaded - bare - expected).max() <= POWER_BALANCE_TOL * np.abs(loaded).max()
    assert np.any(inside) and np.any(~inside)


def test_mujoco_agrees_with_loads_on_rotating_links():
    # a stroke-limited force on the coupler and a torque on the rocker: xfrc_applied lever arms
    # change with the links' angles, and the load switches on and off during the run
    asm = assemble(_fourbar_with_loads())
    cmp = compare(asm, simulate(asm))
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad
    assert cmp.quantities["reactions.B.force"].peak > 100.0


def test_forces_cli_json(capsys):
    assert main(["forces", str(ROOT / "models" / "fourbar.toml"), "--angle", "30deg", "--omega", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= {"balancing_torque", "reactions", "prismatic", "reduced_inertia", "reduced_inertia_derivative"}
    assert set(out["reactions"]) == {"O", "C", "A", "B"}
    assert out["reactions"]["A"]["on"] == "crank" and out["reactions"]["A"]["by"] == "coupler"
    f = forces(load(ROOT / "models" / "fourbar.toml"), np.array([math.radians(30)]), 1.0)
    assert out["balancing_torque"] == pytest.approx(float(f.power_balance_torque[0]), rel=POWER_BALANCE_TOL)
    assert main(["forces", str(ROOT / "models" / "seven_link.toml"), "--angle", "38.117deg", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["prismatic"]) == {"block", "slider"}
    assert set(out["prismatic"]["slider"]) == {"normal_force", "on", "by", "moment"}


def test_forces_cli_samples_and_errors(tmp_path, capsys):
    csv_path = tmp_path / "f.csv"
    assert main(["forces", str(ROOT / "models" / "ga2.toml"), "--samples", "36", "--csv", str(csv_path)]) == 0
    rows = csv_path.read_text().splitlines()
    assert len(rows) == 37 and rows[0].startswith("phi [rad],singular,balancing_torque [N·m],power_balance_torque [N·m]")
    assert main(["forces", str(tmp_path / "none.toml")]) == 2
    assert "no such description file" in capsys.readouterr().err


def test_wrongly_shaped_rates_are_argument_errors():
    from linkgen import ArgumentError

    mech = load(ROOT / "models" / "fourbar.toml")
    phi = np.linspace(0.0, 1.0, 5)
    with pytest.raises(ArgumentError, match=r"^omega must be a scalar or an array of shape \(5,\) \[rad/s\], "
                                            r"got shape \(4,\)$"):
        forces(mech, phi, np.ones(4))
    with pytest.raises(ArgumentError, match=r"^epsilon must be finite \[rad/s²\], got non-finite entries$"):
        forces(mech, phi, 1.0, np.array([0.0, np.inf, 0.0, 0.0, 0.0]))


def test_forces_in_blocks_equal_one_piece(monkeypatch):
    # the same numbers whatever the block size (blocks of 64 angles over 1000, on two threads)
    import linkgen.families.planar.blocks

    mech = load(ROOT / "models" / "seven_link.toml")
    phi = np.linspace(mech.drive.start, mech.drive.start + 1.0, 1000)
    omega, eps = np.linspace(1.0, 3.0, 1000), -2.0
    whole = forces(mech, phi, omega, eps)
    monkeypatch.setattr(linkgen.families.planar.blocks, "BLOCK", 64)
    parts = forces(mech, phi, omega, eps, threads=2)
    assert np.array_equal(whole.balancing_torque, parts.balancing_torque)
    assert np.array_equal(whole.power_balance_torque, parts.power_balance_torque)
    for name in whole.reactions:
        assert np.array_equal(whole.reactions[name], parts.reactions[name]), name
    for name in whole.normal_force:
        assert np.array_equal(whole.normal_force[name], parts.normal_force[name]), name
        assert np.array_equal(whole.moment[name], parts.moment[name]), name
    assert np.array_equal(whole.reduced.inertia, parts.reduced.inertia)
    assert np.array_equal(whole.omega, omega)


def test_power_balance_disagreement_is_found_and_named():
    from linkgen import BalanceError
    from linkgen.families.planar.kinetostatics import BALANCE_TOL, balance_failures

    mech = load(ROOT / "models" / "ga2.toml")
    phi = crank_grid(mech, 36)
    f = forces(mech, phi, 2.0, 1.0)
    scale = np.abs(f.balancing_torque).max() * np.ones(36)
    none = np.zeros(36, dtype=bool)
    assert balance_failures(phi, f.balancing_torque, f.power_balance_torque, scale, none) == ([], 0.0)
    # a wrong term of 10·BALANCE_TOL of the scale at two neighbouring angles is found, by angle
    wrong = f.balancing_torque.copy()
    wrong[[3, 4]] += 10 * BALANCE_TOL * scale[0]
    ranges, worst = balance_failures(phi, wrong, f.power_balance_torque, scale, none)
    assert ranges == [(phi[3], phi[4])] and worst == pytest.approx(10 * BALANCE_TOL, rel=1e-3)
    skip = none.copy()
    skip[[3, 4]] = True  # singular angles marked by the caller are not compared
    assert balance_failures(phi, wrong, f.power_balance_torque, scale, skip) == ([], 0.0)
    assert str(BalanceError(ranges, worst, BALANCE_TOL)).startswith(
        "the balancing torque from the group-by-group solution and from the power balance disagree by up to "
        "1e-07 of the torque scale (allowed 1e-08) at crank angles 30.000°..40.000°")


def test_near_singular_forces_raise_or_are_marked():
    # At a denominator of 1e-16 the forces used to come back as ~1e78 N·m: now the one rule applies.
    from linkgen import SingularityError

    mech = load(ROOT / "models" / "tangent_prp.toml")
    phi = np.array([1e-16, 0.3, 1.0])
    with pytest.raises(SingularityError, match=r"^group II\(2,3\) PRP \[block, slider\] is singular at crank angles "
                                               r"0.000°: its two guides are \(nearly\) parallel"):
        forces(mech, phi, 2.0)
    f = forces(mech, phi, 2.0, on_singular="mark")
    assert f.singular.tolist() == [True, False, False]
    ok = forces(mech, phi[1:], 2.0)
    assert f.balancing_torque[0] == 0.0 and np.array_equal(f.balancing_torque[1:], ok.balancing_torque)
    for name, r in f.reactions.items():
        assert np.all(np.isfinite(r)) and np.array_equal(r[1:], ok.reactions[name]), name


def test_forces_raise_when_the_two_torques_disagree(monkeypatch):
    # Inject a wrong crank equilibrium (the drive torque off by 1e-6 of its size): every call
    # compares it with the power balance and must refuse the result, naming the angles.
    from linkgen import BalanceError
    import linkgen.families.planar.reactions as ks  # the group-by-group solver of the kinetostatics

    solve_systems = ks._checked

    def skewed(x, singular, phi, marked, label, *rest):  # rest: a prismatic drive's stroke flag
        x = solve_systems(x, singular, phi, marked, label, *rest)
        if label.startswith("I(0,1)"):
            x[:, 2] *= 1.0 + 1e-6
        return x

    mech = load(ROOT / "models" / "fourbar.toml")
    phi = np.radians([10.0, 20.0, 30.0])
    forces(mech, phi, 3.0)
    monkeypatch.setattr(ks, "_checked", skewed)
    with pytest.raises(BalanceError, match=r"disagree by up to .* \(allowed 1e-08\) at crank angles 10.000°..30.000°$"):
        forces(mech, phi, 3.0)


# forces() used to keep every intermediate over all angles: 1.1-2 KB per crank angle (1-1.9 GB
# at 10^6 angles). In blocks, the memory besides the results is that of one block whatever the
# number of angles: measured (tracemalloc, ga2, blocks of 4096, two threads) 8.7 MB at 3
# blocks and 8.6 MB at 12 (one thread: 5.1 MB and 4.5 MB); before, 1.06 KB more per angle. Allowed growth: a tenth of the old
# figure's low end per angle.
GROWTH_PER_ANGLE = 110  # bytes


def _result_bytes(obj) -> int:
    """Bytes of every array a result holds (dataclasses and dicts of arrays)."""
    import dataclasses

    if isinstance(obj, np.ndarray):
        return obj.nbytes
    if isinstance(obj, dict):
        return sum(_result_bytes(v) for v in obj.values())
    if dataclasses.is_dataclass(obj):
        return sum(_result_bytes(getattr(obj, f.name)) for f in dataclasses.fields(obj))
    return 0


def _peak_besides_results(asm, n: int) -> int:
    import tracemalloc

    tracemalloc.start()
    try:
        f = forces(asm, np.linspace(0.0, 6.0, n), 2.0)
        return tracemalloc.get_traced_memory()[1] - _result_bytes(f)
    finally:
        tracemalloc.stop()


def test_forces_memory_does_not_grow_with_the_angles(monkeypatch):
    import linkgen.families.planar.blocks as blocks

    monkeypatch.setattr(blocks, "BLOCK", 4096)  # small blocks: a fast test of many blocks
    asm = assemble(load(ROOT / "models" / "ga2.toml"))
    forces(asm, np.linspace(0.0, 6.0, 3 * 4096), 2.0)  # the allocator's one-off warm-up
    # One thread: how many blocks' temporaries are alive at once does not depend on timing.
    monkeypatch.setattr(blocks, "default_threads", lambda: 1)
    one = {n: _peak_besides_results(asm, n) for n in (3 * 4096, 12 * 4096)}
    assert one[12 * 4096] - one[3 * 4096] < GROWTH_PER_ANGLE * 9 * 4096, one
    # Two threads: at most one block's temporaries per thread, however many blocks (whether the
    # two threads overlap over 3 blocks is up to the scheduler, so the bound is absolute).
    monkeypatch.setattr(blocks, "default_threads", lambda: 2)
    two = _peak_besides_results(asm, 12 * 4096)
    assert two < 2 * one[3 * 4096] + GROWTH_PER_ANGLE * 9 * 4096, (one, two)


# The closed-form solutions (families/planar/equilibrium.py) against LAPACK's LU with partial
# pivoting on the same systems. Backward error: |A·x − b| / (|A|·|x| + |b|) is a few units of
# rounding (2.2e-16) for any stable solver whatever the conditioning; 1e-13 allows ~450 of them.
BACKWARD_TOL = 1e-13
# Forward agreement on the bundled models: both solvers lose about cond(A)·2.2e-16; the systems'
# condition numbers there stay below 1e4 outside the marked (near-singular) angles.
MODEL_SOLVER_TOL = 1e-10


def _full(cols, n):
    """The columns (x force, y force, moment) as the (n, 3, k) matrix they make."""
    return np.stack([np.stack([np.broadcast_to(np.asarray(v, float), (n,)) for v in c], axis=1) for c in cols], axis=2)


def _backward_error(a, x, b):
    r = np.einsum("nij,nj->ni", a, x) - b
    size = np.abs(a).sum(axis=2).max(axis=1) * np.abs(x).max(axis=1) + np.abs(b).max(axis=1)
    return np.abs(r).max(axis=1) / size


def test_closed_form_equilibrium_solutions_are_backward_stable():
    from linkgen.families.planar.equilibrium import dyad, three

    rng = np.random.default_rng(7)
    n = 2000
    scale = 10.0 ** rng.uniform(-3, 3, size=(n, 1))  # moment arms from mm to km, as the sizes go
    col = lambda: (rng.normal(size=n), rng.normal(size=n), scale[:, 0] * rng.normal(size=n))  # noqa: E731
    p1, q1, q2, p2 = (col(), col()), (col(), col()), (col(), col()), (col(), col())
    b1, b2 = col(), col()
    (x, singular) = dyad(p1, q1, q2, p2, b1, b2)
    a = np.zeros((n, 6, 6))
    a[:, 0:3, 0:2], a[:, 0:3, 2:4] = _full(p1, n), _full(q1, n)
    a[:, 3:6, 2:4], a[:, 3:6, 4:6] = _full(q2, n), _full(p2, n)
    b = np.concatenate([_full([b1], n)[..., 0], _full([b2], n)[..., 0]], axis=1)
    assert not singular.any()
    assert _backward_error(a, np.stack(x, axis=1), b).max() < BACKWARD_TOL
    c = (col(), col(), col())
    (y, singular) = three(*c, b1)
    assert not singular.any()
    assert _backward_error(_full(c, n), np.stack(y, axis=1), _full([b1], n)[..., 0]).max() < BACKWARD_TOL
    # exactly singular: parallel outer columns, and a zero determinant, are flagged
    par = (p1[0], tuple(2.0 * v for v in p1[0]))
    with np.errstate(invalid="ignore", divide="ignore"):
        assert dyad(par, q1, q2, p2, b1, b2)[1].all()
        assert three(c[0], c[1], c[1], b1)[1].all()


@pytest.mark.parametrize("name", ["seven_link", "press", "tangent_prp", "ga32", "cam_rocker_slider", "planetary_lever"])
def test_equilibrium_systems_agree_with_a_general_solver(monkeypatch, name):
    import linkgen.families.planar.reactions as ks  # the group-by-group solver of the kinetostatics

    asm = assemble(load(ROOT / "models" / f"{name}.toml"))
    drive = asm.mechanism.drive
    phi = np.linspace(drive.start, drive.stop, 97)
    ours = forces(asm, phi, 3.0, 1.0, on_singular="mark")

    def lu_dyad(p1, q1, q2, p2, b1, b2):
        n = phi.shape[0]
        a = np.zeros((n, 6, 6))
        a[:, 0:3, 0:2], a[:, 0:3, 2:4] = _full(p1, n), _full(q1, n)
        a[:, 3:6, 2:4], a[:, 3:6, 4:6] = _full(q2, n), _full(p2, n)
        b = np.concatenate([_full([b1], n)[..., 0], _full([b2], n)[..., 0]], axis=1)
        a[ours.singular] = np.eye(6)
        x = np.linalg.solve(a, b[..., None])[..., 0]
        return tuple(x.T), np.zeros(n, bool)

    def lu_three(c0, c1, c2, b):
        n = phi.shape[0]
        a = _full([c0, c1, c2], n)
        a[ours.singular] = np.eye(3)
        x = np.linalg.solve(a, _full([b], n)[..., 0][..., None])[..., 0]
        return tuple(x.T), np.zeros(n, bool)

    monkeypatch.setattr(ks, "dyad", lu_dyad)
    monkeypatch.setattr(ks, "three", lu_three)
    lu = forces(asm, phi, 3.0, 1.0, on_singular="mark")
    ok = ~ours.singular
    assert ok.sum() > 80
    found = {**ours.reactions, **ours.normal_force, **ours.contact}
    other = {**lu.reactions, **lu.normal_force, **lu.contact}
    peak = max(np.abs(v[ok]).max() for v in found.values())
    for key in found:
        np.testing.assert_allclose(found[key][ok], other[key][ok], rtol=0, atol=MODEL_SOLVER_TOL * peak, err_msg=key)
    scale = np.abs(ours.balancing_torque[ok]).max()
    np.testing.assert_allclose(ours.balancing_torque[ok], lu.balancing_torque[ok], rtol=0, atol=MODEL_SOLVER_TOL * scale)
