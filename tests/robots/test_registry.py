"""The one registry (robots.registry) of everything a user can add: the same rules for every kind — the package's
own first, names checked, a built-in name never taken, a name registered again replaced — the origin of each
thing, entry points that fail in one line, and what a job carries to its worker process. A family of one's own
makes worlds by its spelling like the package's."""

import dataclasses
import pickle
from dataclasses import dataclass

import pytest

import ekm
from ekm.errors import InputError
from robots.controllers.spec import ARCHITECTURES
from robots.generator import FAMILIES, Family
from robots.generator.layout import Layout
from robots.registry import KINDS, Registry, added_here, adopt
from robots.soccer.roster import PLAYERS, Player
from robots.worldnames import load_world


@dataclass(frozen=True)
class Thing:
    name: str
    summary: str = ""


def fresh(check=None) -> Registry:
    registry = Registry("thing", "things", Thing, lambda: (Thing("one"), Thing("two")), check)
    KINDS.remove(registry)  # not one of the package's kinds
    return registry


def test_the_package_s_own_come_first_then_what_is_added_each_with_its_origin():
    things = fresh()
    assert things.names() == ["one", "two"] and things.group == "ekm.things"
    things.register(Thing("three", "added"))
    assert list(things) == ["one", "two", "three"] and len(things) == 3 and "three" in things
    assert [things.origin(n) for n in things] == ["built in", "built in", "added"]
    things.register(Thing("three", "again"))
    assert things["three"].summary == "again" and things.added_here() == (Thing("three", "again"),)


@pytest.mark.parametrize("thing, message", [
    (Thing("one"), "thing 'one': the name of a built-in thing"),
    (Thing("Three!"), "thing 'Three!': a name is lower-case letters, digits, '-' and '_', starting with a letter"),
    (Thing(""), "thing '': a name is lower-case letters"),
    ("three", "register_thing: expected a Thing, got str"),
])
def test_a_bad_registration_is_refused_in_one_line(thing, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        fresh().register(thing)


def test_the_kind_s_own_check_runs_and_an_unknown_name_lists_the_known():
    def no_summary(thing):
        if not thing.summary:
            raise InputError(f"thing {thing.name}: needs a summary")

    things = fresh(no_summary)
    with pytest.raises(InputError, match="thing three: needs a summary"):
        things.register(Thing("three"))
    with pytest.raises(InputError, match=r"thing 'four': unknown \(choose from one, two; ekm things describes them\)"):
        things["four"]


class BrokenEntryPoint:
    name, value = "broken", "nowhere:THING"

    def load(self):
        raise ImportError("No module named 'nowhere'")


class StrangeEntryPoint:
    name, value = "strange", "somewhere:THING"

    def load(self):
        return 42


@pytest.mark.parametrize("entry, message", [
    (BrokenEntryPoint(), "entry point 'broken' (nowhere:THING) of group ekm.things: cannot load (ImportError: No "
                         "module named 'nowhere')"),
    (StrangeEntryPoint(), "entry point 'strange' (somewhere:THING) of group ekm.things: names int, not an ekm Thing"),
])
def test_an_entry_point_that_cannot_give_a_thing_is_one_line(monkeypatch, entry, message):
    import importlib.metadata

    monkeypatch.setattr(importlib.metadata, "entry_points", lambda group: [entry] if group == "ekm.things" else [])
    with pytest.raises(InputError) as refused:
        fresh().names()
    assert str(refused.value) == message


@dataclass(frozen=True)
class StillParams:
    speed: float = 0.0


def build_still(p, field=None, robot=None, spec="still"):  # never called here
    raise AssertionError


def open_field(rng, level):
    """An empty arena, start and goal across it."""
    return Layout({"size": [1.0, 0.8], "start": [0.15, 0.4, 0.0], "goal": [0.85, float(rng.uniform(0.3, 0.5))],
                   "wall_thickness": 0.01})


def test_what_a_script_registers_travels_with_its_jobs_and_a_worker_registers_it(registries):
    player = ekm.register_player("still", StillParams, build_still, "stands still")
    family = ekm.register_family("open-field", open_field, "an empty arena")
    carried = pickle.loads(pickle.dumps(added_here()))  # as a job takes them to a spawned worker
    assert set(carried) == {player, family}
    for registry in (PLAYERS, FAMILIES):  # the worker: a fresh process knows only the package's own
        registry._added.clear()
    adopt(carried)
    assert PLAYERS.origin("still") == FAMILIES.origin("open-field") == "added"
    adopt(carried)  # a worker given them again keeps them
    assert PLAYERS["still"] == player and ARCHITECTURES.added_here() == ()


def test_a_family_of_one_s_own_makes_worlds_by_their_spelling(registries):
    ekm.register_family(Family("open-field", open_field, "an empty arena"))
    w = load_world("open-field:3")
    assert w.name == "open-field:3" and w.difficulty.family == "open-field" and w.difficulty.seed == 3
    assert load_world("open-field:3") == w and ekm.generate("open-field", 3) == w
    assert ekm.families().rows[-1] == {"name": "open-field", "summary": "an empty arena", "origin": "added",
                                       "parameters": []}


def test_a_robot_of_one_s_own_drives_by_its_name_and_is_checked_as_a_robot_file(registries):
    heavy = ekm.register_robot("heavy", {"motor_tau": 0.08, "max_wheel_speed": 0.12}, "a slow, heavy Khepera")
    assert (heavy.motor_tau, heavy.max_wheel_speed, heavy.radius) == (0.08, 0.12, 0.025)  # the rest: the Khepera's
    assert ekm.robot("heavy") == heavy and heavy.about == "a slow, heavy Khepera"
    listed = {r["name"]: r["origin"] for r in ekm.robots().to_dict()["robots"]}
    assert listed["heavy"] == "added" and listed["khepera"] == "built in"
    with pytest.raises(InputError, match="robot wobbly: wheel_base: must be > 0, got 0"):
        ekm.register_robot("wobbly", {"wheel_base": 0})
    with pytest.raises(InputError, match="robot thin: wheel_base: must be > 0, got 0"):  # made in Python, checked
        ekm.register_robot(dataclasses.replace(ekm.robot(), name="thin", wheel_base=0.0))
    with pytest.raises(InputError, match="robot 'worn-wheel': the name of a built-in robot"):
        ekm.register_robot("worn-wheel", {"wheel_gain": [0.8, 1.0]})
    carried = pickle.loads(pickle.dumps(added_here()))
    assert heavy in carried
