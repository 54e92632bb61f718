"""One vocabulary: for every family and every bundled model where the stage applies, the
kinematics and forces results name each quantity the same way as a Python attribute
(``f.reactions["B"].force``), as a ``to_dict()``/JSON key path (``reactions.B.force``) and as a
CSV header (``B.force.x [N]``), and the three give the same numbers.

Element quantities (a point's velocity, a pair's force, a prismatic pair's normal_force) must
match exactly across the three. At the top level every CSV column and every JSON key is an
attribute of the result; the drive's rates ``omega`` and ``epsilon`` are inputs, constant over
the samples, and have no CSV column."""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest

import linkgen
from linkgen.pipeline.registry import family_of, stage
from conftest import every_model

MODELS = sorted((Path(__file__).resolve().parents[1] / "models").glob("*.toml"))
# Samples per model: enough for every column to be (n,), few enough to keep the test cheap.
SAMPLES = 5
# The CSV writes floats with repr() and JSON with json's repr: both round-trip float64 exactly,
# so the three views must agree to the last bit.
EXACT = 0.0


def _cases():
    for path in MODELS:
        desc = linkgen.load(path)
        for name in ("kinematics", "forces"):
            if name in family_of(desc).stages:
                yield pytest.param(path, name, id=f"{path.stem}-{name}")


def _result(path: Path, name: str):
    desc = linkgen.load(path)
    phi = stage(desc, "angles")(desc, SAMPLES)
    return stage(desc, name)(desc, phi, on_singular="mark")


def _numeric(x) -> bool:
    return x is not None and not isinstance(x, str)


def python_names(r) -> dict[tuple[str, ...], np.ndarray]:
    """Element quantities (name, quantity) → value from the result's attributes."""
    out = {}
    for f in dataclasses.fields(r):
        table = getattr(r, f.name)
        if not isinstance(table, Mapping):
            continue
        for name, rec in table.items():
            for q in dataclasses.fields(rec):
                v = getattr(rec, q.name)
                if _numeric(v):
                    out[(name, q.name)] = np.asarray(v, dtype=float)
    return out


def json_names(d: dict) -> dict[tuple[str, ...], np.ndarray]:
    out = {}
    for section, table in d.items():
        if section == "units" or not isinstance(table, dict):
            continue
        for name, rec in table.items():
            for q, v in rec.items():
                if _numeric(v):
                    out[(name, q)] = np.asarray(v, dtype=float)
    return out


def csv_names(cols: dict[str, np.ndarray], top: set[str]) -> dict[tuple[str, ...], np.ndarray]:
    """Headers "name.quantity[.x|.y|.z] [unit]" → (name, quantity): the columns (n,) or (n, k)."""
    parts: dict[tuple[str, ...], dict[str, np.ndarray]] = {}
    for head, col in cols.items():
        key = head.split(" [")[0]
        if key in top:
            continue
        bits = key.split(".")
        axis = bits[-1] if len(bits) == 3 and bits[-1] in ("x", "y", "z") else None
        name, q = (bits[0], ".".join(bits[1:-1] if axis else bits[1:]))
        parts.setdefault((name, q), {})[axis or ""] = col
    return {k: (v[""] if "" in v else np.column_stack([v[a] for a in "xyz" if a in v])) for k, v in parts.items()}


@pytest.mark.parametrize("path,name", list(_cases()))
def test_python_json_and_csv_name_every_quantity_alike(path, name):
    r = _result(path, name)
    d = json.loads(json.dumps(r.to_dict(), allow_nan=False))
    cols = r.columns()
    top = {h.split(" [")[0] for h in cols if "." not in h.split(" [")[0]}
    py, js, cs = python_names(r), json_names(d), csv_names(cols, top)
    assert py, "the result names no quantity"
    assert set(py) == set(js), sorted(set(py) ^ set(js))
    assert set(py) == set(cs), sorted(set(py) ^ set(cs))
    for key, v in py.items():
        np.testing.assert_allclose(js[key], v, rtol=EXACT, atol=EXACT, err_msg=f"JSON {key}")
        np.testing.assert_allclose(cs[key], v.reshape(cs[key].shape), rtol=EXACT, atol=EXACT, err_msg=f"CSV {key}")
    for k in top:
        assert k in d and hasattr(r, k), k
        np.testing.assert_allclose(np.asarray(d[k], dtype=float), np.asarray(getattr(r, k), dtype=float),
                                   rtol=EXACT, atol=EXACT)
    for k, v in d.items():
        assert hasattr(r, k) or k == "units", k


