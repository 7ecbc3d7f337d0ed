"""The trap monitor (evaluation.monitor): progress and a new checkpoint reset it; the ground rule lets a detour
finish and stops a robot circling in place."""

import numpy as np
import pytest

from evaluation.monitor import TrapMonitor


def test_the_trap_monitor_resets_on_progress_and_on_a_new_checkpoint():
    m = TrapMonitor(after=2.0, progress=0.01)
    assert not m.update(0.0, 1.0)
    assert not m.update(1.9, 0.995)  # less than 1 cm closer: no progress yet
    assert m.update(2.0, 0.995)
    m.reset(2.0)
    assert not m.update(3.0, 0.9) and not m.update(4.5, 0.89) and m.update(5.0, 0.895)


def test_the_monitor_lets_a_scripted_detour_finish():
    """A robot 0.3 m from its checkpoint drives 1 m away from it and back round (a blocked door's detour, 13 s
    away from the checkpoint at 8 cm/s): every 5 cm square it enters is new, so with after = 5 s it is never
    trapped; the same monitor without the ground rule fires 5 s after the robot last came closer."""
    checkpoint = np.array([0.3, 0.0])
    path = [np.array([0.0, 0.0]) + (0.08 * t) * np.array([-1.0, 0.0]) for t in np.arange(0.0, 12.5, 0.128)]
    path += [path[-1] + (0.08 * t) * np.array([0.0, 1.0]) for t in np.arange(0.128, 5.0, 0.128)]
    with_ground, distance_only = TrapMonitor(5.0, 0.01, ground=0.05), TrapMonitor(5.0, 0.01, ground=None)
    fired = [(with_ground.update(0.128 * i, float(np.linalg.norm(p - checkpoint)), p),
              distance_only.update(0.128 * i, float(np.linalg.norm(p - checkpoint)), p)) for i, p in enumerate(path)]
    assert not any(a for a, _ in fired)
    first = next(i for i, (_, b) in enumerate(fired) if b)
    assert 0.128 * first == pytest.approx(5.0, abs=0.13)  # never closer than at the start: 5 s after it


def test_the_monitor_stops_a_robot_circling_in_place():
    """Circling 2 cm round the middle of a 5 cm square (a full circle every 2 s), 0.5 m from the checkpoint: it
    never leaves that square, and it comes closest (0.48 m) at the start, so the monitor fires at the first
    update 5 s after the start."""
    m = TrapMonitor(5.0, 0.01, ground=0.05)
    centre, checkpoint = np.array([0.525, 0.525]), np.array([1.025, 0.525])
    for i in range(200):
        t = 0.128 * i
        p = centre + 0.02 * np.array([np.cos(np.pi * t), np.sin(np.pi * t)])
        if m.update(t, float(np.linalg.norm(p - checkpoint)), p):
            break
    assert t == pytest.approx(0.128 * 40)  # the first update at or after 5 s
