"""The catalog of named cases: a wall and/or a body, an offset, and reference values with provenance.

Every case module in :mod:`cases` defines one or more :class:`Case` objects in a
module-level tuple ``CASES``; :func:`all_cases` collects them, and the command
line accepts ``case:NAME`` wherever it accepts a wall or a body.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Callable

from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument

__all__ = ["Case", "Reference", "all_cases", "get_case", "CASE_MODULES"]

#: Modules of this package that define cases, in the order ``coinwall cases`` lists them.
CASE_MODULES = ("stick", "ellipse", "appendix", "large_offset", "constant_width", "rectangle",
                "asymmetric", "few_extrema")


@dataclass(frozen=True)
class Reference:
    """A reference value of a case: what, the value, and where it comes from.

    Attributes
    ----------
    name : str
        What the value is (``"b_c"``, ``"area"``, ...).
    value : object
        The value.
    source : str
        Where it comes from (a paper equation, a closed form).

    Examples
    --------
    >>> from coinwall import get_case
    >>> get_case("ellipse").references[0]
    Reference(name='b_c', value=-0.5, source="Appendix: −1/(1+ε), the minimum of b + b'' at θ = 0, π")
    """

    name: str
    value: object
    source: str


@dataclass(frozen=True, repr=False)
class Case:
    """A named wall and/or body.

    Attributes
    ----------
    name : str
        Identifier used as ``case:NAME``.
    title : str
        One line for listings.
    source : str
        Where the case comes from (paper equation or section, or "coinwall").
    make_wall : callable or None
        Returns the :class:`forward.Wall` (``None`` for a body-only case).
    b0 : float
        The offset the case is meant to be solved at.
    make_outline : callable or None
        Returns a :class:`forward.Outline` of the body, when the body is known in closed form.
    H : float or None
        A wall distance for dynamics, when the paper uses one.
    references : tuple of Reference
    expression, params
        The wall as text and its parameters, when it is an expression.

    Examples
    --------
    >>> from coinwall import get_case, solve_body
    >>> case = get_case("ellipse")
    >>> case.make_wall(), case.b0
    (Wall('sqrt((1+eps*cos(t)**2)/(1+eps))' [eps=1]), 0.0)
    >>> [(reference.name, reference.value) for reference in case.references[:1]]
    [('b_c', -0.5)]
    """

    name: str
    title: str
    source: str
    make_wall: Callable | None
    b0: float = 0.0
    make_outline: Callable | None = None
    H: float | None = None
    references: tuple = field(default=())
    expression: str | None = None
    params: dict = field(default_factory=dict)

    def wall(self):
        """The case's wall (raises InvalidArgument for a body-only case)."""
        if self.make_wall is None:
            raise InvalidArgument(f"case {self.name!r} is a body without a closed-form wall; use it as a body")
        return self.make_wall()

    def outline(self):
        """The case's body outline: closed form if known, else solved from the wall at ``b0``."""
        if self.make_outline is not None:
            return self.make_outline()
        from coinwall.inverse import solve_body

        return solve_body(self.wall(), self.b0).outline

    def reference(self, name):
        """The value of the reference called ``name``."""
        for ref in self.references:
            if ref.name == name:
                return ref.value
        raise KeyError(name)

    @safe_repr
    def __repr__(self) -> str:
        return f"Case({self.name!r}: {self.title}; {self.source})"


def all_cases() -> dict:
    """Every case, by name, in catalog order.

    Returns
    -------
    dict
        ``{name: Case}``.

    Examples
    --------
    >>> from coinwall import all_cases
    >>> cases = all_cases()
    >>> list(cases)[:3], all(case.name == name for name, case in cases.items())
    (['stick', 'stick-uniform', 'ellipse'], True)
    """
    found = {}
    for module_name in CASE_MODULES:
        module = importlib.import_module(f"{__package__}.{module_name}")
        for case in module.CASES:
            found[case.name] = case
    return found


def get_case(name: str) -> Case:
    """The case called ``name`` (with or without the ``case:`` prefix).

    Parameters
    ----------
    name : str
        A case name (``"ellipse"``, ``"case:stick"``, ...); :func:`all_cases` lists them.

    Returns
    -------
    Case

    Raises
    ------
    InvalidArgument
        For an unknown name; the message lists the known ones.

    Examples
    --------
    >>> from coinwall import get_case
    >>> get_case("case:ellipse")
    Case('ellipse': ellipse x² + 2y² = 1 (ε = 1); paper eq. 15–18)
    """
    key = name[5:] if name.startswith("case:") else name
    cases = all_cases()
    if key not in cases:
        raise InvalidArgument(f"unknown case {key!r}; known cases: {', '.join(cases)} "
                              "(list them with `coinwall cases`)")
    return cases[key]
