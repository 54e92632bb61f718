"""Property tests over generated mechanisms, checked by independent code (tests/independent_checks.py).

Random valid mechanisms of every group kind (linkgen.families.planar.corpus) must keep their link lengths,
shapes, guides and relative angles, reproduce their sketch at the sketch angle, have
transfer functions that match finite differences, reactions that balance every link with
its given and d'Alembert loads, a balancing torque that closes virtual work, and the same
physics however the description is written. Hostile files must load or raise
DescriptionError, and what loads must solve to finite numbers or raise a LinkgenError.
"""

from __future__ import annotations

import json
import math
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import strategies as st

import independent_checks as ic
import linkgen
from linkgen import DescriptionError, LinkgenError
from linkgen.families.planar.corpus import KINDS, SCAN_STEP_DEG, denominator_crossings, random_description, to_toml
from linkgen.cli.main import main
from linkgen.families.planar.kinetostatics import forces
from strategies import (
    mechanisms,
    mutate,
    reorder_link_points,
    reorder_tables,
    reverse_slot,
    through_other,
)

# Positions and distances held to this fraction of the mechanism's size, angles to this many
# rad: the closed form rounds at ~1e-16 per operation through at most four chained groups;
# measured ≤ 1.2e-13 over 1000 generated mechanisms (validation/fuzz_closed_form.py), so 1e-10
# leaves two decades for harder draws while a wrong branch or length is off by O(1).
GEOMETRY_TOL = 1e-10
# Transfer functions: |reported − FD(h/2)| / |FD(h) − FD(h/2)| ≈ 1/3 where the central
# difference's h² truncation dominates, the smaller over steps 1e-4 and 1e-3 rad (see
# independent_checks.transfer_errors); measured ≤ 0.62 over 1000 mechanisms, while a
# relative error of 1e-6 planted in the second transfer functions already gives ~8.
FD_STEPS = (1e-4, 1e-3)
FD_RATIO_TOL = 3.0
# Force and moment balance and virtual work, relative to the terms' magnitudes (see
# independent_checks.GLOBAL_SHARE): measured ≤ 5.9e-13 over 1000 mechanisms.
BALANCE_TOL = 1e-9
# Equivalent descriptions: positions relative to size, forces to the largest reaction,
# torques to that times the size: measured ≤ 2.3e-12 over 1000 mechanisms (two rounding
# paths); a different mechanism differs by O(1).
EQUIV_TOL = 1e-9

# Reproducible in CI; no shrinking: examples are seeds of the generator, which do not shrink
# into simpler mechanisms, and a failure prints its description as TOML for replay instead.
COMMON = dict(deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
              suppress_health_check=[HealthCheck.too_slow])


def _angles(desc: dict, n: int = 16) -> np.ndarray:
    lo, hi = ic.crank_range(desc)
    return np.concatenate([[ic.sketch_phi(desc)], np.linspace(lo, hi, n + 2)[1:-1]])


def _epsilon(desc: dict, seed: int) -> float:
    """A crank acceleration of either sign up to ω² (0 for one draw in three)."""
    w = desc["drive"]["omega"]
    return [0.0, 0.7 * w * w, -0.4 * w * w][seed % 3]


def test_corpus_is_deterministic_round_trips_and_covers_what_it_documents():
    seen = {k: 0 for k in KINDS}
    features = dict(compound=0, ternary=0, shape=0, coincident=0, full=0, partial=0, stroke=0, torque=0,
                    gravity=0, inertial=0, density=0, default=0, offset=0)
    sizes, omegas = [], []
    for seed in range(60):
        d = random_description(np.random.default_rng(seed))
        assert d == random_description(np.random.default_rng(seed))
        assert tomllib.loads(to_toml(d)) == d
        mech = linkgen.from_dict(d)
        for g in linkgen.decompose(mech).groups:
            seen[g.kind.value] += 1
        carriers = {}
        for name, spec in d["links"].items():
            for p in spec["points"]:
                carriers[p] = carriers.get(p, 0) + 1
            if name == ic.GROUND:
                continue
            xy = [tuple(d["points"][p]) for p in spec["points"]]
            features["ternary"] += len(xy) >= 3
            features["shape"] += "shape" in spec
            features["coincident"] += len(set(xy)) < len(xy)
            features["inertial"] += "inertial" in spec
            features["density"] += "density" in spec
            features["default"] += "inertial" not in spec and "density" not in spec
        features["compound"] += max(carriers.values()) >= 3
        lo, hi = ic.crank_range(d)
        features["full" if hi - lo > 6.28 else "partial"] += 1
        features["stroke"] += any("stroke" in f for f in d.get("force", []))
        features["torque"] += "torque" in d
        features["gravity"] += "gravity" in d["mechanism"]
        features["offset"] += any(p.get("offset", 0.0) != 0.0 for p in d.get("prismatic", {}).values())
        sizes.append(ic.size(d))
        omegas.append(d["drive"]["omega"])
    assert min(seen.values()) >= 10, seen
    assert min(features.values()) >= 3, features
    assert min(sizes) < 0.05 and max(sizes) > 10.0, (min(sizes), max(sizes))
    assert min(omegas) < 0.5 and max(omegas) > 100.0, (min(omegas), max(omegas))


