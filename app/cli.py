"""Jacobian Lab command line: ``jacobian-lab serve`` and ``jacobian-lab export``.

Examples::

    jacobian-lab serve                      # default robot on http://127.0.0.1:8080
    jacobian-lab serve --robot panda --port 8081
    jacobian-lab serve --urdf my_arm.urdf
    jacobian-lab export puma560 --format latex -o puma_J.tex
"""

from __future__ import annotations

import argparse
import sys

__all__ = ["main"]


def _build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="jacobian-lab",
        description="See a manipulator's Jacobian: interactive browser visualiser and symbolic exports.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    serve = sub.add_parser("serve", help="start the browser app (default command)")
    which = serve.add_mutually_exclusive_group()
    which.add_argument("--robot", help="library robot to show first (see 'jacobian-lab robots')")
    which.add_argument("--urdf", help="path to a URDF file to show first")
    serve.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    serve.add_argument("--port", type=int, default=8080, help="port (default 8080; 0 picks a free one)")
    sub.add_parser("robots", help="list the library robots")
    sub.add_parser("export", help="export J(q) as LaTeX, MathML, Python or JSON", add_help=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``jacobian-lab`` console script."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "export":
        from kinematics.export import main as export_main

        return export_main(argv[1:])
    args = _build_parser().parse_args(argv or ["serve"])
    if args.command == "robots":
        import robots

        for name in robots.names():
            robot = robots.load(name)
            print(f"{name:14s} {robot.dof} joints  {robot.title}")
        return 0
    from kinematics.errors import JacobianLabError

    try:
        from app.server import serve

        serve(robot=args.robot, urdf=args.urdf, host=args.host, port=args.port, block=True)
    except JacobianLabError as exc:
        print(f"jacobian-lab: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
