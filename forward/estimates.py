"""Statistics that say how many samples they rest on, and refuse to be a number without them.

A share of tosses, a mean over collisions or a fraction of orbits is an estimate: it comes with its sample
size, and a standard error that means something only when there are enough samples for the normal
approximation behind it.  :data:`MIN_SAMPLES` (30, the usual threshold of that approximation) is the least
any estimate here is given as a number; below it, or with no samples at all, it is *not enough data*, in
words: "0.0 ± 0.0" from no toss was printed as an answer, and a fairness verdict drawn from it.

* :func:`share` — ``hits`` of ``n`` as a :class:`Share`: its value, standard error and text.  When every
  sample or none is a hit the binomial error ``√(p(1−p)/n)`` is 0, which claims certainty no finite sample
  gives; the text then gives the 95 % bound ``3/n`` instead (the "rule of three").
* :func:`mean_text` — a mean and its count, or "not enough data".
* :func:`finite_text` — a number that may be non-finite (a fit that failed) as text: never "nan".
* :func:`require` — raise :class:`NotEnoughData` when a command's result rests on too few samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import CoinwallError

__all__ = ["MIN_SAMPLES", "NotEnoughData", "Share", "finite_text", "mean_text", "require", "share"]

#: the fewest samples an estimate is given as a number from (the normal approximation of its error)
MIN_SAMPLES = 30


class NotEnoughData(CoinwallError):
    """A result that would rest on fewer samples than it needs (the command line: one line, exit status 2)."""


@dataclass(frozen=True)
class Share:
    """``hits`` of ``n`` samples: a proportion with its sample size.

    Attributes
    ----------
    hits, n : int
    minimum : int
        The fewest samples the share is given as a number from.
    """

    hits: int
    n: int
    minimum: int = MIN_SAMPLES

    @property
    def enough(self) -> bool:
        """Whether there are at least ``minimum`` samples."""
        return self.n >= self.minimum

    @property
    def p(self) -> float:
        """The share (NaN without samples)."""
        return self.hits / self.n if self.n else math.nan

    @property
    def stderr(self) -> float:
        """The binomial standard error ``√(p(1−p)/n)`` (NaN without samples)."""
        return math.sqrt(self.p * (1 - self.p) / self.n) if self.n else math.nan

    def text(self, unit: str = "samples", digits: int = 4) -> str:
        """The share for a reader, with its sample size; "not enough data" below ``minimum``.

        Examples
        --------
        >>> Share(1013, 2000).text("tosses")
        '0.5065 ± 0.0112 (2000 tosses)'
        >>> Share(0, 500).text("tosses")
        '0.0000 (0 of 500 tosses; below 0.0060 at 95 %)'
        >>> Share(0, 0).text("tosses")
        'not enough data (0 tosses; at least 30 needed)'
        """
        if not self.enough:
            return f"not enough data ({self.n} {unit}; at least {self.minimum} needed)"
        if self.hits == 0:
            return f"{0:.{digits}f} (0 of {self.n} {unit}; below {3 / self.n:.{digits}f} at 95 %)"
        if self.hits == self.n:
            return f"{1:.{digits}f} ({self.n} of {self.n} {unit}; above {1 - 3 / self.n:.{digits}f} at 95 %)"
        return f"{self.p:.{digits}f} ± {self.stderr:.{digits}f} ({self.n} {unit})"

    def to_dict(self) -> dict:
        """``{"value", "stderr", "n", "enough"}``; value and error are None without enough samples.

        Examples
        --------
        >>> Share(3, 10).to_dict()
        {'value': None, 'stderr': None, 'n': 10, 'enough': False}
        """
        ok = self.enough
        return {"value": self.p if ok else None, "stderr": self.stderr if ok else None, "n": self.n, "enough": ok}


def share(hits, n, minimum: int = MIN_SAMPLES) -> Share:
    """``hits`` of ``n`` samples as a :class:`Share` (both whole numbers, ``0 <= hits <= n``).

    Parameters
    ----------
    hits, n : int
    minimum : int
        The fewest samples it is given as a number from (default :data:`MIN_SAMPLES`).

    Returns
    -------
    Share

    Raises
    ------
    ValueError
        ``hits`` outside ``[0, n]``.

    Examples
    --------
    >>> share(7, 40).p
    0.175
    """
    hits, n = int(hits), int(n)
    if not 0 <= hits <= n:
        raise ValueError(f"a share needs 0 <= hits <= n, got {hits} of {n}")
    return Share(hits, n, int(minimum))


def mean_text(value, n, unit: str = "samples", fmt: str = ".6g", minimum: int = MIN_SAMPLES) -> str:
    """A mean over ``n`` samples for a reader, with its count; "not enough data" below ``minimum`` or when the mean is
    not finite.

    Examples
    --------
    >>> mean_text(2.27424, 100000, "free flights")
    '2.27424 (over 100000 free flights)'
    >>> mean_text(1.5, 1, "free flights")
    'not enough data (1 free flights; at least 30 needed)'
    """
    if n < minimum or value is None or not math.isfinite(value):
        return f"not enough data ({n} {unit}; at least {minimum} needed)"
    return f"{value:{fmt}} (over {n} {unit})"


def finite_text(value, fmt: str = ".4g", missing: str = "not determined") -> str:
    """``value`` formatted, or ``missing`` when it is None or NaN (an infinity is written as ∞, a real answer: a
    decay that never happens).

    Examples
    --------
    >>> finite_text(float("nan"), missing="not determined (the fit failed)")
    'not determined (the fit failed)'
    >>> finite_text(float("inf"))
    '∞'
    """
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return missing
    if isinstance(value, float) and math.isinf(value):
        return "∞" if value > 0 else "−∞"
    return f"{value:{fmt}}"


def require(n, minimum: int, what: str, advice: str = "", unit: str = "samples") -> None:
    """Raise :class:`NotEnoughData` when ``n`` samples are fewer than ``minimum`` for ``what``.

    Examples
    --------
    >>> require(0, 30, "P(same side) at any bounce", "no toss reached the first bounce")
    Traceback (most recent call last):
    ...
    coinwall.forward.estimates.NotEnoughData: not enough data for P(same side) at any bounce: 0 samples, at least \
30 needed; no toss reached the first bounce
    """
    if n < minimum:
        raise NotEnoughData(f"not enough data for {what}: {n} {unit}, at least {minimum} needed"
                            + (f"; {advice}" if advice else ""))
