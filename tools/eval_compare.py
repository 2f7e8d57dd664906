#!/usr/bin/env python3
"""Compare two evaluation JSONs (`motion-stylizer eval --json`) metric by metric, as the compact
weights' gate needs it (issue 17): every `make eval` metric of the candidate within TOL of the
reference's, relative, and absolute for accuracies and the style shift. Prints a Markdown table of
the changes (bold `!` beyond the tolerance) and exits 1 when any gated one is beyond it.

The style shift is compared absolutely, like the accuracies, because it is a fraction on a fixed scale
(1.0 = as far as a real take of the style is from a `normal` one) whose mean over a row can sit near
zero (the foreign-rig files: -0.16), where 1 % of it is 0.002 and a relative gate would measure
nothing but the sign's noise. Diversity is printed but not gated (`--ungated`): it is how much the
samples differ from each other, not one of the issue's metrics (style shift, accuracy, FID,
geodesic, foot skating; content accuracy and FID are gated too).

    python3 tools/eval_compare.py assets/eval/heldout.json candidate.json [--tol 0.01]
"""
import argparse
import json
import sys

METRICS = ["style_shift", "style_acc", "style_fid", "geodesic", "foot_skate", "content_acc", "content_fid", "diversity"]
ABSOLUTE = {"style_acc", "content_acc", "style_shift"}


def rows(path):
    with open(path) as f:
        return {r["setting"]: r for r in json.load(f)["rows"]}


def change(name, a, b, tol):
    """The cell text and whether the change is beyond the tolerance."""
    digits = 2 if name == "foot_skate" else 3
    if name in ABSOLUTE:
        d = b - a
        return f"{a:.{digits}f} → {b:.{digits}f} ({d:+.3f})", abs(d) > tol + 1e-12
    rel = (b - a) / abs(a) if a != 0 else (0.0 if b == a else float("inf"))
    return f"{a:.{digits}f} → {b:.{digits}f} ({100 * rel:+.1f} %)", abs(rel) > tol + 1e-12


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reference")
    parser.add_argument("candidate")
    parser.add_argument("--tol", type=float, default=0.01)
    parser.add_argument("--ungated", default="diversity", help="metrics printed but not gated")
    parser.add_argument("--skip", default="real,identity", help="rows not compared (unchanged by the weights)")
    args = parser.parse_args()
    ref, cand = rows(args.reference), rows(args.candidate)
    skip = set(args.skip.split(","))
    ungated = set(filter(None, args.ungated.split(",")))
    beyond = []
    print("| row | " + " | ".join(m + (" (not gated)" if m in ungated else "") for m in METRICS) + " |")
    print("|---|" + "---|" * len(METRICS))
    for setting, a in ref.items():
        if setting in skip or setting not in cand:
            continue
        cells = []
        for name in METRICS:
            if a.get(name) is None or cand[setting].get(name) is None:
                cells.append("—")
                continue
            text, bad = change(name, a[name], cand[setting][name], args.tol)
            bad = bad and name not in ungated
            cells.append(f"{text} **!**" if bad else text)
            if bad:
                beyond.append(f"{setting}.{name}")
        print(f"| {setting} | " + " | ".join(cells) + " |")
    print(f"\nbeyond {100 * args.tol:g} %: {len(beyond)}" + (f" ({', '.join(beyond)})" if beyond else ""))
    sys.exit(1 if beyond else 0)


if __name__ == "__main__":
    main()
