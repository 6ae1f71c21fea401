"""viser's private API, part 5: GUI icons read once (see the package).

viser 1.1's ``_icons.svg_from_icon`` opens its 1.9 MB icon archive (about 5,000 entries) for every icon
it does not hold in a 32-entry cache, and the cache does not stop several threads from reading the
same icon at once. A tab's panel asks for about forty icons (every tab of a panel rebuilds the icons of
all its tabs), and a class of tabs connecting at once builds their panels in parallel: measured with
ten tabs arriving together, reading the archive took three quarters of the server's time for eight
seconds, during which every tab's slider waited. :func:`install_icon_cache` opens the archive once
and keeps every icon read.
"""

from __future__ import annotations

import importlib
import threading
import zipfile
from typing import Any

from .core import ViserApiChanged, _private

__all__ = ["install_icon_cache"]

_installed: list[Any] = []


def install_icon_cache() -> None:
    """Make viser read each GUI icon from its archive once per process (idempotent).

    Raises:
        ViserApiChanged: ``svg_from_icon`` or the archive moved.
    """
    if _installed:
        return

    def module(name: str) -> Any:
        return _private(
            "install_icon_cache", f"viser.{name}", lambda: importlib.import_module(f"viser.{name}")
        )

    icons = module("_icons")
    path = _private(
        "install_icon_cache", "viser._icons.ICONS_DIR", lambda: icons.ICONS_DIR / "tabler-icons.zip"
    )
    users = [module("_gui_api"), module("_gui_handles")]
    if not path.is_file() or not all(callable(getattr(m, "svg_from_icon", None)) for m in (icons, *users)):
        raise ViserApiChanged("install_icon_cache", f"svg_from_icon or {path.name} is gone")
    lock = threading.Lock()
    cache: dict[str, str] = {}
    archive: list[zipfile.ZipFile] = []

    def svg_from_icon(icon_name: str) -> str:
        svg = cache.get(icon_name)
        if svg is not None:
            return svg
        with lock:  # one reader: the others wait for the icon instead of reading it too
            if icon_name not in cache:
                if not archive:
                    archive.append(zipfile.ZipFile(path))  # its table of contents, read once
                with archive[0].open(f"{icon_name}.svg") as file:
                    cache[icon_name] = file.read().decode("utf-8")
            return cache[icon_name]

    for user in (icons, *users):
        user.svg_from_icon = svg_from_icon
    _installed.append(svg_from_icon)
