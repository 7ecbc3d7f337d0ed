"""The one exception type for bad user input.

Everything a user hands the package — a world file, a map file, a command-line argument — is checked at
the boundary. A problem raises :class:`InputError` with one line naming *what* is wrong and *where*;
the command line prints that line to stderr and exits with status 2 (no traceback).
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad user input: a world file, map file, CLI argument, NaN, wrong shape or wrong version.

    The message is a single line of the form ``"<where>: <what is wrong>"``, e.g.
    ``"worlds/lab.json: obstacles[2].radius: must be > 0, got -0.1"``.
    """

    exit_status = 2


class Interrupted(Exception):
    """The user stopped a long command (Ctrl-C). The message is one line saying what was kept and how to go
    on, e.g. ``"training stopped at step 30000; resume with: ekm train --resume indirect.checkpoint.npz"``;
    the command line prints it and exits with status 130, as a shell does for SIGINT."""

    exit_status = 130
