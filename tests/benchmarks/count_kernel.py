"""Instructions, branches and modelled mispredictions per collision of the billiard kernel at two git revisions.

Run:  python tests/benchmarks/count_kernel.py [REV_A [REV_B]] [--collisions N]   (default: HEAD against the
working tree, ``.``)

Times on this shared machine move by tens of per cent from day to day; counts do not.  This script runs itself
again under valgrind's callgrind (``--dump-instr=yes --branch-sim=yes``; valgrind must be installed, Debian's
package ``valgrind``), runs the kernels of both revisions (``kernel_ab.py`` loads them) on the coin (ε = 99) at
H = 3 from ``bench_billiard.py``'s start in one process, and sums callgrind's counts over each compiled ``_run``'s own
machine code and the calls it makes (libm's ``sincos`` for the wall).  The mispredictions are those of
callgrind's simple predictor model, not of the processor.  The kernels are compiled for the processor valgrind
presents (no AVX-512) in a temporary cache folder, so the machine code differs in detail from the native one and
the user's kernel cache is not touched.  It takes ~12 minutes (two kernels compiled under valgrind).
"""

import argparse
import collections
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
CODE_SPAN = 16384  # bytes after a kernel's entry counted as its own code (its _run is ~12 KB)


def child(collisions, addresses, revisions):
    # under valgrind: run both kernels, after writing where each one's compiled _run starts
    sys.path.insert(0, str(HERE))
    from bench_billiard import _cpu_run
    from kernel_ab import kernel_text

    from coinwall.cases.ellipse import ellipse_wall
    from coinwall.forward.dynamics.billiard.kernel import HEADER, compiled
    from coinwall.forward.dynamics.billiard.table import Billiard, random_states
    from coinwall.forward.dynamics.billiard.wallcode import load_module, wall_source

    table = Billiard(ellipse_wall(99.0), 3.0)
    state = random_states(table, 1, 1)[0]
    args = compiled(table).args(table)
    source, _ = wall_source(table.wall, "@njit(**OPTIONS)\n")
    kernels = [(rev, load_module(HEADER + source + kernel_text(rev), "coinwall_count")) for rev in revisions]
    with open(addresses, "w", encoding="utf-8") as out:
        for name, module in kernels:
            _cpu_run(module, state, 10, args)  # compile or load
            _sig, overload = next(iter(module._run.overloads.items()))
            entry = overload.library.get_pointer_to_function(overload.fndesc.llvm_func_name)
            out.write(f"{entry} {name}\n")
    for _name, module in kernels:
        _cpu_run(module, state, collisions, args)


def _position(token, current):
    # callgrind's compressed positions: absolute, relative (+n, -n) or the same (*)
    if token == "*":
        return current
    if token[0] in "+-":
        return current + int(token, 0)
    return int(token, 0)


def _name(value, names):
    # callgrind's name compression: "(id) name" defines an id, "(id)" refers to it
    if value.startswith("("):
        key = value.split(")")[0] + ")"
        rest = value[len(key):].strip()
        if rest:
            names[key] = rest
        return names.get(key, key)
    return value


def tally(profile, entries):
    """Per kernel: its own counts (Ir, Bc, Bcm, Bi, Bim) and, per callee, calls and their inclusive Ir."""
    own = {name: [0] * 5 for name in entries.values()}
    calls = {name: collections.defaultdict(lambda: [0, 0]) for name in entries.values()}
    names, callee, pending, instr, line = {}, None, None, 0, 0

    def owner(address):
        for entry, name in entries.items():
            if entry <= address < entry + CODE_SPAN:
                return name
        return None

    with open(profile, encoding="utf-8", errors="replace") as lines:
        for text in lines:
            if text[:1] and text[0] in "0123456789+-*":
                parts = text.split()
                instr, line = _position(parts[0], instr), _position(parts[1], line)
                events = [int(v) for v in parts[2:]] + [0] * 5
                name = owner(instr)
                if pending is not None:  # the line after calls=: the call's inclusive cost
                    if name:
                        calls[name][callee][0] += pending
                        calls[name][callee][1] += events[0]
                    pending = None
                elif name:
                    for k in range(5):
                        own[name][k] += events[k]
            elif text.startswith("cfn="):
                callee = _name(text[4:].strip(), names)
            elif text.startswith("fn="):  # functions and callees share one namespace of ids
                _name(text[3:].strip(), names)
            elif text.startswith("calls="):
                pending = int(text.split("=")[1].split()[0])
    return own, calls


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a", metavar="REV_A", nargs="?", default="HEAD")
    parser.add_argument("b", metavar="REV_B", nargs="?", default=".")
    parser.add_argument("--collisions", type=int, default=200_000)
    parser.add_argument("--child", metavar="ADDRESSES", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(args.collisions, args.child, (args.a, args.b))
        return 0
    if shutil.which("valgrind") is None:
        print("count_kernel: valgrind is not installed (Debian: apt-get install valgrind)", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="coinwall-count-") as folder:
        profile = os.path.join(folder, "callgrind.out")
        addresses = os.path.join(folder, "entries.txt")
        env = dict(os.environ, COINWALL_CACHE_DIR=os.path.join(folder, "cache"))
        command = ["valgrind", "--tool=callgrind", "--dump-instr=yes", "--branch-sim=yes",
                   f"--callgrind-out-file={profile}", sys.executable, __file__, args.a, args.b, "--collisions",
                   str(args.collisions), "--child", addresses]
        run = subprocess.run(command, env=env, capture_output=True, text=True)
        if run.returncode != 0:
            print(run.stderr[-2000:], file=sys.stderr)
            return 1
        with open(addresses, encoding="utf-8") as lines:
            entries = {int(entry): name for entry, name in (row.strip().split(" ", 1) for row in lines)}
        own, calls = tally(profile, entries)
    n = args.collisions + 10
    print(f"per collision (coin eps = 99, H = 3, {args.collisions} collisions each, callgrind; mispredictions "
          "from its predictor model):")
    for name in entries.values():
        ir, bc, bcm, _, _ = own[name]
        libm = sum(inclusive for c, (_, inclusive) in calls[name].items() if "sin" in c or "cos" in c)
        sincos = sum(count for c, (count, _) in calls[name].items() if "sincos" in c)
        print(f"  {name}: own instructions {ir / n:.0f}, libm sin/cos {libm / n:.0f} "
              f"(sincos calls {sincos / n:.2f}), all {(ir + libm) / n:.0f}; "
              f"conditional branches {bc / n:.1f}, mispredicted {bcm / n:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
