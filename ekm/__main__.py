"""The ``ekm`` console script, and ``python -m ekm``: :func:`ekm.cli.main` with SIGINT and SIGTERM handled
from its first moment (:mod:`ekm.interrupts`).

This module imports nothing but :mod:`ekm.interrupts` before it installs the handler, so that a Ctrl-C in
the first fraction of a second, while the command line's modules load, is handled like any other.
"""

from ekm import interrupts


def console() -> None:
    """Run the command line and exit with its status.

    A stopped command leaves without the interpreter's shutdown: every file it writes is complete or gone by
    then (the ``finally`` blocks have run), and tearing down JAX's threads mid-computation at shutdown can
    crash the process (a segmentation fault after the one line)."""
    interrupts.install(hold=True)  # released once the command has read its arguments (ekm.cli.main)
    import os
    import sys

    from ekm.cli import main

    status = main()
    if interrupts.received() is not None or status in interrupts.STATUS.values():
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    sys.exit(status)


if __name__ == "__main__":
    console()
