"""Seeing the mechanism: skeleton drawings, position plans, animations and MuJoCo frames."""