def test_a_prismatic_pairs_normal_force_has_one_name():
    """``f.prismatic["ram"].normal_force`` ↔ JSON prismatic.ram.normal_force ↔ CSV ram.normal_force
    (was ``f.normal_force["ram"]`` in Python)."""
    mech = linkgen.load(Path(__file__).resolve().parents[1] / "models" / "cam_rocker_slider.toml")
    f = linkgen.forces(mech, [0.1, 0.2])
    d = f.to_dict()
    np.testing.assert_array_equal(d["prismatic"]["ram"]["normal_force"], f.prismatic["ram"].normal_force)
    np.testing.assert_array_equal(f.columns()["ram.normal_force [N]"], f.prismatic["ram"].normal_force)
    np.testing.assert_array_equal(np.asarray(d["reactions"]["D"]["force"]), f.reactions["D"].force)
    np.testing.assert_array_equal(f.columns()["D.force.x [N]"], f.reactions["D"].force[:, 0])


def test_every_family_is_walked():
    """The walk above covers kinematics for every family and forces for planar and spatial ones."""
    cases = {(family_of(linkgen.load(p.values[0])).name, p.values[1]) for p in _cases()}
    assert cases == {("planar", "kinematics"), ("planar", "forces"), ("cam", "kinematics"),
                     ("spatial", "kinematics"), ("spatial", "forces")}, cases


# ---------------------------------------------------------------------------------------------
# The design summary and the structure: frozen results whose attributes are their to_dict()
# keys, all the way down (a record's fields, a table's names), with the same keys for the same
# quantity in every family. Neither has samples, so neither writes CSV (the CLI refuses
# --summary with -o FILE.csv, and structure has no -o).

# The keys every family's summary has, and the records they hold (docs/format.md, "Conventions").
SUMMARY_KEYS = {"model", "omega", "epsilon", "drive_range", "units", "outputs", "peak_balancing_torque"}
OUTPUT_KEYS = {"kind", "travel", "limits", "strokes", "time_ratio"}
EXTREME_KEYS = {"value", "phi"}
LIMIT_KEYS = {"phi", "value", "kind"}
# Pair reactions: in every family that computes them (planar, spatial; a stand-alone cam has
# only its contact force).
REACTION_FAMILIES = {"planar", "spatial"}
# The keys every family's structure has.
STRUCTURE_KEYS = {"model", "mobility", "crank", "drive", "lines"}


def _whole_cases(name: str, paths=MODELS):
    for path in paths:
        desc = linkgen.load(path)
        if name in family_of(desc).stages:
            yield pytest.param(path, id=f"{path.stem}-{name}")


def _walk(obj, d, path: str) -> None:
    """``d`` (the JSON data) holds exactly ``obj``'s attributes under their names: a dataclass's
    fields (and its ``units``), a mapping's keys, a tuple's items, the same numbers and words."""
    if dataclasses.is_dataclass(obj):
        names = [f.name for f in dataclasses.fields(obj)]
        assert isinstance(d, dict) and set(d) - {"units"} == set(names), (path, sorted(set(d) ^ set(names)))
        if "units" in d:
            assert d["units"] == dict(obj.units), path
        for n in names:
            _walk(getattr(obj, n), d[n], f"{path}.{n}")
    elif isinstance(obj, Mapping):
        assert isinstance(d, dict) and list(d) == list(obj), (path, list(d), list(obj))
        for k, v in obj.items():
            _walk(v, d[k], f"{path}.{k}")
    elif isinstance(obj, (tuple, list)):
        assert isinstance(d, list) and len(d) == len(obj), path
        for i, (v, x) in enumerate(zip(obj, d)):
            _walk(v, x, f"{path}[{i}]")
    elif obj is None or isinstance(obj, (str, bool)):
        assert d == obj and type(d) is type(obj), (path, d, obj)
    else:
        assert not isinstance(d, bool) and float(d) == float(obj), (path, d, obj)


