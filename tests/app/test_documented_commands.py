"""Issue 26: the commands in README.md and docs/ that start a server are run as printed.

Every ``jacobian-lab serve …`` line of a code block is run as ``python -m app.cli.main serve …`` (the
console script's entry point) with only ``--port 0`` appended (argparse takes the last ``--port``: no
test may hold a fixed port), in a folder holding the files the line names (a small URDF with the links
the lines choose). Each must print its address (and, in classroom mode, a presenter link in the query)
and serve a tab its sliders; then it is stopped. The default workers run wherever the line runs them.
"""

from __future__ import annotations

import re
import shlex

import pytest
from locations import ROOT
from server_process import Server
from wsclient import ViserWsClient

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
URDF = """<robot name="arm">
  <link name="base_link"/><link name="l1"/><link name="tool0"/>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="l1"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="tool0"/>
    <origin xyz="0.4 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>
"""


def documented_serve_commands() -> list[str]:
    """Each distinct ``jacobian-lab serve`` command of the pages' code blocks, its comment left out."""
    found: list[str] = []
    for page in PAGES:
        for block in re.findall(r"```[^\n]*\n(.*?)```", page.read_text(encoding="utf-8"), flags=re.S):
            for line in block.splitlines():
                m = re.search(r"(?:^|&&\s*)jacobian-lab (serve\b[^#]*)", line)
                if m and m.group(1).strip() not in found:
                    found.append(m.group(1).strip())
    return found


def test_the_pages_print_serve_commands_worth_running():
    commands = documented_serve_commands()
    assert "serve" in commands and any("--presenter" in c for c in commands) and len(commands) >= 6


@pytest.mark.slow
@pytest.mark.parametrize("command", documented_serve_commands())
def test_a_documented_serve_command_serves_a_tab_as_printed(tmp_path, command):
    argv = shlex.split(command)
    for name in argv:
        if name.endswith(".urdf"):
            (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
            (tmp_path / name).write_text(URDF)
    server = Server(tmp_path, argv=[*argv, "--port", "0"], cwd=tmp_path)
    try:
        with ViserWsClient(server.url()) as tab:
            tab.wait_for(lambda m: m["type"] == "GuiSliderMessage")
        if "--presenter" in argv:
            printed = "".join(server.out)
            assert re.search(r"open http://\S+/\?presenter=[\w-]{22} in the tab", printed), printed
    finally:
        server.cleanup()
