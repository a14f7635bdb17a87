"""``coinwall simulate``: run the billiard for one orbit and report rate and simple statistics."""

from __future__ import annotations

import json
import time

from .budget import MAX_SECONDS, add_allow_long, check_time, duration
from .common import (
    add_command,
    count,
    device_argument,
    load_table,
    progress_bar,
    seed_argument,
    table_arguments,
    wall_params,
)

__all__ = ["MAX_SECONDS", "NS_PER_COLLISION", "register"]

#: The cost of one collision, with a margin: the numba kernel ~0.5 µs on the ε = 99 ellipse
#: (tests/benchmarks/bench_billiard.py), the numpy reference stepper ~0.3 ms; counted as 1 µs and 500 µs
#: (``section`` and ``correlation`` count their collisions at the kernel's cost too).
NS_PER_COLLISION = {"kernel": 1_000.0, "reference": 500_000.0}

DESCRIPTION = """\
Follow orbits of the billiard equivalent to the body between the walls (the paper's eqs. 1–8).

The particle moves at unit speed in the (θ, η) strip between the lower wall b0 + b(θ) and the
upper wall H − b0 − b(θ + π), reflecting specularly, from a Liouville-random start.  Reports the
collision rate of the numba kernel (compile time apart), the mean free time against Santaló's
π·Area/Perimeter, and the share of collisions with the bottom wall.  With --orbits N, N
Liouville-random orbits of --collisions each (on all CPU cores, or with --device gpu one orbit
per GPU thread), and the mean free time from the collisions counted in a common time window
(± its standard error: it tends to Santaló's value on any table).  Units: κ (radius of
gyration); with --kappa the wall, --H and --b0 are lengths in κ's unit."""

EXAMPLE = 'coinwall simulate "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=99 --H 3 --collisions 1000000'


def register(subparsers):
    """Add the ``simulate`` subcommand."""

    parser = add_command(subparsers, "simulate", help="run the equivalent billiard (numba kernel) for one orbit",
                         description=DESCRIPTION, example=EXAMPLE)
    table_arguments(parser)
    parser.add_argument("--collisions", type=count, default=100_000,
                        help="number of collisions (per orbit with --orbits; default 100000)")
    parser.add_argument("--orbits", type=count, default=1, help="number of Liouville-random orbits (default 1)")
    seed_argument(parser, "the random start states (Liouville measure)")
    parser.add_argument("--method", choices=["kernel", "reference"], default="kernel",
                        help="numba kernel (default) or the slow plain-numpy reference stepper")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON (no progress bar)")
    add_allow_long(parser)
    device_argument(parser)
    parser.set_defaults(run=_cmd_simulate)


def estimated_seconds(collisions: int, method: str) -> float:
    """The run time of ``collisions`` collisions with ``method`` at the measured cost per collision."""
    return collisions * NS_PER_COLLISION[method] * 1e-9


