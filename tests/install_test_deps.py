"""Install what the test suite needs beyond PyPI: Debian's Chromium (for the browser tests).

Run by the README's test command before pytest. Idempotent and quick when
everything is already there. Never downloads a browser build of its own
(``playwright install`` is not used): Chromium comes from Debian's packages.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

CHROMIUM = "/usr/bin/chromium"


def _run(cmd: list[str]) -> int:
    print("+", " ".join(cmd), flush=True)
    return subprocess.call(cmd)


def ensure_chromium() -> bool:
    if os.path.exists(CHROMIUM):
        return True
    if shutil.which("apt-get") is None:
        print(f"install_test_deps: {CHROMIUM} is missing and apt-get is not available; "
              "install Chromium yourself to run the browser tests", file=sys.stderr)
        return False
    sudo = [] if os.geteuid() == 0 else (["sudo", "-n"] if shutil.which("sudo") else None)
    if sudo is None:
        print("install_test_deps: need root to apt-get install chromium", file=sys.stderr)
        return False
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    for cmd in (sudo + ["apt-get", "update", "-qq"], sudo + ["apt-get", "install", "-y", "-qq", "chromium"]):
        print("+", " ".join(cmd), flush=True)
        if subprocess.call(cmd, env=env, stdout=subprocess.DEVNULL) != 0:
            print(f"install_test_deps: '{' '.join(cmd)}' failed", file=sys.stderr)
            return False
    return os.path.exists(CHROMIUM)


def main() -> int:
    ok = ensure_chromium()
    # In CI a missing browser must fail the run (the browser tests would fail anyway).
    if not ok and os.environ.get("CI"):
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
