"""``coinwall simulate``: run the billiard for one orbit and report rate and simple statistics."""

from __future__ import annotations

import json
import math
import time
from .common import load_table, progress_bar, table_arguments

__all__ = ["register"]

_CHUNK = 200_000  # collisions per kernel call: progress updates and bounded memory


def register(subparsers):
    """Add the ``simulate`` subcommand."""

    parser = subparsers.add_parser("simulate", help="run the equivalent billiard (numba kernel) for one orbit")
    table_arguments(parser)
    parser.add_argument("--collisions", type=int, default=100_000, help="number of collisions (default 100000)")
    parser.add_argument("--seed", type=int, default=None, help="seed of the random start state (Liouville measure)")
    parser.add_argument("--method", choices=["kernel", "reference"], default="kernel",
                        help="numba kernel (default) or the slow plain-numpy reference stepper")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON (no progress bar)")
    parser.set_defaults(run=_cmd_simulate)


def _cmd_simulate(args):
    import numpy as np

    from coinwall.forward.dynamics.billiard import compile_kernel, random_states, simulate
    from coinwall.forward.errors import InvalidArgument

    if args.collisions <= 0:
        raise InvalidArgument(f"--collisions must be a positive integer, got {args.collisions}")
    if args.seed is not None and args.seed < 0:
        raise InvalidArgument(f"--seed must be a non-negative integer, got {args.seed}")
    wall, table = load_table(args)
    state = random_states(table, 1, args.seed)[0]
    compile_seconds = compile_kernel(table) if args.method == "kernel" else 0.0
    bar = progress_bar(args, args.collisions, "coll") if args.collisions > _CHUNK else None
    done, total_time, bottom, note = 0, 0.0, 0, ""
    start = time.perf_counter()
    current = state
    try:
        while done < args.collisions:
            n = min(_CHUNK, args.collisions - done)
            traj = simulate(table, current, n, method=args.method)
            got = len(traj)
            if got:
                total_time += float(traj.time[-1])
                bottom += int(np.count_nonzero(traj.side == 0))
                current = traj.final_state
            done += got
            if bar is not None:
                bar.update(got)
            if traj.note:
                note = traj.note
                break
    finally:
        if bar is not None:
            bar.close()
    seconds = time.perf_counter() - start
    area, perimeter = table.area_perimeter()
    summary = {
        "wall": args.wall, "params": dict(wall.params), "kappa": args.kappa, "H": table.H, "b0": table.b0,
        "seed": args.seed,
        "method": args.method, "collisions": done, "seconds": seconds,
        "collisions_per_second": done / seconds if seconds > 0 else None,
        "compile_seconds": compile_seconds,
        "mean_free_time": total_time / done if done else None,
        "santalo_mean_free_time": math.pi * area / perimeter,
        "bottom_fraction": bottom / done if done else None,
        "start": [float(x) for x in state], "final_state": [float(x) for x in current],
        "gap_min": table.gap_min, "gap_max": table.gap_max, "note": note,
    }
    if args.json:
        print(json.dumps(summary, indent=1, allow_nan=False))
        return 0
    print(f"table      {table!r}")
    print(f"start      θ={state[0]:.6g} η={state[1]:.6g} v=({state[2]:.6g}, {state[3]:.6g}) (seed {args.seed})")
    print(f"collisions {done} in {seconds:.3g} s ({summary['collisions_per_second'] or 0:.3g}/s; "
          f"compile/load {compile_seconds:.3g} s, not included)")
    if done:
        print(f"free time  mean {summary['mean_free_time']:.6g} (Santaló π·A/P = {summary['santalo_mean_free_time']:.6g})")
        print(f"bottom     fraction of collisions with the bottom wall {summary['bottom_fraction']:.4f}")
    if note:
        print(f"note       {note}")
    return 0
