"""The JSON schemas of the files forceclosure reads and writes, shipped in the package.

``grasp-file``: a grasp file as ``forceclosure analyze`` reads it (and
:func:`forceclosure.io.grasp_file.parse_grasp_file`); ``regions``: one region
set as ``RegionSet.to_dict()`` returns it and ``forceclosure synthesize --json``
prints it. The files stand beside this module
(``forceclosure/schemas/<name>.schema.json``) in a checkout and in an installed
wheel alike, and are found with :mod:`importlib.resources`. This module imports
nothing of the package but :mod:`forceclosure.errors`.

Examples
--------
>>> schema = load_schema("grasp-file")
>>> schema["title"]
'forceclosure grasp file'
>>> sorted(SCHEMAS)
['grasp-file', 'regions']
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

from ..errors import InputError

__all__ = ["SCHEMAS", "load_schema", "schema_text"]

#: The schemas shipped, by name (the file is ``<name>.schema.json``).
SCHEMAS = ("grasp-file", "regions")


def schema_text(name: str) -> str:
    """The text of the schema ``name``, as shipped.

    Parameters
    ----------
    name : str
        One of :data:`SCHEMAS`.

    Returns
    -------
    str
        The JSON text.

    Raises
    ------
    InputError
        For a name that is not one of :data:`SCHEMAS`.
    """
    if name not in SCHEMAS:
        raise InputError(f"no schema named {name!r}; the schemas are {', '.join(SCHEMAS)}")
    resource = resources.files(__name__) / f"{name}.schema.json"
    return resource.read_text(encoding="utf-8")


def load_schema(name: str) -> dict[str, Any]:
    """The schema ``name`` (JSON Schema, draft 2020-12) parsed: a new dictionary on each call.

    ``name`` is one of :data:`SCHEMAS`; any other is refused as by :func:`schema_text`.
    """
    return json.loads(schema_text(name))
