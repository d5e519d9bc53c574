"""Pictures: region plots (:mod:`.plot`), the interactive view (:mod:`.view`), grasp plots.

Near the top of the layers (geometry → contacts → analysis →
synthesis/gripper → pictures/io → app): it may import everything below and
:mod:`forceclosure.io`, never the app, and nothing below imports it. The
package itself loads nothing (matplotlib loads with a module that draws).
"""

__all__: list[str] = []
