"""For tests that signal a child command: start it with SIGINT at its default.

A shell without job control starts a background job with SIGINT ignored, and an ignored SIGINT
is inherited: a ``gear-dyn`` child of a test suite run that way would never see the Ctrl-C the
test sends (Python installs its KeyboardInterrupt handler only where SIGINT is at its default).
Pass :func:`default_ctrl_c` as ``preexec_fn`` to :class:`subprocess.Popen`.
"""

from __future__ import annotations

import signal


def default_ctrl_c() -> None:
    """In the child before exec: SIGINT at its default, as in a terminal."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
