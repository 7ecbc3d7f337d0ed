"""The package's docstrings and comments state contracts, not history: no timings, no references to speed
rounds, and no document a user does not have (docs/design.md §7: figures live in docs/performance.md,
made by benchmarks/).

Durations that are part of the model stay: the 1 ms float tolerance, the 16 ms sub-step, the 20 ms and
32 ms of the thesis's and Webots's time steps.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("ekm", "planner", "robots", "training", "evaluation")
SOURCES = sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py"))
MODEL_MS = {"1", "16", "20", "32"}

FORBIDDEN = {
    "a timing in microseconds": re.compile(r"\d\s*(µs|us\b)"),
    "a speed round": re.compile(r"\b(first|second|third|fourth|fifth|sixth|seventh|speed)[ -]round", re.I),
    "docs/speed.md, which is gone": re.compile(r"speed\.md"),
    "the design brief, which users do not have": re.compile(r"\bDESIGN\b|shared/"),
}


def offences(text: str) -> list[str]:
    """``["line N: what", …]`` for every forbidden line of ``text``."""
    found = []
    for n, line in enumerate(text.splitlines(), 1):
        found += [f"line {n}: {what}" for what, pattern in FORBIDDEN.items() if pattern.search(line)]
        found += [f"line {n}: a timing of {ms} ms" for ms in re.findall(r"(\d+(?:\.\d+)?)\s*ms\b", line)
                  if ms not in MODEL_MS]
    return found


def test_the_checker_finds_what_it_must():
    bad = "x = 1  # 490 µs a step\n# third round: packed\nsee docs/speed.md\n(DESIGN §3)\n# 2.5 ms per tick\n"
    assert offences(bad) == ["line 1: a timing in microseconds", "line 2: a speed round",
                             "line 3: docs/speed.md, which is gone", "line 4: the design brief, which users do not have",
                             "line 5: a timing of 2.5 ms"]
    assert offences("dt = 0.016  # 16 ms sub-step; basicTimeStep 32 ms\n(docs/design.md §3)\n") == []


def test_sources_are_found():
    assert len(SOURCES) > 50 and any(p.name == "kohonen.py" for p in SOURCES)


@pytest.mark.parametrize("path", SOURCES, ids=[str(p.relative_to(ROOT)) for p in SOURCES])
def test_no_timings_or_history_in_the_package(path):
    assert offences(path.read_text()) == [], f"{path.relative_to(ROOT)}"