def _keys(d) -> set[str]:
    """Every key anywhere in the JSON data."""
    if isinstance(d, dict):
        return set(d).union(*(_keys(v) for v in d.values()))
    if isinstance(d, list):
        return set().union(*(_keys(v) for v in d))
    return set()


@pytest.mark.every_model
@pytest.mark.parametrize("path", list(_whole_cases("summary", every_model(MODELS))))
def test_a_summary_names_every_quantity_as_its_attribute(path):
    """The summary's JSON holds its attributes under their names. On one model per family and feature
    (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo` runs."""
    desc = linkgen.load(path)
    s = stage(desc, "summary")(desc)
    d = json.loads(json.dumps(s.to_dict(), allow_nan=False))
    _walk(s, d, "summary")
    family = family_of(desc).name
    assert set(d) >= SUMMARY_KEYS | ({"peak_reactions", "forces_note"} if family in REACTION_FAMILIES else set())
    assert "at" not in _keys(d), "a drive angle is phi"
    for name, o in d["outputs"].items():
        assert set(o) == OUTPUT_KEYS and o["kind"] in ("slider", "rocker"), name
        assert all(set(x) == LIMIT_KEYS for x in o["limits"] or ()), name
    peaks = [d["peak_balancing_torque"], *d.get("peak_reactions", {}).values(),
             *d.get("min_transmission_angle", {}).values()]
    assert all(set(p) == EXTREME_KEYS for p in peaks if p is not None)


@pytest.mark.parametrize("path", list(_whole_cases("structure")))
def test_a_structure_names_every_quantity_as_its_attribute(path):
    desc = linkgen.load(path)
    s = stage(desc, "structure")(desc)
    d = json.loads(json.dumps(s.to_dict(), allow_nan=False))
    _walk(s, d, "structure")
    assert set(d) >= STRUCTURE_KEYS and d["mobility"] == 1, sorted(d)


def test_every_family_summary_and_structure_are_walked():
    summaries = {family_of(linkgen.load(p.values[0])).name for p in _whole_cases("summary")}
    structures = {family_of(linkgen.load(p.values[0])).name for p in _whole_cases("structure")}
    assert summaries == {"planar", "cam", "spatial"} and structures == {"planar", "spatial"}


# ---------------------------------------------------------------------------------------------
# text() on samples: every family's sampled result prints each angle's block, the same block the
# result computed at that one angle prints (was a bare TypeError from float() of an array).

TEXT_ANGLES = (0.1, 0.2)  # [rad] two drive angles where every bundled model assembles


@pytest.mark.parametrize("path,name", list(_cases()))
def test_text_of_a_sampled_result_is_each_angles_block(path, name):
    desc = linkgen.load(path)
    run = stage(desc, name)
    # a prismatic drive's input is a stroke [m]: two inside its range
    at = np.linspace(desc.drive.start, desc.drive.stop, 4)[1:3] if getattr(desc, "slide_drive", False) else TEXT_ANGLES
    sampled = run(desc, np.array(at), on_singular="mark").text()
    assert sampled == "\n\n".join(run(desc, phi, on_singular="mark").text() for phi in at)


# ---------------------------------------------------------------------------------------------
# One rule for every pair's force (docs/format.md, "Conventions"): it says on which link it acts
# and by which — a revolute's or spherical pair's reaction, a prismatic pair's normal force, a
# gear's tooth force, a cam's contact force (was: only revolutes; prismatic neither, tooth and
# contact only ``on``).

PAIR_TABLES = ("reactions", "prismatic", "tooth", "contact")


def _link_names(path: Path) -> set[str]:
    import tomllib

    data = tomllib.loads(path.read_text())
    return set(data.get("links", {})) | {"ground"} | ({"cam", "follower"} if "cam" in data and "links" not in data
                                                      else set())


@pytest.mark.parametrize("path,name", [c for c in _cases() if c.values[1] == "forces"
                                       or family_of(linkgen.load(c.values[0])).name == "cam"])
