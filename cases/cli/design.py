"""``coinwall design``: a body designed for its odds (a family, target probabilities, a toss model)."""

from __future__ import annotations

import json
import math
import os

from .common import add_command, count, number, progress_bar, written_lines

__all__ = ["register"]

DESCRIPTION = """\
Which member of a family of bodies lands with the given odds?  WALL is a wall expression b(θ) in
units of κ (about the centre of mass, as in `coinwall solve`), or `cylinder` (a body of revolution
with the parameters radius, thickness and rounding: its edges rounded with that radius).  A free
parameter is --param NAME=LO:HI, a fixed one NAME=VALUE.  Each --target NAME=P names an outcome and
its probability (P a decimal or a fraction such as 1/3): heads, tails, edge (planar: the faces whose
valleys hold the body directions 3π/2 and π/2, and all the others; cylinder: bottom face, top face,
rim), or face@DEG (the face whose valley holds the body direction DEG degrees).

Toss models (--model):
  drop      uniform random orientation, no bounce, rests on the face below the centre of mass:
            exact from the outline (angle measure; solid angle for a cylinder)
  flip      turning about a horizontal axis with a uniform phase, --ratio v/ω (0: vigorous); exact
  bounce    the planar toss: a random hand (--height, --v0, --omega, --theta0) in the field --g,
            restitution --e, Coulomb friction --mu on the floor (default 0: frictionless) with
            --rolling resistance and a horizontal launch velocity --vx; Monte Carlo
  bounce3d  the cylinder dropped tumbling (--spin) on a frictionless floor; Monte Carlo
Exact models are solved by root finding to 1e-10; Monte Carlo models by a stochastic root finder
(or weighted least squares for several targets or parameters) with common random numbers, until
each target probability is known to --tolerance at --confidence.  Without --target (and without a
free parameter) the odds of the one body are printed.  docs/design.md has the models' assumptions."""

EXAMPLE = ('coinwall design "abs(cos(t)) + h*abs(sin(t))" --param h=0.05:3 --target edge=1/3 --model drop --json\n'
           'coinwall design cylinder --param thickness=0.1:3 --target edge=1/3 --model drop -o coin.svg\n'
           'coinwall design "abs(cos(t)) + h*abs(sin(t))" --param h=0.2:2 --target edge=1/3 --model bounce --e 0.5 '
           '--figure odds.png\n'
           'coinwall design "abs(cos(t)) + h*abs(sin(t))" --param h=0.2:2 --target edge=1/3 --model bounce --e 0.5 '
           '--mu 0.3 --tolerance 0.02')

#: model-specific flags: their defaults, and the models that read them (given to another: refused)
_FLAGS = {"ratio": ((0.0, ("flip",))), "e": (0.6, ("bounce", "bounce3d")), "mu": (0.0, ("bounce",)),
          "rolling": (0.0, ("bounce",)), "vx": ((0.0, 0.0), ("bounce",)),
          "g": (1.0, ("bounce", "bounce3d")), "height": (2.0, ("bounce", "bounce3d")),
          "v0": ((0.0, 0.0), ("bounce", "bounce3d")), "omega": ((0.0, 3.0), ("bounce",)),
          "theta0": (None, ("bounce",)), "spin": (3.0, ("bounce3d",)), "impacts": (10_000, ("bounce", "bounce3d")),
          "tolerance": (0.005, ("bounce", "bounce3d")), "max_tosses": (10_000_000, ("bounce", "bounce3d")),
          "seed": (0, ("bounce", "bounce3d")), "workers": (None, ("bounce", "bounce3d")),
          "device": ("cpu", ("bounce",))}


def _pair(text: str):
    parts = text.split(",")
    if len(parts) != 2:
        raise ValueError(text)
    mean, sd = (number(p) for p in parts)
    if not (math.isfinite(mean) and math.isfinite(sd) and sd >= 0):
        raise ValueError(text)
    return mean, sd


_pair.__name__ = "MEAN,SD pair"


