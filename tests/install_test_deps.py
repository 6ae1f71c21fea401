"""Install what the test suite needs beyond PyPI, from Debian's packages.

* Chromium (``/usr/bin/chromium``) for the browser tests;
* Node.js and npm, which run KaTeX (pinned in ``tests/katex``) to check that
  the exported LaTeX typesets;
* a C compiler and Octave, which compile and run the exported C and MATLAB/Octave
  Jacobians (``tests/test_export_code.py``);
* nginx (``nginx-light``) and openssl, which run the reverse-proxy configuration of
  ``docs/classroom.md`` (``tests/app/test_reverse_proxy.py``).

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


def _apt_install(packages: list[str], recommends: bool = True) -> bool:
    if shutil.which("apt-get") is None:
        print(
            f"install_test_deps: apt-get is not available; install {' '.join(packages)} yourself",
            file=sys.stderr,
        )
        return False
    sudo = [] if os.geteuid() == 0 else (["sudo", "-n"] if shutil.which("sudo") else None)
    if sudo is None:
        print(f"install_test_deps: need root to apt-get install {' '.join(packages)}", file=sys.stderr)
        return False
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    install = [
        "apt-get",
        "install",
        "-y",
        "-qq",
        *([] if recommends else ["--no-install-recommends"]),
        *packages,
    ]
    for cmd in (sudo + ["apt-get", "update", "-qq"], sudo + install):
        print("+", " ".join(cmd), flush=True)
        if subprocess.call(cmd, env=env, stdout=subprocess.DEVNULL) != 0:
            print(f"install_test_deps: '{' '.join(cmd)}' failed", file=sys.stderr)
            return False
    return True


def ensure_packages() -> bool:
    """Chromium, node, npm, a C compiler, Octave, nginx and openssl, each installed only when missing."""
    wanted = []
    if not os.path.exists(CHROMIUM):
        wanted.append("chromium")
    if shutil.which("node") is None:
        wanted.append("nodejs")
    if shutil.which("npm") is None:
        wanted.append("npm")
    if shutil.which("cc") is None:
        wanted += ["gcc", "libc6-dev"]
    if shutil.which("nginx") is None and not os.path.exists("/usr/sbin/nginx"):
        wanted.append("nginx-light")
    if shutil.which("openssl") is None:
        wanted.append("openssl")
    if wanted and not _apt_install(wanted):
        return False
    # Octave's recommended packages (documentation, a GUI) are large and not needed to run a function.
    if shutil.which("octave-cli") is None and not _apt_install(["octave"], recommends=False):
        return False
    tools = ("node", "npm", "cc", "octave-cli", "openssl")
    nginx = shutil.which("nginx") is not None or os.path.exists("/usr/sbin/nginx")
    return os.path.exists(CHROMIUM) and nginx and all(shutil.which(tool) is not None for tool in tools)


def main() -> int:
    ok = ensure_packages()
    # In CI anything missing fails the run (the tests that need it would fail anyway).
    if not ok and os.environ.get("CI"):
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
