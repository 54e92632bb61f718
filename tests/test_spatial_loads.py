"""Loads on spatial mechanisms (``[[force]]`` and ``[[torque]]``, the planar keys in 3-D): the
loader, the balancing torque against the virtual work of the loads by finite differences of
the positions (no Newton–Euler), MuJoCo's inverse route and forward run, the CLI's columns,
the summary and the MJCF's note."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import tomllib

import numpy as np
import pytest

import linkgen
from linkgen.mujoco.tolerances import FORCE_TOL, INVERSE_TOL
from linkgen.errors import DescriptionError
from linkgen.crosscheck.spatial import check_spatial, derived_settings
from linkgen.families.spatial.description import spatial_from_dict
from linkgen.families.spatial.forces import forces
from linkgen.mujoco.spatial_inverse import inverse_torque
from linkgen.families.spatial.kinematics import solve
from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf
from linkgen.families.spatial.summary import summarize

from conftest import ROOT, SPATIAL_MODELS, input_values

RSSR = ROOT / "models" / "rssr.toml"
# Central differences of the positions with step H [rad]: truncation H²·|P‴|/6 ~ 2e-11 of the
# metre-sized models, rounding eps·L/H ~ 2e-11: both far below 1e-7 of the loads' torque scale.
H = 1e-5
VIRTUAL_WORK_TOL = 1e-7
# A stroke-limited force used below: on over [100°, 170°] of the crank angle.
STROKE = ("100deg", "170deg")
LO, HI = math.radians(100.0), math.radians(170.0)


def _data(path) -> dict:
    return tomllib.loads(path.read_text(encoding="utf-8"))


def _with(path, force=(), torque=()) -> dict:
    data = _data(path)
    data["force"], data["torque"] = list(force), list(torque)
    return data


def _test_loads(mech_data: dict):
    """A force at every point of every moving link (one of them only inside STROKE) and a torque
    on the crank and the output, and on the coupler where it has no idle spin."""
    mech = spatial_from_dict(mech_data)
    chain = solve(mech, [0.0]).chain
    force, torque = [], []
    rng = np.random.default_rng(7)
    for link in (chain.crank, chain.coupler, chain.output):
        for p in mech.link(link).points:
            force.append({"link": link, "point": p, "force": [float(x) for x in rng.uniform(-50, 50, 3)]})
    if not mech.drive.slides:  # a stroke is a range of crank angles
        force[-1]["stroke"] = list(STROKE)
    idle = chain.ua is None and chain.ub is None
    for link in (chain.crank, chain.output) if idle else (chain.crank, chain.coupler, chain.output):
        torque.append({"link": link, "torque": [float(x) for x in rng.uniform(-20, 20, 3)]})
    return force, torque


def _rotation_rate(frames_plus, frames_minus, frames):
    """Ω′ (n, 3) = vee(dR/dφ·Rᵀ) by central differences of the frames."""
    s = np.einsum("nij,nkj->nik", (frames_plus - frames_minus) / (2 * H), frames)
    return 0.5 * np.stack([s[:, 2, 1] - s[:, 1, 2], s[:, 0, 2] - s[:, 2, 0], s[:, 1, 0] - s[:, 0, 1]], axis=1)


def test_loads_are_read_in_3d_with_their_stroke():
    mech = spatial_from_dict(_with(RSSR, [{"link": "coupler", "point": "B", "force": [1, 2, 3], "stroke": list(STROKE)}],
                                   [{"link": "rocker", "torque": [4, 5, 6]}]))
    f, t = mech.forces[0], mech.torques[0]
    assert (f.link, f.point, f.force) == ("coupler", "B", (1.0, 2.0, 3.0))
    np.testing.assert_allclose(f.stroke, (LO, HI), rtol=1e-15)
    assert (t.link, t.torque) == ("rocker", (4.0, 5.0, 6.0))


@pytest.mark.parametrize("entry, message", [
    ({"force": [{"link": "coupler", "point": "B", "force": [1.0, 2.0]}]},
     "force[0].force: must be a list of 3 numbers [Fx, Fy, Fz] [N] in world axes, got [1.0, 2.0]"),
    ({"force": [{"link": "rod", "point": "B", "force": [1, 2, 3]}]},
     "force[0].link: unknown link 'rod'; known links: ground, crank, coupler, rocker"),
    ({"force": [{"link": "crank", "point": "B", "force": [1, 2, 3]}]},
     "force[0].point: 'B' is not a point of link 'crank' (A0, A)"),
    ({"force": [{"link": "crank", "point": "A", "force": [1, 2, 3], "stroke": ["10deg", "10deg"]}]},
     "force[0].stroke: must be [from, to] crank angles with from < to <= from + 360deg"),
    ({"force": [{"link": "crank", "point": "A", "force": [1, 2, 3], "at": 1}]},
     "force[0].at: unknown key; allowed: force, link, point, stroke"),
    ({"torque": [{"link": "rocker", "torque": 5.0}]},
     "torque[0].torque: must be a list of 3 numbers [Tx, Ty, Tz] [N·m] in world axes, got 5.0"),
    ({"torque": [{"link": "rocker", "torque": [0, 0, 1e200]}]},
     "torque[0].torque[2]: must be within ±1e+114 N·m"),
])
def test_a_bad_load_names_the_file_the_field_and_what_is_allowed(tmp_path, entry, message):
    data = _data(RSSR) | entry
    path = tmp_path / "bad.toml"
    path.write_text(RSSR.read_text(encoding="utf-8") + "\n" + _toml(entry), encoding="utf-8")
    with pytest.raises(DescriptionError) as err:
        linkgen.load(path)
    assert str(err.value).startswith(f"{path}: ") and message in str(err.value)
    with pytest.raises(DescriptionError):
        spatial_from_dict(data)


def _toml(entry: dict) -> str:
    return "".join(f"[[{key}]]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in table.items())
                   for key, spec in entry.items() for table in spec)


def test_a_load_table_that_is_not_an_array_of_tables_is_named():
    with pytest.raises(DescriptionError, match=r"^torque: must be an array of tables \(\[\[torque\]\]\)"):
        spatial_from_dict(_data(RSSR) | {"torque": {"link": "rocker", "torque": [0, 0, 1]}})


@pytest.mark.parametrize("path", SPATIAL_MODELS, ids=[p.stem for p in SPATIAL_MODELS])
def test_the_loads_torque_is_their_virtual_work(path):
    """T_loads = −Σ F·dP/dφ − Σ T·Ω′, with dP/dφ and Ω′ by central differences of the closed-form
    positions and frames, and a stroke force only inside its stroke: the difference of the
    balancing torque with and without the loads (it is linear in the loads)."""
    force, torque = _test_loads(_data(path))
    loaded = spatial_from_dict(_with(path, force, torque))
    bare = spatial_from_dict(_with(path))
    phi = input_values(bare, np.linspace(0.0, 2 * np.pi, 72, endpoint=False) + 0.01)
    w, e = 7.0, 3.0
    got = forces(loaded, phi, w, e).balancing_torque - forces(bare, phi, w, e).balancing_torque
    plus, minus, here = solve(bare, phi + H), solve(bare, phi - H), solve(bare, phi)
    expected = np.zeros_like(phi)
    scale = 0.0
    for f in force:
        on = np.ones(phi.shape, bool) if "stroke" not in f else (np.mod(phi - LO, 2 * np.pi) <= HI - LO)
        dp = (plus.at(f["link"], f["point"]).d[0] - minus.at(f["link"], f["point"]).d[0]) / (2 * H)
        expected -= on * (dp @ np.array(f["force"]))
        scale += np.linalg.norm(f["force"]) * here.chain.size
    for t in torque:
        link = t["link"]
        spin = _rotation_rate(plus.frames[link], minus.frames[link], here.frames[link])
        expected -= spin @ np.array(t["torque"])
        scale += np.linalg.norm(t["torque"])
    assert np.abs(got - expected).max() <= VIRTUAL_WORK_TOL * scale
    # and the stroke does switch: the last force's share is zero outside it
    assert bare.drive.slides or not np.all(np.mod(phi - LO, 2 * np.pi) <= HI - LO)


@pytest.mark.parametrize("path", SPATIAL_MODELS, ids=[p.stem for p in SPATIAL_MODELS])
def test_the_power_balance_torque_matches_and_mujoco_inverse_dynamics_agrees(path):
    force, torque = _test_loads(_data(path))
    mech = spatial_from_dict(_with(path, force, torque))
    phi = input_values(mech, np.linspace(0.0, 2 * np.pi, 12, endpoint=False) + 0.01)
    f = forces(mech, phi, 7.0, 3.0)
    scale = np.abs(f.balancing_torque).max()
    assert np.abs(f.balancing_torque - f.power_balance_torque).max() <= INVERSE_TOL * scale
    t_inv, _ = inverse_torque(mech, phi, 7.0, 3.0)
    assert np.abs(t_inv - f.balancing_torque).max() <= INVERSE_TOL * scale


def test_mujoco_runs_the_rssr_with_a_switching_force_and_a_torque():
    """MuJoCo's forward run with a stroke-limited force on the coupler and a torque on the
    rocker: every compared quantity within its tolerance, the coupler's idle spin included
    (a wrench held over an RSSR's integrator step spun it to 3.9e-2 of ω), and the samples
    right after the two switches left out and counted."""
    mech = spatial_from_dict(_with(RSSR, [{"link": "coupler", "point": "B", "force": [10.0, -20.0, 30.0],
                                           "stroke": list(STROKE)}], [{"link": "rocker", "torque": [5.0, 1.0, -2.0]}]))
    r = check_spatial(mech)
    assert r.ok, r.summary()
    assert r.errors["links.coupler.idle_spin"][0] <= r.errors["links.coupler.idle_spin"][1]
    assert sum(k.startswith("reactions.") for k in r.errors) == 4
    assert "after 2 load switch(es) left out" in r.note
    # the loads did act: the balancing torque differs from the unloaded mechanism's
    bare = forces(spatial_from_dict(_with(RSSR)), r.samples["phi"], r.samples["omega"], r.samples["epsilon"])
    assert np.abs(r.samples["closed_torque"] - bare.balancing_torque).max() > 1.0


def test_a_moment_about_an_rssr_couplers_line_is_refused_by_field():
    mech = spatial_from_dict(_with(RSSR, torque=[{"link": "coupler", "torque": [0.0, 0.0, 5.0]}]), "m.toml")
    with pytest.raises(DescriptionError, match=r"^m\.toml: torque\[0\]: has a moment about the line A–B of the coupler "
                                               r"'coupler' .* the coupler turns on two ball joints"):
        forces(mech, np.linspace(0.0, 6.0, 7))
    # nor does `build` write a model whose coupler MuJoCo would spin
    with pytest.raises(DescriptionError, match=r"torque\[0\]: has a moment about the line A–B"):
        derived_settings(mech)
    # a force through the line is fine
    ok = spatial_from_dict(_with(RSSR, [{"link": "coupler", "point": "A", "force": [0.0, 0.0, 5.0]}]))
    assert np.isfinite(forces(ok, np.linspace(0.0, 6.0, 7)).balancing_torque).all()


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True, cwd=ROOT)


def _loaded_file(tmp_path):
    text = RSSR.read_text(encoding="utf-8") + ('\n[[force]]\nlink = "rocker"\npoint = "B"\nforce = [0.0, 40.0, 0.0]\n'
                                                'stroke = ["100deg", "170deg"]\n\n[[torque]]\nlink = "crank"\n'
                                                'torque = [0.0, 0.0, -100.0]\n')
    path = tmp_path / "loaded.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_forces_cli_gives_the_power_balance_column_and_the_summary_the_loads(tmp_path):
    path = _loaded_file(tmp_path)
    out = tmp_path / "f.csv"
    p = _cli("forces", path, "--samples", "36", "--csv", out)
    assert p.returncode == 0, p.stderr
    head, *rows = out.read_text(encoding="utf-8").splitlines()
    cols = head.split(",")
    assert cols[:3] == ["phi [rad]", "balancing_torque [N·m]", "power_balance_torque [N·m]"]
    table = np.array([[float(x) for x in r.split(",")] for r in rows])
    np.testing.assert_allclose(table[:, 1], table[:, 2], rtol=0, atol=INVERSE_TOL * np.abs(table[:, 1]).max())
    p = _cli("forces", path, "--angle", "0deg", "--json")
    assert p.returncode == 0, p.stderr
    # a torque of −100 N·m about the crank axis z is balanced by +100 N·m more at the drive
    bare = forces(spatial_from_dict(_data(RSSR)), [0.0]).balancing_torque[0]
    assert abs(json.loads(p.stdout)["balancing_torque"] - (bare + 100.0)) <= FORCE_TOL * 100.0
    s = summarize(linkgen.load(path))
    phi = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False)
    unloaded = forces(spatial_from_dict(_data(RSSR)), phi).balancing_torque
    on = np.mod(phi - LO, 2 * np.pi) <= HI - LO
    # the crank's torque is in the summary's peak (it lies outside the stroke here)
    assert s.peak_balancing_torque.value >= (unloaded + 100.0)[~on].max() - FORCE_TOL * 100.0
    assert s.peak_balancing_torque.value > 100.0


def test_the_mjcf_says_the_loads_are_applied_by_linkgen():
    mech = spatial_from_dict(_with(RSSR, [{"link": "coupler", "point": "B", "force": [1.0, 0.0, 0.0]}],
                                   [{"link": "rocker", "torque": [0.0, 0.0, 1.0]}]))
    assert "Not in this file: the description's 1 [[force]] and 1 [[torque]] load(s)" in write_spatial_mjcf(mech)
    assert "Not in this file" not in write_spatial_mjcf(spatial_from_dict(_data(RSSR)))