def register(subparsers):
    """Add the ``design`` subcommand."""
    parser = add_command(subparsers, "design", help="a body designed for its odds: a family, targets, a toss model",
                         description=DESCRIPTION, example=EXAMPLE)
    parser.add_argument("wall", help="wall expression in t (units of κ), or 'cylinder'")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=LO:HI",
                        help="a free parameter NAME=LO:HI or a fixed one NAME=VALUE (repeatable)")
    parser.add_argument("--target", action="append", default=[], metavar="NAME=P",
                        help="an outcome and its probability: heads, tails, edge or face@DEG (repeatable)")
    parser.add_argument("--model", choices=("drop", "flip", "bounce", "bounce3d"), default="drop",
                        help="the toss (default drop)")
    parser.add_argument("--b0", type=number, default=0.0, help="offset added to a planar wall (default 0)")
    parser.add_argument("--ratio", type=number, default=None,
                        help="flip: fall speed over spin v/ω, κ/rad (default 0)")
    parser.add_argument("--e", type=number, default=None, help="bounce, bounce3d: restitution in (0, 1] (default 0.6)")
    parser.add_argument("--mu", type=number, default=None,
                        help="bounce: Coulomb's coefficient of friction of the floor (default 0: frictionless)")
    parser.add_argument("--rolling", type=number, default=None, metavar="DELTA",
                        help="bounce, with --mu: rolling resistance, the lever arm (units of κ, in [0, 1]) of the "
                             "floor's push that opposes rolling (default 0: a body rolling without slipping keeps "
                             "its energy)")
    parser.add_argument("--vx", type=_pair, default=None, metavar="MEAN,SD",
                        help="bounce, with --mu: horizontal launch velocity of the centre of mass, κ/s, mean and "
                             "standard deviation (default 0,0)")
    parser.add_argument("--g", type=number, default=None,
                        help="bounce: field, κ/s² (bounce3d: length unit/s²; default 1)")
    parser.add_argument("--height", type=number, default=None,
                        help="bounce, bounce3d: launch height of the body's lowest point above the floor (default 2)")
    parser.add_argument("--v0", type=_pair, default=None, metavar="MEAN,SD",
                        help="bounce, bounce3d: upward launch velocity, mean and standard deviation (default 0,0)")
    parser.add_argument("--omega", type=_pair, default=None, metavar="MEAN,SD",
                        help="bounce: launch spin θ̇ in rad/s, mean and standard deviation (default 0,3)")
    parser.add_argument("--theta0", type=number, default=None,
                        help="bounce: launch orientation, rad (default: uniformly random)")
    parser.add_argument("--spin", type=number, default=None,
                        help="bounce3d: standard deviation of each lab component of the angular velocity, rad/s "
                             "(default 3)")
    parser.add_argument("--impacts", type=count, default=None,
                        help="Monte Carlo: impacts (with --mu, and contact events) per toss at most (10000)")
    parser.add_argument("--tolerance", type=number, default=None,
                        help="Monte Carlo: half-width of each target probability's interval (default 0.005)")
    parser.add_argument("--confidence", type=number, default=None,
                        help="of the Monte Carlo intervals and of --resimulate's comparison (default 0.95)")
    parser.add_argument("--seed", type=count, default=None, metavar="N",
                        help="Monte Carlo: seed of the launches (default 0)")
    parser.add_argument("--max-tosses", type=count, default=None,
                        help="Monte Carlo: the most launches per evaluation (default 1e7)")
    parser.add_argument("--workers", type=count, default=None, help="Monte Carlo: threads (default: every core)")
    parser.add_argument("--device", choices=["cpu", "gpu"], default=None,
                        help="bounce: where the tosses run, all CPU cores (default) or a CUDA GPU (coinwall[gpu])")
    parser.add_argument("--resimulate", type=count, default=None, metavar="N",
                        help="toss the designed body N more times with independent launches and compare")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="the designed body (a cylinder: its section through the axis): .svg .dxf .json .csv "
                             ".png .pdf (repeatable)")
    parser.add_argument("--figure", action="append", default=[], metavar="FILE",
                        help="each probability against each free parameter, with the targets and the intervals "
                             "(.png .svg .pdf; repeatable)")
    parser.add_argument("--kappa", type=number, default=None, metavar="VALUE",
                        help="planar: the radius of gyration in --units, for drawings at real size")
    parser.add_argument("--units", choices=["mm", "cm", "in"], default=None,
                        help="unit of --kappa (a cylinder: the unit of its lengths)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON (no progress bar)")
    parser.set_defaults(run=run)


