"""A real jupyter-server for the notebook tests in Chromium: on 127.0.0.1, a free port, under a
JupyterHub-like prefix, serving ``root`` (its ``/files/`` and the proxy extension when installed)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from fakes import poll


def jupyter_server(root: Path, log: Path, prefix: str, token: str = "") -> tuple[subprocess.Popen, int]:
    """Start jupyter-server at ``prefix`` over ``root`` (``token``: its login; "" for none); returns the
    process and the port it listens on, once it does (its output goes to ``log``)."""
    command = [
        sys.executable,
        "-m",
        "jupyter_server",
        "--allow-root",
        "--ServerApp.ip=127.0.0.1",
        "--ServerApp.port=0",
        f"--ServerApp.base_url={prefix}",
        f"--IdentityProvider.token={token}",
        "--ServerApp.open_browser=False",
        f"--ServerApp.root_dir={root}",
    ]
    server = subprocess.Popen(command, stdout=log.open("w"), stderr=subprocess.STDOUT, cwd=root)

    def port() -> int | None:
        if server.poll() is not None:
            raise AssertionError(f"jupyter-server ended: {log.read_text()}")
        found = re.search(rf"http://127\.0\.0\.1:(\d+){prefix}", log.read_text())
        return int(found.group(1)) if found else None

    return server, poll(port, what="jupyter-server listening")
