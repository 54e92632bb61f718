"""Machine dynamics: the crank driven by a motor instead of a prescribed speed — the one- and
two-mass machine over time, its steady cycle and speed fluctuation, and flywheel sizing."""
