"""A linkage with cam pairs in MuJoCo against its closed form.

The crank turns by its rotor inertia from the closed-form state at the sketch; after a settling
eighth of a turn every step of one turn is compared at MuJoCo's own crank angle: each follower's
coordinate δ (relative to its stroke) and every moving point's position (relative to the largest
extent of a point's path), at every step; each cam's contact force and the balancing torque as
means over WINDOWS equal parts of the turn (relative to their peaks). The tolerances are the
stand-alone cam's (``linkgen.mujoco.cam.CAM_TOLERANCES``): the contact is the same, and its
faceted profile, not the linkage, sets the error.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import mujoco
import numpy as np

from linkgen.errors import SimulationError, angle_ranges
from linkgen.mujoco.cam import CAM_TOLERANCES, PROFILE_POINTS, WINDOWS
from linkgen.mujoco.cam_run import unstable, window_means
from linkgen.mujoco.cam_pair import roller_name
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.mjcf import settings_for, write_mjcf
from linkgen.mujoco.options import MAX_STEPS, within_budget
from linkgen.mujoco.sample import moving_points
from linkgen.mujoco.simulate import PROGRESS_AFTER
from linkgen.mujoco.scene import switch_off_servo
from linkgen.mujoco.state import joint_state
from linkgen.mujoco.tree import site_name
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.cam_pair import ground_pair, lift, sense
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces

# Crank angles over a turn at which the closed form's contact force is checked for leaving the cam.
SCAN = 3600
# Steps between progress reports (about a second of the run on this machine's cores).
PROGRESS_STEPS = 2500


@dataclass(frozen=True)
class CamLinkageCheck:
    """Relative errors by quantity (``errors``: name → (error, tolerance)), steps, timestep [s],
    wall time [s]."""

    model: str
    errors: dict
    steps: int
    timestep: float
    wall: float
    # per compared step: each quantity's error relative to its scale (a force's, its window's), and
    # each cam's contact (``contact_trace``); for the diagnosis (``crosscheck.diagnose_cam``)
    curves: dict = field(default_factory=dict, repr=False)
    contacts: dict = field(default_factory=dict, repr=False)
    # what missed, where and why (``crosscheck.diagnose_cam.cam_linkage_findings``; filled by
    # ``crosscheck.cam.check_cam_linkage``)
    diagnosis: tuple = ()
    # the cam pair each cam quantity belongs to (quantity name → the cam's name)
    cams: dict = field(default_factory=dict, repr=False)

    @property
    def ok(self) -> bool:
        return all(e <= tol for e, tol in self.errors.values())

    def summary(self, wall: str | None = None) -> str:
        """One line; ``wall``: the wall time as the caller measured it (default: this check's)."""
        parts = ", ".join(f"{k} {e:.2e} (tolerance {t:g})" for k, (e, t) in
                          sorted(self.errors.items(), key=lambda kv: -kv[1][0] / kv[1][1]))
        return (f"{'ok  ' if self.ok else 'FAIL'} linkage with a cam in MuJoCo (contact with a {PROFILE_POINTS}-vertex "
                f"profile; forces as {360 / WINDOWS:g}° means): {parts}; {self.steps} steps, "
                f"{wall or f'{self.wall:.2f} s'}")

    def to_json(self) -> dict:
        return self.to_dict()

    @property
    def settings(self) -> dict:
        """The run's timestep [s]."""
        return {"timestep": self.timestep}

    @property
    def quantities(self) -> dict:
        """Each compared quantity as ``mujoco.result_shape`` gives it."""
        from linkgen.mujoco.result_shape import quantity

        return {k: quantity(e, t) for k, (e, t) in self.errors.items()}

    # The cam's contact is compared on its own here, without a loop gap.
    loop_gap = None

    def to_dict(self) -> dict:
        """The result as ``linkgen validate --json`` gives it (``mujoco.result_shape``; the cam's
        contact, compared without a loop gap), with ``cam_linkage``: how the contact was modelled."""
        from linkgen.mujoco.result_shape import validation

        return validation(self.model, self.ok, settings=self.settings, quantities=self.quantities, loop_gap=None,
                          diagnosis=self.diagnosis, steps=self.steps, wall_s=self.wall,
                          cam_linkage={"windows": WINDOWS, "profile_points": PROFILE_POINTS})


def _check_contact(asm: Assembly) -> None:
    """The closed form's contact force must stay ≥ 0 over the turn, or MuJoCo's follower leaves the cam."""
    mech = asm.mechanism
    phi = asm.sketch_phi + np.linspace(0.0, 2 * math.pi, SCAN, endpoint=False)
    f = forces(asm, phi, mech.drive.omega, 0.0)
    for name, n in f.contact.items():
        if np.any(n < 0):
            ranges = ", ".join(f"{math.degrees(a):.1f}°..{math.degrees(b):.1f}°" for a, b in angle_ranges(phi, n < 0)[:3])
            raise SimulationError(f"cam {name!r}: the follower would leave the cam at crank angles {ranges} (contact force "
                                  f"down to {n.min():.3g} N at ω = {mech.drive.omega:g} rad/s); a stronger spring "
                                  f"(spring_preload, spring_rate) or a lower speed keeps it on")


@no_log_file()
def check_cam_linkage(asm: Assembly, progress=None, max_steps: int = MAX_STEPS) -> CamLinkageCheck:
    """Run one turn in MuJoCo and compare it with the closed form (module docstring);
    ``progress(fraction done, seconds elapsed)`` is called every PROGRESS_STEPS steps once the
    run has lasted PROGRESS_AFTER seconds. A run past ``max_steps`` steps is refused before it starts."""
    wall0 = time.perf_counter()
    mech = asm.mechanism
    _check_contact(asm)
    w0 = mech.drive.omega
    settings = settings_for(asm)  # derived with the cam's timestep (mujoco.settings.derive)
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, settings))
    switch_off_servo(model)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:], _ = joint_state(asm, model, asm.sketch_phi, w0, 0.0)
    drive = model.joint(mech.drive.joint)
    dt = model.opt.timestep
    per_turn = int(round(2 * math.pi / w0 / dt))
    lead = per_turn // 8
    within_budget(mech.name, lead + per_turn, dt, max_steps)
    names = moving_points(mech)
    sites = [model.site(site_name(mech, next(l.name for l in mech.links if p in l.points), p)).id for p in names]
    rollers = {cam.name: model.geom(roller_name(cam)).id for cam in mech.cams}
    joints = {cam.name: model.joint(ground_pair(mech, cam)[1].name) for cam in mech.cams}
    phi, om, ep = (np.zeros(per_turn) for _ in range(3))
    pts = np.zeros((per_turn, len(names), 2))
    q = {c: np.zeros(per_turn) for c in rollers}
    normal, depth = ({c: np.zeros(per_turn) for c in rollers} for _ in range(2))
    touching = {c: np.zeros(per_turn, dtype=bool) for c in rollers}
    force6 = np.zeros(6)
    for k in range(lead + per_turn):
        if k >= lead:
            i = k - lead
            mujoco.mj_forward(model, data)
            phi[i] = data.qpos[drive.qposadr[0]] + asm.sketch_phi
            om[i], ep[i] = data.qvel[drive.dofadr[0]], data.qacc[drive.dofadr[0]]
            pts[i] = data.site_xpos[sites, :2]
            for c, gid in rollers.items():
                q[c][i] = data.qpos[joints[c].qposadr[0]]
                for j in range(data.ncon):
                    con = data.contact[j]
                    if gid in (con.geom1, con.geom2):
                        mujoco.mj_contactForce(model, data, j, force6)
                        normal[c][i] += force6[0]
                        touching[c][i], depth[c][i] = True, max(depth[c][i], -float(con.dist))
        t = data.time + model.opt.timestep  # the step's end (data.time restarts with a reset)
        mujoco.mj_step(model, data)
        if progress is not None and k and k % PROGRESS_STEPS == 0 and time.perf_counter() - wall0 > PROGRESS_AFTER:
            progress(k / (lead + per_turn), time.perf_counter() - wall0)
        if not np.isfinite(data.qvel).all() or unstable(data):
            raise SimulationError(f"{mech.name}: MuJoCo diverged at t = {t:.6g} s (step {k}){unstable(data)}")
    kin = solve(asm, phi)
    fc = forces(asm, phi, om, ep)
    curves, contacts, tol, cams = {}, {}, {}, {}
    for cam in mech.cams:
        sig = sense(mech, asm.shapes, cam)
        delta = lift(cam, phi - asm.sketch_phi)[0]
        stroke = float(np.ptp(lift(cam, np.linspace(0.0, 2 * math.pi, SCAN))[0])) or 1.0
        # named as analyze names them: the follower's displacement, the contact force on it
        moved, pushed = f"followers.{cam.follower}.displacement", f"contact.{cam.name}.normal_force"
        curves[moved] = np.abs(sig * q[cam.name] - delta) / stroke
        curves[pushed] = _windowed(normal[cam.name], fc.contact[cam.name])
        tol |= {moved: CAM_TOLERANCES["displacement"], pushed: CAM_TOLERANCES["contact_force"]}
        cams |= {moved: cam.name, pushed: cam.name}
        contacts[cam.name] = {"theta": phi - asm.sketch_phi, "touching": touching[cam.name], "force": normal[cam.name],
                              "force_closed": fc.contact[cam.name], "penetration": depth[cam.name],
                              "step_angle": abs(w0) * dt,
                              "travel": float(np.hypot(*np.ptp(kin.points[cam.roller].p, axis=0))) or 1.0}
    ref = np.stack([kin.points[p].p for p in names], axis=1)
    extent = max(float(np.hypot(*np.ptp(ref[:, j], axis=0))) for j in range(len(names))) or 1.0
    curves["points"] = np.abs(pts - ref).max(axis=(1, 2)) / extent
    curves["balancing_torque"] = _windowed(-settings.armature * ep, fc.balancing_torque)
    tol |= {"points": CAM_TOLERANCES["displacement"], "balancing_torque": CAM_TOLERANCES["cam_torque"]}
    errors = {k: (float(v.max()), tol[k]) for k, v in curves.items()}
    return CamLinkageCheck(mech.name, errors, lead + per_turn, dt, time.perf_counter() - wall0, curves, contacts,
                           cams=cams)


def _windowed(mj: np.ndarray, cf: np.ndarray) -> np.ndarray:
    """Per step, its window's error: the difference of the means of ``mj`` and ``cf`` over each of
    WINDOWS equal parts of the turn, relative to the peak of ``cf`` (steps past the last whole
    window: 0)."""
    a, b = window_means(mj, WINDOWS), window_means(cf, WINDOWS)
    per = mj.shape[0] // WINDOWS
    out = np.zeros(mj.shape[0])
    out[:per * WINDOWS] = np.repeat(np.abs(a - b) / (float(np.abs(cf).max()) or 1.0), per)
    return out


__all__ = ["CamLinkageCheck", "check_cam_linkage"]
