"""A comparison's results file (evaluation.results): one whole line per run, the header checked on resume,
a line cut short by a crash dropped."""

import json

import pytest

from ekm.errors import InputError
from evaluation.results import ResultsFile, read

SETTINGS = {"worlds": ["open-arena", "maze:1000"], "labels": ["fusion", "fields"], "trials": 2, "seed": 0,
            "architectures": ["fusion:beta=0.85", "fields:form=extended"], "config": {"time_limit": 120.0, "recover": True},
            "map": None, "ekm_version": "0.1.0"}


def record(world, label, trial):
    return {"given": world, "world": world, "label": label, "trial": trial, "reached": trial == 0, "trapped": False,
            "arrived": trial == 0, "ended": "stopped at the goal" if trial == 0 else "time limit", "collisions": 0,
            "contact_s": 0.0, "time_s": 30.5 if trial == 0 else None, "path_m": 1.25 if trial == 0 else None}


def test_runs_are_lines_after_a_header_and_read_back_as_written(tmp_path):
    path = tmp_path / "r.jsonl"
    with ResultsFile(path, SETTINGS) as f:
        f.append({"world": "open-arena"}, record("open-arena", "fusion", 0))
        f.append({"world": "maze:1000"}, record("maze:1000", "fields", 1))
    lines = path.read_text().splitlines()
    assert len(lines) == 3 and json.loads(lines[0]) == {"ekm_results": 1, "settings": SETTINGS}
    assert json.loads(lines[2]) == {"job": {"world": "maze:1000"}, "outcome": record("maze:1000", "fields", 1)}
    settings, records = read(path)
    assert settings == SETTINGS and records == [record("open-arena", "fusion", 0), record("maze:1000", "fields", 1)]


def test_an_existing_file_is_never_overwritten(tmp_path):
    path = tmp_path / "r.jsonl"
    path.write_text("someone's results\n")
    with pytest.raises(InputError, match=r"--out .*r.jsonl: exists; continue it with --resume"):
        ResultsFile(path, SETTINGS)
    assert path.read_text() == "someone's results\n"


def test_resume_keeps_the_whole_lines_and_drops_one_cut_short(tmp_path):
    path = tmp_path / "r.jsonl"
    with ResultsFile(path, SETTINGS) as f:
        f.append({}, record("open-arena", "fusion", 0))
        f.append({}, record("open-arena", "fields", 0))
    whole = path.read_text()
    path.write_text(whole + '{"job": {}, "outcome": {"given": "maze:1000", "lab')  # a crash mid-line
    with ResultsFile(path, SETTINGS, resume=True) as f:
        assert sorted(f.done) == [("open-arena", "fields", 0), ("open-arena", "fusion", 0)]
        f.append({}, record("maze:1000", "fusion", 1))
    assert path.read_text().startswith(whole) and len(path.read_text().splitlines()) == 4
    assert read(path)[1][-1] == record("maze:1000", "fusion", 1)


@pytest.mark.parametrize("change, message", [
    ({"worlds": ["open-arena"]}, "worlds: open-arena,maze:1000 in the file, open-arena now"),
    ({"labels": ["fusion", "samba"]}, "labels: fusion,fields in the file, fusion,samba now"),
    ({"trials": 3}, "trials: 2 in the file, 3 now"),
    ({"architectures": ["fusion:beta=0.85", "fields:form=thesis"]},
     "architectures: fields:form=extended in the file, fields:form=thesis now"),
    ({"config": {"time_limit": 60.0, "recover": True}}, "config.time_limit: 120.0 in the file, 60.0 now"),
    ({"ekm_version": "0.2.0"}, "ekm_version: 0.1.0 in the file, 0.2.0 now"),
    ({"engine": "jax"}, "engine: pymunk in the file, jax now"),  # a file that does not say ran on pymunk
])
def test_a_file_from_other_settings_is_refused_naming_the_first_difference(tmp_path, change, message):
    path = tmp_path / "r.jsonl"
    ResultsFile(path, SETTINGS).close()
    with pytest.raises(InputError) as err:
        ResultsFile(path, {**SETTINGS, **change}, resume=True)
    assert str(err.value) == f"--resume {path}: made with other settings ({message})"


