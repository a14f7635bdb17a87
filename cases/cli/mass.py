"""``coinwall mass``: mass properties of a body and the range of κ a mass distribution can reach."""

from __future__ import annotations

import json
import math

from .common import add_command, number, parse_com, parse_params

__all__ = ["POSITION_TOLERANCE", "register"]

#: the moments are exact to rounding (Green's theorem on the Bézier outline): a centre-of-mass
#: coordinate within 1e-12 of the body's size of zero is rounding and prints as 0
POSITION_TOLERANCE = 1e-12

_DESCRIPTION = """\
Mass properties of the lamina inside a body outline: area, centroid and radius of gyration κ of the
uniform lamina (exact, Green's theorem on the Bézier outline), and with --density rho(x, y) the
mass, centre of mass and κ of that density (scikit-fem).  Also the range (0, κ_max] of radii of
gyration that some mass distribution inside the outline, with its centre of mass at the origin,
can have: the wall b(θ) in units of κ describes a physical body only if κ_max >= 1."""

_EXAMPLE = """\
coinwall solve "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=1 -o body.json
coinwall mass body.json --density "1 + 4*r**8\""""


def register(subparsers):
    """Add the ``mass`` subcommand."""
    parser = add_command(subparsers, "mass", help="mass properties of a body (uniform or a density rho(x, y)) and "
                                                  "the range of kappa a mass distribution can reach",
                         description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("body", help="body file: .json/.csv/.svg/.dxf (as for 'coinwall wall')")
    parser.add_argument("--density", default=None, metavar="EXPR",
                        help="density rho(x, y) in x, y, r (body units), e.g. \"1 + 4*r**8\"")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="parameter of the density (repeatable)")
    parser.add_argument("--layer", default=None, help="DXF layer to read")
    parser.add_argument("--com", default=None, metavar="X,Y", help="centre of mass in drawing coordinates")
    parser.add_argument("--kappa", type=number, default=None, help="radius of gyration in drawing units")
    parser.add_argument("--json", action="store_true", help="print JSON (full precision)")
    parser.set_defaults(run=run)


def run(args):
    """Compute the mass properties and print them."""
    import numpy as np

    from coinwall.forward.display import format_number
    from coinwall.forward.formats import load_outline
    from coinwall.forward.massprops import mass_properties, outline_moments
    from coinwall.inverse.realizability import kappa_max

    params = parse_params(args.param)
    outline, note = load_outline(args.body, layer=args.layer, com=parse_com(args.com), kappa=args.kappa)
    exact = outline_moments(outline)
    props = mass_properties(outline, args.density, params) if args.density is not None else None
    kmax, support = kappa_max(outline)
    if args.json:
        print(json.dumps({"body": args.body, "note": note, "uniform": exact.to_dict(),
                          "density": props.to_dict() if props else None,
                          "kappa_max": kmax if math.isfinite(kmax) else None,
                          "kappa_max_support": support.tolist(),
                          "realizable": bool(math.isfinite(kmax) and kmax >= 1.0)}, indent=1, allow_nan=False))
        return 0
    size = max(1.0, float(np.max(np.hypot(*outline.nodes.T))))

    def position(point):
        return ", ".join(format_number(v, POSITION_TOLERANCE * size) for v in point)

    print(f"body       {args.body} ({note})")
    print(f"uniform    area {format_number(exact.area, 0.0, 10)}, centroid ({position(exact.centre)}), "
          f"kappa {format_number(exact.kappa, 0.0, 10)} (about the centroid; 1 for a self-consistent uniform body)")
    if props:
        print(f"density    {args.density}: mass {format_number(props.mass, 0.0, 10)}, centre of mass "
              f"({position(props.centre)}), kappa {format_number(props.kappa, 0.0, 10)} "
              f"({props.elements} triangles, scikit-fem)")
    if math.isfinite(kmax):
        verdict = "some mass distribution gives this wall" if kmax >= 1 else "no mass distribution reaches kappa = 1"
        print(f"range      kappa in (0, {format_number(kmax, 0.0, 10)}] for mass inside the outline with centre of "
              f"mass at the origin: {verdict}")
    else:
        print("range      the origin is not inside the body: no mass distribution has its centre of mass there")
    return 0
