"""The supervised network of our shipped weights rebuilt in PyTorch, for `make bench-perf`.

Layer for layer what `src/model/` runs at inference (conventions in `src/model/layers.rs`):
a conv layer is [nearest ×2] → [reflection pad k//2] → conv (zero pad k//2 for the upsampling and
generator convs instead) → [instance norm, no affine, eps 1e-5] → [LeakyReLU 0.2]; AdaIN is
γ·IN(x) + β with [γ; β] from one linear layer on [style code; one-hot label]. With the content's
posture path (`content_posture` in the header, `src/model/generator.rs`), the generator's output
latent gets a linear map (no bias) of the content latent's mean over time added. Weights come straight
from our bundle (`weights.py`); Burn stores a Linear's weight as [in, out], PyTorch as [out, in].

Two entry points, both from normalised features to normalised features (the stylization pipeline's
network part, `src/stylize/pipeline.rs`):
- `MotionBased`: (content [1, 260, T], style reference [1, 260, T], one-hot label [1, S]) → [1, 260, T],
  the reference's posterior mean as the style code;
- `LabelBased`: (content [1, 260, T], codes [N, style_dim], one-hot labels [N, S]) → [N, 260, T].
"""

import torch
import torch.nn.functional as F
from torch import nn

LEAKY = 0.2
EPS = 1e-5
FEATURES = 260
AE_INPUT = 256


def instance_norm(x):
    mean = x.mean(dim=2, keepdim=True)
    var = ((x - mean) ** 2).mean(dim=2, keepdim=True)
    return (x - mean) / torch.sqrt(var + EPS)


class ConvLayer(nn.Module):
    def __init__(self, w, b, stride=1, upsample=False, zero_pad=False, norm=False, activate=True):
        super().__init__()
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
            x = torch.repeat_interleave(x, 2, dim=2)
        if self.reflect:
            x = F.pad(x, (self.reflect, self.reflect), mode="reflect")
        x = self.conv(x)
        if self.norm:
            x = instance_norm(x)
        if self.activate:
            x = F.leaky_relu(x, LEAKY)
        return x


class AdaIn(nn.Module):
    def __init__(self, w, b):
        super().__init__()
        cond, out2 = w.shape  # Burn: [in, out]
        self.channels = out2 // 2
        self.linear = nn.Linear(cond, out2)
        with torch.no_grad():
            self.linear.weight.copy_(torch.from_numpy(w.T.copy()))
            self.linear.bias.copy_(torch.from_numpy(b))

    def forward(self, x, cond):
        gb = self.linear(cond)
        c = self.channels
        return instance_norm(x) * gb[:, :c, None] + gb[:, c:, None]


