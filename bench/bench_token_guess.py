"""How fast can tabs guess the presenter token, and is the teacher's right token still taken?

Run from a checkout (``PYTHONPATH=$PWD python bench/bench_token_guess.py [--workers N] [--clients K]``):
starts ``jacobian-lab serve --presenter-token TOKEN`` as a teacher does (the default workers unless
``--workers``), then ``K`` scripted tabs, all from 127.0.0.1 (as behind a reverse proxy or a campus
NAT), guess for ``--seconds``: each opens a connection, types wrong tokens until the server refuses its
tries, and reconnects. At the end a fresh tab types the right token. Prints the guesses the server read
and compared per second, what it refused, whether and how fast the teacher's token was taken, and how
long a token of b bits would last at that rate. Run it on two commits to compare (issue 26, point 3:
``docs/security.md``). The guessing tabs are one Python process: the rate is what this client reached,
a lower bound on a determined attacker's.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from server_process import Server  # noqa: E402
from wsclient import ViserWsClient  # noqa: E402

from app.viser_adapter import message_class  # noqa: E402

TOKEN = "lecture-7"  # what a teacher might type by hand (warned about at start)
UPDATE = message_class("GuiUpdateMessage")


def _token_box(ws: ViserWsClient) -> str:
    _, m = ws.wait_for(
        lambda m: m["type"] == "GuiTextMessage" and m.get("props", {}).get("label") == "Presenter token",
        timeout=120,
    )
    return m["uuid"]


def _answer(ws: ViserWsClient, box: str, text: str) -> str:
    mark = ws.mark()
    ws.send(UPDATE(box, {"value": text}))
    _, m = ws.wait_for(
        lambda m: m["type"] == "NotificationShowMessage" or "presenting" in str(m.get("updates", {})),
        after=mark,
        timeout=120,
    )
    return str(m.get("props", {}).get("body", "presenting"))


class Tally:
    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.read = self.refused = self.connections = 0
        self.refusals: dict[str, int] = {}

    def add(self, body: str) -> bool:
        """Count an answer; whether the guess was read (a refusal ends the connection's guessing)."""
        with self.lock:
            if "not the presenter token" in body:
                self.read += 1
                return True
            self.refused += 1
            kind = body.split(":")[0]
            self.refusals[kind] = self.refusals.get(kind, 0) + 1
            return False


def _guesser(url: str, index: int, end: float, tally: Tally) -> None:
    n = 0
    while time.monotonic() < end:
        with ViserWsClient(url) as ws:
            with tally.lock:
                tally.connections += 1
            box = _token_box(ws)
            while time.monotonic() < end:
                n += 1
                if not tally.add(_answer(ws, box, f"guess-{index}-{n}")):
                    break


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=None, help="serve --workers N (default: serve's)")
    parser.add_argument("--clients", type=int, default=16, help="guessing tabs at once")
    parser.add_argument("--seconds", type=float, default=40.0, help="how long they guess [s]")
    args = parser.parse_args()
    argv = ["serve", "--robot", "planar2", "--port", "0", "--presenter-token", TOKEN]
    argv += ["--workers", str(args.workers)] if args.workers else []
    with tempfile.TemporaryDirectory() as tmp:
        server = Server(Path(tmp), argv=argv)
        try:
            url, tally = f"ws://127.0.0.1:{server.port}", Tally()
            end = time.monotonic() + args.seconds
            start = time.monotonic()
            threads = [
                threading.Thread(target=_guesser, args=(url, i, end, tally), daemon=True)
                for i in range(args.clients)
            ]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            spent = time.monotonic() - start
            with ViserWsClient(url) as teacher:
                box = _token_box(teacher)
                t0 = time.monotonic()
                body = _answer(teacher, box, TOKEN)
                took = time.monotonic() - t0
        finally:
            server.cleanup()
    rate = tally.read / spent
    print(f"serve {' '.join(argv[1:])}: {args.clients} guessing tabs from one address for {spent:.0f} s")
    print(f"  guesses read and compared: {tally.read} ({rate:.1f}/s) over {tally.connections} connections")
    print(f"  tries refused unread: {tally.refused} {tally.refusals}")
    teacher_said = "taken" if body == "presenting" else f"refused: {body!r}"
    print(f"  then the teacher's right token from the same address: {teacher_said} ({took:.1f} s)")
    for bits in (20, 30, 40, 64, 128):
        seconds = 2 ** (bits - 1) / max(rate, 1e-9)
        print(f"  a token of {bits:3d} bits: half its space at this rate in {_span(seconds)}")


def _span(seconds: float) -> str:
    for unit, size in (("years", 3.156e7), ("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


if __name__ == "__main__":
    main()