_toml_scalars = (st.booleans() | st.integers(-(2**63), 2**63 - 1) | st.floats(allow_nan=False)
                 | st.text(max_size=8))
_toml_values = st.recursive(
    _toml_scalars,
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=12,
)


@settings(max_examples=100, **COMMON)
@given(st.dictionaries(st.text(max_size=6), _toml_values, max_size=4))
def test_to_toml_round_trips_through_tomllib(data):
    assert tomllib.loads(to_toml(data)) == data


def test_written_description_replays_with_the_cli(tmp_path, capsys):
    """A corpus member written by to_toml and read back by the CLI is the same mechanism:
    the same balancing torque to the last bit (floats are written exactly)."""
    for seed in range(3):
        desc = random_description(np.random.default_rng(seed))
        path = tmp_path / f"m{seed}.toml"
        path.write_text(to_toml(desc))
        phi0 = ic.sketch_phi(desc)
        assert main(["forces", str(path), "--angle", f"{phi0!r}rad", "--json"]) == 0
        got = json.loads(capsys.readouterr().out)["balancing_torque"]
        want = forces(linkgen.from_dict(desc), [phi0], desc["drive"]["omega"], 0.0).balancing_torque[0]
        assert got == want


def test_range_is_assembled_and_holds_the_sketch_angle():
    for seed in range(30):
        d = random_description(np.random.default_rng(seed), margin_deg=5.0)
        lo, hi = ic.crank_range(d)
        phi0 = ic.sketch_phi(d)
        if hi - lo < 2 * math.pi - 1e-9:
            assert lo < phi0 < hi
        linkgen.solve(linkgen.from_dict(d), np.linspace(lo, hi, 721))  # raises if not assembled


def test_partial_range_ends_within_one_scan_step_of_its_margin():
    """Beyond a partial range's ends by the margin and one scan step, a group fails to
    assemble, is marked singular, or its transfer-function denominator changes sign (a dead
    centre narrower than any grid): the range is no narrower than it must be."""
    margin = 5.0
    checked = 0
    for seed in range(40):
        d = random_description(np.random.default_rng(seed), margin_deg=margin, max_groups=2)
        lo, hi = ic.crank_range(d)
        if hi - lo > 2 * math.pi - 1e-9:
            continue
        checked += 1
        reach = math.radians(margin + 2 * SCAN_STEP_DEG)
        for a, b in ((lo - reach, lo), (hi, hi + reach)):
            phi = np.linspace(a, b, 64)
            try:
                kin = linkgen.solve(linkgen.from_dict(d), phi, on_singular="mark")
            except (linkgen.AssemblyError, linkgen.SingularityError):
                continue
            crossing = denominator_crossings(linkgen.assemble(linkgen.from_dict(d)), phi)
            assert kin.singular.any() or crossing.any(), (seed, a, b, to_toml(d))
    assert checked >= 10


def test_load_errors_name_the_file(tmp_path):
    """A message about a file names it (folder commands report many files)."""
    text = to_toml(random_description(np.random.default_rng(4), max_groups=1))
    for i, data in enumerate([text.replace("[drive]", "[drive]\nbogus = 1"), "x = ", text.replace("omega", "omga")]):
        path = tmp_path / f"bad{i}.toml"
        path.write_text(data)
        try:
            linkgen.load(path)
        except DescriptionError as exc:
            assert path.name in str(exc), exc
        else:
            raise AssertionError(f"{data!r} loaded")


