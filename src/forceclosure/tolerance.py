"""The one tolerance behind ``marginal``, in a module of its own so that reading it (the
command line's help does) loads nothing else.

Examples
--------
>>> from forceclosure.tolerance import TOLERANCE
>>> TOLERANCE
1e-06
"""

__all__ = ["TOLERANCE"]

#: The one tolerance behind ``marginal``: margins, singular-value ratios and
#: repelling work within it of zero are on the boundary.
TOLERANCE = 1e-6
