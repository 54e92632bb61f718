"""MuJoCo against the closed form, for every family: tolerances met or missed per named
quantity, the diagnosis of what missed and why, the cost of practical settings, and a machine's
MuJoCo run against its ODE. (The report that gathers them: ``linkgen.report``.)"""
