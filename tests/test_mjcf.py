"""MJCF writer (names, visuals, inertials), numeric poses and MuJoCo's log file, with real MuJoCo."""

import math
import tomllib

import mujoco
import numpy as np
import pytest

from conftest import MODELS, ROOT, every_model
from linkgen import AssemblyError, DescriptionError, SimulationError, StructureError, assemble, from_dict, load, solve
from linkgen.crosscheck.compare import compare
from linkgen.families.planar.geometry import link_shapes
from linkgen.mujoco.mjcf import (
    MUJOCO_MIN_INERTIA,
    MUJOCO_MIN_MASS,
    body_name,
    site_name,
    write_mjcf,
)
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.state import tree_state
from linkgen.families.planar.pose import mechanism_size, state
from linkgen.mujoco.options import Settings
from linkgen.mujoco.simulate import joint_states, simulate

TRIAD = ROOT / "tests" / "data" / "triad_sixbar.toml"
# The numeric pose against the closed form, relative to the mechanism's size (and size·ω for
# velocities): both solve the same constraints to ~1e-13 (measured worst 2.5e-13, g123).
POSE_AGREEMENT = 1e-11
# MuJoCo's constraint residuals at a state from ``tree_state`` [relative to size, size·ω]: the
# state is exact to ~1e-13, MuJoCo's kinematics add rounding only.
STATE_RESIDUAL = 1e-11
# Constraints at qpos0 (as tests/test_mujoco.py): only the %.17g rounding of placements remains.
QPOS0_TOL = 1e-12
# Central differences of positions with step FD_STEP [rad]: truncation ~ FD_STEP²·x‴/6 ≈ 1e-11·size,
# rounding ~ 1e-16·size/FD_STEP ≈ 1e-11·size; the tolerance leaves 100× margin.
FD_STEP = 1e-5
FD_TOL = 1e-9
# A short MuJoCo run of the class-III six-bar against the numeric pose at MuJoCo's own crank angle,
# relative to the size: the soft connects open by ~1e-9 m there (measured 1.0e-9 m over 0.2 s).
RUN_TOL = 1e-7


