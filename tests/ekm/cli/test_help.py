"""The command line explains itself: every sub-command has a one-line description and examples, every
option a help text, and ``ekm train``'s usage shows what it requires."""

import argparse

import pytest

from ekm.cli import COMMANDS, build_parser, main


def subparsers():
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices


def test_every_command_is_listed():
    assert set(subparsers()) == {"worlds", "robots", "families", "plan", "train", "evaluate", "adapt", "architectures",
                                 "run", "compare", "match", "tournament", "players", "bench"}
    assert len(COMMANDS) == 14


@pytest.mark.parametrize("name", sorted(subparsers()))
def test_every_command_has_a_description_examples_and_help_on_every_option(name, capsys):
    with pytest.raises(SystemExit) as done:
        main([name, "--help"])
    out = capsys.readouterr().out
    assert done.value.code == 0
    description = out.split("\n\n")[1]
    assert description.strip() and description.strip().endswith(".")
    assert "examples:\n  ekm " + name in out
    for action in subparsers()[name]._actions:
        assert action.help, f"ekm {name}: {action.option_strings or action.dest} has no help"


def test_train_usage_shows_what_it_requires_and_run_points_to_the_architectures(capsys):
    with pytest.raises(SystemExit):
        main(["train", "--help"])
    assert ("usage: ekm train (--mapping {direct,indirect} | --init MAP.npz) --out MAP.npz [options] | --resume "
            "CKPT.npz") in " ".join(capsys.readouterr().out.split())
    for name in ("run", "compare"):
        with pytest.raises(SystemExit):
            main([name, "--help"])
        out = " ".join(capsys.readouterr().out.split())
        assert "ekm architectures" in out and all(a in out for a in ("fusion", "fields", "samba", "schema"))



def test_the_top_level_help_lists_every_command_with_its_summary(capsys):
    """``ekm --help`` lists every command; a summary holding "95 %" once crashed it, since argparse
    %-formats a sub-command's help."""
    with pytest.raises(SystemExit) as done:
        main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert done.value.code == 0
    assert "with 95 % intervals" in text
    assert all(name in text for name in subparsers())


@pytest.mark.parametrize("argv, line", [
    (["compare", "--architectures", "fields,", "samba"],
     "ekm compare: --architectures fields, samba: a space after a comma ends the list, leaving 'samba' over; write "
     "fields,samba"),
    (["tournament", "samba,", "schema"],
     "ekm tournament: tournament samba, schema: a space after a comma ends the list, leaving 'schema' over; write "
     "samba,schema"),
    (["compare", "--worlds", "open-arena", "--bogus"], "ekm compare: unrecognized arguments: --bogus"),
])
def test_a_word_no_option_takes_is_refused_naming_the_command_and_a_space_after_a_comma(argv, line, capsys):
    assert main(argv) == 2
    assert capsys.readouterr().err == f"error: {line}\n"


@pytest.mark.parametrize("argv, line", [
    (["compare", "--worlds", "open-arena", "--architectures", "feilds"],
     "architecture 'feilds': unknown; did you mean 'fields'? (choose from fusion, fields, samba"),
    (["match", "samab", "schema"], "player 'samab': unknown; did you mean 'samba'? (choose from "),
    (["compare", "--suite", "maez:3"],
     "--suite 'maez:3': unknown world family 'maez'; did you mean 'maze'? (families: "),
    (["worlds", "--generate", "corridr", "--seed", "1", "--out", "w.json"],
     "ekm worlds: argument --generate: invalid choice: 'corridr'; did you mean 'corridor'? (choose from "),
    (["plan", "--world", "three-room"], "three-room: no such world file or named world; did you mean 'three-rooms'? "),
    (["run", "--world", "maze+pilars:1", "--architecture", "samba"],
     "maze+pilars:1: unknown world family 'pilars'; did you mean 'pillars'? (families: "),
    (["run", "--world", "open-arena", "--architecture", "fields", "--robot", "kepera"],
     "kepera: no such robot file or named robot; did you mean 'khepera'? "),
    (["run", "--world", "open-arena", "--architecture", "fields", "--learn", "eror"],
     "learning rule 'eror': unknown; did you mean 'error'? "),
])
def test_a_misspelt_name_gets_a_did_you_mean(argv, line, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {line}") and err.count("\n") == 1, err


def test_run_says_a_run_that_stopped_at_the_goal_after_a_collision_arrived_and_did_not_reach_it():
    from ekm.cli.run import outcome_status

    ended = {"reached": False, "arrived": True, "trapped": False, "collisions": 1}
    assert outcome_status(ended) == "ARRIVED after 1 collision, so did not reach the goal"
    assert outcome_status({**ended, "collisions": 3}) == "ARRIVED after 3 collisions, so did not reach the goal"
    assert outcome_status({**ended, "reached": True, "collisions": 0}) == "REACHED the goal"
    assert outcome_status({**ended, "arrived": False, "trapped": True}) == "TRAPPED"
    assert outcome_status({**ended, "arrived": False}) == "did not reach the goal"
