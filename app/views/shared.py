"""Readouts made once per snapshot, whoever shows them: a room of followers formats the presenter's
numbers once, not once per tab.

Every follower of a process draws the same :class:`~app.core.snapshot.Snapshot` object (the presenter's,
or the one its worker computed for a relayed state). Its readouts (J as HTML, the status line, the
measures, J⁻¹, the course's grid) are pure functions of the snapshot, the state and the language, so
:func:`once` keeps each result beside the snapshot it was made from and hands it to every tab that asks
again with the same arguments. A tab that explores on its own has its own snapshot, hence its own
results. The results go when the snapshot goes (a weak key), so the memory is that of the few
snapshots tabs still show.

Arguments are compared by value when they are small immutable values (text, numbers, tuples of them)
and by identity otherwise (a state, a robot, an array, a translator): never a wrong hit, and every
follower passes the same objects. A function given here must be pure (its result depends only on its
arguments).
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["once", "stats"]

T = TypeVar("T")

_VALUES = (str, int, float, bool, type(None))
_lock = threading.Lock()
_made: weakref.WeakKeyDictionary[Any, dict[tuple, tuple[tuple, Any]]] = weakref.WeakKeyDictionary()
stats = {"made": 0, "shared": 0}
"""How many results were made and how many handed out again (for tests and benches)."""


def _key(value: Any) -> Any:
    if isinstance(value, _VALUES):
        return value
    if isinstance(value, tuple) and all(isinstance(v, _VALUES) for v in value):
        return value
    return ("id", id(value))  # the entry keeps ``value`` alive: its id is never reused meanwhile


def once(snap: Any, fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    """``fn(*args, **kwargs)``, made once for ``snap`` (the snapshot it shows) and shared after.

    Args:
        snap: The snapshot the result belongs to (its lifetime bounds the result's).
        fn: A pure function.
    """
    key = (fn, tuple(_key(a) for a in args), tuple((k, _key(v)) for k, v in sorted(kwargs.items())))
    with _lock:
        made = _made.get(snap)
        if made is not None and key in made:
            stats["shared"] += 1
            return made[key][1]
    result = fn(*args, **kwargs)
    with _lock:
        stats["made"] += 1
        _made.setdefault(snap, {})[key] = ((args, kwargs), result)  # args kept: their ids stay theirs
    return result
