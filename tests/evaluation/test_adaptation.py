"""The adaptation experiment (evaluation.adaptation, ekm adapt): when a curve reaches a level, and one small run."""

import json

from ekm.cli import main
from evaluation.adaptation import first_step


def point(step, e, t5=10.0, p5=1.0):
    return {"step": step, "E_mm": e, "P": {"5": p5}, "T": {"5": t5}, "D": {"25": 0.1}}


def test_first_step_is_the_first_test_at_or_below_the_level_that_the_next_test_confirms():
    curve = [point(0, 9.0), point(500, 2.9), point(1000, 3.2), point(1500, 2.5), point(2000, 2.8)]
    assert first_step(curve, 3.0) == 1500  # 500 dips below, 1000 is back above: not reached yet
    assert first_step(curve, 1.0) is None
    assert first_step(curve[-1:], 3.0) == 2000  # the last test needs no next one


def test_t_counts_only_where_the_map_reaches_the_targets():
    curve = [point(0, 90.0, t5=8.0, p5=0.1), point(500, 5.0, t5=12.0), point(1000, 1.5, t5=12.5)]
    assert first_step(curve, 13.0, "T5") == 500  # step 0's T(5) of 8 is over a tenth of the targets
    assert first_step(curve, 13.0, "T5", reached=0.05) == 0


def test_ekm_adapt_runs_the_three_maps_on_each_robot(capsys, tmp_path):
    png = tmp_path / "adapt.png"
    code = main(["adapt", "--robots", "weak-motor", "--steps", "400", "--every", "200", "--scratch-steps", "400",
                 "--scratch-every", "200", "--targets", "5", "--plot", str(png), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and png.stat().st_size > 10_000
    (row,) = out["robots"]
    assert row["robot"] == "weak-motor" and out["map"]["robot"] == "khepera" and out["setup"]["rate"] == "error"
    curves = row["curves"]
    assert [p["step"] for p in curves["fine-tuned"]] == [0, 200, 400] == [p["step"] for p in curves["scratch"]]
    assert curves["frozen"][0]["E_mm"] == curves["fine-tuned"][0]["E_mm"]  # both start as the same map, same test
    assert curves["scratch"][0]["E_mm"] > 10 * curves["frozen"][0]["E_mm"]  # an untrained map is far off
    assert row["summary"]["steps_to_thesis_E"]["fine_tuned"] == 0
    assert main(["adapt", "--robots", "weak-motor,", "--steps", "10"]) == 2
    assert "empty item" in capsys.readouterr().err
