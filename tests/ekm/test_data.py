"""The maps that ship with the package are what ``ekm train`` makes with its defaults, and they still test as
their files say they did."""

import dataclasses

import pytest

from ekm.config import EKMConfig
from ekm.data import default_map, load_default_map
from evaluation.metrics import summarize
from evaluation.protocol import evaluate
from training.online import TrainConfig


@pytest.mark.parametrize("chart", ["signed", "polar"])
def test_shipped_maps_were_trained_with_ekm_trains_defaults(chart):
    saved = load_default_map(chart)
    assert saved.cfg == dataclasses.replace(EKMConfig(), chart=chart)
    assert saved.trials == 5 and saved.meta["steps"] == 100_000 and saved.meta["seed"] == 0
    assert saved.meta["world"] == "open-arena" and saved.meta["test"] == {"targets": 50, "seed": 0}
    train = dataclasses.asdict(TrainConfig())
    train["arena"] = list(train["arena"])
    assert train.pop("adapt") is None  # a field newer than the maps: its default is what they were trained with
    assert saved.meta["train"] == train


@pytest.mark.parametrize("chart", ["signed", "polar"])
def test_shipped_maps_reproduce_their_recorded_test_figures(chart):
    saved = load_default_map(chart)
    recorded = saved.curve[-1]
    now = summarize(evaluate(saved.ekm, saved.cfg, saved.arena, targets=50, seed=0))
    assert now["E_mm"] == pytest.approx(recorded["E_mm"], rel=1e-5)
    assert now["T"]["25"] == pytest.approx(recorded["T"]["25"], rel=1e-5) and now["capped"] == recorded["capped"]


def test_an_unknown_chart_has_no_shipped_map():
    with pytest.raises(ValueError, match="no shipped map for chart 'round'"):
        default_map("round")
