"""Stopping a command with Ctrl-C (SIGINT) or SIGTERM, whenever the signal arrives (imperative shell).

Python turns SIGINT into :class:`KeyboardInterrupt` wherever the main thread happens to be. Raised inside a
callback that C code runs — JAX's garbage-collection hook while it starts up — the exception is printed as
"Exception ignored" and lost, and the job goes on; raised while a C extension initialises (JAX's, in its
first second) it aborts the process. So :func:`install`'s handler *records* the signal, raises only in the
package's own code and sends itself the signal again a moment later when the main thread is in an import,
JAX or pymunk (:data:`UNSAFE`); and the long loops (training chunks, a run's ticks, a comparison's results)
call :func:`check`, which raises once a signal has been received: a signal is never lost. SIGTERM (what a cluster's scheduler or
``kill`` sends) is handled the same way and ends with its own status, 143.

Only the console script installs the handler (:func:`ekm.cli.console`); in a program that imports
``ekm``, :func:`check` never raises and Python's own handling of Ctrl-C is left alone.

The handler starts *held*: a signal is recorded and nothing is raised until the command has read its arguments
and :func:`release` is called — at once for most commands (:func:`ekm.cli.main`), and for a batch that keeps a
results file (``ekm compare --out``) once that file exists (:func:`evaluation.batch.run_batch`), so that its one
line names the file and how to resume whatever the moment of the signal.
"""

from __future__ import annotations

import os
import signal
import sys
import threading

#: Exit status of a command stopped by each signal, as a shell reports it (128 + the signal's number).
STATUS = {signal.SIGINT: 130, signal.SIGTERM: 143}

_received: int | None = None
_held = False


#: Code a KeyboardInterrupt must not be raised in: an import (a C extension's initialisation aborts the
#: process on it), JAX and jaxlib (their C++ callbacks abort or swallow it), pymunk (its C callbacks swallow
#: it). A signal that arrives there is sent again a moment later, until the main thread is out of them.
UNSAFE = ("<frozen importlib", "/jax/", "/jaxlib/", "/pymunk/")
AGAIN_S = 0.05


def _unsafe(frame) -> bool:
    while frame is not None:
        if any(part in frame.f_code.co_filename for part in UNSAFE):
            return True
        frame = frame.f_back
    return False


def _handler(signum, frame) -> None:
    global _received
    if _received is None:
        _received = signum
    if _held:  # release() raises it
        return
    if _unsafe(frame):
        again = threading.Timer(AGAIN_S, os.kill, (os.getpid(), signum))
        again.daemon = True
        again.start()
        return
    raise KeyboardInterrupt


def install(hold: bool = False) -> None:
    """Handle SIGINT and SIGTERM in this (main) thread: record the signal and raise KeyboardInterrupt — with
    ``hold``, only record it until :func:`release`. A KeyboardInterrupt that C code cannot raise (it reports it
    as "Exception ignored in …") is not printed: :func:`check` raises it again."""
    global _held
    _held = hold
    for signum in STATUS:
        signal.signal(signum, _handler)
    default = sys.unraisablehook

    def hook(unraisable) -> None:
        if _received is not None and isinstance(unraisable.exc_value, KeyboardInterrupt):
            return
        default(unraisable)

    sys.unraisablehook = hook


def check() -> None:
    """Raise KeyboardInterrupt if a signal has been received (one that was raised and lost, or none)."""
    if _received is not None:
        raise KeyboardInterrupt


def release() -> None:
    """Stop holding signals (:func:`install`'s ``hold``): from now on they raise, and one received while held
    raises KeyboardInterrupt here. Without the handler (a program that imports ``ekm``), nothing."""
    global _held
    _held = False
    check()


def received() -> int | None:
    """The signal received, if any."""
    return _received


def status() -> int:
    """The exit status for the signal received: 143 for SIGTERM, 130 for SIGINT or a KeyboardInterrupt
    raised some other way."""
    return STATUS.get(_received, 130)


def ignore_in_worker() -> None:
    """In a worker process of a comparison: leave Ctrl-C to the parent, which stops the workers itself
    (a terminal sends SIGINT to every process of the job; a worker's traceback would bury the parent's
    one line)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
