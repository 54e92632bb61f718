"""The description of a mechanism: frozen dataclasses, the TOML reader, units, the checks a
description must pass, float64 limits and mass properties from geometry. Nothing here solves."""
