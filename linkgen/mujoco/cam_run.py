"""A cam mechanism's run in MuJoCo (``mujoco.cam`` writes its model) and its comparison with the
closed form: every step of a turn from the closed-form state, the follower's displacement at
every step, the contact force and the cam torque as means over a few degrees of cam turn (and at
every step, beside them)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.errors import SimulationError
from linkgen.families.cam.description import CamMechanism
from linkgen.families.cam.kinetics import state
from linkgen.mujoco import cam
from linkgen.mujoco.cam import CAM, CONTACT, FOLLOWER, INTEGRATOR, PROGRESS_STEPS, WINDOWS, cam_mjcf


# MuJoCo's warnings that its state blew up: it then restarts the model from qpos0 and the run goes
# on, finite but meaningless (a cam scaled with its masses kept was "compared" at 1e302 of its stroke).
UNSTABLE = (mujoco.mjtWarning.mjWARN_BADQACC, mujoco.mjtWarning.mjWARN_BADQVEL, mujoco.mjtWarning.mjWARN_BADQPOS)


def unstable(data: mujoco.MjData) -> str:
    """Why MuJoCo's run blew up (": MuJoCo flagged …"), or "" while it has not."""
    bad = [w.name[len("mjWARN_"):] for w in UNSTABLE if data.warning[w].number]
    return f": MuJoCo flagged {', '.join(bad)} and restarted the model from its initial state" if bad else ""


@dataclass(frozen=True)
class CamRun:
    """MuJoCo at every step of the compared turn: cam angle θ [rad], cam speed [rad/s], the
    follower's coordinate from its lowest position q (m or rad) with its velocity and
    acceleration in time, the contact normal force [N], the cam torque from the contact [N·m] and
    the contact's penetration [m] (0 where the roller is off the cam: ``touching`` False); steps
    and timestep [s]."""

    theta: np.ndarray
    omega: np.ndarray
    displacement: np.ndarray
    contact_force: np.ndarray
    cam_torque: np.ndarray
    steps: int
    timestep: float
    velocity: np.ndarray | None = None
    acceleration: np.ndarray | None = None
    penetration: np.ndarray | None = None
    touching: np.ndarray | None = None


