"""``coinwall fit``: the convex body whose wall is nearest to measured samples, in least squares."""

from __future__ import annotations

import json
import math

from .common import add_command, number

__all__ = ["register"]

_DESCRIPTION = """\
Fit a convex body to measured wall samples (noisy, rounded, from a scan): among convex polygons
whose edges have the measured directions as normals, the one whose wall b0 + b is nearest to the
samples in least squares, subject to the radius of curvature b0 + b + b'' >= 0 as a measure (vertex
windows and corners allowed, nothing smoothed; Prince & Willsky's estimator, whose convergence
Gardner, Kiderlen & Milanfar proved, Ann. Statist. 34, 2006).  Prints the rms and largest residual,
the regime and the corners of the fitted body.  -o body.json/.svg/.dxf/... writes the body as
`coinwall solve` does; -o wall.csv or wall.json (with "wall" in its name, or --wall-out) writes the
fitted wall, reusable as a WALL.  At most 2,000 distinct directions."""

_EXAMPLE = """\
coinwall fit scan.csv --b0 0 -o body.json -o fitted-wall.csv --json"""


def register(subparsers):
    """Add the ``fit`` subcommand."""
    parser = add_command(subparsers, "fit", help="least-squares convex fit of measured (noisy) wall samples",
                         description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("samples", help="wall samples: .csv (theta,b; theta_deg for degrees) or .json {theta, b}")
    parser.add_argument("--b0", type=number, default=0.0, help="offset added to the samples (default 0)")
    parser.add_argument("--degrees", action="store_true", help="the angles of the sample file are in degrees")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="the body (.json .svg .dxf .csv .png .pdf, as solve) or, for a file whose name "
                             "contains 'wall', the fitted wall (.csv theta,b or .json {theta, b}) (repeatable)")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
    parser.set_defaults(run=run)


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
    from coinwall.inverse.export import check_outputs, export_body, exporters
    from coinwall.inverse.fit import fit_convex

    from .common import check_body_finite, describe_written, written_lines

    wall_outputs = [p for p in args.output if "wall" in p.rsplit("/", 1)[-1].lower()]
    body_outputs = [p for p in args.output if p not in wall_outputs]
    for path in wall_outputs:
        if not path.lower().endswith((".csv", ".json")):
            raise OutputError(f"output {path!r}: a fitted wall is written as .csv or .json")
    check_paths(wall_outputs, (".csv", ".json"))
    check_paths(body_outputs, sorted(exporters()))
    check_outputs(body_outputs)
    if not args.samples.lower().endswith((".csv", ".json")):
        raise OutputError(f"samples {args.samples!r}: give a .csv (theta,b) or .json ({{theta, b}}) file")
    wall = load_wall_file(args.samples, degrees=args.degrees, noisy=True)
    if wall.samples is None:
        raise OutputError(f"samples {args.samples!r}: a Fourier wall file has no samples to fit")
    theta, values = wall.samples
    fit = fit_convex(theta, values, args.b0)
    body = fit.body
    if args.output:
        refuse_non_finite("the fitted wall", b=fit.fitted)
        check_body_finite(body, "the fitted body")
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
        print(f"fit        rms residual {fit.rms_residual:.4g}, largest {fit.max_residual:.4g} (units of the wall)")
        b_c = f"{body.b_c:.6g}" if math.isfinite(body.b_c) else "inf"
        print(f"body       regime {body.regime} (fitted b_c = {b_c}), {len(body.corners)} corners, "
              f"area {body.area:.6g}, perimeter {body.perimeter:.6g}")
        print(f"outline    convex: {'yes' if body.convex else 'NO'}, simple (valid): {'yes' if body.valid else 'NO'}")
        for line in written_lines(written, replaced):
            print(line)
        if result is not None:
            for line in describe_written(result, replaced):
                print(line)
    for warning in body.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return status