def _cmd_simulate(args):
    from coinwall.forward.dynamics.analysis.orbitstats import CHUNK, MAX_COLLISIONS, orbit_statistics
    from coinwall.forward.dynamics.billiard.table import compile_kernel, random_states
    from coinwall.forward.validation import check_count

    check_count("collisions", args.collisions, maximum=MAX_COLLISIONS)  # before the estimate (orbit_statistics' rule)
    if args.orbits > 1 or args.device != "cpu":
        return _simulate_ensemble(args)
    estimate = check_time(args, estimated_seconds(args.collisions, args.method),
                          f"--collisions {args.collisions} with --method {args.method} "
                          f"({NS_PER_COLLISION[args.method]:g} ns per collision)",
                          f"at most {round(MAX_SECONDS / (NS_PER_COLLISION[args.method] * 1e-9))} collisions")
    wall, table = load_table(args)
    state = random_states(table, 1, args.seed)[0]
    compile_seconds = compile_kernel(table) if args.method == "kernel" else 0.0
    with progress_bar(args, args.collisions, "coll", show=args.collisions > CHUNK) as bar:
        if bar is not None:
            bar.set_description(f"estimate {duration(estimate)}")
        start = time.perf_counter()
        stats = orbit_statistics(table, state, args.collisions, method=args.method,
                                 progress=bar.update if bar is not None else None)
    seconds = time.perf_counter() - start
    done = stats.collisions
    summary = {
        "wall": args.wall, "params": wall_params(wall), "kappa": args.kappa, "H": table.H, "b0": table.b0,
        "seed": args.seed,
        "method": args.method, "collisions": done, "seconds": seconds,
        "collisions_per_second": done / seconds if seconds > 0 else None,
        "compile_seconds": compile_seconds, "estimated_seconds": estimate,
        "mean_free_time": stats.mean_free_time if done else None,
        "santalo_mean_free_time": stats.santalo_mean_free_time,
        "bottom_fraction": stats.bottom_fraction if done else None,
        "start": [float(x) for x in state], "final_state": [float(x) for x in stats.final_state],
        "gap_min": table.gap_min, "gap_max": table.gap_max, "note": stats.note,
    }
    if args.json:
        print(json.dumps(summary, indent=1, allow_nan=False))
        return 0
    print(f"table      {table!r}")
    print(f"start      θ={state[0]:.6g} η={state[1]:.6g} v=({state[2]:.6g}, {state[3]:.6g}) (seed {args.seed})")
    print(f"collisions {done} in {seconds:.3g} s ({summary['collisions_per_second'] or 0:.3g}/s; "
          f"compile/load {compile_seconds:.3g} s, not included; estimated {duration(estimate)} beforehand)")
    if done:
        from coinwall.forward.estimates import mean_text

        # (the collisions of one orbit are not independent samples: no binomial error is claimed)
        print(f"free time  mean {mean_text(summary['mean_free_time'], done, 'free flights')} "
              f"(Santaló π·A/P = {summary['santalo_mean_free_time']:.6g})")
        print(f"bottom     fraction of collisions with the bottom wall "
              f"{mean_text(summary['bottom_fraction'], done, 'collisions', '.4f')}")
    if stats.note:
        print(f"note       {stats.note}")
    return 0


def _simulate_ensemble(args):
    """``--orbits N`` (or ``--device gpu``): N Liouville-random orbits, statistics only
    (:func:`ensemble_statistics`)."""
    from coinwall.forward.dynamics.analysis.orbitstats import ensemble_statistics
    from coinwall.forward.dynamics.billiard.gpu import check_device
    from coinwall.forward.dynamics.billiard.table import compile_kernel, random_states
    from coinwall.forward.errors import InvalidArgument

    check_device(args.device)
    if args.method != "kernel":
        raise InvalidArgument("--orbits and --device follow orbits with the kernel; --method reference runs one orbit")
    total = args.orbits * args.collisions
    if args.device == "cpu":  # the estimate is the CPU kernel's cost; a GPU runs such ensembles fifty times faster
        check_time(args, estimated_seconds(total, "kernel"),
                   f"--orbits {args.orbits} × --collisions {args.collisions} ({NS_PER_COLLISION['kernel']:g} ns per "
                   "collision)", "fewer, or --device gpu,")
    wall, table = load_table(args)
    states = random_states(table, args.orbits, args.seed)
    compile_seconds = compile_kernel(table, device=args.device)
    with progress_bar(args, total, "coll") as bar:
        start = time.perf_counter()
        stats = ensemble_statistics(table, states, args.collisions, device=args.device,
                                    progress=bar.update if bar is not None else None)
    seconds = time.perf_counter() - start
    summary = dict(stats.to_dict(), wall=args.wall, params=wall_params(wall), kappa=args.kappa, seed=args.seed,
                   method="kernel", seconds=seconds,
                   collisions_per_second=stats.collisions / seconds if seconds > 0 else None,
                   compile_seconds=compile_seconds)
    if args.json:
        print(json.dumps(summary, indent=1, allow_nan=False))
        return 0
    print(f"table      {table!r}")
    print(f"orbits     {stats.orbits} Liouville-random (seed {args.seed}) on the {args.device}")
    print(f"collisions {stats.collisions} in {seconds:.3g} s ({summary['collisions_per_second'] or 0:.3g}/s; "
          f"compile/load {compile_seconds:.3g} s, not included)")
    if stats.collisions:
        print(f"free time  mean {stats.mean_free_time:.6g} ± {stats.mean_free_time_stderr:.2g} "
              f"(Santaló π·A/P = {stats.santalo_mean_free_time:.6g})")
        print(f"bottom     fraction of collisions with the bottom wall {stats.bottom_fraction:.4f}")
    for note in stats.notes[:5]:
        print(f"note       {note}")
    if len(stats.notes) > 5:
        print(f"note       ... and {len(stats.notes) - 5} more orbits stopped early")
    return 0
