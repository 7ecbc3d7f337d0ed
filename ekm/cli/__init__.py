"""The ``ekm`` console script (docs/design.md §6): the imperative shell around the packages.

One module per command, each with ``add_parser(sub)`` and ``run(args)`` (the catalogues of what one can add
share one, :mod:`ekm.cli.catalogue`); shared argument types are in :mod:`ekm.cli.args`. Each ``run`` parses
nothing more than argparse does, calls the one function of the Python API it wraps (:mod:`ekm.api`: ``ekm
train`` is :func:`ekm.train`, …) and prints its result — a table, or ``result.to_dict()`` with ``--json`` — or
draws it, so the command line and the API cannot drift apart (``ekm bench`` alone calls
:mod:`training.throughput` directly). Each command imports what it needs inside its function, so ``ekm --help``
starts fast. Bad input of any kind raises :class:`ekm.errors.InputError`; :func:`main` prints its one line on
stderr and exits with status 2 — never a traceback.
"""

from __future__ import annotations

import argparse
import sys

from ekm.cli import adapt, bench, compare, evaluate, match, plan, robots, run, tournament, train, worlds
from ekm.cli.catalogue import ARCHITECTURES, FAMILIES, PLAYERS
from ekm.cli.args import (finite_float, nonneg_float, nonneg_int, output_path, positive_float, positive_int,
                          print_json, show_progress, xy_point)
from ekm.errors import InputError, Interrupted

#: The sub-commands, in the order ``ekm --help`` lists them; a new command is a module added here (a catalogue of a
#: kind one can add is a :class:`ekm.cli.catalogue.Catalogue`).
COMMANDS = (worlds, robots, FAMILIES, plan, train, evaluate, adapt, ARCHITECTURES, run, compare, match, tournament,
            PLAYERS, bench)

__all__ = ["COMMANDS", "build_parser", "main", "finite_float", "nonneg_float", "nonneg_int", "output_path",
           "positive_float", "positive_int", "print_json", "show_progress", "xy_point"]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``ekm train: --steps: must be > 0``) and exit status 2."""

    def error(self, message):
        import re

        from ekm.api.checks import invalid_choice

        wrong = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)$", message)
        if wrong:  # argparse's own choices: with the closest one, as every other unknown name
            message = message[:wrong.start()] + invalid_choice(wrong[1], re.findall(r"'([^']*)'", wrong[2]))
        raise InputError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ekm", description="Extended Kohonen Maps for a Khepera-like robot (Low 2002).")
    from ekm import __version__

    parser.add_argument("--version", action="version", version=f"ekm {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for command in COMMANDS:
        command.add_parser(sub)
    return parser


def parse(parser, argv: list[str]):
    """``parser.parse_args(argv)``, but words it does not know are refused naming the command — and, after a word
    ending in a comma, the space that split a list (``--architectures fields, samba``)."""
    args, extra = parser.parse_known_args(argv)
    if extra:
        raise InputError(unrecognized(f"ekm {args.command}", argv, extra))
    return args


def unrecognized(prog: str, argv: list[str], extra: list[str]) -> str:
    """The one line for the words ``extra`` of ``argv`` that no option of ``prog`` takes."""
    for word in extra:
        i = argv.index(word) if word in argv else -1
        if i > 0 and argv[i - 1].endswith(","):
            return (f"{prog}: {' '.join(argv[max(0, i - 2):i + 1])}: a space after a comma ends the list, leaving "
                    f"{word!r} over; write {argv[i - 1]}{word}")
    return f"{prog}: unrecognized arguments: {' '.join(extra)}"


def main(argv=None) -> int:
    """Run ``ekm ARGV…``; returns the exit status: 0, 2 for bad input, 130 (143 for SIGTERM) when stopped.

    Signals held since the console script started (:mod:`ekm.interrupts`) are released once the arguments are
    read — by the batch runner instead, once its results file exists, for a command whose parser says so
    (``holds_signals(args)``: ``ekm compare`` and ``ekm tournament`` with ``--out`` or ``--resume``)."""
    from ekm import interrupts

    command = "ekm"
    try:
        args = parse(build_parser(), sys.argv[1:] if argv is None else list(argv))
        command = f"ekm {args.command}"
        if not getattr(args, "holds_signals", lambda _: False)(args):
            interrupts.release()  # a signal so far raises now; a batch with a results file releases them itself
        args.func(args)
        interrupts.check()  # a signal lost inside a C callback still stops the command
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return InputError.exit_status
    except Interrupted as exc:
        print(f"interrupted: {exc}", file=sys.stderr)
        return interrupts.status()
    except KeyboardInterrupt:  # outside the long loops, which say what they kept: outputs are written whole or not at all
        print(f"interrupted: {command} stopped", file=sys.stderr)
        return interrupts.status()
    except BrokenPipeError:  # e.g. `ekm plan --json | head`: the reader left, nothing to report
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    return 0
