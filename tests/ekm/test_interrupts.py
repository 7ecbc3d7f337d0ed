"""Signals in the console script (ekm.interrupts): where a KeyboardInterrupt may be raised, and a signal that
was received but not raised is raised by check()."""

import sys

import pytest

from ekm import interrupts


def frame_in(filename: str):
    """A frame whose code comes from ``filename`` (called from this test's frame)."""
    namespace = {"sys": sys}
    exec(compile("def here():\n    return sys._getframe()\n", filename, "exec"), namespace)
    return namespace["here"]()


@pytest.mark.parametrize("filename, unsafe", [
    ("/site-packages/jax/_src/lib/__init__.py", True),   # JAX's gc callback
    ("/site-packages/jaxlib/xla_client.py", True),
    ("<frozen importlib._bootstrap>", True),               # an import: a C extension may be initialising
    ("/site-packages/pymunk/space.py", True),              # pymunk's C callbacks
    ("/work/ekm/training/run.py", False),
    ("/usr/lib/python3.11/concurrent/futures/_base.py", False),
])
def test_a_keyboard_interrupt_is_raised_only_outside_imports_jax_and_pymunk(filename, unsafe):
    assert interrupts._unsafe(frame_in(filename)) is unsafe


def test_check_raises_once_a_signal_was_received_and_the_status_names_it(monkeypatch):
    import signal

    monkeypatch.setattr(interrupts, "_received", None)
    interrupts.check()  # nothing received: nothing happens
    assert interrupts.status() == 130
    monkeypatch.setattr(interrupts, "_received", signal.SIGTERM)
    with pytest.raises(KeyboardInterrupt):
        interrupts.check()
    assert interrupts.status() == 143
    monkeypatch.setattr(interrupts, "_received", signal.SIGINT)
    assert interrupts.status() == 130