def test_every_pair_force_says_on_which_link_and_by_which(path, name):
    d = _result(path, name).to_dict()
    links = _link_names(path)
    tables = [(t, n, rec) for t in PAIR_TABLES for n, rec in d.get(t, {}).items()]
    assert tables or name == "forces", "no pair force"
    for t, n, rec in tables:
        assert {"on", "by"} <= set(rec), f"{t}.{n}: {sorted(rec)}"
        assert rec["on"] in links and rec["by"] in links and rec["on"] != rec["by"], (t, n, rec["on"], rec["by"])


def test_a_prismatic_pair_acts_on_its_slider_by_its_guide():
    """seven_link's [prismatic.block] (its slider and its guide, a moving link, as the file gives
    them)."""
    import tomllib

    path = Path(__file__).resolve().parents[1] / "models" / "seven_link.toml"
    pair = tomllib.loads(path.read_text())["prismatic"]["block"]
    rec = linkgen.forces(linkgen.load(path), 0.5).to_dict()["prismatic"]["block"]
    assert (rec["on"], rec["by"]) == (pair["slider"], pair["guide"])


# ---------------------------------------------------------------------------------------------
# The same quantity the same name in every family's kinematics: the drive angle is ``phi`` (no
# ``theta``), every attribute is in the JSON (``kind`` too; an empty table may be left out), the
# ``units`` give one unit per quantity (not prose), and a follower that turns has a rocker's
# quantities while one that slides has a slider's.

ROCKER = ["angle", "angular_velocity", "angular_acceleration", "angular_jerk"]
SLIDER = ["displacement", "velocity", "acceleration", "jerk"]


@pytest.mark.parametrize("path,name", [c for c in _cases() if c.values[1] == "kinematics"])
def test_kinematics_name_the_drive_phi_and_give_each_quantity_its_unit(path, name):
    r = _result(path, name)
    d = json.loads(json.dumps(r.to_dict(), allow_nan=False))
    phi = "phi [m]" if getattr(linkgen.load(path), "slide_drive", False) else "phi [rad]"  # a prismatic drive's stroke
    assert "theta" not in _keys(d) and phi in r.columns() and "phi" in d
    for f in dataclasses.fields(r):
        if f.compare:
            v = getattr(r, f.name)
            assert f.name in d or (isinstance(v, Mapping) and not v), f.name
    units = d["units"]
    assert all("," not in u for u in units.values()), units
    for table in (v for v in d.values() if isinstance(v, dict) and v is not units):
        for n, rec in table.items():
            for q, v in rec.items():
                assert not _numeric(v) or q in units, f"{n}.{q} has no unit"


@pytest.mark.parametrize("stem,names", [("cam_oscillating", ROCKER), ("cam_translating", SLIDER)])
def test_a_cams_follower_has_a_rockers_or_a_sliders_quantities(stem, names):
    path = Path(__file__).resolve().parents[1] / "models" / f"{stem}.toml"
    d = _result(path, "kinematics").to_dict()
    assert list(d["followers"]["follower"]) == names + ["pressure_angle"]
    assert list(d["contact"]["cam"]) == ["normal_force", "on", "by"]


# ---------------------------------------------------------------------------------------------
# One shape for every family's validation result (mujoco.result_shape): the same keys first,
# each quantity {relative_error, tolerance, ok}, the loop gap {relative, tolerance, ok} (None
# without a loop), radians in the JSON (no key in degrees); each result's own keys after.
# One cheap MuJoCo run per family (about 0.5 s, 4 s and 3 s here).

VALIDATED = {"planar": "fourbar", "spatial": "rssr", "cam": "cam_translating"}
COMMON_VALIDATION = ["model", "ok", "settings", "quantities", "loop_gap", "diagnosis"]


@pytest.fixture(scope="module")
def checks(validated):
    return {family: validated(stem) for family, stem in VALIDATED.items()}


@pytest.fixture(scope="module")
def validations(checks):
    return {family: json.loads(json.dumps(r.to_dict(), allow_nan=False)) for family, r in checks.items()}


def _json_of(x):
    """An attribute's value as JSON data: an object by its ``to_json()``, a tuple as a list."""
    if hasattr(x, "to_json"):
        return x.to_json()
    if isinstance(x, Mapping):
        return {k: _json_of(v) for k, v in x.items()}
    if isinstance(x, (tuple, list)):
        return [_json_of(v) for v in x]
    return x


