"""The paper-check registry (cases/paper): every claim is complete, its thresholds name numbers its check
measures, and the fast run's verdicts are the recorded ones; the report and figures it writes."""

import math
import os

import pytest

from coinwall.cases.paper import CLAIMS, REGISTRY, Report, Row, run_verify
from coinwall.cases.paper.checks import Measured
from coinwall.cases.paper.claims import Above, Below, Claim, Equals, Within, judge, render
from coinwall.cases.paper.report import VERDICTS
from coinwall.forward.errors import CoinwallError

#: The claims as recorded when the report was written (a claim that disappears from the registry fails here).
RECORDED = {
    "stick-specular": "yes", "eq3-typo": "partly", "general-specular": "yes", "eq18": "yes", "eq16-17": "yes",
    "limits": "yes", "eq19": "yes", "eq22": "yes", "eq23-sign": "partly", "bc": "yes", "bc-extremum": "partly",
    "K0": "yes", "eq27": "yes", "case1": "yes", "case2": "yes", "case3-corner": "yes", "case3-R0": "no",
    "case3-thetac": "partly", "case3-deficit": "yes", "case3-positive": "yes",
    "case1-realizable": "no", "case2-realizable": "no", "large-b0": "yes", "extrema": "yes",
    "four-extrema": "no", "theta-half": "no", "equivalence-simulated": "yes",
    "external-fields": "yes", "casino": "partly", "quantum-tunnelling": "yes", "three-d-billiard": "partly",
    "caught-coin-flips": "yes", "design-drop-rectangle": "yes", "design-drop-cylinder": "yes",
    "design-flip-cylinder": "yes", "design-bounce-nickel": "partly",
    "design-bounce-nickel-friction": "partly",
}
CONDITIONS = (Below, Above, Within, Equals)


@pytest.fixture(scope="module")
def fast_run(tmp_path_factory):
    """One fast run of verify, the one docs/cli.md shows (``coinwall verify --fast --out report --figure-format svg``),
    run as tests/test_docs.py runs the documentation's commands (``main(argv)``) in a new folder: the report, the
    numbers every claim's check measured in it, the folder it wrote, and the command's exit status, documented output
    and output.  One run serves every test here and the documentation's example (tests/test_docs.py skips it)."""
    import contextlib
    import io

    from test_docs import ELSEWHERE, _blocks, _console_commands, _elsewhere

    from coinwall.cases.cli.main import main
    from coinwall.cases.paper import verify

    runner = ELSEWHERE["docs/cli.md", "verify"]
    (block,) = [text for lang, text, _ in _blocks("docs/cli.md") if _elsewhere("docs/cli.md", lang, text) == runner]
    ((argv, expected, status),) = _console_commands(block)
    measured, reports = {}, []
    real_measure, real_run = verify.measure, verify.run_verify

    def kept(*args, **kwargs):
        measured.update(real_measure(*args, **kwargs))
        return measured

    def run_kept(*args, **kwargs):
        reports.append(real_run(*args, **kwargs))
        return reports[-1]

    folder = tmp_path_factory.mktemp("verify")
    output = io.StringIO()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(verify, "measure", kept)
        patch.setattr(verify, "run_verify", run_kept)
        patch.chdir(folder)
        with contextlib.redirect_stdout(output), contextlib.redirect_stderr(output):
            code = main(argv)
    (report,) = reports
    out = folder / argv[argv.index("--out") + 1]
    return report, measured, out, (code, status, expected, output.getvalue())


@pytest.fixture(scope="module")
def fast_report(fast_run):
    return fast_run[0]


@pytest.fixture(scope="module")
def fast_measured(fast_run):
    assert fast_run[1], "verify measured nothing"
    return fast_run[1]


def test_registry_is_the_recorded_list():
    assert CLAIMS == tuple(RECORDED)
    assert {key: claim.expected for key, claim in REGISTRY.items()} == RECORDED


@pytest.mark.parametrize("key", CLAIMS)
def test_every_claim_is_complete(key):
    """Key, source, the paper's statement, a check, named thresholds and an expected verdict."""
    claim = REGISTRY[key]
    assert isinstance(claim, Claim) and claim.key == key
    assert claim.claim.strip() and claim.source.strip() and claim.paper.strip() and claim.computed.strip()
    assert callable(claim.check)
    assert claim.thresholds, f"{key}: no threshold"
    for conditions in (claim.thresholds, claim.partly or {}):
        for name, condition in conditions.items():
            assert isinstance(name, str) and isinstance(condition, CONDITIONS)
    assert claim.expected in VERDICTS


