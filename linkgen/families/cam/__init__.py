"""Cam mechanisms: motion programs (rise–dwell–return laws) and the disc cam with a translating
roller follower by inversion — pitch curve, profile, pressure angle, curvature, base radius."""