def _probability(text: str) -> float:
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.validation import parse_number

    parts = text.split("/")
    try:
        values = [parse_number(p) for p in parts]
    except ValueError:
        values = []
    if len(values) not in (1, 2) or not all(math.isfinite(v) for v in values) or (len(values) == 2 and
                                                                                     values[1] == 0):
        raise InvalidArgument(f"--target probability {text!r} must be a number or a fraction A/B")
    return values[0] / values[1] if len(values) == 2 else values[0]


def _targets(texts) -> dict:
    from coinwall.forward.errors import InvalidArgument

    out = {}
    for text in texts:
        name, sep, value = (part.strip() for part in text.partition("="))
        if not sep or not name:
            raise InvalidArgument(f"--target {text!r} must have the form NAME=P, e.g. edge=1/3")
        if name in out:
            raise InvalidArgument(f"--target {name} given twice")
        out[name] = _probability(value)
    return out


def _params(texts):
    """--param NAME=VALUE (fixed) and NAME=LO:HI (free), in order."""
    from coinwall.forward.errors import InvalidParameter
    from coinwall.forward.expression import parse_param

    free, fixed = {}, {}
    for text in texts:
        name, sep, value = text.partition("=")
        if sep and ":" in value:
            parts = value.split(":")
            if len(parts) != 2:
                raise InvalidParameter(f"--param {text!r}: a free parameter is NAME=LO:HI, e.g. h=0.05:3")
            lo, hi = (parse_param(f"{name}={p}")[1] for p in parts)
            key = name.strip()
            if not lo < hi:
                raise InvalidParameter(f"--param {text!r}: LO must be below HI")
            target = free
            value = (lo, hi)
        else:
            key, value = parse_param(text)
            target = fixed
        if key in free or key in fixed:
            raise InvalidParameter(f"--param {key} given twice")
        target[key] = value
    return free, fixed


def _family(args):
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.expression import check_ascii, check_one_line
    from coinwall.inverse.design import Family

    free, fixed = _params(args.param)
    text = args.wall.strip()
    if text == "cylinder":
        return Family("cylinder", None, free, fixed)
    if text.startswith("case:") or os.path.splitext(text)[1].lower() in (".csv", ".json", ".svg", ".dxf"):
        raise InvalidArgument(f"design needs a wall expression with parameters (or 'cylinder'), got {text!r}: a "
                              "wall from a file or a case has no parameter to design")
    check_one_line(check_ascii(text, "wall"), "wall")
    return Family("planar", text, free, fixed, b0=args.b0)


