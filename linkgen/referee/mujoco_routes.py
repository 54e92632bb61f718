"""MuJoCo's two routes at the user's crank angles, for planar linkages (``referee --mujoco``).

- forward: MuJoCo drives the crank over its range (settings derived from the mechanism, as
  ``validate`` runs it) and samples its own states; its difference from the closed form at those
  states is carried to the user's angles (interpolated in φ, the difference being small and
  smooth) and added to the closed form there. So the route's values are MuJoCo's, at the user's
  angles, without interpolating the quantities themselves;
- inverse: ``mj_inverse`` at the closed form's joint state at each of the user's angles, the
  loop forces recovered on the constraint Jacobian (``mujoco.forces.inverse_forces``): the
  reactions and the balancing torque.

Keys are the headers ``linkgen analyze``/``forces`` write; a quantity MuJoCo does not give
(jerks, transfer functions, the reduced inertia's derivative) is absent."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import UnsupportedError
from linkgen.referee.reference import Reference
from linkgen.referee.table import split_header

# Samples of the forward run over the drive range: the difference MuJoCo − closed form varies
# over a crank turn like the quantities themselves, so 720 samples (0.5°) interpolate it to
# ~1e-5 of its own size, far under the size that decides agreement.
FORWARD_SAMPLES = 720


def routes(ref: Reference, phi: np.ndarray, keys: list[str], progress=None) -> dict[str, dict[str, np.ndarray]]:
    """key → {"mujoco_forward": (n,), "mujoco_inverse": (n,)} for the keys MuJoCo gives;
    ``progress`` (a callable taking one line) is told when the runs start."""
    asm = ref.desc
    if not hasattr(asm, "structure"):
        raise UnsupportedError("referee --mujoco: MuJoCo's forward and inverse routes are compared for planar "
                               "linkages; for this family, compare with the closed form (without --mujoco)")
    from linkgen.families.planar.forces_result import forces
    from linkgen.families.planar.motion_result import kinematics
    from linkgen.mujoco.simulate import simulate

    if progress is not None:
        progress("running MuJoCo over the drive range (forward) and at your angles (inverse)")
    run = simulate(asm, omega=ref.omega, epsilon=ref.epsilon, samples=FORWARD_SAMPLES)
    s = run.samples
    mj = _split(s.arrays())
    cf = kinematics(asm, s.crank[0], s.crank[1], s.crank[2]).columns() | forces(asm, s.crank[0], s.crank[1],
                                                                                s.crank[2]).columns()
    here = ref.evaluate(phi, [k for k in keys if split_header(k)[0] in mj])
    out: dict[str, dict[str, np.ndarray]] = {}
    for key, values in here.items():
        name = split_header(key)[0]
        diff = mj[name] - cf[key]
        if name.endswith("angle"):
            diff = (diff + math.pi) % (2 * math.pi) - math.pi
        out[key] = {"mujoco_forward": values + _carry(s.crank[0], diff, phi, asm)}
    for key, values in _inverse(asm, run.model, phi, ref.omega, ref.epsilon).items():
        if key in keys:
            out.setdefault(key, {})["mujoco_inverse"] = values
    return out


def _split(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    out = {}
    for k, v in arrays.items():
        if v.ndim == 2 and v.shape[1] == 2:
            out[f"{k}.x"], out[f"{k}.y"] = v[:, 0], v[:, 1]
        elif v.ndim == 1:
            out[k] = v
    return out


def _carry(phi_mj: np.ndarray, diff: np.ndarray, phi: np.ndarray, asm) -> np.ndarray:
    """``diff`` sampled at MuJoCo's crank angles, at the user's (periodic over a full-turn range;
    NaN outside a partial range)."""
    d = asm.mechanism.drive
    if d.stop - d.start >= 2 * math.pi - 1e-12:
        x = np.mod(phi_mj, 2 * math.pi)
        o = np.argsort(x)
        return np.interp(np.mod(phi, 2 * math.pi), x[o], diff[o], period=2 * math.pi)
    o = np.argsort(phi_mj)
    x, y = phi_mj[o], diff[o]
    return np.where((phi >= x[0]) & (phi <= x[-1]), np.interp(phi, x, y), np.nan)


def _inverse(asm, model, phi: np.ndarray, omega: float, epsilon: float) -> dict[str, np.ndarray]:
    import mujoco

    from linkgen.mujoco.forces import ForceSamples, inverse_forces
    from linkgen.mujoco.state import joint_states

    n = phi.shape[0]
    qpos, qvel, qacc = joint_states(asm, model, phi, np.full(n, omega), np.full(n, epsilon))
    data = mujoco.MjData(model)
    f = ForceSamples.stack([inverse_forces(asm, model, data, float(phi[k]), qpos[k], qvel[k], qacc[k])
                            for k in range(n)])
    out = {"balancing_torque [N·m]": f.balancing_torque}
    for j, r in f.reactions.items():
        out[f"{j}.force.x [N]"], out[f"{j}.force.y [N]"] = r[:, 0], r[:, 1]
    out |= {f"{s}.normal_force [N]": v for s, v in f.normal_force.items()}
    out |= {f"{s}.moment [N·m]": v for s, v in f.moment.items()}
    return out
