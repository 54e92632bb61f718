"""Spatial four-bars: kinetostatics against the energy balance, MuJoCo (forward run and inverse
dynamics) against the closed form, the viewer keyframe, and the CLI."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import mujoco
import numpy as np
import pytest

import linkgen
from linkgen.mujoco.tolerances import GAP_TOL
from linkgen.families.spatial.forces import forces
from linkgen.families.spatial.kinematics import solve
from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf
from linkgen.mujoco.spatial_state import reduced_inertia

from conftest import ROOT, SPATIAL_MODELS, every_model, input_values

RSSR = ROOT / "models" / "rssr.toml"
# Energy balance by central differences of J(φ) with step H: truncation H²·|J‴|/6 relative to
# the torque ~1e-8 for these metre-sized models, rounding eps·J/H ~ 1e-11: 1e-6 of the peak.
H = 1e-4
ENERGY_TOL = 1e-6


@pytest.fixture(params=SPATIAL_MODELS, ids=[p.stem for p in SPATIAL_MODELS])
def spatial(request):
    return linkgen.load(request.param)


@pytest.fixture(params=every_model(SPATIAL_MODELS), ids=lambda p: p.stem)
def spatial_in_mujoco(request):
    """A spatial model (its path) for the every-model MuJoCo checks: on one model per kind of chain
    (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo` runs."""
    return request.param


def test_bundled_spatial_models_cover_the_four_kinds():
    kinds = {solve(linkgen.load(p), [0.0]).chain.kind for p in SPATIAL_MODELS}
    assert {"RSSR"} <= kinds


def test_balancing_torque_equals_the_energy_balance(spatial):
    """τ·ω = dT/dt + (power of gravity against the motion): at constant ω, τ = ½·J′(φ)·ω² −
    Σ m·g·c′(φ), with J′ by central differences of the kinetic energy — no Newton–Euler."""
    phi = input_values(spatial, np.linspace(0.0, 2 * np.pi, 48, endpoint=False))
    w = 7.0
    f = forces(spatial, phi, w, 0.0)
    h = float(np.ptp(input_values(spatial, [0.0, H])))  # H of a turn, or the same fraction of a slider's range
    jp = (reduced_inertia(spatial, solve(spatial, phi + h)) - reduced_inertia(spatial, solve(spatial, phi - h))) / (2 * h)
    k = solve(spatial, phi)
    g = np.array(spatial.gravity)
    grav = np.zeros_like(phi)
    for link in (k.chain.crank, k.chain.coupler, k.chain.output):
        l = spatial.link(link)
        c = k.at(link, l.points[0]) if len(l.points) == 1 else (k.at(link, l.points[0]) + k.at(link, l.points[1])) * 0.5
        grav += l.mass * (c.d[1] @ g)
    expected = 0.5 * jp * w**2 - grav
    scale = np.abs(expected).max()
    assert np.abs(f.balancing_torque - expected).max() <= ENERGY_TOL * scale


@pytest.mark.every_model
def test_mujoco_agrees_with_the_closed_form(spatial_in_mujoco, validated):
    spatial = linkgen.load(spatial_in_mujoco)
    r = validated(spatial_in_mujoco.stem)  # linkgen.validate(spatial), made once a session
    bad = {k: v for k, v in r.errors.items() if v[0] > v[1]}
    assert not bad, r.summary()
    assert r.gap <= GAP_TOL
    assert r.ok
    assert ("inverse.balancing_force" if spatial.drive.slides else "inverse.balancing_torque") in r.errors
    if r.kind in ("RSSR", "RSSP", "PSSR", "PSSP", "RCCC"):  # determinate: every reaction compared
        assert sum(k.startswith("reactions.") for k in r.errors) == 4
    else:
        assert "indeterminate" in r.note
    if r.kind == "RCCC":  # the later links' copies of the cylindrical pairs' points are compared too
        assert {"points.A:coupler.position", "points.B:output.position", "points.B0:output.position"} <= set(r.errors)


@pytest.mark.every_model
def test_keyframe_turns_the_crank_at_omega(spatial_in_mujoco):
    spatial = linkgen.load(spatial_in_mujoco)
    model = mujoco.MjModel.from_xml_string(write_spatial_mjcf(spatial))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("sketch").id)
    drive = model.joint(spatial.drive.joint).qposadr[0]
    q0 = data.qpos[drive]
    # a second, or (a slider input) 0.8 of the way from the sketch to the end of the range
    end = 1.0 if not spatial.drive.slides else 0.8 * spatial.drive.range[1] / spatial.drive.omega
    while data.time < end:
        mujoco.mj_step(model, data)
    assert abs((data.qpos[drive] - q0) - spatial.drive.omega * data.time) <= 0.01 * spatial.drive.omega


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True, cwd=ROOT)


def test_analyze_json_gives_points_with_jerk_and_the_output():
    p = _cli("analyze", RSSR, "--angle", "30deg", "--omega", "1", "--json")
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert set(d["points"]["B"]) == {"position", "velocity", "acceleration", "jerk"}
    assert len(d["points"]["B"]["jerk"]) == 3
    k = solve(linkgen.load(RSSR), [np.radians(30.0)])
    assert np.allclose(d["points"]["B"]["jerk"], k.points["B"].d[3][0], rtol=0, atol=1e-12)
    assert "rocker" in d["links"] and "angular_jerk" in d["links"]["rocker"]
    # jerk scales with ω³ at ε = 0
    p2 = json.loads(_cli("analyze", RSSR, "--angle", "30deg", "--omega", "2", "--json").stdout)
    assert np.allclose(p2["points"]["B"]["jerk"], 8 * np.array(d["points"]["B"]["jerk"]), rtol=1e-12, atol=1e-12)


def test_planar_only_commands_refuse_a_spatial_file_in_one_line():
    p = _cli("simulate", RSSR)
    assert p.returncode == 2
    assert "spatial" in p.stderr and "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1


def test_forces_cli_names_the_links_of_each_reaction():
    p = _cli("forces", RSSR, "--angle", "30deg", "--json")
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["statically_indeterminate"] == 0
    # the planar convention: on the pair's first link by its second, in the order of [links.*]
    assert d["reactions"]["A"]["on"] == "crank" and d["reactions"]["A"]["by"] == "coupler"


# The coupler's spin about its own line given at the start, as a fraction of the crank speed.
INJECTED_SPIN = 0.5


@pytest.mark.parametrize("model", ["rssr", "rssp"])
def test_the_idle_spin_keeps_its_rate_and_leaves_the_output_alone(model):
    """The RSSR/RSSP coupler's idle freedom: started spinning about its line at 0.5·ω, MuJoCo keeps
    that spin (nothing on two ball joints turns an axisymmetric rod about its line) while the
    output follows the closed form at MuJoCo's crank angle as closely as without spin."""
    from linkgen.mujoco.tolerances import REL_TOL
    from linkgen.mujoco.scene import SERVO
    from linkgen.crosscheck.spatial import derived_settings
    from linkgen.families.spatial.kinematics import assembled_chain
    from linkgen.mujoco.spatial_state import joint_state

    mech = linkgen.load(ROOT / "models" / f"{model}.toml")
    chain = assembled_chain(mech)
    w0 = mech.drive.omega
    settings, _ = derived_settings(mech, w0, chain)
    m = mujoco.MjModel.from_xml_string(write_spatial_mjcf(mech, settings, chain))
    m.actuator(SERVO).biasprm[:] = 0.0
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:] = joint_state(m, chain, solve(mech, [0.0], chain), 0, w0)
    mujoco.mj_forward(m, d)
    a, b = (d.site(p).xpos.copy() for p in mech.link(chain.coupler).points[:2])
    axis = (b - a) / np.linalg.norm(b - a)
    ball = m.joint(chain.pair_a).dofadr[0]
    d.qvel[ball:ball + 3] += d.body(chain.coupler).xmat.reshape(3, 3).T @ (INJECTED_SPIN * w0 * axis)
    crank, out = m.joint(chain.drive), m.joint(chain.pair_out)
    r6 = np.zeros(6)
    phis, turns, spins = [], [], []
    for _ in range(24):  # half a turn, every 7.5°
        for _ in range(int(round(np.pi / 24 / w0 / m.opt.timestep))):
            mujoco.mj_step(m, d)
        mujoco.mj_forward(m, d)
        a, b = (d.site(p).xpos for p in mech.link(chain.coupler).points[:2])
        axis = (b - a) / np.linalg.norm(b - a)
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, m.body(chain.coupler).id, r6, 0)
        phis.append(d.qpos[crank.qposadr[0]] + chain.phi_s)
        turns.append(d.qpos[out.qposadr[0]])
        spins.append(r6[:3] @ axis)
    assert phis[-1] > np.pi / 2  # the crank did turn
    np.testing.assert_allclose(spins, INJECTED_SPIN * w0, rtol=0, atol=REL_TOL * w0)
    cf = solve(mech, np.array(phis), chain)
    scale = chain.size if chain.kind == "RSSP" else 1.0  # the slider's metres over the size, the rocker's radians
    assert np.abs(np.array(turns) - cf.turn.d[0]).max() / scale <= REL_TOL


def test_structure_names_where_a_chain_cannot_assemble(tmp_path):
    """rssr with a 0.5 m crank: A = (−0.5, 0, 0) at 180° is √(1.1² + 0.2²) = 1.118 m from the
    nearest point of B's circle, beyond the 1 m coupler, so a range around 180° is named."""
    text = (ROOT / "models" / "rssr.toml").read_text(encoding="utf-8")
    text = text.replace("A = [0.25, 0.0, 0.0]", "A = [0.5, 0.0, 0.0]").replace("length = 0.25", "length = 0.5", 1)
    path = tmp_path / "partial.toml"
    path.write_text(text, encoding="utf-8")
    p = _cli("structure", path)
    assert p.returncode == 0, p.stderr
    line = p.stdout.strip().splitlines()[-1]
    lo, hi = (float(x) for x in re.search(r"at crank angles ([\d.]+)°\.\.([\d.]+)°", line).groups())
    assert 130.0 < lo < 180.0 < hi < 230.0 and abs((lo + hi) / 2 - 180.0) < 0.2  # the chain is symmetric in y
    assert "whole turn" in _cli("structure", RSSR).stdout.strip().splitlines()[-1]


def test_a_long_spatial_run_reports_progress(monkeypatch):
    """rssr under 1000 g took 3e5 steps and a minute in silence (fuzz campaign seed 2030): the
    spatial MuJoCo run reports its progress like the planar and cam runs."""
    from linkgen.mujoco import options
    from linkgen.crosscheck import spatial as crosscheck

    monkeypatch.setattr(options, "PROGRESS_AFTER", 0.0)
    monkeypatch.setattr(crosscheck, "PROGRESS_STEPS", 500)
    calls = []
    crosscheck.check_spatial(linkgen.load(ROOT / "models" / "rssr.toml"), samples=36,
                             progress=lambda f, t: calls.append(f))
    assert calls and all(0 < f <= 1 for f in calls) and calls == sorted(calls)
