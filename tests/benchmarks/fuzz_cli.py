"""The larger command-line fuzz run, outside the default test run.

Draws random inputs from the same tables as ``tests/cases/cli/test_fuzz_cli.py`` (bad numbers for every numeric
flag, bad and odd walls, random expression text, hostile files, valid files broken in one place, whole requests
that must be refused) and
checks each against the same contract (``tests/cli_fuzz.py``).  Prints, per category, the inputs tried
and those handled cleanly, and lists every failure; the counts of the last run are in
docs/cli-limits.md ("Fuzz tests").

Run::

    python tests/benchmarks/fuzz_cli.py --inputs 3000 --seed 1

Exit status 0 when every input was handled cleanly, 1 otherwise.
"""

from __future__ import annotations

import argparse
import collections
import os
import random
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from cli_fuzz import (  # noqa: E402
    BAD_NUMBERS,
    BAD_OUTPUTS,
    BAD_REQUESTS,
    BAD_WALLS,
    BASE_COMMANDS,
    FILE_COMMANDS,
    INPUT_AS_OUTPUT,
    MUTATION_TARGETS,
    MUTATIONS,
    NUMERIC_FLAGS,
    ODD_WALLS,
    OUTPUT_COMMANDS,
    WALL_COMMANDS,
    Worker,
    check_clean,
    hostile_files,
    make_folder,
    mutate,
    mutation_request,
    snapshot,
    valid_files,
    with_flag,
    with_output,
)
from cli_fuzz_classes import (  # noqa: E402
    ENCODINGS,
    LONG_REQUESTS,
    MEANINGLESS,
    NO_DATA,
    ODD_NAMES,
    OTHERS,
    STORE_DAMAGES,
    WRONG_KIND,
    others_check,
    others_files,
    random_no_data,
    random_wrong_kind,
    reference_store,
    store_equal,
    store_request,
)

_TOKENS = list("t0123456789.+-*/^()e ,") + ["cos", "sin", "sqrt", "log", "pi", "abs", "exp", "tan", "**"]
_JUNK = [b"nan", b"-1e308", b"\x00", b"<g>", b"0\nEOF\n", b"{", b",", b"inf", b"\xff\xfe", b"1e400", b'"x"',
         b"\n\n\n", b"-", b"[[[[", b"</svg>", b"0\nSECTION\n", b"&a;", b"1e-320"]


#: the classes of inputs drawn (each equally often)
CATEGORIES = ["number", "wall", "odd-wall", "text-wall", "hostile-file", "mutated-file", "output-name", "input-output",
              "request", "encoding", "no-data", "wrong-kind", "long", "meaningless", "store"]
#: with --others: the round's classes fixed in other parts of the code (each row names its area)
OTHER_CATEGORY = "others"


OTHERS_ON = False