class Network(nn.Module):
    """Every network of the supervised model that stylization runs."""

    def __init__(self, config, t):
        super().__init__()
        if not config["supervised"] or config["vae"]:
            raise ValueError("the benchmark rebuilds the supervised plain-AE model")

        def conv(prefix, **kw):
            return ConvLayer(t[prefix + ".conv.weight"], t.get(prefix + ".conv.bias"), **kw)

        a, s = "autoencoder.", "stylizer."
        self.enc = nn.ModuleList([
            conv(a + "encoder.down1", stride=2),
            conv(a + "encoder.down2", stride=2),
            conv(a + "encoder.out", activate=False),
        ])
        self.dec = nn.ModuleList([
            conv(a + "decoder.first"),
            conv(a + "decoder.up1", upsample=True, zero_pad=True),
            conv(a + "decoder.up2", upsample=True, zero_pad=True),
            conv(a + "decoder.out", activate=False),
        ])
        self.content = nn.ModuleList([
            conv(s + "content_encoder.down", stride=2, norm=True),
            conv(s + "content_encoder.mid", norm=True),
            conv(s + "content_encoder.out", activate=False),
        ])
        self.style_down1 = conv(s + "style_encoder.down1", stride=2)
        self.style_rest = nn.ModuleList([
            conv(s + "style_encoder.down2", stride=2),
            conv(s + "style_encoder.down3", stride=2),
        ])
        self.style_out = conv(s + "style_encoder.out", activate=False)
        g = s + "generator."
        self.gen_convs = nn.ModuleList([
            conv(g + "block1.conv", zero_pad=True),
            conv(g + "block2.conv", zero_pad=True),
            conv(g + "block3.conv", upsample=True, zero_pad=True),
        ])
        self.gen_adain = nn.ModuleList([
            AdaIn(t[g + f"block{i}.adain.linear.weight"], t[g + f"block{i}.adain.linear.bias"]) for i in (1, 2, 3)
        ])
        self.gen_out = conv(g + "out", activate=False)
        self.reg = nn.ModuleList([
            conv("regressor.conv1"),
            conv("regressor.conv2"),
            conv("regressor.conv3"),
            conv("regressor.out", activate=False),
        ])
        self.style_dim = config["style_dim"]
        self.posture = None
        if config.get("content_posture", False):
            w = t[g + "posture.weight"]  # Burn: [in, out]
            self.posture = nn.Linear(w.shape[0], w.shape[1], bias=False)
            with torch.no_grad():
                self.posture.weight.copy_(torch.from_numpy(w.T.copy()))

    def encode(self, features):
        x = features[:, :AE_INPUT]
        for layer in self.enc:
            x = layer(x)
        return x

    def content_code(self, latent):
        """The content code and, with the posture path, the latent's mean over time `[B, D_z]`."""
        posture = latent.mean(dim=2) if self.posture is not None else None
        for layer in self.content:
            latent = layer(latent)
        return latent, posture

    def style_mean(self, latent, label):
        h = self.style_down1(latent)
        h = torch.cat([h, label[:, :, None].expand(-1, -1, h.shape[2])], dim=1)
        for layer in self.style_rest:
            h = layer(h)
        g = self.style_out(h.mean(dim=2, keepdim=True))
        return g[:, : self.style_dim, 0]

    def generate(self, content, posture, code, label):
        cond = torch.cat([code, label], dim=1)
        x = content
        for conv, adain in zip(self.gen_convs, self.gen_adain):
            x = adain(conv(x), cond)
        x = self.gen_out(x)
        if posture is not None:
            x = x + self.posture(posture)[:, :, None]
        return x

    def finish(self, content_features, latent):
        x = latent
        for layer in self.dec:
            x = layer(x)
        n = x.shape[0]
        angular = content_features[:, 0:1].expand(n, -1, -1)
        r = torch.cat([angular, x[:, 3:AE_INPUT]], dim=1)
        for layer in self.reg:
            r = layer(r)
        return torch.cat([angular, r, x[:, 3:]], dim=1)


class MotionBased(nn.Module):
    def __init__(self, net):
        super().__init__()
        self.net = net

    def forward(self, content, style, label):
        n = self.net
        code, posture = n.content_code(n.encode(content))
        mean = n.style_mean(n.encode(style), label)
        return n.finish(content, n.generate(code, posture, mean, label))


class LabelBased(nn.Module):
    def __init__(self, net):
        super().__init__()
        self.net = net

    def forward(self, content, codes, labels):
        n = self.net
        code, posture = n.content_code(n.encode(content))
        code = code.expand(codes.shape[0], -1, -1)
        if posture is not None:
            posture = posture.expand(codes.shape[0], -1)
        return n.finish(content, n.generate(code, posture, codes, labels))


def load(path):
    from weights import read_bundle

    config, tensors = read_bundle(path)
    net = Network(config, tensors).eval()
    return config, net


def flops(module, *inputs):
    """Floating-point operations of one forward pass: 2 per multiply-add of every convolution
    and linear layer (the elementwise work — norms, activations, padding — is left out; it is
    under 1 % here)."""
    total = 0

    def conv_hook(m, _inp, out):
        nonlocal total
        n, c_out, t_out = out.shape
        total += 2 * n * c_out * t_out * m.in_channels * m.kernel_size[0]

    def linear_hook(m, inp, _out):
        nonlocal total
        total += 2 * inp[0].shape[0] * m.in_features * m.out_features

    hooks = []
    for m in module.modules():
        if isinstance(m, nn.Conv1d):
            hooks.append(m.register_forward_hook(conv_hook))
        elif isinstance(m, nn.Linear):
            hooks.append(m.register_forward_hook(linear_hook))
    with torch.no_grad():
        module(*inputs)
    for h in hooks:
        h.remove()
    return total
