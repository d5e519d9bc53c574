"""The command line: one module a command (``cmd_*``), each parsing its flags, calling the
library and printing; :mod:`.cli` dispatches.

The top of the layers (geometry → contacts → analysis → synthesis/gripper → io → pictures →
datasets → app): it may import any of them, and nothing in the library imports it. The
package itself loads nothing, so ``forceclosure --help`` stays free of numpy.
"""

__all__: list[str] = []
