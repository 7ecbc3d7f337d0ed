"""Issue 21's targets on the generated test worlds (seeds 1000-1019 of each family, never tuned on), slow.

The thresholds are the issue's, not numbers the code produced: the default neural fields reach the goal
without a collision in at least 85 % of the 120 worlds and 70 % of every family's 20, and in every family
the best architecture reaches at least 90 %.
"""

import pytest

FAMILIES = ("corridor", "traps", "clutter", "maze", "movers", "blocked")


@pytest.fixture(scope="module")
def table():
    import ekm

    return ekm.compare(suite=",".join(f"{f}:20" for f in FAMILIES), trials=1, workers=2)


@pytest.mark.slow
def test_the_default_fields_reach_85_percent_overall_and_70_percent_in_every_family(table):
    rows = {r["family"]: r for r in table.families if r["architecture"] == "fields"}
    assert rows["all"]["success_rate"] >= 0.85, rows["all"]
    for f in FAMILIES:
        assert rows[f]["worlds"] == 20 and rows[f]["success_rate"] >= 0.70, rows[f]


@pytest.mark.slow
def test_in_every_family_the_best_architecture_reaches_90_percent(table):
    for f in FAMILIES:
        best = max(r["success_rate"] for r in table.families if r["family"] == f)
        assert best >= 0.90, f


@pytest.mark.slow
def test_no_generated_world_fails_to_start(table):
    assert all(r["failed"] == 0 for r in table.families)