def test_a_file_that_does_not_name_its_engine_resumes_on_pymunk_and_one_of_jax_only_on_jax(tmp_path):
    old, jax_file = tmp_path / "old.jsonl", tmp_path / "jax.jsonl"
    ResultsFile(old, SETTINGS).close()
    ResultsFile(old, {**SETTINGS, "engine": "pymunk"}, resume=True).close()
    ResultsFile(jax_file, {**SETTINGS, "engine": "jax"}).close()
    with pytest.raises(InputError, match=r"engine: jax in the file, pymunk now"):
        ResultsFile(jax_file, {**SETTINGS, "engine": "pymunk"}, resume=True)


@pytest.mark.parametrize("text, message", [
    ("", "not an ekm results file"),
    ('{"ekm_results": 2, "settings": {}}\n', "not an ekm results file"),
    ('{"ekm_results": 1, "settings": {}}\n{"job": {}}\n', "line 2: not a finished run or game"),
])
def test_what_is_not_a_results_file_is_refused_in_one_line(tmp_path, text, message):
    path = tmp_path / "r.jsonl"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read(path)
    with pytest.raises(InputError, match="no such results file"):
        read(tmp_path / "missing.jsonl")


@pytest.mark.parametrize("change, error", [
    ({"trial": "x"}, 'line 3: outcome.trial: must be a whole number, got "x"'),
    ({"reached": 1}, "line 3: outcome.reached: must be true or false, got 1"),
    ({"time_s": -2.0}, "line 3: outcome.time_s: must be >= 0, got -2.0"),
    ({"label": ""}, 'line 3: outcome.label: must be a non-empty string, got ""'),
    ({"failed": 7}, "line 3: outcome.failed: must be a non-empty string, got 7"),
    ({"collisions": None}, "line 3: outcome.collisions: must be a whole number, got null"),
])
def test_a_record_read_back_is_checked_like_a_world_file_naming_its_line_and_key(tmp_path, change, error):
    path = tmp_path / "r.jsonl"
    with ResultsFile(path, SETTINGS) as f:
        f.append({}, record("open-arena", "fusion", 0))
        f.append({}, {**record("open-arena", "fields", 0), **change})
    with pytest.raises(InputError) as e:
        read(path)
    assert str(e.value) == f"{path}: {error}"


def test_a_record_without_a_key_the_table_reads_is_refused(tmp_path):
    path = tmp_path / "r.jsonl"
    with ResultsFile(path, SETTINGS) as f:
        f.append({}, {k: v for k, v in record("open-arena", "fusion", 0).items() if k != "ended"})
    with pytest.raises(InputError, match=r"r.jsonl: line 2: outcome.ended: missing$"):
        read(path)


def test_resuming_a_tournaments_file_as_a_comparison_says_whose_file_it_is_and_the_mirror(tmp_path):
    cup, cmp = tmp_path / "cup.jsonl", tmp_path / "cmp.jsonl"
    cup_settings = {"tournament": ["schema", "ekm"], "labels": ["schema", "ekm"], "seeds": 2}
    ResultsFile(cup, cup_settings).close()
    ResultsFile(cmp, SETTINGS).close()
    with pytest.raises(InputError) as e:
        ResultsFile(cup, SETTINGS, resume=True)
    assert str(e.value) == (f"--resume {cup}: a tournament's results file, not a comparison's (ekm compare --out "
                            f"writes those)")
    with pytest.raises(InputError) as e:
        ResultsFile(cmp, cup_settings, resume=True)
    assert str(e.value) == (f"--resume {cmp}: a comparison's results file, not a tournament's (ekm tournament --out "
                            f"writes those)")
