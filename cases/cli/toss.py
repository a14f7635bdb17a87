"""``coinwall toss``: the toss that lands: basin map of the outcome over launch velocity and spin."""

from __future__ import annotations

import json
import math
import os

from .budget import add_allow_long, check_time
from .common import (
    DEFAULT_SEED,
    add_command,
    count,
    device_argument,
    load_wall,
    number,
    progress_bar,
    seed_argument,
    wall_arguments,
    wall_options,
    wall_params,
    written_lines,
)

__all__ = ["register"]

DESCRIPTION = """\
The toss that lands: the body is launched from a rest orientation with its centre of mass at
--height (units of κ) above the floor, with upward velocity v0 and spin ω0 (θ̇), in the field --g
(κ/s²; with --kappa in metres every length, speed and the field are in SI), and bounces on the floor with restitution --e and Coulomb
friction --mu (0: frictionless impacts, Newton's restitution on the normal velocity) until its
outcome is decided: its energy below the barrier of the floor's valley it is in, or at rest.  With
friction a body whose bounces die out slides, rolls and rocks on the floor (with --rolling, against
a rolling resistance) until it lifts off again or settles; without it, it slides for ever
(undecided).  With --catch it is caught the first time it meets the floor (Keller's coin).  Reports
the basin map of the outcome over the grid --v0 × --omega (heads/tails/edge for a coin, else the
rest faces by the angle of their normal), the number of floor impacts it took, each undecided toss
counted by its reason, and with --spread the probability of each outcome under a Gaussian spread of
(v0, ω0) with its standard error.  With --uncertainty it reports
instead the uncertainty exponent α of the basin boundary (Grebogi, Ott and Yorke) over the box of
--v0 × --omega: the share f(ε) of launches whose outcome changes when moved by ±ε (a fraction of
the box's sides, in a random direction), fitted to f ∝ ε^α (α = 1 for a smooth boundary, less for
a fractal one; --samples launches per ε).  With --device gpu the tosses run on a CUDA GPU, one
per thread, friction and contact phases included."""

EXAMPLE = ('coinwall toss case:coin --g 1 --e 0.6 --height 1.2 --v0 0:3:300 --omega 0:8:300 -o basin.png\n'
           'coinwall toss case:egg --e 0.8 --mu 0.3 --rolling 0.01 -o egg.png\n'
           'coinwall toss case:coin --g 1 --e 0.6 --height 1.2 --spread 2,5,0.05,0.2 --samples 20000 --seed 1\n'
           'coinwall toss case:coin --g 1 --e 0.6 --height 1.2 --v0 0:3 --omega 0:8 --uncertainty 1e-6:1e-2:5')


def _grid(text: str):
    """``LO:HI:N`` -> N numbers from LO to HI; ``LO:HI`` (a range, as --uncertainty reads it) has N = 120."""
    parts = text.split(":")
    if len(parts) not in (2, 3):
        raise ValueError(text)
    lo, hi = number(parts[0]), number(parts[1])
    n = count(parts[2]) if len(parts) == 3 else 120
    if not (math.isfinite(lo) and math.isfinite(hi) and hi >= lo and 1 <= n <= 4096):
        raise ValueError(text)
    return lo, hi, n


def _spread(text: str):
    parts = [number(p) for p in text.split(",")]
    if len(parts) != 4 or not all(math.isfinite(p) for p in parts) or parts[2] < 0 or parts[3] < 0:
        raise ValueError(text)
    return parts


def _epsilons(text: str):
    """``LO:HI:N`` -> N log-spaced ε from LO to HI, in (0, 0.1]."""
    parts = text.split(":")
    if len(parts) != 3:
        raise ValueError(text)
    lo, hi = number(parts[0]), number(parts[1])
    n = count(parts[2])
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi <= 0.1 and 2 <= n <= 50):
        raise ValueError(text)
    return lo, hi, n


