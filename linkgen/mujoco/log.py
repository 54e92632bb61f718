"""Keep MuJoCo's log file out of the user's working directory.

MuJoCo (4.0, engine_util_errmem.c) sends every warning and error to its log handler. The
default handler, unless a legacy ``mju_user_warning``/``mju_user_error`` is installed, appends
the message to ``MjLogConfig.logfile`` — ``MUJOCO_LOG.TXT``, relative, so in the current
working directory — when ``logto_file`` is set (the default), and prints it to stderr. Errors
raised inside Python calls (a model that does not compile, a bad argument) become Python
exceptions through a thread-local handler and write nothing; warnings (``mj_warning``: the
first unstable or diverging step of each kind per MjData, also from ``rollout``'s threads) go
to the global handler and so to the file.

``no_log_file`` turns the file off while linkgen compiles, steps or reads a model, and puts
the previous configuration back afterwards (the setting is global to the process: nested and
concurrent uses share one switch, counted). Warnings still reach stderr, and MjData.warning
keeps counting them, which is what linkgen reports.
"""

from __future__ import annotations

import contextlib
import threading

import mujoco

_lock = threading.Lock()
_depth = 0
_saved: mujoco.MjLogConfig | None = None


class no_log_file(contextlib.ContextDecorator):
    """Context manager and decorator: MuJoCo writes no log file inside (see the module docstring)."""

    def __enter__(self) -> "no_log_file":
        global _depth, _saved
        with _lock:
            if _depth == 0:
                _saved = mujoco.MjLogConfig.get()
                config = mujoco.MjLogConfig.get()
                config.logto_file = False
                config.set()
            _depth += 1
        return self

    def __exit__(self, *exc) -> bool:
        global _depth, _saved
        with _lock:
            _depth -= 1
            if _depth == 0 and _saved is not None:
                _saved.set()
                _saved = None
        return False


__all__ = ["no_log_file"]