@pytest.mark.parametrize("key", CLAIMS)
def test_thresholds_name_measured_numbers(key, fast_measured):
    """Every condition (also the ``partly`` ones a ``yes`` never reaches) refers to something the check
    measures, and every template fills from the check's numbers and the claim's inputs."""
    claim, measured = REGISTRY[key], fast_measured[key]
    assert set(claim.thresholds) | set(claim.partly or {}) <= set(measured)
    for template in (claim.paper, claim.computed, claim.detail):
        render(template, claim, measured)


def test_fast_run_keeps_every_verdict(fast_report):
    """Every claim present, every verdict as recorded (a row that agreed and starts to disagree, or the
    reverse, fails here)."""
    assert tuple(r.key for r in fast_report.rows) == CLAIMS
    assert {r.key: r.agreement for r in fast_report.rows} == {key: REGISTRY[key].expected for key in CLAIMS}
    assert all(r.unchanged for r in fast_report.rows)
    assert fast_report.ok
    assert fast_report.counts() == {"yes": 24, "partly": 8, "no": 5}


def test_report_to_dict_and_repr(fast_report):
    doc = fast_report.to_dict()
    assert doc["ok"] is True and doc["fast"] is True and doc["figures"] == list(fast_report.figures)
    assert [row["key"] for row in doc["rows"]] == list(CLAIMS)
    assert set(doc["rows"][0]) == {"key", "claim", "source", "paper", "computed", "agreement", "expected", "detail"}
    assert "37 claims" in repr(fast_report) and "every verdict as recorded" in repr(fast_report)
    assert repr(Report(rows=None)) == "Report(<unprintable>)"


def test_changed_verdict_is_flagged():
    row = Row("k", "a claim", "eq. 1", "p", "c", "no", "yes")
    report = Report((row,))
    assert not report.ok and "<-- was 'yes'" in report.table() and "SOME VERDICTS CHANGED" in report.table()


def test_conditions_and_judge():
    assert Below(1.0).holds(0.5) and not Below(1.0).holds(1.0)
    assert Above(1.0).holds(2) and not Above(1.0).holds(1.0)
    assert Within(2.0, 0.05).holds(2.04) and not Within(2.0, 0.05).holds(1.9)
    assert Equals(2).holds(2) and not Equals(False).holds(True)
    claim = Claim("k", "c", "s", "p", lambda resolution: {}, thresholds={"x": Below(1.0)}, expected="yes")
    assert judge(claim, {"x": 0.5}) == "yes" and judge(claim, {"x": 2.0}) == "no"
    partly = Claim("k", "c", "s", "p", lambda resolution: {}, thresholds={"x": Below(1.0)},
                   partly={"y": Below(1.0)}, expected="partly")
    assert judge(partly, {"x": 2.0, "y": 0.5}) == "partly" and judge(partly, {"x": 2.0, "y": 2.0}) == "no"
    estimate = Claim("k", "c", "s", "p", lambda resolution: {}, thresholds={"x": Below(1.0)}, partly={})
    assert judge(estimate, {"x": 2.0}) == "partly"


def test_measured_prints_zero_at_its_tolerance():
    """A minimiser's 1.7e-8 for an exact 0 prints as 0 (never -0); a value above its tolerance keeps its format."""
    assert f"{Measured(1.69e-8, 1e-7):.3g}" == "0" and f"{Measured(-1e-9, 1e-7):.3g}" == "0"
    assert f"{Measured(0.25, 1e-7):.3g}" == "0.25"
    assert math.isclose(float(Measured(0.25, 1e-7)), 0.25)


def test_run_verify_names_its_arguments(tmp_path):
    with pytest.raises(CoinwallError, match="`fast`"):
        run_verify(fast="yes")
    with pytest.raises(CoinwallError, match="`figure_format`"):
        run_verify(fast=True, figure_format=".jpg")
    with pytest.raises(CoinwallError, match="`out`"):
        run_verify(fast=True, out=3)
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(CoinwallError, match="`out`"):
        run_verify(fast=True, out=str(blocker / "sub"))


