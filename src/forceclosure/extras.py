"""The optional parts of forceclosure and the extra that installs each.

The core (analysis, synthesis, the gripper, PNG pictures) needs only what
``pip install forceclosure`` installs. The parts below need more, imported only
when used; all but the MuJoCo adapter (whose caller holds MuJoCo's objects
already) import it through :func:`require`, which turns a missing package into
one line naming the extra to install:

============  ================  ==============================================
extra         package           what needs it
============  ================  ==============================================
``table``     pyarrow           the dataset's Parquet tables (``results.parquet``)
``view``      plotly            the interactive HTML view (``--html``)
``dask``      distributed       running a dataset on a Dask cluster (``--scheduler``)
``export``    h5py              ACRONYM-style HDF5 export
``mujoco``    mujoco            contacts from a MuJoCo scene
============  ================  ==============================================

(``pip install 'forceclosure[test]'``, as the README's set-up does, installs
them all.) This module imports nothing of the package but
:mod:`forceclosure.errors`.

Examples
--------
>>> require("json", "reading JSON", "table").dumps([1])
'[1]'
"""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import InputError

__all__ = ["EXTRAS", "MissingExtra", "require"]

#: The optional extras, by name: the package each installs (its top-level module).
EXTRAS = {"table": "pyarrow", "view": "plotly", "dask": "distributed", "export": "h5py",
          "mujoco": "mujoco"}


class MissingExtra(InputError, ImportError):
    """An optional package is not installed; the message names the extra that installs it."""


def require(module: str, what: str, extra: str) -> ModuleType:
    """Import ``module`` for ``what``, or refuse in one line naming the extra to install.

    Parameters
    ----------
    module : str
        The module to import (``"pyarrow.parquet"``).
    what : str
        What needs it, as the message says it (``"the dataset's table"``).
    extra : str
        The extra of forceclosure that installs it (a key of :data:`EXTRAS`).

    Returns
    -------
    module
        The imported module.

    Raises
    ------
    MissingExtra
        (an :class:`~forceclosure.errors.InputError` and an :class:`ImportError`) when the
        module cannot be imported: "``what`` needs ``package``: install forceclosure's
        '``extra``' extra (pip install 'forceclosure[``extra``]')".
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        package = module.partition(".")[0]
        raise MissingExtra(f"{what} needs {package}: install forceclosure's '{extra}' extra "
                           f"(pip install 'forceclosure[{extra}]')") from None