@settings(max_examples=150, **COMMON)
@given(mechanisms())
def test_geometry_is_held_and_the_sketch_points_are_reproduced(mechanism):
    _, desc = mechanism
    kin = linkgen.solve(linkgen.from_dict(desc), _angles(desc, 24))
    figs = ic.geometry_errors(desc, kin)
    for key in ("distance", "guide", "ground", "sketch_point", "frame", "relative_angle", "crank"):
        assert figs[key] <= GEOMETRY_TOL, (key, figs, to_toml(desc))


@settings(max_examples=150, **COMMON)
@given(mechanisms())
def test_assembly_mode_reproduces_the_sketch_link_angles(mechanism):
    """Every link's angle at the sketch crank angle is its sketch angle (a one-point link's
    is 0): the assembly mode comes from the whole sketch, not from the points alone."""
    _, desc = mechanism
    kin = linkgen.solve(linkgen.from_dict(desc), _angles(desc, 2))
    figs = ic.geometry_errors(desc, kin)
    assert figs["sketch_angle"] <= GEOMETRY_TOL, (figs, to_toml(desc))


@settings(max_examples=80, **COMMON)
@given(mechanisms())
def test_transfer_functions_match_finite_differences(mechanism):
    _, desc = mechanism
    asm = linkgen.assemble(linkgen.from_dict(desc))
    figs = ic.transfer_errors(desc, lambda a: linkgen.solve(asm, a), _angles(desc, 12), FD_STEPS)
    assert max(figs.values()) <= FD_RATIO_TOL, (figs, to_toml(desc))


@settings(max_examples=150, **COMMON)
@given(mechanisms())
def test_every_link_balances_and_virtual_work_closes(mechanism):
    k, desc = mechanism
    mech = linkgen.from_dict(desc)
    phi = _angles(desc, 24)
    omega, eps = desc["drive"]["omega"], _epsilon(desc, k)
    f = forces(mech, phi, omega, eps)
    kin = linkgen.solve(mech, phi)
    figs = ic.balance_errors(desc, kin, f, omega, eps)
    assert max(figs.values()) <= BALANCE_TOL, (figs, to_toml(desc))


def _physics(desc: dict, phi: np.ndarray):
    mech = linkgen.from_dict(desc)
    kin = linkgen.solve(mech, phi)
    f = forces(mech, phi, desc["drive"]["omega"], 0.0)
    return mech, kin, f


def _compare(a: dict, b: dict, flip: str | None = None, moved: str | None = None) -> dict[str, float]:
    """Worst differences between the physics of two equivalent descriptions ``a`` and ``b``:
    ``flip`` names a prismatic pair whose line was reversed (its normal force changes sign),
    ``moved`` a link whose frame was moved (its angle shifts by the sketch difference)."""
    phi = _angles(a, 12)
    ma, ka, fa = _physics(a, phi)
    mb, kb, fb = _physics(b, phi)
    size = ic.size(a)
    out = {"points": max(float(np.max(np.hypot(*(ka.points[p].p - kb.points[p].p).T))) for p in a["points"]) / size}
    shift = {n: 0.0 for n in a["links"]}
    if moved is not None:
        shift[moved] = ic.sketch_frame_angle(b, moved) - ic.sketch_frame_angle(a, moved)
    out["angles"] = max(float(np.max(np.abs(ic.wrap(kb.links[n].angle.v - ka.links[n].angle.v - shift[n]))))
                        for n in a["links"] if n != ic.GROUND)
    na, nb = ic.net_joint_forces(a, fa), ic.net_joint_forces(b, fb)
    assert set(na) == set(nb)
    scale = max([float(np.max(np.hypot(*v.T))) for v in na.values()]
                + [float(np.max(np.abs(v))) for v in fa.normal_force.values()] + [1e-300])
    out["joints"] = max(float(np.max(np.hypot(*(na[k] - nb[k]).T))) for k in na) / scale
    for name in fa.normal_force:
        sign = -1.0 if name == flip else 1.0
        diff = float(np.max(np.abs(fb.normal_force[name] - sign * fa.normal_force[name])))
        out["joints"] = max(out["joints"], diff / scale)
    mscale = scale * size + float(np.max(np.abs(fa.balancing_torque)))
    out["torques"] = float(np.max(np.abs(fb.balancing_torque - fa.balancing_torque))) / mscale
    for name in fa.moment:
        out["torques"] = max(out["torques"], float(np.max(np.abs(fb.moment[name] - fa.moment[name]))) / mscale)
    return out


