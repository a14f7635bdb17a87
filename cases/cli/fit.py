"""``coinwall fit``: the convex body whose wall is nearest to measured samples, in least squares."""

from __future__ import annotations

import json
import math

from .common import add_command, number, sample_arguments

__all__ = ["register"]

_DESCRIPTION = """\
Fit a convex body to measured wall samples (noisy, rounded, from a scan).  First the least-squares
projection: among convex polygons whose edges have the measured directions as normals, the one whose
wall b0 + b is nearest to the samples, subject to b0 + b + b'' >= 0 as a measure (Prince & Willsky's
estimator; Gardner, Kiderlen & Milanfar, Ann. Statist. 34, 2006).  It has a vertex window wherever the
noise dips, so the corners are then tested: with the noise sigma (--b-sd or a column b_sd, or estimated from
the residuals), neighbouring vertex windows are merged while the edge between them is not supported, and a
window is a corner only when rounding it off (radius of curvature half that next to it) raises chi^2
by more than chance allows (Bonferroni over the candidates).  The body returned has exactly those
corners and a positive radius of curvature elsewhere, within chi^2 <= N + 3 sqrt(2N) of the samples.
b_c is an estimate with a 95 % confidence interval, assuming b + b'' differs from the harmonics the data
resolve by at most a tail bound (--tail-bound, default from the decay of the resolved harmonics).  The regime
is what the data say: corner (b0 below the interval), critical (a corner is supported), convex (b0 above the
interval, none supported or close) or undecided.  -o body.json/.svg/.dxf/... writes the body as
`coinwall solve` does; -o wall.csv or
wall.json (with "wall" in its name) writes the fitted wall, reusable as a WALL.  At most 2,000
distinct directions."""

_EXAMPLE = """\
coinwall fit scan.csv --b0 0 -o body.json -o fitted-wall.csv --json
coinwall fit scan.csv --b-sd 0.002"""


def register(subparsers):
    """Add the ``fit`` subcommand."""
    parser = add_command(subparsers, "fit", help="least-squares convex fit of measured (noisy) wall samples",
                         description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("samples", help="wall samples: .csv (theta,b; theta_deg for degrees) or .json {theta, b}")
    parser.add_argument("--b0", type=number, default=0.0, help="offset added to the samples (default 0)")
    sample_arguments(parser, halfwidths=False)
    parser.add_argument("--tail-bound", type=number, default=None, metavar="T",
                        help="the smoothness b_c's confidence interval assumes: b + b'' differs from the harmonics the "
                             "data resolve by at most T (default: from the decay of the resolved harmonics)")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="the body (.json .svg .dxf .csv .png .pdf, as solve) or, for a file whose name "
                             "contains 'wall', the fitted wall (.csv theta,b or .json {theta, b}) (repeatable)")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
    parser.set_defaults(run=run)


_REGIMES = {
    "corner": "b0 is below the confidence interval of b_c: no convex body has this wall (the body is the nearest one)",
    "critical": "the data demand a corner (rounding it off costs more than the noise allows)",
    "convex": "no corner is supported and no candidate comes close: the data allow a strictly convex body",
    "undecided": "no corner is supported, but b0 lies within the confidence interval of b_c or a candidate is "
                 "neither confirmed nor ruled out: the data allow both a strictly convex body and one with a corner",
}


def _vertex_windows(fit):
    import numpy as np

    from coinwall.inverse.discrete import discrete_curvature

    rho, _ = discrete_curvature(fit.theta, fit.b0 + fit.least_squares)
    zero = rho <= 1e-9 * max(1.0, float(np.max(np.abs(fit.least_squares)))) / np.min(np.diff(fit.theta)) ** 2
    return int(np.count_nonzero(zero & ~np.roll(zero, 1))) if not zero.all() else 1


def _wall_document(fit, path):
    import numpy as np

    if path.lower().endswith(".json"):
        doc = {"theta": fit.theta.tolist(), "b": fit.fitted.tolist(),
               "note": f"coinwall fit: least-squares convex fit at b0 = {fit.b0:g}"}
        return (json.dumps(doc, indent=1, allow_nan=False) + "\n").encode()
    rows = "\n".join(f"{t!r},{b!r}" for t, b in zip(fit.theta.tolist(), np.asarray(fit.fitted).tolist()))
    return f"# coinwall fit: least-squares convex fit at b0 = {fit.b0:g}\ntheta,b\n{rows}\n".encode()