def draw(rng: random.Random, base: str, hostile: tuple):
    """One random request: (category, argv, certainly_bad, files to write into the working folder); for the
    "encoding" class the terminal is the last element of the category (``encoding:ascii``), for "store" the
    damage (``store:fifo-chunk``)."""
    kind = rng.choice(CATEGORIES + ([OTHER_CATEGORY] if OTHERS_ON else []))
    if kind == "request":
        return kind, list(rng.choice(BAD_REQUESTS)), True, {}
    if kind == OTHER_CATEGORY:
        area, argv, bad = rng.choice(OTHERS)
        return f"others:{area}", list(argv), bad, {}
    if kind == "encoding":
        terminal = rng.choice(sorted(ENCODINGS))
        command = rng.choice(sorted(BASE_COMMANDS))
        argv = [command] + BASE_COMMANDS[command]
        if command == "scan":
            argv = [a for a in argv if a not in ("--workers", "1")] + ["--scheduler", "synchronous"]
        if "-o" in argv and rng.random() < 0.5:
            argv = [command] + with_output(argv[1:], rng.choice(ODD_NAMES))
        return f"encoding:{terminal}", argv, False, {}
    if kind == "no-data":
        return kind, list(rng.choice(NO_DATA)) if rng.random() < 0.3 else random_no_data(rng), False, {}
    if kind == "wrong-kind" and rng.random() < 0.7:
        return "wrong-kind:random", None, True, {}
    if kind in ("wrong-kind", "long", "meaningless"):
        table = {"wrong-kind": WRONG_KIND, "long": LONG_REQUESTS, "meaningless": MEANINGLESS}[kind]
        return kind, list(rng.choice(table)), True, {}
    if kind == "store":
        how = rng.choice(sorted(STORE_DAMAGES))
        return f"store:{how}", None, STORE_DAMAGES[how], {}
    if kind == "output-name":
        command = rng.choice(OUTPUT_COMMANDS)
        return kind, [command] + with_output(BASE_COMMANDS[command], rng.choice(BAD_OUTPUTS)), True, {}
    if kind == "input-output":
        argv = rng.choice(INPUT_AS_OUTPUT)
        if "linked.csv" in argv:
            argv = [a if a != "linked.csv" else "samples.csv" for a in argv]
        return kind, list(argv), True, {}
    if kind == "number":
        command = rng.choice(sorted(NUMERIC_FLAGS.keys() - {"critical"}))
        flag, value_kind = rng.choice(sorted(NUMERIC_FLAGS[command].items()))
        value = rng.choice(BAD_NUMBERS[value_kind])
        argv = with_flag(BASE_COMMANDS[command], flag, value, joined=rng.random() < 0.5)
        return kind, [command] + argv, True, {}
    if kind in ("wall", "odd-wall", "text-wall"):
        command = rng.choice(list(WALL_COMMANDS))
        if kind == "wall":
            wall = rng.choice(BAD_WALLS)
        elif kind == "odd-wall":
            wall = rng.choice(ODD_WALLS)
        else:
            wall = "".join(rng.choice(_TOKENS) for _ in range(rng.randint(0, 30)))
        return kind, [command, wall] + BASE_COMMANDS[command][1:], kind == "wall", {}
    if kind == "hostile-file":
        folder, files = hostile
        command = rng.choice(sorted(FILE_COMMANDS))
        name = rng.choice(sorted(files))
        return kind, [command, os.path.join(folder, name)] + BASE_COMMANDS[command][1:], True, {}
    argv, source = mutation_request(rng.choice(MUTATION_TARGETS), "broken")
    with open(os.path.join(base, source), "rb") as fh:
        data = fh.read()
    for _ in range(rng.randint(1, 3)):
        data = mutate(data, rng.choice(MUTATIONS), rng.random(), rng.choice(_JUNK))
    return kind, argv, False, {argv[1]: data}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--inputs", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--smoke", action="store_true", help="5 inputs: checks the script")
    parser.add_argument("--others", action="store_true",
                        help="also draw the round's classes fixed in other parts of the code (the 'others:AREA' rows)")
    args = parser.parse_args(argv)
    global OTHERS_ON
    OTHERS_ON = args.others
    if args.smoke:
        args.inputs = 5
    rng = random.Random(args.seed)
    tried, clean = collections.Counter(), collections.Counter()
    failures = []
    start = time.perf_counter()
    worker = Worker(timeout=args.timeout)
    terminals = {}  # a worker per terminal of the "encoding" class, started when first drawn
    with tempfile.TemporaryDirectory() as tmp:
        base = os.path.join(tmp, "base")
        hostile_dir = os.path.join(tmp, "hostile")
        os.mkdir(base)
        os.mkdir(hostile_dir)
        valid_files(base, worker)
        reference_store(base, worker)
        hostile = (hostile_dir, hostile_files(hostile_dir))
        for k in range(args.inputs):
            kind, request, bad, files = draw(rng, base, hostile)
            folder = make_folder(base, tmp)
            for name, data in files.items():
                with open(os.path.join(folder, name), "wb") as fh:
                    fh.write(data)
            if kind.startswith("store:"):
                request = store_request(base, folder, kind.split(":", 1)[1], rng)
            if kind == "wrong-kind:random":
                request = random_wrong_kind(rng, folder)
            if kind.startswith("others:"):
                others_files(folder)
            before = snapshot(folder)
            runner = worker
            if kind.startswith("encoding:"):
                terminal = kind.split(":", 1)[1]
                runner = terminals.setdefault(terminal, Worker(timeout=args.timeout, env=ENCODINGS[terminal]))
            result = runner.run(request, folder)
            problems = check_clean(request, result, before, snapshot(folder), certainly_bad=bad)
            if kind.startswith("encoding:") and terminal != "latin-1" and result["rc"] in (0, 1) and \
                    any(ord(c) > 127 for c in result["stdout"] + result["stderr"]):
                problems.append(f"coinwall {request}: printed a character the {terminal} terminal cannot show")
            if kind.startswith("store:") and result["rc"] == 0 and not bad and \
                    not store_equal(os.path.join(folder, "s.zarr"), os.path.join(base, "ref.zarr")):
                problems.append(f"{kind}: resumed to arrays that differ from the undamaged store's (silently wrong)")
            if kind.startswith("store:") and not bad and result["rc"] != 0:
                problems.append(f"{kind}: a repairable store was refused: {result['stderr'][-300:]!r}")
            if kind.startswith("others:"):
                problems += [f"coinwall {request}: {p}" for p in others_check(folder, request, result)]
            if kind == "no-data" and result["rc"] in (0, 1) and "0.0000 ± 0.0000" in result["stdout"]:
                problems.append(f"coinwall {request}: a share from no data printed as an answer")
            tried[kind] += 1
            shutil.rmtree(folder, ignore_errors=True)
            if problems:
                failures += problems
            else:
                clean[kind] += 1
            if (k + 1) % 100 == 0:
                print(f"{k + 1} inputs, {len(failures)} problems, {time.perf_counter() - start:.0f} s", file=sys.stderr)
    worker.close()
    for runner in terminals.values():
        runner.close()
    print(f"seed {args.seed}, {sum(tried.values())} inputs in {time.perf_counter() - start:.0f} s")
    print("| category | tried | handled cleanly |\n|---|---:|---:|")
    for kind in sorted(tried):
        print(f"| {kind} | {tried[kind]} | {clean[kind]} |")
    print(f"| all | {sum(tried.values())} | {sum(clean.values())} |")
    for problem in failures:
        print(problem)
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
