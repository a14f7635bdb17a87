"""Export options: physical scale (κ in mm, cm or in) and the tolerance of approximated outlines.

A solved body lives in units of the radius of gyration κ.  Giving κ in a
physical unit turns those numbers into a real size: every coordinate is
multiplied by ``kappa`` and the file states the unit.  Without a scale the
numbers stay in units of κ and the file says so.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import check_choice, check_positive, check_range

__all__ = ["ExportOptions", "UNITS", "DEFAULT_RELATIVE_TOLERANCE"]

#: physical units accepted for ``units``, with their DXF ``$INSUNITS`` code
UNITS = {"mm": 4, "cm": 5, "in": 1}
#: tolerance used when none is given, as a fraction of the body's largest diameter
DEFAULT_RELATIVE_TOLERANCE = 1e-4


@dataclass(frozen=True)
class ExportOptions:
    """How to write a body.

    Attributes
    ----------
    kappa : float or None
        Radius of gyration in ``units``; ``None`` keeps body units (κ).
    units : str or None
        ``"mm"``, ``"cm"`` or ``"in"``; required with ``kappa``, refused without it.
    tolerance : float or None
        Largest allowed distance between an exported approximation (polyline)
        and the exact outline, in output units (``units`` if scaled, else κ).
        ``None``: ``DEFAULT_RELATIVE_TOLERANCE`` times the largest diameter.
    dimension : bool
        Draw the largest diameter with its length (SVG).
    cut : bool
        Cut-ready drawing: one closed contour on one layer and nothing else (DXF: a single
        LWPOLYLINE within the tolerance on layer ``CUT``; SVG: a single path, no marks), so that laser
        or CNC software that takes every layer cuts the outline once.

    Examples
    --------
    >>> from coinwall import Wall, solve_body
    >>> disc = solve_body(Wall.from_expression("1"), 0.0, points=64)
    >>> from coinwall import export_body
    >>> result = export_body(disc, ["disc.svg"], kappa=12.0, units="mm", cut=True)
    >>> result.options.units, result.options.cut
    ('mm', True)
    """

    kappa: float | None = None
    units: str | None = None
    tolerance: float | None = None
    dimension: bool = False
    cut: bool = False

    def __post_init__(self):
        if self.kappa is not None:
            # a part from a micrometre to a kilometre across (in any of the units): beyond that the drawing's
            # coordinates lose the precision of its tolerance, or the part is not one anyone can cut
            check_range("kappa", self.kappa, 1e-6, 1e6, why="a real radius of gyration in mm, cm or in")
            if self.units is None:
                raise InvalidArgument(f"`kappa` {self.kappa:g} needs `units`; choose one of {', '.join(UNITS)}")
        if self.units is not None:
            check_choice("units", self.units, tuple(UNITS))
            if self.kappa is None:
                raise InvalidArgument(f"`units` {self.units} needs `kappa` (the radius of gyration in {self.units})")
        if self.tolerance is not None:
            check_positive("tolerance", self.tolerance)

    @property
    def scale(self) -> float:
        """Output length per unit κ (1 without a physical scale)."""
        return 1.0 if self.kappa is None else float(self.kappa)

    @property
    def unit_name(self) -> str:
        """The output unit as text: ``"mm"`` … or ``"kappa"``."""
        return self.units or "kappa"

    def tolerance_for(self, diameter: float) -> float:
        """The tolerance in output units for a body of largest diameter ``diameter`` (in output units)."""
        if self.tolerance is not None:
            if not self.tolerance < 0.1 * diameter:
                # an outline within such a tolerance need not resemble the body at all
                raise InvalidArgument(f"`tolerance` {self.tolerance:g} {self.unit_name} is not below a tenth of the "
                                      f"body's diameter ({diameter:.4g} {self.unit_name}); give a smaller tolerance")
            return float(self.tolerance)
        return DEFAULT_RELATIVE_TOLERANCE * max(float(diameter), 1e-300)

    def to_dict(self) -> dict:
        """The options as a JSON-ready dict."""
        return asdict(self)
