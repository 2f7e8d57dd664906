#!/usr/bin/env python3
"""Content accuracy per row of an evaluation JSON (`motion-stylizer eval --json`), pooled by the
Bandai data set its target style comes from: set 2's seven styles (~400 takes each) against set 1's
nine others (~11 takes each, one per set 1 content). `normal`, in both sets, counts with set 2.
Weighted by outputs, from the JSON's per-label rows (`labels`, with `content_acc` since
2026-12-07); the `real` row gives the held-out takes of those styles.

    python3 tools/content_by_set.py assets/eval/heldout.json
"""
import argparse
import json

# Bandai set 2's styles under the unified labels (elderly = old, exhausted = tired), and `normal`.
SET2 = {"normal", "active", "feminine", "masculine", "old", "tired", "youthful"}
ROWS = ["real", "identity", "sup_motion", "sup_label", "unsup_motion"]


def pooled(labels, setting, in_set2):
    rows = [
        l
        for l in labels
        if l["setting"] == setting and l.get("content_acc") is not None and (l["style"] in SET2) == in_set2
    ]
    n = sum(l["outputs"] for l in rows)
    if n == 0:
        return None, 0
    return sum(l["content_acc"] * l["outputs"] for l in rows) / n, n


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("json", help="an evaluation JSON with per-label content accuracies")
    args = parser.parse_args()
    with open(args.json) as f:
        labels = json.load(f).get("labels", [])
    if not any(l.get("content_acc") is not None for l in labels):
        raise SystemExit(f"{args.json}: no per-label content accuracies (an older eval, or no content classes)")
    print("| row | targets of set 2's styles | targets of set 1's styles |")
    print("|---|---|---|")
    for setting in ROWS:
        cells = []
        for in_set2 in (True, False):
            acc, n = pooled(labels, setting, in_set2)
            cells.append("—" if acc is None else f"{acc:.3f} ({n})")
        print(f"| {setting} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
