"""Spatial four-bars (RSSR, RSSP, RCCC, spherical, Bennett) in closed form: the chain's
geometry, positions to jerk by dual-number jets, Newton–Euler forces and the design summary."""