_grid.__name__ = "grid LO:HI:N or range LO:HI (N up to 4096)"
#: the units of the numbers in the JSON (the shape `coin3d bounce` gives): units of κ, also with --kappa (which reads
#: the inputs in SI)
UNITS = {"length": "kappa", "field": "kappa/s^2"}
#: draws of --spread and --uncertainty by default (the basin map, a grid, takes none)
_SAMPLES = 10_000
_epsilons.__name__ = "epsilons LO:HI:N (0 < LO < HI <= 0.1, 2 <= N <= 50)"
_spread.__name__ = "spread V0,OMEGA0,SIGMA_V0,SIGMA_OMEGA0"


def register(subparsers):
    """Add the ``toss`` subcommand."""
    parser = add_command(subparsers, "toss", help="the toss that lands: gravity, a floor, restitution; basin maps",
                         description=DESCRIPTION, example=EXAMPLE)
    wall_arguments(parser, intervals=False)
    parser.add_argument("--g", type=number, default=1.0, help="field in κ/s² (default 1; m/s² with --kappa)")
    parser.add_argument("--e", type=number, default=0.6,
                        help="coefficient of restitution in (0, 1]; 0 (perfectly plastic) on a floor only (default 0.6)")
    parser.add_argument("--mu", type=number, default=0.0,
                        help="Coulomb's coefficient of friction of the floor (default 0: frictionless)")
    parser.add_argument("--rolling", type=number, default=0.0, metavar="DELTA",
                        help="with --mu: rolling resistance, the lever arm (units of κ, in [0, 1]) of the floor's "
                             "push that opposes rolling (default 0: a body rolling without slipping keeps its energy)")
    parser.add_argument("--height", type=number, default=None,
                        help="launch height of the centre of mass (κ; default: b0 + 2 × the largest wall value, at "
                             "least b0 + 1, i.e. clear of the floor at every angle)")
    parser.add_argument("--b0", type=number, default=0.0, help="offset added to the wall (default 0)")
    parser.add_argument("--H", type=number, default=None, help="a ceiling at this height (κ; default: none)")
    parser.add_argument("--kappa", type=number, default=None, metavar="METRES",
                        help="radius of gyration in metres: the wall, --b0, --H, --height, --rolling and the launch "
                             "speeds (--v0, --spread) are then in m and m/s and --g in m/s² (results in units of κ)")
    parser.add_argument("--theta0", type=number, default=None,
                        help="launch orientation (rad; default: heads' rest angle for a coin, else the first)")
    parser.add_argument("--v0", type=_grid, default=(0.0, 3.0, 120), metavar="LO:HI:N",
                        help="grid of launch velocities (κ/s; default 0:3:120)")
    parser.add_argument("--omega", type=_grid, default=(0.0, 8.0, 120), metavar="LO:HI:N",
                        help="grid of spins ω0 = θ̇ (rad/s; default 0:8:120)")
    parser.add_argument("--impacts", type=count, default=10_000,
                        help="impacts per toss at most; a toss still bouncing then is undecided (default 10000)")
    parser.add_argument("--catch", action="store_true", help="stop at the first floor contact (Keller's toss)")
    parser.add_argument("--slide", action="store_true",
                        help="without friction: follow tosses that come to slide on a smooth floor until they lift "
                             "off (slow)")
    parser.add_argument("--spread", type=_spread, default=None, metavar="V0,OMEGA0,SV,SW",
                        help="instead of the map: outcome fractions for (v0, ω0) ~ Gaussian(mean, sigma)")
    parser.add_argument("--uncertainty", type=_epsilons, default=None, metavar="LO:HI:N",
                        help="instead of the map: the uncertainty exponent of the outcome over the --v0 × --omega box, "
                             "from N log-spaced ε between LO and HI (fractions of the box's sides)")
    parser.add_argument("--samples", type=count, default=_SAMPLES,
                        help="draws for --spread, launches per ε for --uncertainty (default 10000)")
    seed_argument(parser, "the --spread or --uncertainty draws")
    parser.add_argument("--workers", type=count, default=None, help="threads (default: all cores)")
    device_argument(parser)
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="basin map: figure (.png, .svg, .pdf), .csv (v0,omega0,outcome,name,bounces) or .json "
                             "(repeatable)")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON (no progress bar)")
    add_allow_long(parser)
    parser.set_defaults(run=_cmd_toss)


