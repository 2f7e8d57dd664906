"""Plot a training run's loss.csv (and eval.csv) to a PNG: python3 tools/plot_losses.py RUN_DIR OUT.png

Needs matplotlib. Loss columns are smoothed with a moving average of 50 steps; held-out metrics from
eval.csv are drawn on a second row. Used for the loss curves committed beside the weights.
"""
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

run, out = sys.argv[1], sys.argv[2]
skip = {"step", "elapsed_s", "lr", "regressor_lr", "kl"}

def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows

def smooth(v, k=50):
    out, acc = [], 0.0
    for i, x in enumerate(v):
        acc += x
        if i >= k:
            acc -= v[i - k]
        out.append(acc / min(i + 1, k))
    return out

loss = read(f"{run}/loss.csv")
try:
    ev = read(f"{run}/eval.csv")
except FileNotFoundError:
    ev = []
cols = [c for c in loss[0] if c not in skip and not c.endswith("grad_norm")]
fig, axes = plt.subplots(2 if ev else 1, 1, figsize=(9, 7 if ev else 4), squeeze=False)
steps = [int(r["step"]) for r in loss]
for c in cols:
    vals = [float(r[c]) for r in loss]
    if max(vals) > 0:
        axes[0][0].plot(steps, smooth(vals), label=c)
axes[0][0].set_yscale("log"); axes[0][0].set_xlabel("step"); axes[0][0].set_title(f"{run}: training losses (moving average of 50)")
axes[0][0].legend(fontsize=7)
if ev:
    es = [int(r["step"]) for r in ev]
    for c in ev[0]:
        if c in ("step", "elapsed_s"):
            continue
        axes[1][0].plot(es, [float(r[c]) for r in ev], marker="o", label=c)
    axes[1][0].set_yscale("log"); axes[1][0].set_xlabel("step"); axes[1][0].set_title("held-out")
    axes[1][0].legend(fontsize=7)
plt.tight_layout()
plt.savefig(out, dpi=80)
