"""The MuJoCo side: the MJCF writer (a spanning tree plus loop-closing ``connect``s), settings
derived from the mechanism, the simulation and the read-out of joint forces."""
