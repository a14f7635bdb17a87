"""``coinwall coin3d``: the coin in three dimensions: caught tosses, the real flips, bounced tosses."""

from __future__ import annotations

import json
import math

from .budget import add_allow_long
from .common import DEFAULT_SEED, add_command, count, number, progress_bar, seed_argument, written_lines

__all__ = ["register"]

#: the defaults of the flags some modes read, and which mode reads which (a flag given to another is refused)
_DEFAULTS = {"psi": None, "samples": 20_000, "seed": DEFAULT_SEED, "e": 0.6, "bounces": 10, "g": 9.81, "ceiling": None,
             "height": 1.0}
_READS = {"caught": {"psi", "samples", "seed"}, "fit": set(), "bounce": set(_DEFAULTS)}

DESCRIPTION = """\
The coin in three dimensions.  A body of revolution bouncing on horizontal walls is a billiard in
(θ, η) (tilt of the axis, height / transverse radius of gyration) with the spinning top's potential;
see docs/coin3d.md.  Three questions:

  caught  P(same side) of a coin caught in the hand, by simulating the precessing coin, against
          Diaconis, Holmes & Montgomery's ½ + arcsin(cot²ψ)/π (ψ: angle between the angular momentum
          and the coin's normal, degrees).
  fit     the ψ (one value, and the σ of a spread about 90°) implied by the 350,757 caught flips of
          Bartoš et al. (2023), overall and per tosser, with 95 % likelihood-ratio intervals: of all
          flips as one binomial, and with the spread between the 48 tossers (quasi-binomial);
          -o draws the data against the model.
  bounce  the same toss landing on a frictionless floor with restitution --e (or between two walls,
          --ceiling): P(side up at the n-th bounce = start side) for n = 1 … --bounces."""

EXAMPLE = ("coinwall coin3d caught --psi 70 --samples 100000 --seed 1\n"
           "coinwall coin3d fit -o bartos.png\n"
           "coinwall coin3d bounce --psi 81.16 --e 0.6 --bounces 10 --samples 20000 --seed 1")


def register(subparsers):
    """Add the ``coin3d`` subcommand."""
    parser = add_command(subparsers, "coin3d", help="the coin in 3-D: caught tosses, the real flips, bounces",
                         description=DESCRIPTION, example=EXAMPLE)
    parser.add_argument("mode", choices=("caught", "fit", "bounce"), help="what to compute (see above)")
    parser.add_argument("--psi", type=number, default=_DEFAULTS["psi"],
                        help="angle between angular momentum and normal, degrees (caught: required; bounce: default "
                             "the value fitted to the real flips)")
    parser.add_argument("--samples", type=count, default=_DEFAULTS["samples"], help="tosses simulated (default 20000)")
    seed_argument(parser, "the draws (caught, bounce)")
    parser.add_argument("--e", type=number, default=_DEFAULTS["e"], help="bounce: restitution in (0, 1] (default 0.6)")
    parser.add_argument("--bounces", type=count, default=_DEFAULTS["bounces"],
                        help="bounce: floor impacts followed (default 10)")
    parser.add_argument("--g", type=number, default=_DEFAULTS["g"], help="bounce: gravity in m/s² (default 9.81)")
    parser.add_argument("--ceiling", type=number, default=_DEFAULTS["ceiling"],
                        help="bounce: a second wall this high above the floor (m; default none)")
    parser.add_argument("--height", type=number, default=_DEFAULTS["height"],
                        help="bounce: launch height above the floor (m; default 1)")
    parser.add_argument("--tosser", default=None, help="fit: one tosser (T01 … T48) instead of the table")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="fit: figure of the data against the model (.png, .svg, .pdf; repeatable)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    add_allow_long(parser)
    parser.set_defaults(run=_cmd_coin3d)


def _finite(name, value):
    from coinwall.forward.errors import InvalidArgument

    if value is not None and not math.isfinite(value):
        raise InvalidArgument(f"{name} must be a finite number, got {value}")


