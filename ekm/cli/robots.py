"""``ekm robots``: list the named robots, print one's file as a template (``--show``), or validate robot files
(``--check``) (docs/design.md §2, §10)."""

from __future__ import annotations

from ekm.cli.args import command, print_json


def add_parser(sub) -> None:
    p = command(sub, "robots", "list the named robots, print one's file as a template, or check robot files",
                ["ekm robots", "ekm robots --show khepera > my-robot.json   # a template to edit",
                 "ekm robots --check my-robot.json",
                 "ekm run --world three-rooms --architecture fields --robot my-robot.json --learn"],
                more="A robot file holds every parameter of the robot (docs/guide/robots.md); --robot NAME|FILE on "
                     "train, evaluate, run and compare drives it.")
    p.add_argument("--show", metavar="ROBOT", help="print a robot's file (a named robot or a file): a template")
    p.add_argument("--check", metavar="FILE", nargs="+", help="validate robot files (exit 2 on the first bad one)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """List the named robots (:func:`ekm.robots`), print one's file, or validate robot files."""
    from ekm.api.robots import robot, robots
    from ekm.errors import InputError
    from robots.robotfile import describe, robot_json

    if args.show is not None:
        if args.check or args.json:
            raise InputError("ekm robots: --show prints one robot's file; drop --check and --json")
        print(robot_json(robot(args.show)), end="")
        return
    result = robots(check=args.check)
    if args.json:
        print_json(result.to_dict())
        return
    if args.check:
        for path, r in zip(args.check, result.items):
            print(f"{path}: ok, robot {r.name} ({describe(r)})")
        return
    width = max(len(r.name) for r in result.items)
    for r, origin in zip(result.items, result.origins()):
        print(f"{r.name.ljust(width)}  {describe(r)}" + ("" if origin == "built in" else f" ({origin})"))
        print(f"{''.ljust(width)}  {r.about}")
