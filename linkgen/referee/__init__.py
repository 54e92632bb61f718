"""The referee: a solver author's results against linkgen's closed form and MuJoCo, with a
diagnosis of every difference (``compare.referee``), its report (``report``) and the reference
suite a solver author takes home (``suite``). It reads the mechanism's stages through the
registry (``pipeline``) and MuJoCo's routes through ``crosscheck``/``mujoco``."""

import sys
import types


class _Package(types.ModuleType):
    """This package, callable as ``linkgen.referee(mech, table, ...)``: importing a submodule sets
    the attribute ``linkgen.referee`` to the package, over the API's function of that name, so
    the package answers the call the same way (``compare.referee``, with the API's checks)."""

    def __call__(self, source, table, **options):
        from linkgen.referee.compare import referee

        return referee(source, table, **options)


sys.modules[__name__].__class__ = _Package