def _cmd_coin3d(args):
    from coinwall.forward.errors import InvalidArgument

    for name in ("psi", "e", "g", "ceiling", "height"):
        _finite(f"--{name}", getattr(args, name))
    if args.samples > 10 ** 7:
        raise InvalidArgument(f"--samples must be at most 1e7, got {args.samples}")
    if args.bounces > 1000:
        raise InvalidArgument(f"--bounces must be at most 1000, got {args.bounces}")
    # a flag another mode reads is refused, not ignored (its value would silently change nothing)
    for name, default in _DEFAULTS.items():
        if name not in _READS[args.mode] and getattr(args, name) != default:
            raise InvalidArgument(f"--{name} does nothing in `coin3d {args.mode}`; leave it out")
    if args.output and args.mode != "fit":
        raise InvalidArgument("-o draws the fit's figure: use it with `coin3d fit`")
    if args.tosser is not None and args.mode != "fit":
        raise InvalidArgument("--tosser belongs to `coin3d fit`")
    if args.tosser is not None and args.output:
        raise InvalidArgument("-o draws all the tossers; leave out --tosser to draw it")
    if args.mode == "caught":
        return _caught(args)
    if args.mode == "fit":
        return _fit(args)
    return _bounce(args)


def _caught(args):
    from coinwall.forward.dynamics.coin3d.caught import dhm_same_side, simulate_caught
    from coinwall.forward.errors import InvalidArgument

    if args.psi is None:
        raise InvalidArgument("`coin3d caught` needs --psi (degrees, 0 to 180)")
    if not 0 <= args.psi <= 180:
        raise InvalidArgument(f"--psi must be an angle in degrees from 0 to 180, got {args.psi}")
    from coinwall.forward.estimates import MIN_SAMPLES, require, share

    require(args.samples, MIN_SAMPLES, "P(same side)", "raise --samples")
    p, se = simulate_caught(math.radians(args.psi), args.samples, seed=args.seed)
    dhm = float(dhm_same_side(math.radians(args.psi)))
    one = share(round(p * args.samples), args.samples)
    # (a share of 0 or 1 has no binomial error: its distance from DHM is not a number of standard errors)
    z = (p - dhm) / se if se > 0 else None
    out = {"psi_degrees": args.psi, "samples": args.samples, "seed": args.seed, "same_side": p, "stderr": se,
           "dhm": dhm, "z": z}
    if args.json:
        print(json.dumps(out, indent=1, allow_nan=False))
    else:
        print(f"caught     ψ = {args.psi:g}°: P(same side) = {one.text('tosses', 5)}, seed {args.seed}")
        difference = f"difference {z:+.2f} standard errors" if z is not None else f"difference {p - dhm:+.5f}"
        print(f"DHM        ½ + arcsin(cot²ψ)/π = {dhm:.5f}  ({difference})")
    return 0


def _fit(args):
    from coinwall.cases.bartos import bartos_fits, plot_bartos
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    check_paths(args.output, FIGURE_FORMATS)
    fits = bartos_fits()
    if args.tosser is not None:
        if args.tosser not in fits.tossers:
            raise InvalidArgument(f"--tosser must be one of T01 … T{len(fits.tossers):02d}, got {args.tosser!r}")
        one = fits.tossers[args.tosser]
        if args.json:
            print(json.dumps(one.to_dict(), indent=1))
            return 0
        below = (f" (the model's P(same) is at least ½: the share seen, {one.p:.5f}, lies below its interval)"
                 if one.p < one.p_low else "")
        print(f"{args.tosser}  {one.same:,} same side of {one.flips:,}: {one.p:.5f} [{one.p_low:.5f}, "
              f"{one.p_high:.5f}] (95 %, one binomial, likelihood ratio){below}")
        print(f"     ψ = {one.psi:.2f}° [{one.psi_low:.2f}, {one.psi_high:.2f}]; spread σ = {one.sigma:.2f}° "
              f"[{one.sigma_low:.2f}, {one.sigma_high:.2f}]")
        return 0
    files = {path: figure_bytes(plot_bartos(fits), path) for path in args.output}
    written = write_all(files)
    if args.json:
        print(json.dumps(dict(fits.to_dict(), outputs=args.output), indent=1))
        return 0
    o, w = fits.overall, fits.overall_overdispersed
    print(f"all flips  {o.same:,} same side of {o.flips:,}: {o.p:.5f} [{o.p_low:.5f}, {o.p_high:.5f}] (95 %, "
          "one binomial, likelihood ratio)")
    print(f"           [{w.p_low:.5f}, {w.p_high:.5f}] with the spread between tossers (quasi-binomial, dispersion "
          f"φ = Pearson χ² {fits.pearson_statistic:.1f} / {fits.dof} = {fits.dispersion:.2f})")
    print(f"one ψ      {o.psi:.2f}° [{o.psi_low:.2f}, {o.psi_high:.2f}] binomial; "
          f"[{w.psi_low:.2f}, {w.psi_high:.2f}] with the spread between tossers")
    print(f"spread     ψ = 90° − |δ|, δ ~ N(0, σ²): σ = {o.sigma:.2f}° [{o.sigma_low:.2f}, {o.sigma_high:.2f}] "
          f"binomial; [{w.sigma_low:.2f}, {w.sigma_high:.2f}] with the spread between tossers")
    print(f"tossers    homogeneity: χ² = {fits.lr_statistic:.1f} on {fits.dof} dof, p = {fits.p_value:.2g} (the "
          "tossers differ: the binomial interval is that of one tosser who made every flip)")
    for name, f in fits.tossers.items():
        print(f"  {name}  {f.same:>6}/{f.flips:<6} {f.p:.4f}  ψ = {f.psi:5.2f}° [{f.psi_low:5.2f}, {f.psi_high:5.2f}]")
    for line in written_lines(written, written.replaced):
        print(line)
    return 0