#: the work of a toss, measured on 2 shared cores (one thread): about 1.4 µs per floor impact (16 elastic tosses of
#: 10⁶ impacts in 22 s) and 30 µs to set up and decide a toss; counted as 2 µs and 50 µs
NS_PER_IMPACT, NS_PER_TOSS = 2_000.0, 50_000.0


def _check_work(args, tosses: int) -> None:
    """Refuse (without --allow-long) a run estimated past one hour: every toss may bounce --impacts times when
    nothing settles (e = 1); with e < 1 the energy above the barrier falls by about 1 − e² an impact, so a toss
    takes about 10 + 30/(1 − e²) impacts (measured means: 8 at e = 0.6, 58 at e = 0.95).  The estimate is the CPU's,
    with --device gpu too (a GPU's rate of tosses has not been measured)."""
    import os

    impacts = args.impacts if args.e >= 1 else min(args.impacts, 10 + 30 / (1 - args.e ** 2))
    threads = max(1, min(args.workers or os.cpu_count() or 1, os.cpu_count() or 1))
    seconds = tosses * (NS_PER_TOSS + NS_PER_IMPACT * impacts) * 1e-9 / threads
    check_time(args, seconds, f"{tosses} tosses of up to {impacts:.3g} impacts each (--impacts {args.impacts}, --e "
                              f"{args.e:g}; {NS_PER_IMPACT * 1e-3:g} µs per impact, {threads} threads)",
               "fewer tosses or a smaller --impacts")


