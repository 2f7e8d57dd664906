"""PyTorch side of `make bench-perf` (run by bench/perf/run.mjs with bench/perf/.venv's python).

  python torch_bench.py parity WEIGHTS.bin DUMP_DIR ONNX_DIR
      Rebuilds the supervised network (torch_model.py), runs it on the inputs our side wrote to
      DUMP_DIR (examples/perf_bench.rs), prints the max abs difference to our outputs, exports both
      entry points to ONNX (ONNX_DIR/motion.onnx, label10.onnx, label1.onnx) and prints one JSON
      line: differences, FLOP counts. Exit status 1 when a difference is above 1e-4.
  python torch_bench.py time WEIGHTS.bin DUMP_DIR REPEATS THREADS
      torch.set_num_threads(THREADS), one warm-up, then REPEATS timed runs of each piece of work;
      prints one JSON line (medians and all times, ms).
"""

import json
import warnings
import os
import sys
import time

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import torch_model  # noqa: E402

TOLERANCE = 1e-4
warnings.filterwarnings("ignore", category=UserWarning)
warnings.filterwarnings("ignore", category=DeprecationWarning)


def inputs(dump):
    with open(os.path.join(dump, "dims.json")) as f:
        d = json.load(f)
    t, c, s, k = d["frames"], d["features"], d["style_dim"], d["num_styles"]

    def load(name, shape):
        return torch.from_numpy(np.fromfile(os.path.join(dump, name), dtype="<f4").reshape(shape))

    return {
        "content": load("content.f32", (1, c, t)),
        "style": load("style.f32", (1, c, t)),
        "label1": load("label1.f32", (1, k)),
        "codes10": load("codes10.f32", (10, s)),
        "labels10": load("labels10.f32", (10, k)),
        "motion_out": load("motion_out.f32", (1, c, t)),
        "label10_out": load("label10_out.f32", (10, c, t)),
    }


def work(net, x):
    """The timed pieces of work: name → (module, inputs)."""
    motion, label = torch_model.MotionBased(net), torch_model.LabelBased(net)
    return {
        "net_motion": (motion, (x["content"], x["style"], x["label1"])),
        "net_label1": (label, (x["content"], x["codes10"][:1], x["labels10"][:1])),
        "net_label10": (label, (x["content"], x["codes10"], x["labels10"])),
    }


def parity(weights, dump, onnx_dir):
    _, net = torch_model.load(weights)
    x = inputs(dump)
    jobs = work(net, x)
    with torch.no_grad():
        motion = jobs["net_motion"][0](*jobs["net_motion"][1])
        label10 = jobs["net_label10"][0](*jobs["net_label10"][1])
    diff = {
        "torch_vs_ours_motion": float((motion - x["motion_out"]).abs().max()),
        "torch_vs_ours_label10": float((label10 - x["label10_out"]).abs().max()),
    }
    flops = {name: torch_model.flops(m, *a) for name, (m, a) in jobs.items()}
    os.makedirs(onnx_dir, exist_ok=True)
    names = {
        "net_motion": (["content", "style", "label"], "motion.onnx"),
        "net_label1": (["content", "codes", "labels"], "label1.onnx"),
        "net_label10": (["content", "codes", "labels"], "label10.onnx"),
    }
    for name, (m, a) in jobs.items():
        input_names, file = names[name]
        # Static shapes (the benchmark's): the TorchScript-based exporter, no onnxscript needed.
        torch.onnx.export(
            m, a, os.path.join(onnx_dir, file), input_names=input_names, output_names=["features"],
            opset_version=17, dynamo=False,
        )
    ok = all(v <= TOLERANCE for v in diff.values())
    print(json.dumps({"ok": ok, "tolerance": TOLERANCE, "max_abs_diff": diff, "flops": flops,
                      "torch": torch.__version__}))
    return 0 if ok else 1


def timing(weights, dump, repeats, threads):
    torch.set_num_threads(threads)
    _, net = torch_model.load(weights)
    x = inputs(dump)
    out = {"threads": torch.get_num_threads(), "torch": torch.__version__, "all": {}}
    with torch.inference_mode():
        for name, (m, a) in work(net, x).items():
            m(*a)
            ms = []
            for _ in range(repeats):
                t = time.perf_counter()
                m(*a).numpy()
                ms.append((time.perf_counter() - t) * 1e3)
            out[name + "_ms"] = float(np.median(ms))
            out["all"][name] = [round(v, 3) for v in ms]
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    mode = sys.argv[1]
    if mode == "parity":
        sys.exit(parity(sys.argv[2], sys.argv[3], sys.argv[4]))
    elif mode == "time":
        sys.exit(timing(sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5])))
    else:
        sys.exit(f"unknown mode {mode!r}")
