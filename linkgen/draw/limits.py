"""The sizes a picture may have, in one place for the drawing code and the command line (which
checks them when it reads its options, without importing MuJoCo or matplotlib)."""

# A MuJoCo frame [px]: MuJoCo's offscreen buffer in the written model is 1280×960 (its
# <visual><global offwidth/offheight>); below 16 px nothing of the mechanism can be seen.
MIN_SIDE = 16
MAX_WIDTH, MAX_HEIGHT = 1280, 960
# Frames of an animation over the drive range: two to move at all; 2000 keeps a GIF under a few
# hundred MB.
MIN_FRAMES, MAX_FRAMES = 2, 2000

__all__ = ["MAX_FRAMES", "MAX_HEIGHT", "MAX_WIDTH", "MIN_FRAMES", "MIN_SIDE"]