def _cmd_toss(args):
    import numpy as np

    from coinwall.forward.dynamics.billiard.gpu import check_device
    from coinwall.forward.dynamics.floor.field import FieldTable
    from coinwall.forward.dynamics.floor.hand import heads_fraction
    from coinwall.forward.dynamics.floor.toss import basin_map, launch_states
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    if args.impacts > 10 ** 9 or args.samples > 10 ** 8:
        raise InvalidArgument(f"--impacts must be at most 1e9 and --samples at most 1e8, got {args.impacts} and "
                              f"{args.samples}")
    check_paths(args.output, FIGURE_FORMATS + (".csv", ".json"))
    if args.spread is not None and args.output:
        raise InvalidArgument("-o writes the basin map; --spread prints fractions only (drop one of them)")
    if args.uncertainty is not None and (args.output or args.spread is not None):
        raise InvalidArgument("--uncertainty prints the exponent only: drop -o and --spread")
    # flags the basin map does not read are refused, not ignored
    if args.spread is None and args.uncertainty is None and (args.samples != _SAMPLES or args.seed != DEFAULT_SEED):
        raise InvalidArgument("--samples and --seed are for --spread and --uncertainty; the basin map is a grid "
                              "(--v0, --omega)")
    if args.catch and args.slide:
        raise InvalidArgument("--slide follows tosses that slide on the floor; --catch stops at the first contact "
                              "(drop one of them)")
    if args.slide and args.mu > 0:
        raise InvalidArgument("--slide follows tosses on a frictionless floor; with --mu the contact phases are "
                              "followed anyway (drop --slide)")
    # --g, --e, --mu, --rolling, --b0, --H are checked by FieldTable, --theta0 by check_options and launch_states
    if args.height is not None and not math.isfinite(args.height):
        raise InvalidArgument(f"--height must be a finite number, got {args.height}")
    if args.kappa is not None and not (math.isfinite(args.kappa) and args.kappa > 0):
        raise InvalidArgument(f"--kappa must be a positive length in metres, got {args.kappa}")
    if args.kappa is not None:
        _to_kappa_units(args)
    g = args.g
    if args.device == "gpu" and args.workers is not None:
        raise InvalidArgument("--workers sets the CPU's threads; with --device gpu the tosses run on the GPU (drop one)")
    check_device(args.device)  # before any work
    _check_work(args, args.samples if args.spread is not None else
                2 * args.samples * args.uncertainty[2] if args.uncertainty is not None else args.v0[2] * args.omega[2])
    wall = load_wall(args.wall, args.param, **wall_options(args))
    if args.kappa is not None:  # the wall in metres, like --b0 (as the billiard commands read --kappa)
        wall = wall.scaled(1.0 / args.kappa)
    table = FieldTable(wall, g=g, e=args.e, b0=args.b0, H=args.H, mu=args.mu, rolling=args.rolling)
    height = args.height
    if height is None:
        height = args.b0 + 2.0 * float(np.max(wall(np.linspace(0, 2 * np.pi, 1024, endpoint=False))))
        height = max(height, args.b0 + 1.0)
        try:  # the library's check of a launch height, said of the default the user did not choose
            launch_states(table, 0.0, 0.0, height, args.theta0)
        except InvalidArgument as exc:
            if not str(exc).startswith("`height`"):  # not about the height (a wall without valleys): as it is
                raise
            raise InvalidArgument(f"the default launch height {height:g} (b0 + 2 × the largest wall value) does not "
                                  f"fit: {exc}; give --height") from None
    if args.spread is not None:
        mean, sigma = args.spread[:2], args.spread[2:]
        with progress_bar(args, args.samples, "toss") as bar:
            spread = heads_fraction(table, mean, sigma, height, samples=args.samples, theta0=args.theta0,
                                    seed=args.seed, impacts=args.impacts, catch=args.catch, workers=args.workers,
                                    progress=bar.update if bar is not None else None, slide=args.slide,
                                    device=args.device)
        summary = dict(spread.to_dict(), wall=args.wall, params=wall_params(wall), seed=args.seed, units=UNITS, g=g,
                       e=args.e, mu=args.mu, rolling=args.rolling,
                       height=height)
        from coinwall.forward.estimates import MIN_SAMPLES, require

        decided = round(args.samples * (1 - spread.fractions.get("undecided", (0.0, 0.0))[0]))
        require(decided, MIN_SAMPLES, "the outcome fractions", f"of {args.samples} tosses, {decided} were decided "
                f"within --impacts {args.impacts}: raise --samples or --impacts", unit="decided tosses")
        if args.json:
            print(json.dumps(summary, indent=1, allow_nan=False))
        else:
            print(f"table      {table!r}")
            print(f"spread     {spread!r}")
            print(f"draws      {args.samples} ({decided} decided within --impacts {args.impacts}), seed {args.seed}; ± "
                  "is the binomial standard error")
            _print_undecided(spread.undecided, args.samples)
        return 0
    if args.uncertainty is not None:
        return _uncertainty(args, table, height, g, wall_params(wall))
    v = np.linspace(*args.v0[:2], args.v0[2])
    w = np.linspace(*args.omega[:2], args.omega[2])
    with progress_bar(args, v.size * w.size, "toss") as bar:
        result = basin_map(table, v, w, height, theta0=args.theta0, impacts=args.impacts, catch=args.catch,
                           workers=args.workers, progress=bar.update if bar is not None else None, slide=args.slide,
                           device=args.device)
    files = {}
    for path in args.output:
        ext = os.path.splitext(path)[1].lower()
        if ext in FIGURE_FORMATS:
            ax = result.plot(title=f"{args.wall} {' '.join(args.param)}".strip())
            files[path] = figure_bytes(ax.figure, path)
        elif ext == ".csv":
            files[path] = result.to_csv().encode()
        else:
            files[path] = json.dumps(dict(result.to_dict(), wall=args.wall, params=wall_params(wall)),
                                     allow_nan=False).encode()
    written = write_all(files)
    summary = {"wall": args.wall, "params": wall_params(wall), "units": UNITS, "g": g, "e": args.e, "mu": args.mu, "rolling": args.rolling,
               "height": height, "theta0": result.theta0, "grid": [int(w.size), int(v.size)],
               "names": list(result.names), "fractions": result.fractions(), "status": result.status_counts(),
               "undecided": result.undecided_counts(), "mean_bounces": float(np.mean(result.bounces)),
               "outputs": args.output}
    if args.json:
        print(json.dumps(summary, indent=1, allow_nan=False))
    else:
        print(f"table      {table!r}")
        print(f"map        {result!r}")
        print(f"bounces    mean {summary['mean_bounces']:.3g} floor impacts before the outcome was decided")
        _print_undecided(summary["undecided"], result.outcome.size)
        for line in written_lines(written, written.replaced):
            print(line)
    return 0


