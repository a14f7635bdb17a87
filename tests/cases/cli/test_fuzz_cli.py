"""Fuzz tests of the command line: bad arguments and malformed files for every subcommand.

The contract (``tests/cli_fuzz.py``): exit status 2 for input that is certainly bad, at most two
stderr lines, no traceback or raw warning, no file created or replaced; for input that may or may not
be valid (mutated files, odd walls), never a crash, a hang or a traceback.  Examples are derandomized so
the default run is reproducible and bounded (about a minute); ``tests/benchmarks/fuzz_cli.py`` runs a
larger, random sample and reports its counts (docs/cli-limits.md ("Fuzz tests")).
"""

from __future__ import annotations

import os

import pytest

hypothesis = pytest.importorskip("hypothesis")
from cli_fuzz import (  # noqa: E402
    BAD_NUMBERS,
    BAD_OUTPUTS,
    BAD_REQUESTS,
    BAD_WALLS,
    BASE_COMMANDS,
    FILE_COMMANDS,
    INPUT_AS_OUTPUT,
    LOOKALIKES,
    MUTATION_TARGETS,
    MUTATIONS,
    NUMERIC_FLAGS,
    ODD_WALLS,
    OUTPUT_COMMANDS,
    VALID_FILES,
    WALL_COMMANDS,
    Worker,
    check_clean,
    hostile_files,
    make_folder,
    mutate,
    mutation_request,
    plant_lookalikes,
    snapshot,
    valid_files,
    with_flag,
    with_output,
)
from cli_fuzz_classes import (  # noqa: E402
    LONG_REQUESTS,
    MEANINGLESS,
    NO_DATA,
    STORE_DAMAGES,
    WRONG_KIND,
    reference_store,
    store_equal,
    store_request,
)
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

