"""Jacobian Lab command line: ``jacobian-lab serve``, ``robots``, ``export``, ``handout`` and ``record``.

Examples::

    jacobian-lab serve                      # default robot on http://127.0.0.1:8080
    jacobian-lab serve --robot panda --port 8081
    jacobian-lab serve --urdf my_arm.urdf --tip tool0
    jacobian-lab export puma560 --format latex -o puma_J.tex
    jacobian-lab handout trr --symbolic-params -o trr.html  # the derivation, step by step
    jacobian-lab record puma560 -o puma_demo     # a demo any static web server can play

Every mistake on the command line (an unknown robot, a URDF that cannot be read, a link that is
not in it, a port outside 0..65535, a host name that does not resolve to an address of this
machine) is reported on stderr at once with exit status 2, before any server starts.
"""

from __future__ import annotations

import argparse
import sys

from app.core.i18n import CODES

from .export import add_chain_arguments, xacro_arguments
from .packages import add_package_arguments, package_options

__all__ = ["main"]


def _port(text: str) -> int:
    try:
        port = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a port number from 0 to 65535, got {text!r}") from None
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"expected a port number from 0 to 65535, got {port}")
    return port


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
    add_chain_arguments(serve)
    add_package_arguments(serve)
    serve.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    serve.add_argument("--port", type=_port, default=8080, help="port (default 8080; 0 picks a free one)")
    serve.add_argument(
        "--workers",
        type=_workers,
        default=None,
        metavar="N",
        help="server processes behind the one address (default: one per core, at most 16; "
        "1: a single process; in classroom mode the presenter reaches the tabs of every process)",
    )
    present = serve.add_mutually_exclusive_group()
    present.add_argument(
        "--presenter-token",
        metavar="TOKEN",
        help="classroom mode: the tab where TOKEN is typed presents, every other tab follows",
    )
    present.add_argument(
        "--presenter",
        nargs="?",
        const="",
        metavar="TOKEN",
        help="classroom mode; alone, with a random strong token and a presenter link (printed); a weak "
        "TOKEN given by hand is warned about",
    )
    serve.add_argument(
        "--lang",
        choices=CODES,
        default="",
        help="the room's language (default: each tab speaks its browser's; a tab may still choose its own)",
    )
    serve.add_argument(
        "--allow-origin",
        metavar="ORIGIN",
        action="append",
        default=[],
        help="also let pages from ORIGIN (e.g. https://course.example.org) connect, for a deliberate "
        "embedding; by default only the lab's own page may (repeatable)",
    )
    serve.add_argument(
        "--trusted-proxy",
        metavar="ADDR",
        action="append",
        default=[],
        help="a reverse proxy in front of the lab (an address such as 127.0.0.1, or a network such as "
        "10.0.0.0/8): its X-Forwarded-For header names the client in the log; any other peer's header is "
        "ignored (repeatable)",
    )
    sub.add_parser("robots", help="list the library robots")
    sub.add_parser(
        "export",
        help="export J(q) as LaTeX, MathML or JSON, or a controller's T, J, Jdot (and dJ/dq) as "
        "Python/NumPy, C or MATLAB/Octave code",
        add_help=False,
    )
    sub.add_parser(
        "handout",
        help="the derivation of J step by step, as an HTML page or a LaTeX document",
        add_help=False,
    )
    sub.add_parser("record", help="record a demo that plays from any static web server", add_help=False)
    return parser


def _workers(text: str) -> int:
    from .workers import WORKER_CAP

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number of processes, got {text!r}") from None
    if not 1 <= value <= WORKER_CAP:
        raise argparse.ArgumentTypeError(f"expected 1 to {WORKER_CAP} processes, got {value}")
    return value


def _fail(message: str) -> int:
    print(f"jacobian-lab: error: {message}", file=sys.stderr)
    return 2


def _serve(args: argparse.Namespace) -> int:
    import robots
    from kinematics.errors import JacobianLabError

    if args.robot is None and args.urdf is None and (args.base or args.tip):
        return _fail("--base and --tip choose a chain of the URDF given with --urdf")
    from app.services.lifecycle import check_listen_address

    try:
        check_listen_address(args.host, args.port)
    except ValueError as exc:
        return _fail(str(exc))
    from app.viser_adapter.core import trusted_proxies
    from app.viser_adapter.handshake import normalized_origin

    try:
        for origin in args.allow_origin:
            normalized_origin(origin)
    except ValueError as exc:
        return _fail(f"--allow-origin: {exc}")
    try:
        trusted_proxies(args.trusted_proxy)
    except ValueError as exc:
        return _fail(f"--trusted-proxy: {exc}")
    token = args.presenter_token if args.presenter_token is not None else args.presenter
    if token == "" and args.presenter == "":  # --presenter alone
        from app.services.classroom import random_token

        token = random_token()
    elif token is not None:
        if not 1 <= len(token.strip()) <= 200:
            return _fail("--presenter-token needs 1 to 200 characters (not only spaces)")
        from app.services.classroom import token_weakness

        weak = token_weakness(token)
        if weak:
            print(f"jacobian-lab: warning: {weak}", file=sys.stderr)
    from .workers import default_workers, serve_workers

    workers = args.workers if args.workers is not None else default_workers()
    try:  # fail before the server starts (and before viser is imported)
        xacro, packages = xacro_arguments(args), package_options(args)
        if args.urdf or args.robot:
            robots.load(
                args.urdf or args.robot, base_link=args.base, tip_link=args.tip, xacro_args=xacro, **packages
            )
        if workers > 1:
            options = {"robot": args.robot, "urdf": args.urdf, "base_link": args.base, "tip_link": args.tip}
            options["allow_origin"], options["trusted_proxy"] = args.allow_origin, args.trusted_proxy
            options["xacro_args"] = xacro
            options.update(packages)  # plain strings: the worker processes are spawned
            options["language"] = args.lang
            return serve_workers(workers, options, host=args.host, port=args.port, presenter_token=token)
        from app.server import serve

        serve(
            robot=args.robot,
            urdf=args.urdf,
            base_link=args.base,
            tip_link=args.tip,
            host=args.host,
            port=args.port,
            block=True,
            presenter_token=token,
            allow_origin=args.allow_origin,
            xacro_args=xacro,
            language=args.lang,
            trusted_proxy=args.trusted_proxy,
            **packages,
        )
    except (JacobianLabError, ValueError, RuntimeError) as exc:
        return _fail(str(exc))
    except KeyboardInterrupt:
        pass
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``jacobian-lab`` console script; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "export":
        from .export import main as export_main

        return export_main(argv[1:])
    if argv and argv[0] == "handout":
        from .handout import main as handout_main

        return handout_main(argv[1:])
    if argv and argv[0] == "record":
        from .record import main as record_main

        return record_main(argv[1:])
    try:
        args = _build_parser().parse_args(argv or ["serve"])
    except SystemExit as exc:  # --help, or a usage error already printed by argparse
        return exc.code if isinstance(exc.code, int) else 2
    if args.command == "robots":
        import robots

        for name in robots.names():
            robot = robots.load(name)
            print(f"{name:14s} {robot.dof} joints  {robot.title}")
        return 0
    return _serve(args)


if __name__ == "__main__":
    raise SystemExit(main())