@pytest.mark.parametrize("family", sorted(VALIDATED))
def test_every_familys_validation_result_has_one_shape(checks, validations, family):
    d = validations[family]
    assert list(d)[:len(COMMON_VALIDATION)] == COMMON_VALIDATION, list(d)
    for key in COMMON_VALIDATION:  # each common key is the result's attribute of that name
        assert json.loads(json.dumps(_json_of(getattr(checks[family], key)))) == d[key], key
    assert d["ok"] is True and d["model"] == VALIDATED[family] and d["diagnosis"] == []
    assert d["quantities"] and isinstance(d["settings"], dict) and "timestep" in d["settings"]
    for name, q in d["quantities"].items():
        assert {"relative_error", "tolerance", "ok"} <= set(q), name
        assert q["ok"] is (q["relative_error"] <= q["tolerance"]), name
    if family == "cam":
        assert d["loop_gap"] is None
    else:
        assert {"relative", "tolerance", "ok"} <= set(d["loop_gap"])
    assert not [k for k in _keys(d) if k.endswith("_deg")], "JSON is SI: angles in radians"


def test_the_loop_gaps_drive_angle_is_in_radians(validations):
    """fourbar's loop gap is largest somewhere on its turn, φ in [0, 2π) (was ``at_deg``)."""
    gap = validations["planar"]["loop_gap"]
    assert "at_deg" not in gap and 0.0 <= gap["phi"] < 2 * np.pi


def test_left_out_samples_and_findings_name_their_angles_as_their_attributes():
    """``LeftOut`` (was from_deg/to_deg) and ``Finding`` (was ranges_deg): keys = attributes, rad."""
    from linkgen.crosscheck.diagnose import Finding
    from linkgen.mujoco.simulate import LeftOut

    lo = LeftOut("load switch", 0.5, 0.75, 12)
    assert lo.to_json() == {"reason": "load switch", "phi_from": 0.5, "phi_to": 0.75, "samples": 12}
    f = Finding("points.B.position", [(0.5, 0.75)], 2e-6, 1e-6, "load switch", "...")
    d = f.to_json()
    assert set(d) == {x.name for x in dataclasses.fields(f)} and d["ranges"] == [[0.5, 0.75]]


def _resolves(d: dict, name: str) -> bool:
    """``name`` ("table.element.quantity" or a top-level key) is a path in the result data ``d``
    that ends at a quantity (numbers), not at a table or an element."""
    node = d
    for part in name.split("."):
        if not isinstance(node, dict) or part not in node:
            return False
        node = node[part]
    return not isinstance(node, dict)


# MuJoCo compares what analyze does not give for a spatial chain: every moving link's angular
# velocity vector (the coupler's too) and the coupler's idle spin about its own line.
SPATIAL_ONLY_COMPARED = {"links.coupler.angular_velocity", "links.coupler.idle_spin"}


@pytest.mark.parametrize("family", sorted(VALIDATED))
def test_validation_names_each_quantity_as_analyze_and_forces_do(validations, family):
    """A compared quantity's name is its path in the closed form's results: the stand-alone cam's
    ``followers.follower.angle``, ``contact.cam.normal_force``, ``balancing_torque`` (were
    displacement, contact_force, cam_torque), a spatial pair's ``reactions.B0.force`` (was
    reactions.B0), the four-bar's ``links.rocker.angle``, ... (``inverse.`` marks the same
    quantity by MuJoCo's inverse dynamics)."""
    desc = linkgen.load(Path(__file__).resolve().parents[1] / "models" / f"{VALIDATED[family]}.toml")
    data = [stage(desc, s)(desc, 0.5).to_dict() for s in ("kinematics", "forces") if s in family_of(desc).stages]
    d = validations[family]
    names = [*d["quantities"], *d.get("instantaneous", {})]
    missing = [n for n in names if not any(_resolves(x, n.removeprefix("inverse.")) for x in data)
               and n not in SPATIAL_ONLY_COMPARED]
    assert not missing, missing