FUZZ = settings(max_examples=60, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


@pytest.fixture(scope="module")
def worker():
    w = Worker(timeout=90)
    yield w
    w.close()


@pytest.fixture(scope="module")
def base(tmp_path_factory, worker):
    folder = tmp_path_factory.mktemp("fuzz-base")
    valid_files(folder, worker)
    return folder


@pytest.fixture(scope="module")
def hostile(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz-hostile")
    return folder, hostile_files(folder)


def run_checked(worker, base, tmp_path, argv, certainly_bad):
    folder = make_folder(base, tmp_path)
    before = snapshot(folder)
    result = worker.run(argv, folder)
    problems = check_clean(argv, result, before, snapshot(folder), certainly_bad=certainly_bad)
    assert not problems, "\n".join(problems)
    return result


@pytest.mark.parametrize("command", sorted(BASE_COMMANDS))
def test_base_commands_are_valid(worker, base, tmp_path, command):
    """The fuzzer breaks one piece of a valid command; each base command must itself succeed."""
    folder = make_folder(base, tmp_path)
    # a base command's first run compiles its kernels (a field kernel takes ~30 s of CPU, minutes on a loaded
    # machine with a cold cache): it gets ten minutes; every fuzzed variant after it keeps the worker's limit
    result = worker.run([command] + BASE_COMMANDS[command], folder, timeout=600)
    assert result["rc"] == 0, result
    if "-o" in BASE_COMMANDS[command]:
        assert os.path.getsize(os.path.join(folder, BASE_COMMANDS[command][-1])) > 0


_FLAGS = [(c, f, kind) for c, flags in sorted(NUMERIC_FLAGS.items()) for f, kind in sorted(flags.items())]


@FUZZ
@given(choice=st.sampled_from(_FLAGS), data=st.data(), joined=st.booleans())
def test_bad_numbers_are_refused(worker, base, tmp_path, choice, data, joined):
    command, flag, kind = choice
    value = data.draw(st.sampled_from(BAD_NUMBERS[kind]), label="value")
    argv = [command] + with_flag(BASE_COMMANDS[command], flag, value, joined)
    run_checked(worker, base, tmp_path, argv, certainly_bad=True)


@FUZZ
@given(command=st.sampled_from(WALL_COMMANDS), wall=st.sampled_from(BAD_WALLS))
def test_bad_walls_are_refused(worker, base, tmp_path, command, wall):
    argv = [command, wall] + BASE_COMMANDS[command][1:]
    run_checked(worker, base, tmp_path, argv, certainly_bad=True)


@pytest.mark.parametrize("argv", BAD_REQUESTS, ids=lambda a: " ".join(a)[:60])
def test_bad_requests_are_refused(worker, base, tmp_path, argv):
    """Densities with no finite mass, bodies whose energies leave floating point, quantum solves past the time
    bound, a no-break space in a number: one line, exit 2, nothing written."""
    run_checked(worker, base, tmp_path, argv, certainly_bad=True)


@pytest.mark.parametrize("command", sorted(FILE_COMMANDS))
def test_hostile_files_are_refused(worker, base, hostile, tmp_path, command):
    """Every certainly-bad file (empty, binary, words, NaN, nested 10^5 deep, entity bombs, a FIFO, a folder,
    a missing file, ...) given to every subcommand that reads files: refused, one line, nothing written."""
    folder, files = hostile
    failures = []
    for name in sorted(files):
        argv = [command, os.path.join(folder, name)] + BASE_COMMANDS[command][1:]
        work = make_folder(base, tmp_path)
        before = snapshot(work)
        result = worker.run(argv, work)
        failures += check_clean(argv, result, before, snapshot(work), certainly_bad=True)
    assert not failures, "\n".join(failures)


@FUZZ
@given(command=st.sampled_from(WALL_COMMANDS), wall=st.one_of(st.sampled_from(ODD_WALLS),
       st.lists(st.sampled_from(list("t0123456789.+-*/^()e ,") + ["cos", "sin", "sqrt", "log", "pi", "abs", "exp",
                                                                  "tan", "**"]), max_size=30).map("".join)))
def test_odd_walls_never_crash(worker, base, tmp_path, command, wall):
    argv = [command, wall] + BASE_COMMANDS[command][1:]
    run_checked(worker, base, tmp_path, argv, certainly_bad=False)


@FUZZ
@given(target=st.sampled_from(MUTATION_TARGETS), how=st.sampled_from(MUTATIONS), where=st.floats(0, 1),
       junk=st.sampled_from([b"nan", b"-1e308", b"\x00", b"<g>", b"0\nEOF\n", b"{", b",", b"inf", b"\xff\xfe",
                             b"1e400", b'"x"', b"\n\n\n", b"-"]))
def test_mutated_files_never_crash(worker, base, tmp_path, target, how, where, junk):
    """A valid input broken in one place may still be valid; it must never crash, hang or leave a file."""
    argv, source = mutation_request(target, "broken")
    assert source in VALID_FILES
    with open(os.path.join(base, source), "rb") as fh:
        data = mutate(fh.read(), how, where, junk)
    folder = make_folder(base, tmp_path)
    with open(os.path.join(folder, argv[1]), "wb") as fh:
        fh.write(data)
    before = snapshot(folder)
    result = worker.run(argv, folder)
    problems = check_clean(argv, result, before, snapshot(folder), certainly_bad=False)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("command", OUTPUT_COMMANDS)
def test_output_names_the_filesystem_cannot_hold_are_refused(worker, base, tmp_path, command):
    """`-o d/d/…/x` (thousands of levels) or a 300-byte name: one line, exit 2, no folder made."""
    failures = []
    for name in BAD_OUTPUTS:
        argv = [command] + with_output(BASE_COMMANDS[command], name)
        work = make_folder(base, tmp_path)
        before = snapshot(work)
        failures += check_clean(argv, worker.run(argv, work), before, snapshot(work), certainly_bad=True)
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("argv", INPUT_AS_OUTPUT, ids=" ".join)
def test_an_input_is_never_an_output(worker, base, tmp_path, argv):
    folder = make_folder(base, tmp_path)
    os.link(os.path.join(folder, "samples.csv"), os.path.join(folder, "linked.csv"))
    before = snapshot(folder)
    result = worker.run(argv, folder)
    problems = check_clean(argv, result, before, snapshot(folder), certainly_bad=True)
    assert not problems and "input file" in result["stderr"], "\n".join(problems) or result["stderr"]


@pytest.mark.parametrize("command", OUTPUT_COMMANDS)
def test_users_files_that_look_like_old_temporaries_survive(worker, base, tmp_path, command):
    """A user's `.coinwall-settings.json` (two days old) used to be swept as a stale temporary by the next write."""
    folder = make_folder(base, tmp_path)
    plant_lookalikes(folder)
    before = snapshot(folder)
    result = worker.run([command] + BASE_COMMANDS[command], folder)
    assert result["rc"] == 0, result
    after = snapshot(folder)
    assert {name: after.get(name) for name in LOOKALIKES} == {name: before[name] for name in LOOKALIKES}


# ------------------------------------------------------------------------------------------- round three
@pytest.mark.slow  # (each case has its own test in test_statistics_and_bounds.py, in the default run)
@pytest.mark.parametrize("argv", NO_DATA, ids=" ".join)
def test_statistics_from_no_data_are_never_numbers(worker, base, tmp_path, argv):
    """A share from no toss, a mean of one flight, a fit of nothing: refused or marked "not enough data", never
    "0.0 ± 0.0" or NaN (:func:`cli_fuzz.check_clean` looks for both)."""
    result = run_checked(worker, base, tmp_path, argv, certainly_bad=False)
    if result["rc"] == 2:
        assert "not enough data" in result["stderr"] or "--" in result["stderr"], result["stderr"]


@pytest.mark.parametrize("argv", WRONG_KIND + LONG_REQUESTS + MEANINGLESS, ids=" ".join)
def test_wrong_kinds_long_runs_and_meaningless_options_are_refused(worker, base, tmp_path, argv):
    run_checked(worker, base, tmp_path, argv, certainly_bad=True)


@pytest.fixture(scope="module")
def store_base(base, worker):
    pytest.importorskip("zarr")
    reference_store(base, worker)
    return base


@pytest.mark.parametrize("how", ["swap-dims", "command-attr", "extra-array", "devzero-chunk"])
def test_a_damaged_store_is_refused_or_resumed_to_the_same_arrays(worker, store_base, tmp_path, how):
    _store_case(worker, store_base, tmp_path, how)


@pytest.mark.slow
@pytest.mark.parametrize("how", sorted(STORE_DAMAGES))
def test_every_store_damage(worker, store_base, tmp_path, how):
    _store_case(worker, store_base, tmp_path, how)


def _store_case(worker, base, tmp_path, how):
    import random

    folder = make_folder(base, tmp_path)
    argv = store_request(base, folder, how, random.Random(how))
    before = snapshot(folder)
    result = worker.run(argv, folder)
    problems = check_clean(argv, result, before, snapshot(folder), certainly_bad=STORE_DAMAGES[how])
    assert not problems, "\n".join(problems)
    if not STORE_DAMAGES[how]:
        assert result["rc"] == 0, result
        assert store_equal(os.path.join(folder, "s.zarr"), os.path.join(base, "ref.zarr"))
