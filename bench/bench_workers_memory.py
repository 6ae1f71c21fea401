"""Resident memory of ``jacobian-lab serve --workers N`` once every worker has shown the symbolic J.

Starts ``serve --workers N --robot panda`` in a process of its own, opens tabs (viser's websocket
protocol, no rendering) until every worker serves one that has received the Panda's symbolic J(q)
(the panel asks for it at once; the worker serving a tab is read from the log, as the tests do), then
sums over the server's whole process tree (the parent, the workers, the symbolic process(es) and
multiprocessing's resource tracker) the PSS (``/proc/PID/smaps_rollup``: pages shared by k processes
count 1/k in each, so the sum is the tree's real footprint) and the RSS (shared pages counted in each
process). Printed per process and in total, with each process's command line shortened.

The disk cache of symbolic results (``$XDG_CACHE_HOME/jacobian-lab``) is a fresh folder warmed by a first
run of the same command, so every measured run reads the J from disk and none spends CPU on SymPy's
simplification (the memory of a J read from the cache is what a class sees once anyone computed it);
with ``--cold`` each run starts from an empty folder, so the J is computed (SymPy's working memory
stays in the process that computed it).

Usage::

    python bench/bench_workers_memory.py                    # --workers 2 and 4
    python bench/bench_workers_memory.py --workers 2 --cache /tmp/jl-cache
    python bench/bench_workers_memory.py --workers 2 --cold   # every run computes the J (no disk cache)
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

from bench.common import tree  # noqa: E402


def _has_mathml(m: dict) -> bool:
    content = m.get("updates", m.get("props", {})).get("content")
    return isinstance(content, str) and "<math" in content


def memory_kib(pid: int) -> tuple[int, int]:
    """(PSS, RSS) of process ``pid`` [KiB] (0, 0 when it ended)."""
    try:
        text = Path(f"/proc/{pid}/smaps_rollup").read_text()
    except OSError:
        return 0, 0
    pss = int(re.search(r"^Pss:\s+(\d+) kB", text, re.M).group(1))  # type: ignore[union-attr]
    rss = int(re.search(r"^Rss:\s+(\d+) kB", text, re.M).group(1))  # type: ignore[union-attr]
    return pss, rss


def role(pid: int, workers: set[int]) -> str:
    if pid in workers:
        return "worker"
    try:
        cmd = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return "?"
    if "resource_tracker" in cmd:
        return "resource tracker"
    if "spawn_main" in cmd:
        return "symbolic process"
    if "app.cli.main" in cmd:
        return "parent"
    return cmd[:60]


def measure(workers: int, port: int, cache: Path, log: Path) -> dict[int, tuple[int, int, str]]:
    env = dict(os.environ, PYTHONPATH=str(ROOT), XDG_CACHE_HOME=str(cache), PYTHONUNBUFFERED="1")
    command = [sys.executable, "-u", "-m", "app.cli.main", "serve", "--robot", "panda"]
    command += ["--port", str(port), "--workers", str(workers)]
    with log.open("w") as err:
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=err, text=True, cwd=ROOT, env=env)
    try:
        assert proc.stdout is not None
        match = None
        for line in proc.stdout:
            match = re.search(r"open http://[^:]+:(\d+)", line)
            if match:
                break
        if match is None:
            raise RuntimeError(f"the server did not start: {log.read_text()[-2000:]}")
        url = f"ws://127.0.0.1:{match.group(1)}"
        listed = re.search(r"worker processes: ([\d ]+)\)", line)
        pids = {int(p) for p in listed.group(1).split()} if listed else {proc.pid}
        served: dict[int, ViserWsClient] = {}
        extra: list[ViserWsClient] = []
        for _ in range(60):
            if set(served) == pids:
                break
            before = len(re.findall(r"connected \(\d+ open in process", log.read_text()))
            ws = ViserWsClient(url).__enter__()
            ws.wait_for(_has_mathml, timeout=300)
            end = time.monotonic() + 30
            logged = r"connected \(\d+ open in process (\d+)\)"
            while len(found := re.findall(logged, log.read_text())) <= before:
                if time.monotonic() > end:
                    raise RuntimeError("the tab's connection was not logged")
                time.sleep(0.05)
            pid = int(found[before])
            if pid in served:
                extra.append(ws)
            else:
                served[pid] = ws
        if set(served) != pids:
            raise RuntimeError(f"tabs did not reach every worker: {sorted(served)} of {sorted(pids)}")
        for ws in extra:  # one tab per worker is measured
            ws.__exit__(None, None, None)
        time.sleep(2.0)  # let the workers settle (closed tabs released)
        found_mem = {}
        for p in tree(proc.pid):
            pss, rss = memory_kib(p)
            found_mem[p] = (pss, rss, role(p, pids))
        for ws in served.values():
            ws.__exit__(None, None, None)
        return found_mem
    finally:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(30)
        except subprocess.TimeoutExpired:
            proc.kill()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, nargs="+", default=[2, 4])
    parser.add_argument("--port", type=int, default=18150)
    parser.add_argument("--cache", type=Path, default=None, help="disk cache folder (default: a fresh one)")
    parser.add_argument("--cold", action="store_true", help="an empty disk cache for every run: J computed")
    args = parser.parse_args()
    cache = args.cache or Path(tempfile.mkdtemp(prefix="jl-mem-"))
    log = Path(tempfile.mkdtemp(prefix="jl-mem-log-")) / "serve.log"
    if not args.cold and not (cache / "jacobian-lab" / "symbolic").exists():
        print(f"warming the disk cache in {cache} (one worker computes the Panda's J once)", flush=True)
        measure(1, args.port, cache, log)
    for n in args.workers:
        if args.cold:
            cache = Path(tempfile.mkdtemp(prefix="jl-mem-cold-"))
        found = measure(n, args.port, cache, log)
        pss = sum(v[0] for v in found.values())
        rss = sum(v[1] for v in found.values())
        print(f"\n--workers {n}: {len(found)} processes, PSS {pss / 1024:.0f} MiB, RSS {rss / 1024:.0f} MiB")
        for pid, (p, r, what) in sorted(found.items()):
            print(f"  {pid:>8} {what:<18} PSS {p / 1024:7.1f} MiB  RSS {r / 1024:7.1f} MiB")


if __name__ == "__main__":
    main()