def run(args):
    """Fit, write, print."""
    import sys

    from coinwall.forward.errors import OutputError
    from coinwall.forward.formats.output import check_paths, existing_files, refuse_non_finite, transaction, write_all
    from coinwall.forward.formats.wallfile import load_wall_file
    from coinwall.inverse.export import check_outputs, export_body
    from coinwall.inverse.fit import fit_convex

    from .common import describe_written, wall_options, written_lines

    wall_outputs = [p for p in args.output if "wall" in p.rsplit("/", 1)[-1].lower()]
    body_outputs = [p for p in args.output if p not in wall_outputs]
    for path in wall_outputs:
        if not path.lower().endswith((".csv", ".json")):
            raise OutputError(f"output {path!r}: a fitted wall is written as .csv or .json")
    check_paths(wall_outputs)
    check_outputs(body_outputs)
    if not args.samples.lower().endswith((".csv", ".json")):
        raise OutputError(f"samples {args.samples!r}: give a .csv (theta,b) or .json ({{theta, b}}) file")
    options = wall_options(args)
    wall = load_wall_file(args.samples, degrees=options["degrees"], b_sd=options["b_sd"], theta_sd=options["theta_sd"],
                          noisy=True)
    if wall.samples is None:
        raise OutputError(f"samples {args.samples!r}: a Fourier wall file has no samples to fit")
    theta, values = wall.samples
    sd = wall.sample_data.sd
    fit = fit_convex(theta, values, args.b0, sd=sd, tail=args.tail_bound)
    body = fit.body
    if args.output:
        refuse_non_finite("the fitted wall", b=fit.fitted)
    replaced = existing_files(args.output)
    with transaction():  # the wall files and the body files are one all-or-nothing commit
        written = write_all({p: _wall_document(fit, p) for p in wall_outputs}) if wall_outputs else []
        result = export_body(body, body_outputs) if body_outputs else None
    status = 1 if body.warnings else 0
    if args.json:
        doc = fit.to_dict()
        doc["outputs"] = list(args.output)
        print(json.dumps(doc, indent=1, allow_nan=False))
    else:
        print(f"samples    {args.samples}: {int(fit.counts.sum())} samples at {fit.theta.size} directions")
        source = "given" if fit.sigma_given else "estimated from the residuals"
        print(f"noise      sigma {fit.sigma:.4g} ({source})")
        print(f"fit        rms residual {fit.rms_residual:.4g}, largest {fit.max_residual:.4g} (units of the wall); "
              f"chi^2 {fit.chi2:.5g} (bound {fit.chi2_bound:.5g}); least squares alone: "
              f"{_vertex_windows(fit)} vertex windows")
        found = fit.critical
        print(f"b_c        {found.estimate:.6g} (estimate), {found.level:.0%} confidence interval [{found.lower:.6g}, "
              f"{found.upper:.6g}], assuming {found.assumption} (--tail-bound)")
        print(f"regime     {fit.regime}: {_REGIMES[fit.regime]}")
        print(f"corners    {fit.corners} supported of {len(fit.tests)} candidates "
              f"(chi^2 growth when rounded off > {fit.threshold:.3g})")
        for test in fit.tests:
            if test.verdict != "round":
                print(f"           {test.verdict:9s} window {math.degrees(test.window[0]) % 360:7.2f} deg + "
                      f"{math.degrees(test.window[1] - test.window[0]):6.2f} deg, chi^2 growth {test.statistic:.4g}")
        print(f"body       {len(body.corners)} corners, area {body.area:.6g}, perimeter {body.perimeter:.6g}")
        for note in fit.notes:
            print(f"note       {note}")
        print(f"outline    convex: {'yes' if body.convex else 'NO'}, simple (valid): {'yes' if body.valid else 'NO'}")
        for line in written_lines(written, replaced):
            print(line)
        if result is not None:
            for line in describe_written(result, replaced):
                print(line)
    for warning in body.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return status
