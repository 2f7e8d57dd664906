#!/usr/bin/env python3
"""Print the Markdown table of an evaluation JSON (`motion-stylizer eval --json`) as EVALUATION.md
shows it: value ± 95 % half-width, "—" where a metric does not apply.

    python3 tools/eval_table.py assets/eval/heldout.json [--columns style_acc,style_fid,...]
"""
import argparse
import json

HEADERS = {
    "style_acc": "style acc ↑",
    "style_fid": "style FID ↓",
    "geodesic": "geodesic ↓",
    "diversity": "diversity",
    "diversity_cm": "diversity (cm)",
    "foot_skate": "foot skating (cm/s) ↓",
    "foot_skate_ref": "… of the references (cm/s)",
    "style_shift": "style shift ↑",
}


def cell(row, name):
    value = row.get(name)
    if value is None:
        return "—"
    digits = 2 if name.endswith("_cm") or name.startswith("foot_skate") or name == "style_shift" else 3
    ci = row.get(f"{name}_ci")
    return f"{value:.{digits}f}" + ("" if ci is None else f" ± {ci:.{digits}f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("json")
    parser.add_argument("--columns", default=",".join(HEADERS))
    args = parser.parse_args()
    columns = args.columns.split(",")
    with open(args.json) as f:
        rows = json.load(f)["rows"]
    print("| setting | " + " | ".join(HEADERS.get(c, c) for c in columns) + " |")
    print("|---|" + "---|" * len(columns))
    for row in rows:
        print(f"| `{row['setting']}` | " + " | ".join(cell(row, c) for c in columns) + " |")


if __name__ == "__main__":
    main()
