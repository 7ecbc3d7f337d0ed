"""``ekm architectures`` and architectures of your own (ekm.register_architecture, the ``ekm.architectures``
entry-point group): listed, spelled NAME:k=v and checked as the built-in ones, run by ``ekm run`` and
``ekm compare`` — the example package ``examples/wander`` through its entry point."""

import json
import os
import re
import subprocess
import sys
from dataclasses import dataclass, field

import pytest

import ekm
from ekm.errors import InputError
from robots.controllers import spec
from robots.controllers.spec import ARCHITECTURES

BUILT_IN = ["fusion", "fields", "samba", "schema", "subsumption", "damn", "deliberation"]
ENCODING = {"fusion": "continuous", "fields": "continuous", "samba": "discrete", "schema": "continuous",
            "subsumption": "discrete", "damn": "discrete", "deliberation": "discrete"}





def test_every_built_in_architecture_is_listed_with_its_parameters(cli):
    code, out, _ = cli("architectures", "--json")
    rows = json.loads(out)["architectures"]
    assert code == 0 and [r["name"] for r in rows][:7] == BUILT_IN
    assert {r["name"]: r["encoding"] for r in rows[:7]} == ENCODING
    fusion = rows[0]
    assert fusion["origin"] == "built in" and fusion["map"] == ["polar"]
    beta = next(p for p in fusion["parameters"] if p["name"] == "beta")
    assert beta["default"] == "0.85" and beta["type"] == "float" and "Eq. 4.11" in beta["help"]
    sensors = next(p for p in fusion["parameters"] if p["name"] == "sensors")
    assert sensors["choices"] == ["short", "long"]
    code, out, _ = cli("architectures")
    assert all(f"{name} (built in;" in out for name in BUILT_IN) and re.search(r"\n    beta += 0\.85 \(float\)  ", out)
    assert "deliberation (built in; drives no EKM; discrete responses)" in out


@dataclass(frozen=True)
class StillParams:
    speed: float = field(default=0.0, metadata={"help": "wheel speed, m/s"})


def build_still(p, ekm_map=None, cfg=None, spec="still", robot=None):
    import jax.numpy as jnp

    from robots.controllers.base import Controller
    from robots.params import KHEPERA

    robot = robot or KHEPERA
    return Controller(name="still", spec=spec, sensors=robot.short_range, init=lambda: jnp.zeros(()),
                      step=lambda s, obs: (s, jnp.full(2, p.speed)), params=p, robot=robot)


def test_an_architecture_registered_in_python_is_listed_spelled_and_run(registries, cli):
    ekm.register_architecture("still", StillParams, build_still, "stands still")
    assert "still" in ekm.architectures().names()
    code, out, _ = cli("architectures", "still")
    assert code == 0 and out.startswith("still (added; drives no EKM)") and "speed = 0 (float)  wheel speed, m/s" in out
    assert str(spec.parse_architecture("still:speed=0.01")) == "still:speed=0.01"
    outcome = ekm.run("open-arena", "still", time_limit=3)
    assert not outcome.reached and outcome.path_m == 0.0
    code, _, err = cli("run", "--world", "open-arena", "--architecture", "still:speed=fast")
    assert code == 2 and err == "error: architecture still: speed: must be a number, got 'fast'\n"


@pytest.mark.parametrize("args, message", [
    (("fusion", StillParams, build_still), "the name of a built-in architecture"),
    (("Still!", StillParams, build_still), "a name is lower-case letters"),
    (("still", dict, build_still), "params must be a dataclass"),
    (("still", dataclass(frozen=True)(type("NoDefault", (), {"__annotations__": {"x": float}})), build_still),
     "every field has a default"),
    (("still", StillParams, "build"), "build must be callable"),
])
def test_a_bad_registration_is_refused_in_one_line(registries, args, message):
    with pytest.raises(InputError, match=message):
        ekm.register_architecture(*args)


def test_an_architecture_says_its_response_encoding_or_nothing(registries):
    with pytest.raises(InputError, match="encoding must be one of continuous, discrete, None, got 'smooth'"):
        ekm.register_architecture("still", StillParams, build_still, encoding="smooth")
    ekm.register_architecture("still", StillParams, build_still, encoding="discrete")
    assert next(r for r in ekm.architectures().rows if r["name"] == "still")["encoding"] == "discrete"


def test_an_installed_package_adds_an_architecture_through_its_entry_point(registries, installed, monkeypatch):
    monkeypatch.syspath_prepend(str(installed("wander")))
    ARCHITECTURES._loaded = False
    rows = {r["name"]: r for r in ekm.architectures().rows}
    assert rows["wander"]["origin"] == "entry point"
    assert [p["name"] for p in rows["wander"]["parameters"]] == ["speed", "near"]
    assert ekm.run("open-arena", "wander:speed=0.06", seed=0).reached


def test_the_example_package_runs_through_ekm_compare_beside_fields(installed):
    """As a user runs it after ``pip install ./examples/wander``: the console script, two worker processes."""
    path = installed("wander")
    env = {**os.environ, "PYTHONPATH": str(path)}
    proc = subprocess.run([sys.executable, "-m", "ekm", "compare", "--worlds", "open-arena", "--architectures",
                           "wander,fields", "--trials", "2", "--workers", "2", "--json"],
                          capture_output=True, text=True, env=env, cwd=path)
    assert proc.returncode == 0, proc.stderr
    rows = {r["architecture"]: r for r in json.loads(proc.stdout)["results"]}
    assert rows["wander"]["success_rate"] == 1.0 and rows["fields"]["success_rate"] == 1.0


def test_a_map_of_the_chart_an_architecture_does_not_drive_is_refused(cli, tmp_path):
    signed = ekm.load().save(tmp_path / "signed.npz")  # the shipped map: signed chart
    code, _, err = cli("run", "--world", "open-arena", "--architecture", "fusion", "--map", signed)
    assert code == 2 and err.count("\n") == 1
    assert "architecture fusion: drives a polar-chart map" in err and "ekm train --mapping indirect --chart polar" in err
    code, _, err = cli("compare", "--worlds", "open-arena", "--architectures", "fields,fusion", "--map", signed)
    assert code == 2 and "architecture fusion: drives a polar-chart map" in err
