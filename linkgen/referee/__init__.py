"""The referee: a solver author's results against linkgen's closed form and MuJoCo, with a
diagnosis of every difference (``compare.referee``), its report (``report``) and the reference
suite a solver author takes home (``suite``). It reads the mechanism's stages through the
registry (``pipeline``) and MuJoCo's routes through ``crosscheck``/``mujoco``."""