def test_the_documented_command_prints_what_the_documentation_shows(fast_run):
    """docs/cli.md's ``coinwall verify`` example: its exit status and its output as documented (tests/test_docs.py's
    reading of console blocks)."""
    from test_docs import _match_output

    code, status, expected, output = fast_run[3]
    assert code == status, output
    problem = _match_output(expected, output)
    assert problem is None, f"{problem}\nactual output:\n{output}"


def test_run_verify_creates_the_folder_and_writes_vector_figures(fast_run):
    report, _, out = fast_run[:3]
    assert report.ok and report.markdown_path == os.path.join(out.name, "paper-check.md")
    text = (out / "paper-check.md").read_text(encoding="utf-8")
    assert "![fig4_critical.svg](figures/fig4_critical.svg)" in text
    assert "| 27 | Rigid body and billiard" in text
    for name in ("fig4_critical.svg", "appendix_gallery.svg"):
        assert (out / "figures" / name).read_bytes().startswith(b"<?xml")
    assert not [p.name for p in out.rglob(".coinwall-*")]


def test_markdown_cells_keep_their_columns_and_the_command_names_the_folder():
    """A `|` inside a cell (|Δv|, |P − ½|) is escaped, so every table row keeps its six columns; the page
    names the folder it was written to, not always `docs`."""
    from coinwall.cases.paper.report import Report, Row

    row = Row("k", "a claim", "eq. 1", "|x| < 1", "max |Δ| = 1e-15", "yes", "yes")
    page = Report((row,), (), "out/notes/paper-check.md", 1.0, True).markdown()
    line = next(s for s in page.splitlines() if s.startswith("| 1 |"))
    assert len(line.replace("\\|", "").split("|")) == 8  # six cells between seven bars
    assert "`coinwall verify --out out/notes --fast`" in page


def test_the_table_prints_every_claim_whole_and_wraps(fast_report):
    """No claim is cut (it was cut at 46 characters); every line fits the width; each row's result follows it."""
    for width in (80, 100):
        table = fast_report.table(width=width)
        assert all(len(line) <= width for line in table.splitlines()), width
        flat = " ".join(table.split())
        for i, row in enumerate(fast_report.rows, 1):
            assert f"{i}. " + " ".join(row.claim.split()) in flat
            assert " ".join(row.computed.split()) in flat
    long = Row("k", "a claim of sixty characters or more, which the old table cut at 46", "s", "p",
               "a computed text " * 12, "yes", "yes")
    text = Report((long,)).table(width=60)
    assert "cut at 46" in text and all(len(line) <= 60 for line in text.splitlines())


def test_the_page_is_the_same_bytes_whatever_the_run_took(fast_report):
    """paper-check.md is tracked: regenerating it must not change it when nothing but the time changed."""
    import dataclasses

    other = dataclasses.replace(fast_report, seconds=fast_report.seconds + 1234.5, markdown_path="docs/paper-check.md")
    same = dataclasses.replace(fast_report, markdown_path="docs/paper-check.md")
    assert other.markdown() == same.markdown()
    assert "1234" not in other.markdown() and " s)" not in other.markdown().splitlines()[2]


def test_three_verdicts_say_what_was_computed(fast_measured):
    """The 3-D conjecture is about rigid bodies in general: shown for bodies of revolution (the axis torque of a
    floor's impulse vanishes), not for a triaxial one (it does not). The casino rule is judged on every e, with
    fairness at the last bounces, not one: at e = 0.3 the coin settles with more bias than it was caught with.
    The caught coin is compared with tossers its ψ was not fitted to."""
    three = fast_measured["three-d-billiard"]
    assert three["revolution_axis_torque"] < 1e-12 < 0.1 < three["general_axis_torque"]
    casino = fast_measured["casino"]
    assert set(casino["per_e"]) == {0.3, 0.6, 0.9}
    bias, stderr, fair, settled = casino["per_e"][0.3]
    assert fair is None and abs(bias) > abs(casino["caught_bias"]) + 4 * stderr and settled > 0.5
    assert casino["per_e"][0.9][2] is not None and casino["per_e"][0.9][2] <= casino["bounces"] - 2
    caught = fast_measured["caught-coin-flips"]
    assert caught["n_a"] + caught["n_b"] == 350_757 and abs(caught["psi_a"] - caught["psi_b"]) > 1.0
    assert caught["psi_spread_low"] < caught["psi_low"] < caught["psi"] < caught["psi_high"] < caught["psi_spread_high"]
