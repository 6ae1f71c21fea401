"""viser's private API, part 3: cheaper prop assignment (see the package)."""

from __future__ import annotations

from typing import Any

from .core import ViserApiChanged, _private

__all__ = ["install_fast_prop_casts"]


# --------------------------------------------------------------------------- faster prop assignment
_FAST_CAST_INSTALLED = False


def install_fast_prop_casts() -> None:
    """Make every handle prop assignment cheaper, with the same result.

    viser 1.1's ``AssignablePropsBase._cast_value_recursive`` builds four ``numpy.typing``
    aliases (``npt.NDArray[np.float32]``, ...) on every assignment to compare the prop's type
    hint with them: about a third of the cost of moving a scene node. This builds them once.
    Idempotent.

    Raises:
        ViserApiChanged: the method moved.
    """
    global _FAST_CAST_INSTALLED
    if _FAST_CAST_INSTALLED:
        return
    import numpy as np
    import numpy.typing as npt

    props_api = _private(
        "install_fast_prop_casts",
        "viser._assignable_props_api.AssignablePropsBase._cast_value_recursive",
        lambda: __import__("viser._assignable_props_api", fromlist=["AssignablePropsBase"]),
    )
    base = props_api.AssignablePropsBase
    if not callable(getattr(base, "_cast_value_recursive", None)):
        raise ViserApiChanged("install_fast_prop_casts", "AssignablePropsBase._cast_value_recursive is gone")
    f16, f32, f64, u8 = (npt.NDArray[t] for t in (np.float16, np.float32, np.float64, np.uint8))
    colors_to_uint8 = props_api.colors_to_uint8

    def cast(self: Any, hint: Any, value: Any, prop_name: str) -> Any:
        if hint == f32:
            return np.asarray(value).astype(np.float32)
        if hint == f64:
            return np.asarray(value).astype(np.float64)
        if hint == f16:
            return np.asarray(value).astype(np.float16)
        if hint == u8 and "color" in prop_name:
            return colors_to_uint8(value)
        if isinstance(value, np.ndarray):
            return value
        if (
            isinstance(value, tuple)
            and getattr(hint, "__origin__", None) is tuple
            and len(getattr(hint, "__args__", ())) == 2
            and hint.__args__[1] is ...
        ):
            element = hint.__args__[0]
            return tuple(cast(self, element, item, prop_name) for item in value)
        return value

    base._jl_original_cast = base._cast_value_recursive
    base._cast_value_recursive = cast
    _FAST_CAST_INSTALLED = True
