"""PyTorch side of `make bench-train` (run by bench/perf/train_run.mjs with bench/perf/.venv's python):
our two training steps rebuilt in PyTorch, from the weights, batch and noise our side wrote
(`examples/train_perf_bench.rs dump DIR`).

  python torch_train.py parity DIR [--f64]
      Runs the first steps (as many as DIR holds, 3) of both stages and compares every loss term
      and gradient norm with ours (DIR/losses.json); prints one JSON line with the relative
      differences; exit status 1 when a loss term is above 1e-4 or a gradient norm above 1e-3.
      --f64: also runs the steps in float64 and says how far each float32 side is from it.
  python torch_train.py time DIR REPEATS THREADS
      torch.set_num_threads(THREADS), one warm-up step of each stage, then REPEATS timed steps of
      each; prints one JSON line (seconds per step, and per phase as ours reports them).

What is rebuilt (src/train/, src/model/; the conventions of src/model/layers.rs), written as a
PyTorch user would write it (the authors' reference code: nn.Conv1d, reflection padding,
InstanceNorm1d without affine, LeakyReLU 0.2, nearest ×2 upsampling, AdaIN):
- stage 1, `AeTrainer::step`: the motion autoencoder's loss (smooth-L1 reconstruction of the 260
  features from the 256 the encoder sees + 0.001 latent L1 + 0.001 latent smoothness) and the
  global regressor's L1, one backward pass for both, `clip_grad_norm_(·, 0.5)` per network, Adam
  β = (0.9, 0.999), ε = 1e-8, lr 1e-4 (regressor 2e-4);
- stage 2, `StylizerTrainer::step` (supervised): latents of the frozen autoencoder (no gradient),
  then `stylizer_loss` term by term in the same order with the same stacked batches (five noise
  draws per step, read from DIR), backward, one `clip_grad_norm_` over both encoders and one over
  the generator, Adam at lr 1e-4 on the stylizer. The frozen decoder passes gradients to the
  generator but has none of its own.
Dropout is 0 on both sides (our dump sets it in the config): masks drawn by two generators could
not agree.
"""

import json
import os
import sys
import time

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from weights import read_burnpack  # noqa: E402

# Relative, per term and step. The gradient norms get more room: Adam's first update is close to
# lr·sign(g) for every weight, so float32 rounding in weights whose gradient is near 0 moves step 2's
# gradient more than its losses (both float32 sides are ~1e-4 from a float64 run there).
TOLERANCE = 1e-4
NORM_TOLERANCE = 1e-3
LEAKY = 0.2
EPS = 1e-5
AE_INPUT = 256


