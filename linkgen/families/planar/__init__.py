"""Closed-form planar kinematics and kinetostatics: geometric primitives, Assur groups, the
structural decomposition, assembly, positions/velocities/accelerations/jerks over arrays of crank
angles, joint reactions and the driving torque, and the numeric pose for any structure."""
