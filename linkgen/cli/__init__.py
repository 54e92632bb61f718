"""The ``linkgen`` command: one module per command group (closed-form, forces, MuJoCo)."""