@pytest.mark.parametrize("how", ["tables", "points", "reverse", "through"])
@settings(max_examples=80, **COMMON)
@given(mechanism=mechanisms())
def test_equivalent_descriptions_give_equal_physics(how, mechanism):
    """tables: points, links, pairs and forces reordered; points: one link's points
    reordered; reverse: a slot's direction reversed by 180°; through: a guide line given
    through another point of its link with the matching offset."""
    seed, desc = mechanism
    rng = np.random.default_rng([seed, 1])
    flip = moved = None
    prismatic = sorted(desc.get("prismatic", {}))
    if how == "tables":
        other = reorder_tables(desc, rng)
    elif how == "points":
        other = reorder_link_points(desc, rng)
        if other is not None:
            moved = next(n for n in desc["links"] if desc["links"][n]["points"] != other["links"][n]["points"])
    elif not prismatic:
        other = None
    elif how == "reverse":
        flip = prismatic[rng.integers(len(prismatic))]
        other = reverse_slot(desc, flip)
    else:
        other = through_other(desc, prismatic[rng.integers(len(prismatic))], rng)
    assume(other is not None)  # no link or pair of that kind to rewrite
    figs = _compare(desc, other, flip, moved)
    assert max(figs.values()) <= EQUIV_TOL, (how, figs, to_toml(desc), to_toml(other))


def _outcome(path) -> str:
    """'rejected' (DescriptionError), 'refused (<error type>)' (another LinkgenError after
    loading) or 'ok' (loaded and solved to finite numbers); any other exception propagates."""
    try:
        mech = linkgen.load(path)
    except DescriptionError:
        return "rejected"
    lo, hi = mech.drive.start, mech.drive.stop
    phi = np.linspace(lo, hi, 7)
    try:
        f = forces(mech, phi, mech.drive.omega, mech.drive.epsilon)
    except LinkgenError as exc:
        return f"refused ({type(exc).__name__})"
    values = [f.balancing_torque, *f.reactions.values(), *f.normal_force.values(), *f.moment.values()]
    assert all(np.all(np.isfinite(v)) for v in values), "non-finite forces returned without an error"
    return "ok"


@settings(max_examples=200, **COMMON)
@given(mechanisms(max_groups=2))
def test_mutated_files_load_or_raise_description_error(tmp_path_factory, mechanism):
    seed, desc = mechanism
    path = tmp_path_factory.mktemp("hostile") / "m.toml"
    path.write_bytes(mutate(desc, np.random.default_rng([seed, 2])))
    _outcome(path)


@settings(max_examples=100, **COMMON)
@given(st.binary(min_size=0, max_size=400))
def test_random_bytes_raise_description_error(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("bytes") / "m.toml"
    path.write_bytes(data)
    _outcome(path)


def test_byte_order_mark_is_accepted(tmp_path):
    desc = random_description(np.random.default_rng(1), max_groups=1)
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + to_toml(desc).encode())
    assert _outcome(path) == "ok"


def _scaled_geometry(desc: dict, s: float) -> dict:
    out = {**desc, "points": {p: [x * s, y * s] for p, (x, y) in desc["points"].items()}}
    out["links"] = {n: {k: (v * s if k == "length" else v) for k, v in spec.items()}
                    for n, spec in desc["links"].items()}
    return out


def _hostile_cases():
    base = random_description(np.random.default_rng(3), max_groups=1)
    text = to_toml(base)
    fast = {**base, "drive": {**base["drive"], "omega": 1e155}}
    return {
        "binary": bytes(range(256)),
        "latin-1": text.replace('"corpus"', '"corp\u00fcs"').encode("latin-1"),
        "nested arrays": (text + "x = " + "[" * 5000 + "]" * 5000 + "\n").encode(),
        "nested tables": (text + "[" + ".".join(["t"] * 5000) + "]\n").encode(),
        "size 1e-300 m": to_toml(_scaled_geometry(base, 1e-300)).encode(),
        "size 1e300 m": to_toml(_scaled_geometry(base, 1e300)).encode(),
        "omega 1e155": to_toml(fast).encode(),
        "empty": b"",
    }


@pytest.mark.parametrize("case", list(_hostile_cases()))
def test_hostile_file_loads_or_raises_description_error(tmp_path, case):
    path = tmp_path / "m.toml"
    path.write_bytes(_hostile_cases()[case])
    _outcome(path)
