"""Public names imported on first use: the one rule of the package's lazy facades.

``import forceclosure`` (and ``import forceclosure.synthesis``) must not load NumPy, SciPy
or numba (``forceclosure --help`` answers at once; tests/test_startup.py). So a facade
names where each public name lives and imports its module when the name is first asked
for (PEP 562, a module's ``__getattr__`` and ``__dir__``). This module imports nothing of
the package. A facade's ``__init__`` reads::

    _HOME = {"analyze": "analysis.closure", ...}
    __getattr__, __dir__ = lazy_names(__name__, _HOME)
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Mapping
from importlib import import_module
from typing import Any

__all__ = ["lazy_names"]


def lazy_names(package: str, home: Mapping[str, str]
               ) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """A package's ``__getattr__`` and ``__dir__`` that import each public name on first use.

    Parameters
    ----------
    package : str
        The package's ``__name__`` (it must be in ``sys.modules``, as it is while its
        ``__init__`` runs).
    home : mapping of str to str
        Each public name and the module, relative to ``package``, that defines it.

    Returns
    -------
    (__getattr__, __dir__)
        ``__getattr__(name)`` imports ``home[name]``, keeps the value in the package's
        namespace (later look-ups do not come back) and returns it; any other name raises
        :class:`AttributeError`. ``__dir__()`` lists the package's namespace and every
        name of ``home``.

    Examples
    --------
    ``json.decoder`` defines ``JSONDecoder``:

    >>> get, names = lazy_names("json", {"JSONDecoder": "decoder"})
    >>> get("JSONDecoder").__module__, "JSONDecoder" in names()
    ('json.decoder', True)
    >>> get("nonsense")
    Traceback (most recent call last):
    ...
    AttributeError: module 'json' has no attribute 'nonsense'
    """
    namespace = vars(sys.modules[package])

    def __getattr__(name: str) -> Any:
        if name in home:
            value = getattr(import_module(f".{home[name]}", package), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(home))

    return __getattr__, __dir__
