"""The command line (:mod:`.cli`) and the dataset runner (:mod:`.dataset`), outside the library.

The top of the layers (geometry → contacts → analysis → synthesis/gripper →
pictures/io → app): it may import any of them, and nothing in the library
imports it. The package itself loads nothing, so ``forceclosure --help``
stays free of numpy.
"""

__all__: list[str] = []
