"""The trap monitor (evaluation.monitor): progress and a new checkpoint reset it; the ground rule lets a detour
finish and stops a robot circling in place."""

import math

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


# --------------------------------------------------------------------------- issue 35: loops

def square_loop(laps: float, side: float = 0.5, speed: float = 0.16, dt: float = 0.128):
    """Positions every ``dt`` of a robot driving ``laps`` times round the square of ``side`` from (1, 1)
    counter-clockwise at ``speed``: a loop of 4 x side = 2 m, one lap in 12.5 s at 0.16 m/s."""
    corners = np.array([[1, 1], [1 + side, 1], [1 + side, 1 + side], [1, 1 + side]], float)
    out = []
    for k in range(int(laps * 4 * side / (speed * dt)) + 1):
        s = (k * speed * dt) % (4 * side)
        leg = int(s // side)
        out.append(corners[leg] + (s - leg * side) * (corners[(leg + 1) % 4] - corners[leg]) / side)
    return out


def first_fired(monitor, path, checkpoint, dt=0.128):
    for i, p in enumerate(path):
        if monitor.update(dt * i, float(np.linalg.norm(p - checkpoint)), p):
            return dt * i
    return None


def test_a_robot_scripted_round_a_2_m_loop_twice_is_stopped():
    """Round a 2 m square twice at 0.16 m/s (25 s), the checkpoint at (3, 3): it comes closest at the far corner
    (1.5, 1.5), 1 m into the first lap, and never closer. From the end of the first lap (2 m, 12.5 s) every metre is
    on old ground, so with loop = 1.5 m the monitor fires 1.5 m later: at 3.5 m, 21.9 s, in the second lap. The time
    rule alone (after = 20 s) waits for 20 s after the last new square, which the first lap ends on: 32.5 s, after
    the two laps are over -- the loop the issue saw go on for the whole time limit."""
    checkpoint, path = np.array([3.0, 3.0]), square_loop(2.0)
    t = first_fired(TrapMonitor(20.0, 0.01, ground=0.05, loop=1.5), path, checkpoint)
    assert t == pytest.approx(3.5 / 0.16, abs=0.6)
    assert first_fired(TrapMonitor(20.0, 0.01, ground=0.05, loop=None), path, checkpoint) is None


def test_a_scripted_long_detour_onto_new_ground_is_not_stopped():
    """From (0, 0), 3 m straight away from the checkpoint at (3, 0), 0.3 m across, and 6 m back on the parallel
    line to x = 3 (56 s at 0.16 m/s): the distance grows for 19 s, longer than after = 15 s, and the robot drives
    9 m, six times the loop length, but every 5 cm square it enters is new -- never stopped."""
    checkpoint = np.array([3.0, 0.0])
    corners = [np.array(c, float) for c in ([0, 0], [-3, 0], [-3, 0.3], [3, 0.3])]
    path = []
    for a, b in zip(corners, corners[1:]):
        n = int(np.linalg.norm(b - a) / (0.16 * 0.128))
        path += [a + (b - a) * k / n for k in range(n)]
    assert first_fired(TrapMonitor(15.0, 0.01, ground=0.05, loop=1.5), path, checkpoint) is None
    # driving back over the outward line instead (the 0.3 m across squashed to a 1.9 s stop at (-3, 0)) is old
    # ground, never closer than the start until x > 0: the monitor fires 1.5 m into it, at (3 + 0.3 + 1.5) / 0.16 s
    back = [p * np.array([1, 0]) for p in path]
    t = first_fired(TrapMonitor(15.0, 0.01, ground=0.05, loop=1.5), back, checkpoint)
    assert t == pytest.approx(4.8 / 0.16, abs=0.6)


def test_heading_back_to_a_checkpoint_aimed_at_before_is_not_progress():
    """A robot that turns back and forth between checkpoints 0 and 1 every second, standing still 0.8 m from one and
    1.0 m from the other (ground off): each is measured afresh the first time it is aimed at (0 s and 1 s), never
    again, so the time-out runs from the last progress, the first distance to 1 at 1 s: trapped at 21 s. Had every
    change of checkpoint reset the monitor, it would never fire."""
    m = TrapMonitor(after=20.0, progress=0.01, ground=None)
    fired = []
    for k in range(30):
        index = k % 2
        if k:
            m.aim(index, float(k))
        fired.append(m.update(float(k), 0.8 if index == 0 else 1.0))
    assert fired.index(True) == 21


def test_the_monitor_remembers_the_last_eight_checkpoints_aimed_at():
    """Checkpoints 0, 1, …, 9 aimed at in turn, each left 0.5 m away: back to 2 (left eight aims ago) its 0.5 m comes
    back, so 0.495 m is no progress; back to 0 (nine ago, forgotten) is measured afresh; a new plan forgets all."""
    m = TrapMonitor(after=20.0, progress=0.01, ground=None)
    m.update(0.0, 0.5)
    for i in range(1, 10):
        m.aim(i, float(i))
        m.update(float(i), 0.5)
    m.aim(2, 10.0)
    assert m.best == 0.5 and m.since == 9.0
    m.aim(0, 11.0)
    assert m.best == math.inf and m.since == 11.0
    m.reset(12.0)
    m.aim(3, 12.0)
    assert m.best == math.inf