#: bounce: the units of its lengths and field (JSON ``units``, the shape ``toss`` gives): the coin is the real coin of
#: the experiment, so SI, as any command is with ``--kappa`` in metres
UNITS = {"length": "m", "field": "m/s^2"}

#: bounce: the measured cost of following one toss to one bounce (2 shared cores: 20,000 tosses × 10 bounces in
#: about 6 s, 30 µs, at the default height and field), counted as 100 µs per second of the first flight (at least
#: one); a toss the search cannot follow may take up to a second, which the estimate does not foresee
US_PER_BOUNCE_SECOND = 100.0
#: bounce: the fastest first impact followed (m/s; a coin dropped from about 130 m).  Beyond it the search fails
#: for a growing share of tosses (measured: 0.5 % at 31 m/s, 4 % at 89 m/s, 27 % at 198 m/s)
MAX_IMPACT_SPEED = 50.0
#: bounce: the most the coin may turn in its first flight (radians, spin × flight time): the phase of a longer
#: flight keeps too few digits to place the contact (measured: 1 % of tosses failed at 1.6e5 rad, 16 % at 1.6e6)
MAX_FLIGHT_TURNS = 1e6


def _first_flight(args, speed, spin):
    """Seconds and turns of the first flight (up, then down to the floor) of the fastest toss."""
    top = max(abs(v) for v in speed)
    if args.g > 0:
        impact = math.sqrt(top ** 2 + 2 * args.g * args.height)
        seconds = (top + impact) / args.g
    else:  # between two walls without a field: up to the ceiling at constant speed
        impact = top
        seconds = (args.ceiling - args.height) / top
    return seconds, impact, seconds * (spin[0] + 3 * spin[1])