def _model(args):
    from coinwall.forward.errors import InvalidArgument
    from coinwall.inverse.design import Bounce, Bounce3D, Drop, Flip, Launch, Launch3D

    for flag, (default, models) in _FLAGS.items():
        value = getattr(args, flag)
        if value is not None and args.model == "bounce3d" and flag in ("mu", "rolling", "vx"):
            raise InvalidArgument(f"--{flag}: the bounce3d toss has a frictionless floor (friction is in the planar "
                                  "bounce toss)")
        if value is not None and args.model not in models:
            raise InvalidArgument(f"--{flag.replace('_', '-')} does nothing in the {args.model} toss; leave it out")
        if value is None:
            setattr(args, flag, default)
    if args.device == "gpu" and args.workers is not None:
        raise InvalidArgument("--workers sets the CPU's threads; with --device gpu the tosses run on the GPU (drop one)")
    if args.confidence is None:
        args.confidence = 0.95
    elif args.model in ("drop", "flip") and args.resimulate is None:
        raise InvalidArgument(f"--confidence does nothing in the exact {args.model} toss without --resimulate (its "
                              "interval is the bracket of the root); leave it out")
    if args.resimulate is not None and args.model == "flip":
        raise InvalidArgument("--resimulate needs a toss drawn at random; the flip toss has none (drop, bounce and "
                              "bounce3d do)")
    if args.model == "drop":
        return Drop()
    if args.model == "flip":
        return Flip(args.ratio)
    if args.model == "bounce":
        launch = Launch(g=args.g, height=args.height, v0=args.v0, omega=args.omega, theta0=args.theta0, vx=args.vx)
        return Bounce(e=args.e, mu=args.mu, launch=launch, impacts=args.impacts, workers=args.workers,
                      rolling=args.rolling, device=args.device)
    launch = Launch3D(g=args.g, height=args.height, v0=args.v0, spin=args.spin)
    return Bounce3D(e=args.e, launch=launch, impacts=args.impacts, workers=args.workers)


def _body(result, family):
    """The designed planar body (a cylinder: its section through the axis), solved as `coinwall solve` does."""
    from coinwall.forward.wall import Wall
    from coinwall.inverse import solve_body

    if family.kind == "planar":
        return solve_body(result.body(), family.b0, cross_check=True)
    v = result.values
    r, d, eps = v["radius"], 0.5 * v["thickness"], v["rounding"]
    section = Wall.from_expression("a*abs(cos(t)) + c*abs(sin(t)) + r", {"a": r - eps, "c": d - eps, "r": eps})
    return solve_body(section, 0.0, cross_check=True)


def run(args):
    """Design (or evaluate), write the body and the figure, print the result."""
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, transaction, write_all
    from coinwall.inverse import realizability
    from coinwall.inverse.design import design, design_curves, odds, plot_design, resimulate
    from coinwall.inverse.export import ExportOptions, check_outputs, export_body


    family = _family(args)
    model = _model(args)
    targets = _targets(args.target)
    if args.resimulate is not None and not 1000 <= args.resimulate <= 10 ** 8:
        raise InvalidArgument(f"--resimulate must be between 1000 and 1e8 tosses, got {args.resimulate}")
    if family.kind == "cylinder" and args.kappa is not None:
        raise InvalidArgument("--kappa scales a planar wall; a cylinder's lengths are in --units already")
    kappa = 1.0 if family.kind == "cylinder" and args.units else args.kappa
    ExportOptions(kappa=kappa, units=args.units)
    check_outputs(args.output)
    check_paths(args.figure, FIGURE_FORMATS)
    with progress_bar(args, None, "toss", show=not model.exact) as bar:
        tick = bar.update if bar is not None else None
        if not targets:
            if family.free:
                raise InvalidArgument("give a --target for each outcome to design for (or fix every parameter to "
                                      "print the odds of one body)")
            if args.output or args.figure or args.resimulate:
                raise InvalidArgument("-o, --figure and --resimulate belong to a design: give a --target")
            from coinwall.inverse.design.solvers import z_value

            # enough tosses for the worst case p = ½ to be known to --tolerance
            tosses = math.ceil(1.1 * (z_value(args.confidence) / args.tolerance) ** 2 / 4)
            table = odds(family, model, seed=args.seed, progress=tick, confidence=args.confidence,
                         tosses=min(tosses, args.max_tosses))
            return _print_odds(args, family, model, table)
        result = design(family, targets, model, tolerance=args.tolerance, confidence=args.confidence, seed=args.seed,
                        max_tosses=args.max_tosses, progress=tick)
        check = resimulate(result, args.resimulate, seed=args.seed, progress=tick) if args.resimulate else None
        curves = design_curves(result, progress=tick) if args.figure else None
    warnings = list(result.warnings)
    body = physical = None
    if args.output or family.kind == "planar":
        body = _body(result, family)
        warnings += list(body.warnings)
        physical = realizability(body)
        if family.kind == "planar" and body.regime == "corner":
            warnings.append(f"at the design point b0 = {family.b0:g} is below the critical offset b_c = "
                            f"{body.b_c:.6g}: no convex body has this wall, so the odds of the wall are not those "
                            "of the body drawn (the largest body under it); raise --b0")
    written, result_files = [], None
    with transaction():
        if args.figure:
            fig = plot_design(result, curves)
            files = {path: figure_bytes(fig, path, close=path == args.figure[-1]) for path in args.figure}
            written = write_all(files)
        if args.output:
            result_files = export_body(body, args.output, kappa=kappa, units=args.units)
    doc = result.to_dict()
    if body is not None:
        doc["body"] = {"regime": body.regime, "b0": body.b0, "b_c": body.b_c if math.isfinite(body.b_c) else None,
                       "max_wall_error": body.max_wall_error, "realizability": physical.to_dict()}
    if check is not None:
        doc["resimulation"] = dict(check.to_dict(), agrees=check.agrees(result.confidence))
        if not check.agrees(result.confidence):
            warnings.append("the independent re-simulation disagrees with the design beyond the intervals: "
                            + ", ".join(f"{k} {v:+.2f}σ" for k, v in check.z.items()))
    doc["warnings"] = warnings
    doc["outputs"] = list(args.output) + list(args.figure)
    if args.json:
        print(json.dumps(doc, indent=1, allow_nan=False))
    else:
        _print_design(result, body, physical, check)
        for line in written_lines(written, written.replaced) if written else []:
            print(line)
        if result_files is not None:
            from .common import describe_written

            for line in describe_written(result_files):
                print(line)
    import sys

    for warning in warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return 1 if warnings else 0