class ConvLayer(nn.Module):
    """[nearest ×2] → [reflection pad k//2] → conv (zero pad k//2 instead where `zero_pad`) →
    [instance norm] → [LeakyReLU 0.2] (src/model/layers.rs `ConvLayer`)."""

    def __init__(self, t, prefix, stride=1, upsample=False, zero_pad=False, norm=False, activate=True):
        super().__init__()
        w = t[prefix + ".conv.weight"]
        b = t.get(prefix + ".conv.bias")
        out_c, in_c, k = w.shape
        self.conv = nn.Conv1d(in_c, out_c, k, stride=stride, padding=(k // 2) if zero_pad else 0, bias=b is not None)
        with torch.no_grad():
            self.conv.weight.copy_(torch.from_numpy(w))
            if b is not None:
                self.conv.bias.copy_(torch.from_numpy(b))
        self.reflect = 0 if zero_pad else k // 2
        self.upsample, self.norm, self.activate = upsample, norm, activate

    def forward(self, x):
        if self.upsample:
            x = F.interpolate(x, scale_factor=2, mode="nearest")
        if self.reflect:
            x = F.pad(x, (self.reflect, self.reflect), mode="reflect")
        x = self.conv(x)
        if self.norm:
            x = F.instance_norm(x, eps=EPS)
        if self.activate:
            x = F.leaky_relu(x, LEAKY)
        return x


class AdaIn(nn.Module):
    """γ·IN(x) + β, [γ; β] = Linear([style code; one-hot label])."""

    def __init__(self, t, prefix):
        super().__init__()
        w, b = t[prefix + ".linear.weight"], t[prefix + ".linear.bias"]
        cond, out2 = w.shape  # Burn: [in, out]
        self.channels = out2 // 2
        self.linear = nn.Linear(cond, out2)
        with torch.no_grad():
            self.linear.weight.copy_(torch.from_numpy(w.T.copy()))
            self.linear.bias.copy_(torch.from_numpy(b))

    def forward(self, x, cond):
        gb = self.linear(cond)
        c = self.channels
        return F.instance_norm(x, eps=EPS) * gb[:, :c, None] + gb[:, c:, None]


class Encoder(nn.Module):
    def __init__(self, t):
        super().__init__()
        p = "autoencoder.encoder."
        self.layers = nn.Sequential(
            ConvLayer(t, p + "down1", stride=2),
            ConvLayer(t, p + "down2", stride=2),
            ConvLayer(t, p + "out", activate=False),
        )

    def forward(self, features):
        return self.layers(features[:, :AE_INPUT])


class Decoder(nn.Module):
    def __init__(self, t):
        super().__init__()
        p = "autoencoder.decoder."
        self.layers = nn.Sequential(
            ConvLayer(t, p + "first"),
            ConvLayer(t, p + "up1", upsample=True, zero_pad=True),
            ConvLayer(t, p + "up2", upsample=True, zero_pad=True),
            ConvLayer(t, p + "out", activate=False),
        )

    def forward(self, z):
        return self.layers(z)


class Regressor(nn.Module):
    def __init__(self, t):
        super().__init__()
        self.layers = nn.Sequential(
            ConvLayer(t, "regressor.conv1"),
            ConvLayer(t, "regressor.conv2"),
            ConvLayer(t, "regressor.conv3"),
            ConvLayer(t, "regressor.out", activate=False),
        )

    def forward(self, x):
        return self.layers(x)


def regressor_input(x):
    return torch.cat([x[:, 0:1], x[:, 3:AE_INPUT]], dim=1)


def regressor_target(x):
    return x[:, 1:3]


class ContentEncoder(nn.Module):
    def __init__(self, t):
        super().__init__()
        p = "content_encoder."
        self.layers = nn.Sequential(
            ConvLayer(t, p + "down", stride=2, norm=True),
            ConvLayer(t, p + "mid", norm=True),
            ConvLayer(t, p + "out", activate=False),
        )

    def forward(self, z):
        return self.layers(z)


class StyleEncoder(nn.Module):
    def __init__(self, t, style_dim):
        super().__init__()
        p = "style_encoder."
        self.down1 = ConvLayer(t, p + "down1", stride=2)
        self.rest = nn.Sequential(ConvLayer(t, p + "down2", stride=2), ConvLayer(t, p + "down3", stride=2))
        self.out = ConvLayer(t, p + "out", activate=False)
        self.style_dim = style_dim

    def forward(self, z, label):
        h = self.down1(z)
        h = torch.cat([h, label[:, :, None].expand(-1, -1, h.shape[2])], dim=1)
        g = self.out(self.rest(h).mean(dim=2, keepdim=True))[:, :, 0]
        d = self.style_dim
        return g[:, :d], g[:, d:]


class Generator(nn.Module):
    def __init__(self, t):
        super().__init__()
        p = "generator."
        self.convs = nn.ModuleList([
            ConvLayer(t, p + "block1.conv", zero_pad=True),
            ConvLayer(t, p + "block2.conv", zero_pad=True),
            ConvLayer(t, p + "block3.conv", upsample=True, zero_pad=True),
        ])
        self.adain = nn.ModuleList([AdaIn(t, p + f"block{i}.adain") for i in (1, 2, 3)])
        self.out = ConvLayer(t, p + "out", activate=False)

    def forward(self, content, style, label):
        cond = torch.cat([style, label], dim=1)
        x = content
        for conv, adain in zip(self.convs, self.adain):
            x = adain(conv(x), cond)
        return self.out(x)


# ---- losses (src/train/losses.rs) ----

def smooth_l1(pred, target):
    return F.smooth_l1_loss(pred, target)


def kl_to_standard_normal(mean, logvar):
    return (0.5 * (logvar.exp() + mean.square() - logvar - 1.0)).mean()


def kl_gaussians(mean1, logvar1, mean2, logvar2):
    return (0.5 * (logvar2 - logvar1) + (logvar1.exp() + (mean1 - mean2).square()) / (2.0 * logvar2.exp()) - 0.5).mean()


def sample(dist, eps):
    mean, logvar = dist
    return mean + (0.5 * logvar).exp() * eps


class PhaseTimes:
    """Seconds per phase summed over the steps measured, as ours (src/train/trainer.rs `PhaseTimes`):
    forward (latents and losses included), backward, clip (norms and clipping), update (reading
    the losses back and the Adam step)."""

    NAMES = ("forward", "backward", "clip", "update")

    def __init__(self):
        self.steps = 0
        self.sums = dict.fromkeys(self.NAMES, 0.0)

    def add(self, marks):
        self.steps += 1
        for name, a, b in zip(self.NAMES, marks, marks[1:]):
            self.sums[name] += b - a

    def mean(self):
        return {k: v / max(self.steps, 1) for k, v in self.sums.items()}


def partner_permutation(batch):
    return [i ^ 1 for i in range(batch)] if batch % 2 == 0 else [(i + 1) % batch for i in range(batch)]


# ---- the two trainers ----

def _load(dir_):
    with open(os.path.join(dir_, "meta.json")) as f:
        meta = json.load(f)
    b, c, t = meta["batch"], meta["features"], meta["frames"]
    steps, draws, sd = meta["steps"], meta["draws_per_step"], meta["config"]["style_dim"]

    def f32(name, shape):
        return torch.from_numpy(np.fromfile(os.path.join(dir_, name), dtype="<f4").reshape(shape).copy())

    def bpk(name):
        with open(os.path.join(dir_, name), "rb") as f:
            return read_burnpack(f.read())

    labels = torch.zeros(b, meta["config"]["num_styles"])
    labels[torch.arange(b), torch.tensor(meta["labels"])] = 1.0
    data = {
        "motion1": f32("motion1.f32", (b, c, t)),
        "motion2": f32("motion2.f32", (b, c, t)),
        "labels": labels,
        "noise": f32("noise.f32", (steps, draws, b, sd)),
    }
    return meta, bpk("ae.bpk"), bpk("stylizer.bpk"), data


class AeTrainer:
    """`AeTrainer::step`: autoencoder + regressor, one backward, clipped per network, Adam each."""

    def __init__(self, meta, t):
        tc = meta["train"]
        self.tc = tc
        self.encoder, self.decoder, self.regressor = Encoder(t), Decoder(t), Regressor(t)
        self.ae_params = list(self.encoder.parameters()) + list(self.decoder.parameters())
        self.optim_ae = torch.optim.Adam(self.ae_params, lr=tc["lr"], betas=(0.9, 0.999), eps=1e-8)
        self.optim_reg = torch.optim.Adam(self.regressor.parameters(), lr=tc["regressor_lr"], betas=(0.9, 0.999), eps=1e-8)
        self.phases = None

    def step(self, x):
        t0 = time.perf_counter()
        tc = self.tc
        z = self.encoder(x)
        reconstruction = smooth_l1(self.decoder(z), x)
        sparsity = z.abs().mean()
        smoothness = (z[:, :, 1:] - z[:, :, :-1]).abs().mean()
        ae_loss = reconstruction + sparsity * tc["lambda_l1"] + smoothness * tc["lambda_smooth"]
        regressor_loss = F.l1_loss(self.regressor(regressor_input(x)), regressor_target(x))
        t1 = time.perf_counter()
        self.optim_ae.zero_grad(set_to_none=True)
        self.optim_reg.zero_grad(set_to_none=True)
        (ae_loss + regressor_loss).backward()
        t2 = time.perf_counter()
        clip = tc["grad_clip_norm"]
        ae_norm = torch.nn.utils.clip_grad_norm_(self.ae_params, clip)
        reg_norm = torch.nn.utils.clip_grad_norm_(self.regressor.parameters(), clip)
        t3 = time.perf_counter()
        report = {
            "ae_loss": ae_loss.item(),
            "reconstruction": reconstruction.item(),
            "sparsity": sparsity.item(),
            "smoothness": smoothness.item(),
            "kl": 0.0,
            "regressor_loss": regressor_loss.item(),
            "ae_grad_norm": ae_norm.item(),
            "regressor_grad_norm": reg_norm.item(),
        }
        self.optim_ae.step()
        self.optim_reg.step()
        if self.phases is not None:
            self.phases.add([t0, t1, t2, t3, time.perf_counter()])
        return report


class StylizerTrainer:
    """`StylizerTrainer::step` (supervised) with `stylizer_loss`, on the frozen autoencoder."""

    def __init__(self, meta, t_ae, t):
        tc = meta["train"]
        self.tc, self.w = tc, meta["stylizer_weights"]
        self.encoder, self.decoder = Encoder(t_ae), Decoder(t_ae)
        for p in list(self.encoder.parameters()) + list(self.decoder.parameters()):
            p.requires_grad_(False)
        self.content = ContentEncoder(t)
        self.style = StyleEncoder(t, meta["config"]["style_dim"])
        self.generator = Generator(t)
        self.enc_params = list(self.content.parameters()) + list(self.style.parameters())
        self.gen_params = list(self.generator.parameters())
        self.optim = torch.optim.Adam(self.enc_params + self.gen_params, lr=tc["lr"], betas=(0.9, 0.999), eps=1e-8)
        self.phases = None

    def latent(self, x):
        with torch.no_grad():
            return self.encoder(x)

    def step(self, motion1, motion2, labels, eps):
        """`eps`: `[5, B, style_dim]`, the step's five noise draws in order."""
        t0 = time.perf_counter()
        b = motion1.shape[0]
        perm = partner_permutation(b)
        z1, z2 = self.latent(motion1), self.latent(motion2)
        z3, m3 = z2[perm], motion2[perm]
        sl, sl3 = labels, labels[perm]
        rows = lambda x, i: x[i * b:(i + 1) * b]  # noqa: E731

        z12 = torch.cat([z1, z2])
        c12 = self.content(z12)
        mean12, logvar12 = self.style(z12, torch.cat([sl, sl]))
        c1, c2 = rows(c12, 0), rows(c12, 1)
        n1 = (rows(mean12, 0), rows(logvar12, 0))
        n2 = (rows(mean12, 1), rows(logvar12, 1))
        c3 = c2[perm]
        n3 = (n2[0][perm], n2[1][perm])

        s1, s2, s3 = sample(n1, eps[0]), sample(n2, eps[1]), sample(n3, eps[2])
        g = self.generator(torch.cat([c1, c2, c2.detach()]), torch.cat([s1, s2, s3]), torch.cat([sl, sl, sl3]))
        r1, r2, zt = rows(g, 0), rows(g, 1), rows(g, 2)
        ct = self.content(zt)
        nt = self.style(zt, sl3)
        s2b = sample((n2[0].detach(), n2[1].detach()), eps[3])
        st = sample(nt, eps[4])
        g = self.generator(torch.cat([ct, c3.detach()]), torch.cat([s2b, st]), torch.cat([sl, sl3]))
        rr2, rr3 = rows(g, 0), rows(g, 1)

        poses = self.decoder(torch.cat([r1, r2, rr2, rr3]))
        rec_latent = smooth_l1(r1, z1) + smooth_l1(r2, z2)
        rec_pose = smooth_l1(rows(poses, 0), motion1) + smooth_l1(rows(poses, 1), motion2)
        cyc_latent = smooth_l1(rr2, z2) + smooth_l1(rr3, z3)
        cyc_pose = smooth_l1(rows(poses, 2), motion2) + smooth_l1(rows(poses, 3), m3)
        kl = kl_to_standard_normal(*n1) + kl_to_standard_normal(*n2) + kl_to_standard_normal(*nt)
        hsa = kl_gaussians(*n1, *n2)
        w = self.w
        loss = (rec_latent + rec_pose) * w["rec"] + (cyc_latent + cyc_pose) * w["cyc"] + kl * w["kl"] + hsa * w["hsa"]

        t1 = time.perf_counter()
        self.optim.zero_grad(set_to_none=True)
        loss.backward()
        t2 = time.perf_counter()
        clip = self.tc["grad_clip_norm"]
        enc_norm = torch.nn.utils.clip_grad_norm_(self.enc_params, clip)
        gen_norm = torch.nn.utils.clip_grad_norm_(self.gen_params, clip)
        t3 = time.perf_counter()
        report = {
            "loss": loss.item(),
            "rec_latent": rec_latent.item(),
            "rec_pose": rec_pose.item(),
            "cyc_latent": cyc_latent.item(),
            "cyc_pose": cyc_pose.item(),
            "kl": kl.item(),
            "hsa": hsa.item(),
            "encoders_grad_norm": enc_norm.item(),
            "generator_grad_norm": gen_norm.item(),
        }
        self.optim.step()
        if self.phases is not None:
            self.phases.add([t0, t1, t2, t3, time.perf_counter()])
        return report


def build(dir_, dtype=torch.float32):
    """Both trainers and the data of DIR, in `dtype` (float64: the reference the parity check can
    measure both float32 sides against)."""
    previous = torch.get_default_dtype()
    torch.set_default_dtype(dtype)
    try:
        meta, t_ae, t_st, data = _load(dir_)
        data = {k: v.to(dtype) for k, v in data.items()}
        return meta, AeTrainer(meta, t_ae), StylizerTrainer(meta, t_ae, t_st), data
    finally:
        torch.set_default_dtype(previous)


class FlopCounter:
    """Floating-point operations of one training step: 2 per multiply-add of every convolution and
    linear layer, times 1 (forward) + 1 if the layer's input needs a gradient + 1 if its weight does
    (the two products of the backward pass). Norms, activations, losses and Adam are left out."""

    def __init__(self, modules):
        self.total = 0
        self.hooks = [m.register_forward_hook(self.hook) for root in modules for m in root.modules()
                      if isinstance(m, (nn.Conv1d, nn.Linear))]

    def hook(self, m, inp, out):
        x = inp[0]
        if isinstance(m, nn.Conv1d):
            n, c_out, t_out = out.shape
            macs = n * c_out * t_out * m.in_channels * m.kernel_size[0]
        else:
            macs = x.shape[0] * m.in_features * m.out_features
        self.total += 2 * macs * (1 + int(x.requires_grad) + int(m.weight.requires_grad))

    def remove(self):
        for h in self.hooks:
            h.remove()
        return self.total


def run_steps(dir_, dtype=torch.float32):
    """The first steps of both stages (reports), and the FLOPs of one step of each (counted on the
    first)."""
    meta, ae, st, d = build(dir_, dtype)
    out = {"ae": [], "stylizer": []}
    flops = {}
    for k in range(meta["steps"]):
        count = k == 0
        c = FlopCounter([ae.encoder, ae.decoder, ae.regressor]) if count else None
        out["ae"].append(ae.step(d["motion1"]))
        if count:
            flops["ae"] = c.remove()
            c = FlopCounter([st.encoder, st.decoder, st.content, st.style, st.generator])
        out["stylizer"].append(st.step(d["motion1"], d["motion2"], d["labels"], d["noise"][k]))
        if count:
            flops["stylizer"] = c.remove()
    return meta, out, flops


def rel_diff(a, b):
    return abs(a - b) / max(abs(a), abs(b), 1e-12) if a != b else 0.0


def is_norm(term):
    return term.endswith("_grad_norm")


def compare(a, b):
    """Relative differences term by term and step by step of two runs' reports, and the largest
    ones over the loss terms and over the gradient norms."""
    # Terms only one side reports: ours has the loss terms added after the paper's (issue 14's
    # style statistics, content shape, ...), off by default and reported as 0 then; anything else
    # is a mismatch.
    for stage in a:
        for x, y in zip(a[stage], b[stage]):
            for t in set(x) ^ set(y):
                if (x if t in x else y)[t] != 0:
                    raise SystemExit(f"parity: {stage}: the term {t!r} is {x.get(t)} (ours) / {y.get(t)} (PyTorch)")
    diff = {stage: [{t: rel_diff(x[t], y[t]) for t in x if t in y} for x, y in zip(a[stage], b[stage])] for stage in a}
    worst = lambda keep: max(v for stage in diff.values() for step in stage for t, v in step.items() if keep(t))  # noqa: E731
    by_step = {
        stage: [max(v for t, v in step.items() if not is_norm(t)) for step in steps] for stage, steps in diff.items()
    }
    return {
        "losses": worst(lambda t: not is_norm(t)),
        "grad_norms": worst(is_norm),
        "losses_by_step": by_step,
        "terms": diff,
    }


def parity(dir_, f64=False):
    with open(os.path.join(dir_, "losses.json")) as f:
        ours = json.load(f)
    meta, theirs, flops = run_steps(dir_)
    d = compare(ours, theirs)
    out = {
        "width": meta["width"],
        "steps": meta["steps"],
        "max_rel_diff_losses": d["losses"],
        "max_rel_diff_grad_norms": d["grad_norms"],
        "max_rel_diff_losses_by_step": d["losses_by_step"],
        "rel_diff": d["terms"],
        "ours": ours,
        "torch": theirs,
        "flops": flops,
        "torch_version": torch.__version__,
        "torch_cpu_capability": torch.backends.cpu.get_cpu_capability(),
        "tolerance_losses": TOLERANCE,
        "tolerance_grad_norms": NORM_TOLERANCE,
    }
    if f64:
        _, ref, _ = run_steps(dir_, torch.float64)
        for name, run in (("ours", ours), ("torch", theirs)):
            r = compare(run, ref)
            out[f"{name}_vs_float64"] = {"losses": r["losses"], "grad_norms": r["grad_norms"]}
        out["float64"] = ref
    out["ok"] = d["losses"] <= TOLERANCE and d["grad_norms"] <= NORM_TOLERANCE
    print(json.dumps(out))
    return 0 if out["ok"] else 1


def timing(dir_, repeats, threads):
    torch.set_num_threads(threads)
    meta, ae, st, d = build(dir_)
    steps = meta["steps"]
    ae.step(d["motion1"])
    st.step(d["motion1"], d["motion2"], d["labels"], d["noise"][0])
    ae.phases, st.phases = PhaseTimes(), PhaseTimes()
    ae_s, st_s, ae_cpu_s, st_cpu_s = [], [], [], []
    for k in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        ae.step(d["motion1"])
        ae_s.append(time.perf_counter() - t0)
        ae_cpu_s.append(time.process_time() - c0)
        t0, c0 = time.perf_counter(), time.process_time()
        st.step(d["motion1"], d["motion2"], d["labels"], d["noise"][(k + 1) % steps])
        st_s.append(time.perf_counter() - t0)
        st_cpu_s.append(time.process_time() - c0)
    print(json.dumps({
        "width": meta["width"],
        "threads": torch.get_num_threads(),
        "ae_s": ae_s,
        "stylizer_s": st_s,
        "ae_cpu_s": ae_cpu_s,
        "stylizer_cpu_s": st_cpu_s,
        "ae_phases_s": ae.phases.mean(),
        "stylizer_phases_s": st.phases.mean(),
        "torch_version": torch.__version__,
        "torch_cpu_capability": torch.backends.cpu.get_cpu_capability(),
    }))
    return 0


if __name__ == "__main__":
    mode = sys.argv[1] if len(sys.argv) > 1 else ""
    if mode == "parity" and len(sys.argv) in (3, 4) and sys.argv[3:] in ([], ["--f64"]):
        sys.exit(parity(sys.argv[2], f64=sys.argv[3:] == ["--f64"]))
    if mode == "time" and len(sys.argv) == 5:
        sys.exit(timing(sys.argv[2], int(sys.argv[3]), int(sys.argv[4])))
    sys.exit(__doc__)