def _bounce(args):
    from coinwall.cases.bartos import bartos_fits
    from coinwall.forward.dynamics.coin3d.bounced import same_side_by_bounce
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.estimates import MIN_SAMPLES, require

    from .budget import check_time

    if args.g < 0 or (args.g == 0 and args.ceiling is None):
        raise InvalidArgument(f"--g must be positive (or 0 with a --ceiling: the coin would fly off), got {args.g}")
    if not args.height > 0:
        raise InvalidArgument(f"--height must be a positive launch height in metres, got {args.height:g}")
    fitted = args.psi is None
    psi = bartos_fits().overall.psi if fitted else args.psi
    speed = (2.2, 2.7) if args.g > 0 else (-2.7, -2.2)
    spin = (240.0, 20.0)
    seconds, impact, turns = _first_flight(args, speed, spin)
    if impact > MAX_IMPACT_SPEED:
        raise InvalidArgument(f"--height {args.height:g} with --g {args.g:g}: the coin meets the floor at {impact:.3g} m/s; "
                              f"the bounces are followed up to {MAX_IMPACT_SPEED:g} m/s (a drop of about "
                              f"{MAX_IMPACT_SPEED ** 2 / (2 * args.g) if args.g > 0 else math.inf:.3g} m at this --g)")
    if turns > MAX_FLIGHT_TURNS:
        raise InvalidArgument(f"--g {args.g:g} with --height {args.height:g}: the first flight lasts {seconds:.3g} s, in "
                              f"which the coin turns {turns:.3g} rad; beyond {MAX_FLIGHT_TURNS:g} rad its phase keeps "
                              "too few digits to place the contact: raise --g or lower --height")
    check_time(args, args.samples * args.bounces * US_PER_BOUNCE_SECOND * 1e-6 * max(1.0, seconds),
               f"--samples {args.samples} × --bounces {args.bounces} (a first flight of {seconds:.3g} s)",
               "fewer --samples or --bounces")
    with progress_bar(args, args.samples, "toss") as bar:
        study = same_side_by_bounce(psi, args.e, samples=args.samples, bounces=args.bounces, seed=args.seed, g=args.g,
                                    height=args.height, ceiling=args.ceiling, speed=speed, spin=spin,
                                    progress=bar.update if bar is not None else None)
    failed = study.failed
    require(int(study.reached.max(initial=0)), MIN_SAMPLES, "P(same side) at any bounce",
            f"of {args.samples} tosses {int(study.reached[0]) if study.reached.size else 0} reached the first bounce "
            f"(status: {', '.join(f'{k}: {v}' for k, v in study.status.items())})")
    if args.json:
        print(json.dumps(dict(study.to_dict(), seed=args.seed, units=UNITS), indent=1, allow_nan=False))
        return 1 if failed > 0.01 * args.samples else 0
    import numpy as np

    where = f"a ceiling {args.ceiling:g} m above the floor" if args.ceiling is not None else "a floor"
    print(f"toss       ψ = {psi:.2f}°{' (fitted to the real flips)' if fitted else ''}, e = {args.e:g}, "
          f"g = {args.g:g} m/s², {where}, launched from {args.height:g} m; {args.samples} tosses, "
          f"seed {args.seed}")
    print("units      SI: the coin of the experiment (radius 12 mm, thickness 1.75 mm), lengths in m, g in m/s²")
    print(f"settled    {study.settled:.3f} of the tosses by bounce {study.same.size} (energy below the equator's "
          "barrier: the side can no longer change)")
    # how each toss's run ended (the kernel's status); "impact budget reached": followed to the last bounce
    names = sorted(study.status, key=lambda k: -study.status[k])
    for k, name in enumerate(names):
        shown = "followed to the last bounce" if name == "impact budget reached" else name
        print(f"{'ended' if k == 0 else '':<11}{study.status[name]:>8}  {shown}")
    print(f"{'bounce':>8}  P(same side) ± standard error (tosses that reached the bounce)")
    for n, one in enumerate(study.shares(), start=1):
        print(f"{n:>8}  {one.text('tosses')}")
    ok = study.enough
    n = study.bounces_to_fair()
    far = np.flatnonzero(ok & (np.abs(study.same - 0.5) - 2 * study.stderr > 0.001))
    last = int(np.flatnonzero(ok)[-1]) + 1
    if n:
        verdict = f"within 0.001 of ½ from bounce {n}"
    elif far.size:
        verdict = (f"not fair: at bounce {int(far[-1]) + 1} P(same side) is more than 0.001 from ½ by two standard "
                   "errors (on a frictionless floor L_z and L₃ are kept, see docs/coin3d.md)")
    else:
        verdict = ("not resolved: two standard errors (±{:.4f}) are wider than 0.001 at every bounce; raise "
                   "--samples".format(2 * float(np.min(study.stderr[ok]))))
    if last < ok.size:
        verdict += f" (bounces after {last} were reached by fewer than {MIN_SAMPLES} tosses: no share there)"
    print("fair       " + verdict)
    stopped = int(study.reached[0] - study.reached[-1]) if study.reached.size else 0
    if stopped > 0.01 * max(int(study.reached[0]), 1):
        print(f"note       {stopped} of {int(study.reached[0])} tosses stopped before bounce {study.reached.size} "
              "(a face flat on the floor, or a graze the search could not resolve; see the tosses above): "
              "each bounce's share is over the tosses that reached it")
    if failed > 0.01 * args.samples:
        import sys

        print(f"warning: the search could not follow {failed} of {args.samples} tosses ({failed / args.samples:.1%}): "
              "the shares are over the others, and may be biased", file=sys.stderr)
        return 1
    return 0