def _to_kappa_units(args) -> None:
    """``--kappa METRES``: the lengths, speeds and the field given in SI (m, m/s, m/s²) -> units of κ, in which the
    toss is computed and reported (the wall is scaled where it is read)."""
    k = args.kappa
    args.g, args.b0, args.rolling = args.g / k, args.b0 / k, args.rolling / k
    args.H = None if args.H is None else args.H / k
    args.height = None if args.height is None else args.height / k
    args.v0 = (args.v0[0] / k, args.v0[1] / k, args.v0[2])
    if args.spread is not None:
        v0, omega0, sigma_v0, sigma_omega0 = args.spread
        args.spread = [v0 / k, omega0, sigma_v0 / k, sigma_omega0]


def _print_undecided(counts, total):
    """Each reason for an undecided toss on its own line: its count, share and meaning."""
    from coinwall.forward.dynamics.floor.toss import reason_lines

    for line in reason_lines(counts, total):
        print(f"undecided  {line}")


def _uncertainty(args, table, height, g, params):
    import numpy as np

    from coinwall.forward.dynamics.floor.uncertainty import uncertainty_exponent
    from coinwall.forward.errors import InvalidArgument

    if not (args.v0[1] > args.v0[0] and args.omega[1] > args.omega[0]):
        raise InvalidArgument(f"--uncertainty needs a box: --v0 and --omega must have LO < HI, got "
                              f"{args.v0[0]:g}:{args.v0[1]:g} and {args.omega[0]:g}:{args.omega[1]:g}")
    lo, hi, n = args.uncertainty
    eps = np.geomspace(lo, hi, n)
    with progress_bar(args, 3 * args.samples * n, "toss") as bar:  # each launch and its two ε-neighbours
        result = uncertainty_exponent(table, args.v0[:2], args.omega[:2], height, epsilons=eps, samples=args.samples,
                                      theta0=args.theta0, seed=args.seed, impacts=args.impacts, catch=args.catch,
                                      workers=args.workers, progress=bar.update if bar is not None else None,
                                      device=args.device)
    from coinwall.forward.estimates import require

    # a point of the fit is log f(ε) with relative error 1/√count: it needs 10 uncertain launches at least
    usable = int(np.sum(np.asarray(result.counts) >= 10))
    require(usable, 2, "the uncertainty exponent", f"uncertain launches {list(map(int, result.counts))} of "
            f"{args.samples} per ε: raise --samples or widen the ε range", unit="ε values with 10 uncertain launches")
    if args.json:
        print(json.dumps(dict(result.to_dict(), wall=args.wall, params=params, seed=args.seed, units=UNITS, g=g,
                                    height=height),
                         indent=1, allow_nan=False))
        return 0
    print(f"table      {table!r}")
    print(f"exponent   {result!r}")
    print(f"draws      {result.samples} launches per ε, seed {args.seed}")
    print("epsilon        uncertain fraction")
    for e, f, c in zip(result.epsilons, result.fractions, result.counts):
        print(f"{e:<14.4g} {f:.5f}  ({c} of {result.samples})")
    return 0
