"""Argument types and helpers shared by the ``ekm`` commands: checked numbers and points, output
paths checked before long work starts, stable JSON output, and when to show progress bars."""

from __future__ import annotations

import argparse
import json
import math
import sys

from ekm.api.checks import invalid_choice, output_path, plot_path, sign_problem
from ekm.provenance import provenance

__all__ = ["add_batch_options", "command", "finite_float", "in_this_process", "nonneg_float", "nonneg_int", "one_of",
           "output_path", "plot_path", "positive_float", "positive_int", "print_columns", "print_json", "print_written",
           "provenance",
           "show_progress", "xy_point"]


def command(sub, name: str, summary: str, examples: list[str], *, usage: str | None = None, more: str = ""):
    """The parser of one sub-command: ``summary`` (one line) as its entry in ``ekm --help`` and its description,
    and an epilog of ``examples`` (then ``more``), printed as written."""
    epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples) + (f"\n\n{more}" if more else "")
    # argparse %-formats a sub-command's help (``ekm --help``), so "95 % intervals" must reach it as "95 %% …"
    return sub.add_parser(name, help=summary.replace("%", "%%"), description=summary[0].upper() + summary[1:] + ".", usage=usage,
                          epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter)


def _whole_number(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None


def finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text}")
    return value


def _signed(parse, *, strict: bool):
    """An argparse type: ``parse`` the text, then require > 0 (``strict``) or >= 0."""

    def check(text: str):
        value = parse(text)
        problem = sign_problem(value, strict, shown=text)
        if problem:
            raise argparse.ArgumentTypeError(problem)
        return value

    return check


positive_int = _signed(_whole_number, strict=True)
nonneg_int = _signed(_whole_number, strict=False)
positive_float = _signed(finite_float, strict=True)
nonneg_float = _signed(finite_float, strict=False)


def xy_point(text: str) -> tuple[float, float]:
    """``"X,Y"`` in metres → ``(x, y)``."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise argparse.ArgumentTypeError("")
        return finite_float(parts[0]), finite_float(parts[1])
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"must be X,Y in metres (e.g. 0.1,0.3), got {text!r}") from None


def one_of(choices):
    """An argparse type for one of ``choices``, worded as :func:`ekm.api.checks.choice` words it (the API
    checks the same value; give the option ``metavar="{a,b}"`` for the help)."""

    def check(text: str) -> str:
        if text not in choices:
            raise argparse.ArgumentTypeError(invalid_choice(text, choices))
        return text

    return check


def print_json(obj) -> None:
    """Write ``obj`` as the command's stable JSON output."""
    json.dump(obj, sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def show_progress(args) -> bool:
    """Progress bars only on a terminal and never with ``--json``."""
    return not getattr(args, "json", False) and sys.stderr.isatty()


def print_columns(lines) -> None:
    """``lines`` (tuples of cells, the head first) as left-aligned columns two spaces apart."""
    widths = [max(len(str(line[i])) for line in lines) for i in range(len(lines[0]))]
    for line in lines:
        print("  ".join(str(v).ljust(w) for v, w in zip(line, widths)).rstrip())


def print_written(args, plot) -> None:
    """The last lines of a batch command (``ekm compare``, ``ekm tournament``): where its results file
    (``--out`` or ``--resume``) and its ``plot`` are."""
    for path, what in ((args.out or args.resume, "results"), (plot, "plot")):
        if path:
            print(f"{what} written to {path}")


def add_batch_options(p, unit: str, resume: str) -> None:
    """The options of a command whose ``unit`` s (runs, games) go through the batch runner (:mod:`evaluation.batch`):
    where they go (``--workers``, ``--scheduler``) and their results file (``--out``; ``--resume``, helped by
    ``resume``)."""
    import os

    p.add_argument("--workers", type=positive_int, default=None,
                   help=f"local worker processes, each on a CPU of its own (default: the machine's cores, "
                        f"{os.cpu_count()})")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help=f"send the {unit}s to a running Dask scheduler (tcp://host:8786; needs ekm[cluster])")
    p.add_argument("--out", metavar="RESULTS.jsonl",
                   help=f"append every finished {unit} to this results file as it arrives (JSON Lines; must not exist)")
    p.add_argument("--resume", metavar="RESULTS.jsonl", help=resume)
    # a signal before the results file exists waits for it, so that the line names it (ekm.interrupts)
    p.set_defaults(holds_signals=lambda args: bool(args.out or args.resume))


def in_this_process(args) -> None:
    """With ``--workers 1`` and no ``--scheduler`` the jobs run in this process: one CPU for it
    (:mod:`evaluation.pinning`)."""
    if args.workers == 1 and not args.scheduler:
        from evaluation.pinning import pin_to_one_cpu

        pin_to_one_cpu()
