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
