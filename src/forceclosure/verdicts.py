"""The three verdicts of force-closure, as words and as the kernels' integer codes.

One home for the rule every layer shares: a grasp is ``closure`` (force-closure
with margin, Theorem 1), ``none`` (provably not) or ``marginal`` (within the
tolerance of the boundary). :class:`Verdict` is the word (the value the JSON
outputs and Parquet columns carry); :class:`VerdictCode` is the integer the
compiled kernels and every ``code`` array hold (0 ``none``, 1 ``marginal``,
2 ``closure``, also the order of the words in :data:`VERDICT_WORDS`). This
module imports nothing of the package, and NumPy only when an array is read.

References
----------
V.-D. Nguyen, "Constructing Force-Closure Grasps", IJRR 7(3), 1988, §2
(Theorem 1: force-closure as a positive span of the wrenches).

Examples
--------
>>> import numpy as np
>>> Verdict.CLOSURE.code, VerdictCode(1).verdict
(<VerdictCode.CLOSURE: 2>, <Verdict.MARGINAL: 'marginal'>)
>>> codes = np.array([2, 0, 1, 2], np.int8)
>>> verdict_words(codes).tolist(), int(np.sum(codes == VerdictCode.CLOSURE))
(['closure', 'none', 'marginal', 'closure'], 2)
"""

from __future__ import annotations

from enum import IntEnum, StrEnum
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["ERROR", "VERDICT_WORDS", "Verdict", "VerdictCode", "closed_median",
           "verdict_counts", "verdict_words"]


class Verdict(StrEnum):
    """``closure``: force-closure with margin; ``none``: provably not;
    ``marginal``: within the tolerance of the boundary."""

    CLOSURE = "closure"
    MARGINAL = "marginal"
    NONE = "none"

    @property
    def code(self) -> VerdictCode:
        """The integer code of this verdict (as the kernels and ``code`` arrays hold it)."""
        return _CODE_OF[self]

    @classmethod
    def of_code(cls, code: int) -> Verdict:
        """The verdict of an integer code (0, 1 or 2).

        Raises
        ------
        IndexError
            For a code that is not 0, 1 or 2.
        """
        if not 0 <= code <= 2:
            raise IndexError(f"no verdict has the code {code}")
        return _BY_CODE[code]


class VerdictCode(IntEnum):
    """The integer codes of the verdicts, as the compiled kernels write them."""

    NONE = 0
    MARGINAL = 1
    CLOSURE = 2

    @property
    def verdict(self) -> Verdict:
        """The verdict this code stands for."""
        return _BY_CODE[self]


_BY_CODE = (Verdict.NONE, Verdict.MARGINAL, Verdict.CLOSURE)
_CODE_OF = {v: VerdictCode(c) for c, v in enumerate(_BY_CODE)}

#: The verdicts' words in the order of their codes: ``VERDICT_WORDS[code]`` is the word.
VERDICT_WORDS: tuple[str, ...] = tuple(v.value for v in _BY_CODE)
#: The code of a grasp that was refused, not analysed (a bad entry of a grasp file or array;
#: in a partial results file, a grasp not analysed yet).
ERROR = -1


def verdict_words(code: ArrayLike) -> NDArray[np.str_]:
    """The words of an array of verdict codes (each 0, 1 or 2), as an array of strings.

    Parameters
    ----------
    code : int array
        Verdict codes (:class:`VerdictCode`).

    Returns
    -------
    str array
        ``"none"``, ``"marginal"`` or ``"closure"`` for each, shaped like ``code``.
    """
    import numpy as np

    return np.array(VERDICT_WORDS)[np.asarray(code)]


def verdict_counts(code: ArrayLike, errors: bool = False) -> dict[str, int]:
    """How many grasps got each verdict (``closure``, ``marginal``, ``none``), and with
    ``errors`` how many were refused (:data:`ERROR`).

    Examples
    --------
    >>> verdict_counts([2, 0, 2, -1], errors=True)
    {'closure': 2, 'marginal': 0, 'none': 1, 'errors': 1}
    """
    import numpy as np

    code = np.asarray(code)
    counts = {v.value: int(np.count_nonzero(code == v.code)) for v in Verdict}
    if errors:
        counts["errors"] = int(np.count_nonzero(code == ERROR))
    return counts


def closed_median(values: ArrayLike, code: ArrayLike) -> float | None:
    """The median of ``values`` over the grasps whose verdict is ``closure`` (NaN, a value
    not computed, left out); None when no closed grasp has one.

    Examples
    --------
    >>> closed_median([0.1, 0.5, 0.3, float("nan")], [2, 0, 2, 2])
    0.2
    """
    import numpy as np

    closed = np.asarray(values, dtype=float)[np.asarray(code) == VerdictCode.CLOSURE]
    closed = closed[~np.isnan(closed)]
    return float(np.median(closed)) if len(closed) else None
