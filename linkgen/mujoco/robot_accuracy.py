"""The accuracy line of the robot build's header (``robot``): MuJoCo's errors at the file's
settings for this mechanism, predicted as ``linkgen check-settings`` predicts them
(``mujoco.accuracy.predict``), what that figure is for (a crank held at ω by a heavy rotor) and
the factors a light crank held by the file's servo shows, or one statement why nothing is
predicted (no loop, a crank not turning forward through the range, another family)."""

from __future__ import annotations

import math

from linkgen.mujoco.options import Settings

# The bundled four-bar (models/fourbar.toml) built with a velocity servo (kv 2e5 N·m·s/rad) held
# at its ω = 10 rad/s at the file's settings, measured over a turn after 1 s against the closed
# form at the reached states: reactions 2.46e-2 and crank torque 6.2e-2 of their peaks, against
# the 8.0e-3 and 1.14e-2 predicted for a crank held by a heavy rotor (the gap 1.46e-3 against
# 1.27e-3): the factors the header quotes for a light crank held by a servo.
SERVO_FACTORS = (3.1, 5.4)
# Past this relative error the prediction, linear in the loop gap, says only "far off": the
# bound check-settings applies (crosscheck.check_settings.LINEAR, measured over the bundled models
# and 20 generated ones; tests/test_robot_build.py holds the two equal).
FAR_OFF = 0.1


def accuracy_comment(source, settings: Settings) -> str:
    """One line of the accuracy MuJoCo gives this mechanism at the file's settings, predicted as
    ``linkgen check-settings`` predicts it (``mujoco.accuracy.predict``: from the closed form's
    loop forces and MuJoCo's constraint model, for the crank turning at the description's ω; no
    MuJoCo step), or why it is not predicted."""
    from linkgen.errors import LinkgenError
    from linkgen.families.planar.assembly import Assembly, assemble
    from linkgen.families.planar.description import Mechanism

    if not isinstance(source, (Mechanism, Assembly)):
        return ("not predicted here (linkgen check-settings predicts planar linkages); linkgen validate with its "
                "practical option measures what MuJoCo's usual settings cost. ")
    mech = source.mechanism if isinstance(source, Assembly) else source
    from linkgen.mujoco.tree import spanning_tree

    if not spanning_tree(mech).closures:
        return ("nothing to predict: the links form a tree with no loop to close, so none of the loop errors linkgen "
                "check-settings predicts arise (no constraint, no gap); the joint torques and reactions are MuJoCo's "
                "rigid-body dynamics, off only by its integration step. ")
    reason = _unpredictable_drive(mech.drive)
    if reason:
        return f"not predicted: {reason}. "
    try:
        asm = source if isinstance(source, Assembly) else assemble(source)
        p = predict_at(asm, settings)
    except LinkgenError as exc:
        return f"not predicted: {exc}. "
    e = p.errors
    return (f"predicted for the crank held at ω = {p.omega:g} rad/s by a heavy rotor (as linkgen check-settings "
            f"predicts and runs it: the closed form's loop forces through MuJoCo's constraint model): loop "
            f"gap {e.gap:.2g} of the size ({e.gap * p.size:.2g} m), point positions {e.position:.2g} of the size, "
            f"reactions {e.reaction:.2g} of the peak reaction, crank torque {e.torque:.2g} of its peak. "
            + (f"Past {FAR_OFF:g} the prediction, linear in the loop gap, says only that these settings are far off "
               "for this mechanism: run linkgen check-settings for the measured figures. " if e.worst > FAR_OFF else "")
            + f"A crank "
            f"with only this file's armature, held at ω by a servo (its position or velocity actuator), keeps the "
            f"gap and the positions but reads larger "
            f"reactions and crank torque (the four-bar at 10 rad/s: {SERVO_FACTORS[0]:g} and {SERVO_FACTORS[1]:g} "
            f"times the figures above). "
            f"linkgen check-settings, given this file's timestep and integrator (2ms, implicitfast) and a tolerance, "
            f"measures them and finds the cheapest settings that meet it. ")


def _unpredictable_drive(drive) -> str | None:
    """Why the prediction cannot follow this drive, or None: it models the crank turning forward
    through the whole drive range from its start at the description's ω > 0 and ε (ω² + 2·ε·Δφ
    above 0 to the range's end); a crank turning backwards, standing or stopping inside the range
    is a state it does not model (its figures there would be meaningless, not small)."""
    end = drive.omega**2 + 2.0 * drive.epsilon * (drive.stop - drive.start)
    if not (math.isfinite(drive.omega) and drive.omega > 0):
        return (f"the prediction follows the crank turning forward through the drive range, and this description's "
                f"drive.omega is {drive.omega:g} rad/s (give a speed above 0 to have MuJoCo's accuracy stated)")
    if not end > 0:
        return (f"the prediction follows the crank turning forward through the whole drive range, and at drive.omega "
                f"{drive.omega:g} rad/s and drive.epsilon {drive.epsilon:g} rad/s² it stops before the range's end")
    return None


def predict_at(asm, settings: Settings):
    """``mujoco.accuracy.predict`` at ``settings`` with the rotor inertia that holds the crank at
    the description's ω (as ``check-settings`` runs it)."""
    from dataclasses import replace

    import mujoco

    from linkgen.mujoco.accuracy import predict
    from linkgen.mujoco.log import no_log_file
    from linkgen.mujoco.mjcf import _write
    from linkgen.mujoco.options import PLACEHOLDER
    from linkgen.mujoco.settings import derive

    mech = asm.mechanism
    with no_log_file():
        model = mujoco.MjModel.from_xml_string(_write(asm, PLACEHOLDER, keyframe=False))  # derive needs no keyframe
    validation, _ = derive(asm, model, omega=mech.drive.omega, epsilon=mech.drive.epsilon)
    return predict(asm, replace(settings, armature=validation.armature))


__all__ = ["FAR_OFF", "SERVO_FACTORS", "accuracy_comment", "predict_at"]
