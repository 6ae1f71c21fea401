"""Where a server's time goes, from py-spy's collapsed stacks (``bench_app_load.py --profile DIR``).

Prints the share of samples per thread, then the functions with the most samples, counted once per
stack (inclusive) and at the top of the stack (self), e.g.::

    python bench/profile_stacks.py /tmp/prof/server-60.txt --top 40
    python bench/profile_stacks.py /tmp/prof/server-60.txt --under "visit (app/tab/session.py"
"""

from __future__ import annotations

import argparse
import collections
import re
from pathlib import Path


def read(path: Path) -> list[tuple[list[str], int]]:
    """(frames root first, count) per line of py-spy's raw output."""
    stacks = []
    for line in path.read_text().splitlines():
        stack, _, count = line.rpartition(" ")
        if stack and count.isdigit():
            stacks.append((stack.split(";"), int(count)))
    return stacks


def short(frame: str) -> str:
    """``name (path/to/file.py:123)`` → ``name (file.py)``: functions summed over their lines."""
    return re.sub(r"\((?:[^()]*/)?([^/():]+\.py)(?::\d+)?\)", r"(\1)", frame)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("stacks", type=Path)
    parser.add_argument("--top", type=int, default=30)
    parser.add_argument("--under", default="", help="only stacks through a frame containing this text")
    args = parser.parse_args()
    stacks = read(args.stacks)
    if args.under:
        stacks = [(s, c) for s, c in stacks if any(args.under in f for f in s)]
    total = sum(c for _, c in stacks) or 1
    threads: collections.Counter[str] = collections.Counter()
    inclusive: collections.Counter[str] = collections.Counter()
    own: collections.Counter[str] = collections.Counter()
    for frames, count in stacks:
        threads[frames[0]] += count
        for name in {short(f) for f in frames[1:]}:
            inclusive[name] += count
        own[short(frames[-1])] += count
    print(f"{total} samples")
    for name, count in threads.most_common(8):
        print(f"  {100 * count / total:5.1f} %  {name}")
    print("inclusive:")
    for name, count in inclusive.most_common(args.top):
        print(f"  {100 * count / total:5.1f} %  {name}")
    print("self:")
    for name, count in own.most_common(args.top):
        print(f"  {100 * count / total:5.1f} %  {name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