def run_cam(cm: CamMechanism, revolutions: float = 1.0, progress=None, max_steps: int | None = None,
            mjcf_text: str | None = None) -> CamRun:
    """Turn the cam from θ = 0 at ω, the follower starting on the cam at its closed-form state;
    record every step over ``revolutions`` turns after a settling eighth of a turn.
    ``progress(fraction done, seconds elapsed)`` is called every PROGRESS_STEPS steps once the
    run has lasted PROGRESS_AFTER seconds. A run past ``max_steps`` steps (default
    ``mujoco.options.MAX_STEPS``) is refused before it starts. ``mjcf_text``: the model to run
    (default ``cam_mjcf(cm)``; validation/cam_contact.py runs variants of it)."""
    import time

    from linkgen.mujoco.log import no_log_file
    from linkgen.mujoco.options import MAX_STEPS, PROGRESS_AFTER, within_budget  # read at call time (tests lower it)

    wall0 = time.perf_counter()

    f = cm.follower
    with no_log_file():
        model = mujoco.MjModel.from_xml_string(cam_mjcf(cm) if mjcf_text is None else mjcf_text)
        data = mujoco.MjData(model)
        cam_q, fol = model.joint(CAM), model.joint(FOLLOWER)
        st = state(cm, [0.0])
        sign = 1.0 if f.kind == "translating" else -1.0
        data.qpos[fol.qposadr[0]] = sign * st.displacement[0]
        data.qvel[cam_q.dofadr[0]] = cm.omega
        data.qvel[fol.dofadr[0]] = sign * st.velocity[0]
        dt = model.opt.timestep
        per_turn = round(2 * math.pi / cm.omega / dt)
        lead = per_turn // 8
        total = lead + int(round(revolutions * per_turn))
        within_budget(cm.name, total, dt, MAX_STEPS if max_steps is None else max_steps)
        out = np.zeros((total - lead, 9))
        roller, profile = model.geom(CONTACT).id, model.geom("cam:profile").id
        force6 = np.zeros(6)
        for k in range(total):
            if k >= lead:
                mujoco.mj_forward(model, data)
                n_sum, torque, depth, touching = 0.0, 0.0, 0.0, 0.0
                for c in range(data.ncon):
                    con = data.contact[c]
                    if roller not in (con.geom1, con.geom2):
                        continue
                    touching, depth = 1.0, max(depth, -float(con.dist))
                    mujoco.mj_contactForce(model, data, c, force6)
                    on_cam = force6[0] * con.frame[:3] * (1.0 if con.geom2 == profile else -1.0)
                    n_sum += float(force6[0])
                    torque -= float(con.pos[0] * on_cam[1] - con.pos[1] * on_cam[0])  # the drive balances it
                out[k - lead] = (float(data.qpos[cam_q.qposadr[0]]), float(data.qvel[cam_q.dofadr[0]]),
                                 sign * float(data.qpos[fol.qposadr[0]]), n_sum, torque,
                                 sign * float(data.qvel[fol.dofadr[0]]), sign * float(data.qacc[fol.dofadr[0]]), depth,
                                 touching)
            t = data.time + dt  # the step's end (data.time restarts with a reset)
            mujoco.mj_step(model, data)
            if progress is not None and k and k % PROGRESS_STEPS == 0 and time.perf_counter() - wall0 > PROGRESS_AFTER:
                progress(k / total, time.perf_counter() - wall0)
            if not np.isfinite(data.qvel).all() or unstable(data):
                raise SimulationError(f"the cam mechanism diverged in MuJoCo at t = {t:.6g} s{unstable(data)}")
    return CamRun(out[:, 0], out[:, 1], out[:, 2], out[:, 3], out[:, 4], total, dt, out[:, 5], out[:, 6], out[:, 7],
                  out[:, 8] > 0)


def window_means(x: np.ndarray, windows: int) -> np.ndarray:
    """Means of ``x`` over ``windows`` equal parts (its last few samples past them left out)."""
    n = (x.shape[0] // windows) * windows
    return x[:n].reshape(windows, -1).mean(axis=1)


def compare_cam(cm: CamMechanism, windows: int = WINDOWS, run: CamRun | None = None) -> dict:
    """MuJoCo against the closed form at MuJoCo's own cam angles and speeds: the follower's
    displacement at every step (relative to the stroke), and the contact force and cam torque as
    means over ``windows`` equal parts of the turn (relative to their peaks) — the faceted profile
    makes the roller's contact a train of small impacts, whose mean is the smooth force.
    ``run``: a run already made (default: one turn, ``run_cam``); ``crosscheck.diagnose_cam``
    says why a quantity missed."""
    run = run_cam(cm) if run is None else run
    ref = state(cm, run.theta, float(np.mean(run.omega)))
    q = cm.follower.output(run.theta)[0]
    errs = {"displacement": float(np.abs(run.displacement - q).max() / max(float(np.ptp(q)), 1e-300))}
    for name, mj, cf in (("contact_force", run.contact_force, ref.contact_force),
                         ("cam_torque", run.cam_torque, ref.cam_torque)):
        a, b = window_means(mj, windows), window_means(cf, windows)
        errs[name] = float(np.abs(a - b).max() / (float(np.abs(cf).max()) or 1.0))
        errs[name + "_instantaneous"] = float(np.abs(mj - cf).max() / (float(np.abs(cf).max()) or 1.0))
    return {"model": cm.name, "kind": cm.follower.kind, "errors_relative": errs, "steps": run.steps,
            "timestep": run.timestep,
            "integrator": INTEGRATOR, "windows": windows, "profile_points": cam.PROFILE_POINTS}  # read at call time


__all__ = ["UNSTABLE", "CamRun", "compare_cam", "run_cam", "unstable", "window_means"]