def _print_odds(args, family, model, table):
    rows = {k: {"p": p, "interval": [max(0.0, p - h), min(1.0, p + h)]} for k, (p, h) in table.items()}
    if args.json:
        print(json.dumps({"family": family.to_dict(), "model": model.to_dict(), "outcomes": rows,
                          "seed": None if model.exact else args.seed,
                          "confidence": args.confidence}, indent=1, allow_nan=False))
        return 0
    print(f"family     {family.describe()}")
    print(f"model      {model!r}")
    if not model.exact:
        print(f"seed       {args.seed}")
    for name, (p, h) in table.items():
        shown = f"{p:.5f} ± {h:.2g} ({100 * args.confidence:g}%)" if h else f"{p:.12g}"
        print(f"outcome    {name:<10} P = {shown}")
    return 0


def _print_design(result, body, physical, check):
    print(f"family     {result.family.describe()}")
    print(f"model      {result.model!r}")
    if result.tosses:  # a Monte Carlo model: the seed of its launches (the re-simulation draws a stream apart)
        print(f"seed       {result.seed}")
    kind = f"{100 * result.confidence:g}%" if result.model.exact is False else "bracket of the root"
    for name, v, (a, b) in zip(result.family.names, result.x, result.interval):
        print(f"design     {name} = {v:.12g} in [{a:.12g}, {b:.12g}] ({kind}; {result.method})")
    for name, (p, h) in result.probabilities.items():
        target = f"   target {result.targets[name]:.6g}" if name in result.targets else ""
        spread = f" ± {h:.2g}" if h else ""
        print(f"outcome    {name:<10} P = {p:.10g}{spread}{target}")
    if result.undecided is not None:
        p, h = result.undecided
        print(f"undecided  {p:.4g} ± {h:.2g} of {result.tosses} tosses (the odds above are among the decided ones; "
              f"{result.total_tosses} tossed in all)")
    if body is not None:
        kmax = f"{physical.kappa_max:.6g}" if math.isfinite(physical.kappa_max) else "—"
        print(f"body       {body.regime} at b0 = {body.b0:g}; uniform body: κ {physical.kappa_uniform:.6g}, centroid "
              f"offset {physical.centroid_offset:.3g}, κ_max {kmax} (units of the wall)")
    if check is not None:
        print(f"check      {check!r}")