def _dict(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def _hostile_fourbar() -> dict:
    """The four-bar with names that collided under the old scheme: a link named ``world``, a ground
    point ``x_bar1`` next to a link ``pivot_x``, a tracer point ``B__rocker`` where point B is also
    on link ``rocker``, and a tracer point T on top of the coupler's first point A."""
    return {
        "mechanism": {"name": "hostile", "gravity": [0.0, -9.81]},
        "points": {"x_bar1": [0.0, 0.0], "A": [0.3, 0.0], "B": [1.0143, 0.6999], "C": [1.0, 0.0],
                   "B__rocker": [0.6, 0.5], "T": [0.3, 0.0]},
        "links": {
            "ground": {"points": ["x_bar1", "C"]},
            "world": {"points": ["x_bar1", "A"], "length": 0.3, "density": 10.0},
            "pivot_x": {"points": ["A", "B", "B__rocker", "T"],
                        "inertial": {"mass": 10.0, "com": [0.5, 0.0], "inertia": 0.0}},
            "rocker": {"points": ["C", "B"], "length": 0.7, "density": 10.0},
        },
        "drive": {"joint": "x_bar1", "omega": 10.0},
    }


def _names(model, objtype, count):
    return [mujoco.mj_id2name(model, objtype, i) for i in range(count)]


def test_generated_names_never_meet_user_names():
    mech = from_dict(_hostile_fourbar())
    model = mujoco.MjModel.from_xml_string(write_mjcf(mech))
    user = set(mech.link_names) | set(mech.points) | {j.name for j in mech.revolutes}
    o = mujoco.mjtObj
    for objtype, count in ((o.mjOBJ_BODY, model.nbody), (o.mjOBJ_JOINT, model.njnt), (o.mjOBJ_EQUALITY, model.neq),
                           (o.mjOBJ_SITE, model.nsite), (o.mjOBJ_GEOM, model.ngeom), (o.mjOBJ_SENSOR, model.nsensor),
                           (o.mjOBJ_ACTUATOR, model.nu), (o.mjOBJ_LIGHT, model.nlight),
                           (o.mjOBJ_MATERIAL, model.nmat)):
        names = _names(model, objtype, count)
        assert len(set(names)) == len(names), (objtype, names)
        made_up = [n for n in names if n not in user and n != "world"]
        assert all(":" in n for n in made_up), (objtype, made_up)
    # findable by the user's names
    assert model.body(body_name("world")).id != 0 and model.body("world").id == 0
    for link in mech.moving_links:
        assert model.body(body_name(link)).name in (link, "link:world")
    for j in mech.revolutes:
        assert mujoco.mj_name2id(model, o.mjOBJ_JOINT, j.name) >= 0 or model.equality(j.name).id >= 0
    for p in mech.points:
        assert model.site(p).id >= 0
    assert model.site("B:rocker").id != model.site("B__rocker").id


def test_hostile_names_simulate_and_match_the_closed_form():
    asm = assemble(from_dict(_hostile_fourbar()))
    cmp = compare(asm, simulate(asm))
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad
    assert "points.B__rocker.position" in cmp.quantities and "points.T.acceleration" in cmp.quantities


def test_coincident_points_make_no_zero_length_bar():
    mech = from_dict(_hostile_fourbar())
    model = mujoco.MjModel.from_xml_string(write_mjcf(mech))
    geoms = _names(model, mujoco.mjtObj.mjOBJ_GEOM, model.ngeom)
    assert "pivot_x:bar:A-B" in geoms and "pivot_x:bar:A-B__rocker" in geoms and "pivot_x:bar:A-T" not in geoms
    capsules = model.geom_type == mujoco.mjtGeom.mjGEOM_CAPSULE
    assert np.all(model.geom_size[capsules, 1] > 0)
    assert np.all(model.geom_contype == 0) and np.all(model.geom_conaffinity == 0)


def _scaled(d: dict, k: float) -> dict:
    d = {**d, "points": {p: [k * x, k * y] for p, (x, y) in d["points"].items()},
         "links": {n: {**s, **({"length": k * s["length"]} if "length" in s else {})} for n, s in d["links"].items()}}
    return d


def test_visuals_scale_with_the_mechanism_and_inertials_stay():
    base = _dict(ROOT / "models" / "fourbar.toml")
    models = {}
    for k in (1.0, 0.02 / 1.2323, 30 / 1.2323):  # the four-bar at 1.23 m, 2 cm and 30 m
        models[k] = mujoco.MjModel.from_xml_string(write_mjcf(from_dict(_scaled(base, k))))
    ref = models[1.0]
    for k, m in models.items():
        np.testing.assert_allclose(m.geom_size, k * ref.geom_size, rtol=1e-12)
        np.testing.assert_allclose(m.site_size[:, 0], k * ref.site_size[:, 0], rtol=1e-12)  # spheres: radius only
        for link, length in (("crank", 0.3), ("coupler", 1.0), ("rocker", 0.7)):  # uniform bars, 10 kg/m
            mass = 10.0 * k * length
            b = m.body(link)
            assert b.mass[0] == pytest.approx(mass, rel=1e-14)
            assert b.inertia[2] == pytest.approx(mass * (k * length) ** 2 / 12, rel=1e-14)
    # a 1 µm four-bar: bars shorter than MuJoCo's least capsule (1e-7 m) become dots, and it compiles
    tiny = mujoco.MjModel.from_xml_string(write_mjcf(from_dict(_scaled(base, 1e-6 / 1.2323))))
    geoms = _names(tiny, mujoco.mjtObj.mjOBJ_GEOM, tiny.ngeom)
    assert {"crank:dot", "coupler:dot", "rocker:dot"} <= set(geoms) and not any(":bar:" in g for g in geoms)


def _one_body(mass: float, izz: float) -> str:
    return (f'<mujoco><worldbody><body><joint type="hinge"/><inertial pos="0 0 0" mass="{mass!r}" '
            f'diaginertia="{izz / 2!r} {izz / 2!r} {izz!r}"/></body></worldbody></mujoco>')


def test_mujoco_mass_and_inertia_limits_are_the_measured_ones():
    mujoco.MjModel.from_xml_string(_one_body(MUJOCO_MIN_MASS, 1.0))
    mujoco.MjModel.from_xml_string(_one_body(1.0, 2 * MUJOCO_MIN_INERTIA))
    with pytest.raises(ValueError, match="mass and inertia"):
        mujoco.MjModel.from_xml_string(_one_body(float(np.nextafter(MUJOCO_MIN_MASS, 0.0)), 1.0))
    with pytest.raises(ValueError, match="mass and inertia"):
        mujoco.MjModel.from_xml_string(_one_body(1.0, float(np.nextafter(2 * MUJOCO_MIN_INERTIA, 0.0))))


def test_inertia_floor_is_relative_and_tiny_masses_are_named():
    d = _hostile_fourbar()
    mech = from_dict(d)
    model = mujoco.MjModel.from_xml_string(write_mjcf(mech))
    span = float(np.hypot(1.0143 - 0.3, 0.6999))  # the coupler's longest distance, A to B
    floor = model.body("pivot_x").inertia[2]
    assert floor == pytest.approx(10.0 * (1e-6 * span) ** 2, rel=1e-12)  # a point mass given inertia 0
    d["links"]["pivot_x"]["inertial"]["mass"] = 1e-16
    with pytest.raises(DescriptionError) as err:
        write_mjcf(from_dict(d))
    assert err.value.field == "links.pivot_x.inertial.mass" and "MuJoCo's smallest body mass" in str(err.value)
    d["links"]["pivot_x"]["inertial"]["mass"] = MUJOCO_MIN_MASS  # the least mass, inertia 0: MuJoCo's own floor
    model = mujoco.MjModel.from_xml_string(write_mjcf(from_dict(d)))
    assert model.body("pivot_x").inertia[2] == 2 * MUJOCO_MIN_INERTIA


def _warn_nan(model) -> None:
    d = mujoco.MjData(model)
    d.qvel[:] = np.nan
    mujoco.mj_step(model, d)
    assert d.warning[mujoco.mjtWarning.mjWARN_BADQVEL].number == 1


def test_mujoco_log_file_stays_out_of_the_working_directory(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    log = tmp_path / "MUJOCO_LOG.TXT"
    model = mujoco.MjModel.from_xml_string(_one_body(1.0, 1.0))
    _warn_nan(model)  # MuJoCo's default: the file appears in the working directory
    assert log.is_file()
    log.unlink()
    with no_log_file():
        with no_log_file():  # nested uses share the switch
            _warn_nan(model)
        _warn_nan(model)
    assert not log.exists()
    assert mujoco.MjLogConfig.get().logto_file  # the previous configuration is back
    # through linkgen: gravity of 1e12 m/s² at a coarse timestep makes MuJoCo warn of huge accelerations
    d = _dict(ROOT / "models" / "fourbar.toml")
    d["mechanism"]["gravity"] = [0.0, -1e12]
    capfd.readouterr()
    with pytest.raises(SimulationError):
        simulate(assemble(from_dict(d)), settings=Settings(timestep=0.01, timeconst=0.02, armature=1e4))
    assert "WARNING" in capfd.readouterr().err, "MuJoCo did not warn: the check below proves nothing"
    assert not log.exists()


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(MODELS), ids=lambda p: p.stem)
def test_numeric_pose_matches_the_closed_form(path):
    """The numeric pose and MuJoCo's joint state agree with the closed form. On one model per family and
    feature (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo` runs."""
    mech = load(path)
    asm = assemble(mech)
    phi, omega = np.linspace(mech.drive.start, mech.drive.stop, 13), 3.0
    st = state(mech, phi, omega)
    kin = solve(asm, phi)
    size = mechanism_size(mech)
    for link in mech.moving_links:
        for p, local in asm.shapes[link].local.items():
            np.testing.assert_allclose(st.point(link, local), kin.points[p].p, rtol=0, atol=POSE_AGREEMENT * size)
            np.testing.assert_allclose(st.point_velocity(link, local), kin.points[p].d1 * omega, rtol=0,
                                       atol=POSE_AGREEMENT * size * omega)
    text = write_mjcf(asm)
    model = mujoco.MjModel.from_xml_string(text)
    qpos, qvel = tree_state(mech, model, phi, omega)
    want_q, want_v, _ = joint_states(asm, model, phi, np.full(phi.shape, omega), np.zeros(phi.shape))
    np.testing.assert_allclose(qpos, want_q, rtol=0, atol=POSE_AGREEMENT * max(size, 1.0))
    np.testing.assert_allclose(qvel, want_v, rtol=0, atol=POSE_AGREEMENT * max(size, 1.0) * omega)
    assert write_mjcf(mech) == text  # a class-II Mechanism is written from its closed form


def test_class_three_builds_and_its_state_holds_in_mujoco():
    mech = load(TRIAD)
    with pytest.raises(StructureError):
        assemble(mech)
    model = mujoco.MjModel.from_xml_string(write_mjcf(mech))
    d = mujoco.MjData(model)
    mujoco.mj_forward(model, d)
    assert d.ne == 6 and np.abs(d.efc_pos[:d.ne]).max() < QPOS0_TOL
    size, omega = mechanism_size(mech), mech.drive.omega
    phi = np.radians(np.arange(0.0, 360.0, 45.0))
    qpos, qvel = tree_state(mech, model, phi, omega)
    st = state(mech, phi, omega)
    shapes = link_shapes(mech)
    for k in range(phi.shape[0]):
        d.qpos[:], d.qvel[:] = qpos[k], qvel[k]
        mujoco.mj_forward(model, d)
        assert np.abs(d.efc_pos[:d.ne]).max() < STATE_RESIDUAL * size
        assert np.abs(d.efc_vel[:d.ne]).max() < STATE_RESIDUAL * size * omega  # J·q̇ = 0 by MuJoCo's Jacobian
        for link in mech.links:
            for p in link.points:
                got = d.site(site_name(mech, link.name, p)).xpos[:2]
                np.testing.assert_allclose(got, st.point(link.name, shapes[link.name].local[p])[k], rtol=0,
                                           atol=STATE_RESIDUAL * size)


def test_class_three_velocities_are_derivatives_of_positions():
    mech = load(TRIAD)
    phi = np.radians(np.arange(0.0, 360.0, 30.0))
    st, hi, lo = state(mech, phi, 1.0), state(mech, phi + FD_STEP), state(mech, phi - FD_STEP)
    size = mechanism_size(mech)
    for link in mech.moving_links:
        np.testing.assert_allclose(st.velocity[link], (hi.origin[link] - lo.origin[link]) / (2 * FD_STEP),
                                   rtol=0, atol=FD_TOL * size)
        np.testing.assert_allclose(st.angular_velocity[link], (hi.angle[link] - lo.angle[link]) / (2 * FD_STEP),
                                   rtol=0, atol=FD_TOL)


def test_class_three_runs_in_mujoco():
    mech = load(TRIAD)
    model = mujoco.MjModel.from_xml_string(write_mjcf(mech))
    d = mujoco.MjData(model)
    phi0 = math.radians(10.0)
    qpos, qvel = tree_state(mech, model, [phi0], mech.drive.omega)
    d.qpos[:], d.qvel[:] = qpos[0], qvel[0]
    for _ in range(round(0.2 / model.opt.timestep)):  # 0.2 s, about 57° of crank
        mujoco.mj_step(model, d)
    assert not any(w.number for w in d.warning)
    crank = d.body("crank")
    phi = phi0 + np.remainder(math.atan2(crank.xmat[3], crank.xmat[0]) - phi0, 2 * math.pi)
    assert math.radians(40.0) < phi - phi0 < math.radians(80.0)
    st, shapes = state(mech, [phi]), link_shapes(mech)
    for link in mech.moving_links:
        for p, local in shapes[link].local.items():
            np.testing.assert_allclose(d.site(site_name(mech, link, p)).xpos[:2], st.point(link, local)[0], rtol=0,
                                       atol=RUN_TOL * mechanism_size(mech))


def test_pose_errors_are_named():
    d = _dict(TRIAD)
    d["links"]["arm1"]["length"] = 0.5  # the sketch makes it 0.2909 m
    with pytest.raises(DescriptionError, match="points"):
        state(from_dict(d), [0.5])
    d = _dict(TRIAD)  # this geometry assembles only from 16.3° to 34.3° of crank
    d["points"].update(P1=[0.3, 0.4], P2=[0.55, 0.3], P3=[0.35, 0.15], G1=[0.1, 0.6], G2=[0.75, 0.55])
    mech = from_dict(d)
    state(mech, np.radians([20.0, 33.0]))
    with pytest.raises(AssemblyError, match="34.3"):
        state(mech, np.radians([40.0]))


def test_writing_a_model_compiles_it_once(monkeypatch):
    """Deriving the settings and setting the sketch keyframe share one MuJoCo compile: a cam's
    4000-vertex profile mesh costs ~1 s a compile, and the writer compiled it three times."""
    import linkgen.mujoco.mjcf as mjcf_module

    compiles = []
    real = mujoco.MjModel.from_xml_string
    monkeypatch.setattr(mujoco.MjModel, "from_xml_string", lambda *a, **k: compiles.append(1) or real(*a, **k))
    text = mjcf_module.write_mjcf(assemble(load(ROOT / "models" / "fourbar.toml")))
    assert len(compiles) == 1
    assert text == (ROOT / "models" / "fourbar.xml").read_text()  # the same file as before
