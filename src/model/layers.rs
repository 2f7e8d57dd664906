//! Building blocks: 1-D convolution layers over time (layout `[batch, channels, time]` at every
//! network's input and output; inside, the layers compute on `[channels, batch, time]`, see
//! [`to_cbt`]) with reflection or zero padding, instance norm, AdaIN, LeakyReLU 0.2, nearest ×2
//! upsampling.
//!
//! Conventions (from the authors' released code):
//! - A "conv layer" is: [reflection pad k/2] → conv (stride 1 or 2) → [instance norm] →
//!   [dropout] → [LeakyReLU 0.2]. For k3 the pad is 1 on each side, so stride 1 keeps the length
//!   and stride 2 maps an even length `L` to exactly `L/2`.
//! - The upsampling layers of the motion decoder and the generator use nearest ×2 then a k3 conv
//!   with *zero* padding 1 (that is what the reference does there), then LeakyReLU.
//! - Weights are Xavier-normal, biases zero (the reference's `init_weight`); the AdaIN linear
//!   layer's bias starts at γ = 1, β = 0.
//! - Instance norm: per sample and channel over time, biased variance, ε = 1e-5, no affine
//!   (PyTorch `InstanceNorm1d` defaults).

use burn::module::Param;
use burn::nn::conv::{Conv1d, Conv1dConfig};
use burn::nn::{Dropout, DropoutConfig, Initializer, Linear, LinearConfig, PaddingConfig1d};
use burn::prelude::*;
use std::sync::Arc;

use super::cpu_conv::{self, CpuBias, CpuTaps, shifted_products};

/// Negative slope of every LeakyReLU.
pub const LEAKY_SLOPE: f64 = 0.2;
/// Instance-norm epsilon.
pub const NORM_EPS: f64 = 1e-5;

/// LeakyReLU with slope 0.2.
///
/// On an autodiff device (training) it is written `x + 0.8·relu(−x)`: Burn differentiates its LeakyReLU as a
/// comparison, a scaling and a masked select (three masked passes over the activation in the
/// backward, ~10 % of a training step on flex), ReLU with its own fused backward. Positive values
/// come out exactly, negative ones within a rounding of `0.2·x`. Inference keeps Burn's fused
/// LeakyReLU (the same bytes as before).
pub fn leaky_relu<const D: usize>(x: Tensor<D>) -> Tensor<D> {
    if x.device().is_autodiff() {
        let negative = burn::tensor::activation::relu(x.clone().neg());
        return x + negative * (1.0 - LEAKY_SLOPE);
    }
    burn::tensor::activation::leaky_relu(x, LEAKY_SLOPE)
}

/// Reflection padding of the time axis (dim 2) by `pad` frames on each side.
///
/// PyTorch's `ReflectionPad1d` needs `pad < length`; for the degenerate length-1 case (short
/// clips deep in the style encoder/classifier) the frame is repeated instead, so any clip whose
/// length is a multiple of 8 goes through every network.
pub fn reflect_pad_time(x: Tensor<3>, pad: usize) -> Tensor<3> {
    if pad == 0 {
        return x;
    }
    let t = x.dims()[2];
    if t == 1 {
        return x.repeat_dim(2, 2 * pad + 1);
    }
    if pad == 1 {
        // Cheaper than the generic `Tensor::pad` (one concatenation, no zero fill).
        let left = x.clone().narrow(2, 1, 1);
        let right = x.clone().narrow(2, t - 2, 1);
        return Tensor::cat(vec![left, x, right], 2);
    }
    assert!(pad < t, "reflection pad {pad} needs a length above it, got {t}");
    x.pad([(pad, pad)], burn::tensor::ops::PadMode::Reflect)
}

/// Instance normalisation without affine parameters: per sample and channel, over time.
pub fn instance_norm(x: Tensor<3>) -> Tensor<3> {
    let (var, mean) = x.clone().var_mean_bias(2);
    (x - mean) / (var + NORM_EPS).sqrt()
}

/// Nearest-neighbour upsampling ×2 along time: `[B, C, T]` → `[B, C, 2T]`, each frame twice.
pub fn upsample_nearest2(x: Tensor<3>) -> Tensor<3> {
    let [b, c, t] = x.dims();
    x.unsqueeze_dim::<4>(3).repeat_dim(3, 2).reshape([b, c, 2 * t])
}

/// One-hot rows for `labels` (`[labels.len(), num_classes]`). Labels must be `< num_classes`.
pub fn one_hot(labels: &[usize], num_classes: usize, device: &Device) -> Tensor<2> {
    let mut data = vec![0f32; labels.len() * num_classes];
    for (row, &label) in labels.iter().enumerate() {
        assert!(label < num_classes, "label {label} out of range {num_classes}");
        data[row * num_classes + label] = 1.0;
    }
    Tensor::from_data(TensorData::new(data, [labels.len(), num_classes]), device)
}

/// The channels `range` of a `[B, C, T]` tensor (a slice of the feature layout, say).
pub fn channels(x: Tensor<3>, range: std::ops::Range<usize>) -> Tensor<3> {
    x.narrow(1, range.start, range.len())
}

/// A 1-D convolution with Xavier-normal weights and (optionally) a zero bias. `zero_pad` frames of
/// zero padding are applied by the convolution itself.
pub fn xavier_conv1d(
    channels_in: usize,
    channels_out: usize,
    kernel: usize,
    stride: usize,
    zero_pad: usize,
    bias: bool,
    device: &Device,
) -> Conv1d {
    let padding = if zero_pad > 0 { PaddingConfig1d::Explicit(zero_pad, zero_pad) } else { PaddingConfig1d::Valid };
    let mut conv = Conv1dConfig::new(channels_in, channels_out, kernel)
        .with_stride(stride)
        .with_padding(padding)
        .with_bias(false)
        .with_initializer(Initializer::XavierNormal { gain: 1.0 })
        .init(device);
    if bias {
        conv.bias = Some(Initializer::Zeros.init([channels_out], device));
    }
    conv
}

/// Settings of one [`ConvLayer`].
#[derive(Clone, Debug)]
pub struct ConvLayerConfig {
    pub channels_in: usize,
    pub channels_out: usize,
    pub kernel: usize,
    pub stride: usize,
    /// Nearest ×2 upsampling before the convolution; implies zero padding (reference's
    /// `SimpleConv1dLayer` / `StyleConv1dLayer`).
    pub upsample: bool,
    /// Zero padding inside the convolution instead of reflection padding before it.
    pub zero_pad: bool,
    pub instance_norm: bool,
    pub dropout: f64,
    pub activate: bool,
    pub bias: bool,
}

impl ConvLayerConfig {
    /// Reflection-padded conv (pad `kernel/2`), bias, LeakyReLU, no norm, no dropout.
    pub fn new(channels_in: usize, channels_out: usize, kernel: usize) -> Self {
        Self {
            channels_in,
            channels_out,
            kernel,
            stride: 1,
            upsample: false,
            zero_pad: false,
            instance_norm: false,
            dropout: 0.0,
            activate: true,
            bias: true,
        }
    }
    /// Stride 2 (halves an even length for k3).
    pub fn down(mut self) -> Self {
        self.stride = 2;
        self
    }
    /// Nearest ×2 upsampling then a zero-padded conv.
    pub fn up(mut self) -> Self {
        self.upsample = true;
        self.zero_pad = true;
        self
    }
    /// Zero padding instead of reflection.
    pub fn zero_padded(mut self) -> Self {
        self.zero_pad = true;
        self
    }
    /// Instance norm after the conv.
    pub fn norm(mut self) -> Self {
        self.instance_norm = true;
        self
    }
    /// Dropout with probability `p` after the conv (and norm).
    pub fn dropout(mut self, p: f64) -> Self {
        self.dropout = p;
        self
    }
    /// No activation (output layers).
    pub fn linear_out(mut self) -> Self {
        self.activate = false;
        self
    }
    /// No bias.
    pub fn no_bias(mut self) -> Self {
        self.bias = false;
        self
    }

    pub fn init(&self, device: &Device) -> ConvLayer {
        let pad = self.kernel / 2;
        let (reflect_pad, zero_pad) = if self.zero_pad { (0, pad) } else { (pad, 0) };
        ConvLayer {
            conv: xavier_conv1d(
                self.channels_in,
                self.channels_out,
                self.kernel,
                self.stride,
                zero_pad,
                self.bias,
                device,
            ),
            upsample: self.upsample,
            reflect_pad,
            instance_norm: self.instance_norm,
            dropout: (self.dropout > 0.0).then(|| DropoutConfig::new(self.dropout).init()),
            activate: self.activate,
            prepared: None,
        }
    }
}

/// [upsample ×2] → [reflection pad] → conv → [instance norm] → [dropout] → [LeakyReLU 0.2].
#[derive(Module, Debug)]
pub struct ConvLayer {
    pub conv: Conv1d,
    pub upsample: bool,
    pub reflect_pad: usize,
    pub instance_norm: bool,
    pub dropout: Option<Dropout>,
    pub activate: bool,
    /// The taps inference convolves with, once [`ConvLayer::fold_for_inference`] has computed
    /// them (not part of the weights; never set in training).
    #[module(skip)]
    prepared: Option<PreparedTaps>,
}

/// What [`ConvLayer::fold_for_inference`] computes once from a layer's weights.
#[derive(Clone, Debug)]
enum PreparedTaps {
    /// An upsampling layer's folded taps ([`fold_upsampling_taps`]), `[2·C_out, 2·C_in]`; on the
    /// CPU also its bias as values, for the interleave with the bias and the activation in one
    /// pass ([`super::cpu_conv::interleave_parities`]).
    Upsampling(Tensor<2>, Option<Arc<CpuBias>>),
    /// A kernel-3, stride-1 layer's taps one after another ([`split_taps`]), `[3, C_out, C_in]`;
    /// on the CPU also as values with the bias, for the products into one buffer
    /// ([`super::cpu_conv`]).
    Shifted(Tensor<3>, Option<Arc<CpuTaps>>),
}

impl ConvLayer {
    /// Inference only: computes once the taps the layer's forward then convolves with, for the
    /// layers where that saves copies: an upsampling layer's folded taps
    /// ([`fold_upsampling_taps`]: it convolves the frames as they are, [`upsample2_conv1d_gemm_cbt`],
    /// 2/3 of the multiply-adds, without the upsampled copy), and a kernel-3, stride-1 layer's taps
    /// one after another ([`split_taps`]: three products on shifted views of the padded frames,
    /// [`conv3_shifted_cbt`], without building columns). Computing them on every call costs more
    /// than it saves at one sample (the folded taps: 1.5-1.8x slower), so without this the layer
    /// upsamples and builds columns. The taps are a copy of the weights as they are now: a layer
    /// that is trained or gets other weights afterwards must not have them
    /// (`stylize::Weights::prepare_for_inference` calls this; trainers never do). Other layers
    /// (stride 2, kernel 1): nothing.
    pub fn fold_for_inference(&mut self) {
        let [_, _, k] = self.conv.weight.dims();
        self.prepared = if self.upsample && self.reflect_pad == 0 {
            fold_upsampling_taps(&self.conv).map(|folded| {
                let on_cpu = (folded.device() == Device::flex())
                    .then(|| CpuBias::new(self.conv.bias.as_ref().map(|b| b.val()), self.conv.weight.dims()[0]))
                    .flatten();
                PreparedTaps::Upsampling(folded, on_cpu)
            })
        } else if !self.upsample && k == 3 && self.conv.stride == 1 && self.padding().is_some() {
            let taps = split_taps(&self.conv);
            let on_cpu = (taps.device() == Device::flex())
                .then(|| CpuTaps::new(taps.clone(), self.conv.bias.as_ref().map(|b| b.val())))
                .flatten();
            Some(PreparedTaps::Shifted(taps, on_cpu))
        } else {
            None
        };
    }

    /// The kernel-3 layer's padding as [`conv3_shifted_cbt`] takes it: reflection (`true`) or zero
    /// (`false`) padding of 1 on either side; `None` for other paddings.
    fn padding(&self) -> Option<bool> {
        match (self.reflect_pad, gemm_padding(&self.conv)) {
            (1, Some(0)) => Some(true),
            (0, Some(1)) => Some(false),
            _ => None,
        }
    }

    /// `x`: `[B, C_in, T]` → `[B, C_out, T']`.
    pub fn forward(&self, x: Tensor<3>) -> Tensor<3> {
        from_cbt(self.forward_cbt(to_cbt(x)))
    }

    /// The same layer on the batch-inner layout `[C_in, B, T]` → `[C_out, B, T']` (see
    /// [`to_cbt`]): chains of layers stay in it, so the convolution's matrix product needs no
    /// transposition of its input or output (in training, none in the backward either).
    pub fn forward_cbt(&self, x: Tensor<3>) -> Tensor<3> {
        let prepared = self.prepared.as_ref().filter(|_| !x.is_tracked());
        let mut x = match (prepared, self.padding()) {
            // Inference: the upsampling and the convolution in one, on the frames as they are.
            (Some(PreparedTaps::Upsampling(folded, on_cpu)), _) if folded.device() == x.device() => {
                let fuse = !self.instance_norm && self.dropout.is_none() && self.activate;
                if let Some(bias) = on_cpu
                    && let Some(out) = upsample2_conv1d_on_cpu(folded.clone(), bias, x.clone(), fuse)
                {
                    if fuse {
                        return out;
                    }
                    out
                } else {
                    upsample2_conv1d_gemm_cbt(&self.conv, Some(folded.clone()), x)
                }
            }
            // Inference: three products on shifted views of the padded frames, no columns.
            (Some(PreparedTaps::Shifted(taps, on_cpu)), Some(reflect))
                if taps.device() == x.device()
                    && x.dims()[1] >= SHIFTED_MIN_BATCH
                    && (!reflect || x.dims()[2] >= 2) =>
            {
                let frames = x.dims()[2];
                // Without a norm, the activation goes over the whole contiguous product (one
                // vectorised pass; the padding frames' few extra values are cut after): on the
                // cut view flex would go block by block, 4 % of a ten-sample batch.
                let fuse = !self.instance_norm && self.dropout.is_none() && self.activate;
                if let Some(cpu) = on_cpu
                    && let Some(out) = conv3_shifted_on_cpu(cpu, x.clone(), reflect, fuse)
                {
                    if fuse {
                        return out;
                    }
                    out
                } else {
                    let padded = conv3_shifted_padded_cbt(&self.conv, taps, x, reflect);
                    if fuse {
                        return leaky_relu(padded).narrow(2, 0, frames);
                    }
                    padded.narrow(2, 0, frames)
                }
            }
            _ => {
                let x = if self.upsample { upsample_nearest2(x) } else { x };
                let x = reflect_pad_time(x, self.reflect_pad);
                // The convolution as one matrix product for the batch on the weights as stored, in
                // inference and in training (there differentiated as plain tensor ops: its backward is
                // two matrix products, 1.3-1.9x faster than Burn's convolution backward on flex;
                // `examples/conv_train_bench.rs`).
                conv1d_gemm_cbt(&self.conv, x)
            }
        };
        if self.instance_norm {
            x = instance_norm(x);
        }
        if let Some(dropout) = &self.dropout {
            x = dropout.forward(x);
        }
        if self.activate {
            x = leaky_relu(x);
        }
        x
    }
}

/// `[B, C, T]` → the batch-inner layout `[C, B, T]` the layers compute in (a view: a copy happens
/// only where an operation needs contiguous data; none for one clip). Every per-sample operation
/// of the networks (convolution over time, instance norm, upsampling, padding) works on time,
/// the last axis, in either layout; in this one the convolution of the whole batch is a single
/// matrix product `[C_out, C_in·k] × [C_in·k, B·T]` with no transposition around it.
pub fn to_cbt(x: Tensor<3>) -> Tensor<3> {
    let [b, c, t] = x.dims();
    if b == 1 { x.reshape([c, 1, t]) } else { x.swap_dims(0, 1) }
}

/// `[C, B, T]` → `[B, C, T]`, the inverse of [`to_cbt`].
pub fn from_cbt(x: Tensor<3>) -> Tensor<3> {
    let [c, b, t] = x.dims();
    if b == 1 { x.reshape([1, c, t]) } else { x.swap_dims(0, 1) }
}

/// A per-sample vector `[B, S]` tiled over `len` time steps in the batch-inner layout: `[S, B, len]`.
pub fn tile_time_cbt(v: Tensor<2>, len: usize) -> Tensor<3> {
    v.swap_dims(0, 1).unsqueeze_dim::<3>(2).repeat_dim(2, len)
}

/// The zero padding `conv1d_gemm_cbt` applies itself, or `None` for the shapes it leaves to
/// `conv.forward` (dilation, groups, kernels other than 1 and 3, asymmetric padding).
fn gemm_padding(conv: &Conv1d) -> Option<usize> {
    let [_, _, k] = conv.weight.dims();
    let stride = conv.stride;
    let supported = conv.dilation == 1 && conv.groups == 1 && ((k == 1 && stride == 1) || (k == 3 && stride <= 2));
    match &conv.padding {
        PaddingConfig1d::Valid if supported => Some(0),
        PaddingConfig1d::Explicit(l, r) if supported && l == r => Some(*l),
        _ => None,
    }
}

/// `conv`'s convolution on `[B, C_in, T]`: [`conv1d_gemm_cbt`] between layout changes.
pub fn conv1d_gemm(conv: &Conv1d, x: Tensor<3>) -> Tensor<3> {
    if gemm_padding(conv).is_none() {
        return conv.forward(x);
    }
    from_cbt(conv1d_gemm_cbt(conv, to_cbt(x)))
}

/// `conv`'s convolution (dilation 1, one group; its own zero padding if any) on the batch-inner
/// layout `[C_in, B, T]` → `[C_out, B, T_out]`, as one matrix product for the whole batch: the
/// kernel's taps of the input stacked into columns `[C_in·k, B·T_out]` (ordered channel-major,
/// tap-minor: the weight's own `[C_out, C_in, k]` layout viewed as `[C_out, C_in·k]`, so no weight
/// is copied or re-laid out), times the weight, plus the bias. Kernel 1 at stride 1 and kernel 3
/// at stride 1 or 2 (what the networks use); other shapes go to `conv.forward`. The same numbers
/// as `conv.forward` up to float rounding (sums in another order). Burn's flex convolution
/// re-lays out every weight into a new buffer and the input into channels-last on every call,
/// then multiplies clip by clip; this is 1.1-1.3x faster natively, the same in wasm
/// (bench/README.md).
pub fn conv1d_gemm_cbt(conv: &Conv1d, x: Tensor<3>) -> Tensor<3> {
    let weight = conv.weight.val();
    let [c_out, c_in, k] = weight.dims();
    let stride = conv.stride;
    let Some(pad) = gemm_padding(conv) else { return to_cbt(conv.forward(from_cbt(x))) };
    let [_, b, t] = x.dims();
    let x = if pad > 0 {
        let zeros = Tensor::<3>::zeros([c_in, b, pad], &x.device());
        Tensor::cat(vec![zeros.clone(), x, zeros], 2)
    } else {
        x
    };
    let t_pad = t + 2 * pad;
    if t_pad < k {
        return to_cbt(conv.forward(from_cbt(x)));
    }
    let t_out = (t_pad - k) / stride + 1;
    // Time of all clips side by side: one product for the whole batch (the weights packed once,
    // and a wide right-hand side even where T is short).
    let cols = if k == 1 {
        x.reshape([c_in, b * t_out])
    } else if !x.is_tracked() {
        // Without a graph (inference): the taps as one strided view of `x` (flex's unfold is a
        // view: `[C_in, B, T_out, k]`, stride 2 included), laid out `[C_in, k, B, T_out]` by one
        // copy. The same columns as the stacked taps below, which copy each tap twice (made
        // contiguous, then concatenated). Not in training: Burn differentiates unfold window by
        // window.
        x.unfold::<4, _>(2, k, stride).permute([0, 3, 1, 2]).reshape([c_in * k, b * t_out])
    } else {
        let taps: Vec<Tensor<3>> = (0..k)
            .map(|j| {
                if stride == 1 {
                    return x.clone().narrow(2, j, t_out);
                }
                // Stride 2: tap j of output t reads frame 2t + j.
                let span = if j + 2 * t_out <= t_pad {
                    x.clone().narrow(2, j, 2 * t_out)
                } else {
                    let span = x.clone().narrow(2, j, 2 * t_out - 1);
                    Tensor::cat(vec![span.clone(), span.narrow(2, 0, 1)], 2)
                };
                span.reshape([c_in, b, t_out, 2]).narrow(3, 0, 1).reshape([c_in, b, t_out])
            })
            .collect();
        Tensor::stack::<4>(taps, 1).reshape([c_in * k, b * t_out])
    };
    let out = weight.reshape([c_out, c_in * k]).matmul(cols);
    let out = match &conv.bias {
        Some(bias) => out + bias.val().reshape([c_out, 1]),
        None => out,
    };
    out.reshape([c_out, b, t_out])
}

/// The folded taps of `conv` (kernel 3, stride 1, zero padding 1) after nearest ×2 upsampling,
/// `[2·C_out, C_in·2]`: `[W₀, W₁+W₂]` for the even outputs over `[W₀+W₁, W₂]` for the odd ones
/// (see [`upsample2_conv1d_gemm_cbt`]); `None` for other shapes.
pub fn fold_upsampling_taps(conv: &Conv1d) -> Option<Tensor<2>> {
    let [c_out, c_in, k] = conv.weight.dims();
    if k != 3 || conv.stride != 1 || gemm_padding(conv) != Some(1) {
        return None;
    }
    // Built on the weight's taps as rows `[3, C_out·C_in]` ([`split_taps`]: one transposing copy,
    // then every slice, sum and stack is of whole rows), turned back to `[C_out, C_in·2]` per
    // parity by one transposing copy and stacked even over odd. (Slicing the taps out of the
    // weight as stored, `narrow` on its last dimension then `cat`, goes element by element in
    // flex: 3x slower.)
    let taps = split_taps(conv).reshape([3, c_out * c_in]);
    let tap = |j: usize| taps.clone().narrow(0, j, 1);
    let parity = |a: Tensor<2>, b: Tensor<2>| Tensor::cat(vec![a, b], 0).transpose().reshape([c_out, c_in * 2]);
    let even = parity(tap(0), tap(1) + tap(2));
    let odd = parity(tap(0) + tap(1), tap(2));
    Some(Tensor::cat(vec![even, odd], 0))
}

/// `conv` (kernel 3, stride 1, zero padding 1) on `x` upsampled ×2 by repeating each frame, on the
/// batch-inner layout: `[C_in, B, T]` → `[C_out, B, 2T]`, without building the upsampled input;
/// `folded`: [`fold_upsampling_taps`] of `conv` if computed already.
///
/// With `u` the upsampled frames (`u[2s] = u[2s+1] = x[s]`) output `2s` reads `(x[s-1], x[s], x[s])`
/// and output `2s+1` reads `(x[s], x[s], x[s+1])` (zeros past either end): a two-tap convolution
/// of `x` with the taps folded, `[W₀, W₁+W₂]` for the even outputs and `[W₀+W₁, W₂]` for the odd
/// ones. Both read the same windows of two frames, so one product of the stacked folded weights
/// `[2·C_out, C_in·2]` with the columns `[C_in·2, B·(T+1)]` gives both, then they are interleaved.
/// Two thirds of the multiply-adds of the upsampled convolution and a third of its columns. The
/// sums differ from the upsampled convolution's by float rounding only (the folded taps are added
/// first: outputs within 6e-6 of the network's before, `bench/README.md`); inference only —
/// training differentiates the upsampled convolution as written. Other shapes fall back to
/// upsampling then [`conv1d_gemm_cbt`].
pub fn upsample2_conv1d_gemm_cbt(conv: &Conv1d, folded: Option<Tensor<2>>, x: Tensor<3>) -> Tensor<3> {
    let Some(folded) = folded.or_else(|| fold_upsampling_taps(conv)) else {
        return conv1d_gemm_cbt(conv, upsample_nearest2(x));
    };
    let c_out = conv.weight.dims()[0];
    let [_, b, t] = x.dims();
    let out = interleave_parities(folded.matmul(upsampling_columns(x)), c_out, b, t);
    match &conv.bias {
        Some(bias) => out + bias.val().reshape([c_out, 1, 1]),
        None => out,
    }
}

/// The columns of [`upsample2_conv1d_gemm_cbt`]'s product: windows of two frames of `x`
/// `[C_in, B, T]` zero-padded by one frame on either side, `[C_in·2, B·(T+1)]`.
fn upsampling_columns(x: Tensor<3>) -> Tensor<2> {
    let [c_in, b, t] = x.dims();
    let zeros = Tensor::<3>::zeros([c_in, b, 1], &x.device());
    let padded = Tensor::cat(vec![zeros.clone(), x, zeros], 2);
    // Windows of two frames (a view), laid out `[C_in, 2, B, T+1]` by one copy.
    padded.unfold::<4, _>(2, 2, 1).permute([0, 3, 1, 2]).reshape([c_in * 2, b * (t + 1)])
}

/// [`upsample2_conv1d_gemm_cbt`] on flex with the folded taps and the bias as values
/// ([`CpuBias`]): the parities interleaved, the bias added and (with `activate`) the LeakyReLU in
/// one pass over the product ([`super::cpu_conv::interleave_parities`]); the same bytes as the
/// tensor path. `None` where the product is not `f32` (the caller takes the tensor path).
pub fn upsample2_conv1d_on_cpu(folded: Tensor<2>, bias: &CpuBias, x: Tensor<3>, activate: bool) -> Option<Tensor<3>> {
    let [_, b, t] = x.dims();
    let device = x.device();
    let c_out = bias.c_out();
    let data = folded.matmul(upsampling_columns(x)).into_data();
    let values = cpu_conv::interleave_parities(data.as_slice::<f32>().ok()?, c_out, b, t, Some(bias), activate)?;
    Some(Tensor::from_data(TensorData::new(values, [c_out, b, 2 * t]), &device))
}

/// The two parities of [`upsample2_conv1d_gemm_cbt`]'s product `[2·C_out, B·(T+1)]` interleaved
/// into `[C_out, B, 2T]`: output `2s + p` of channel `c`, clip `b` is the product's row
/// `p·C_out + c`, column `b·(T+1) + s + p`. On the CPU in one pass of plain Rust over the values
/// ([`cpu_conv::interleave_parities`]: the three copies of the tensor operations took 4 % of a
/// ten-sample batch on an AVX-512 Xeon), elsewhere by [`interleave_parities_by_tensor_ops`]; the
/// same values moved either way, so the same bytes.
pub fn interleave_parities(product: Tensor<2>, c_out: usize, b: usize, t: usize) -> Tensor<3> {
    if product.device() != Device::flex() {
        return interleave_parities_by_tensor_ops(product, c_out, b, t);
    }
    let device = product.device();
    let data = product.into_data();
    let values = data.as_slice::<f32>().ok().and_then(|v| cpu_conv::interleave_parities(v, c_out, b, t, None, false));
    match values {
        Some(values) => Tensor::from_data(TensorData::new(values, [c_out, b, 2 * t]), &device),
        None => interleave_parities_by_tensor_ops(Tensor::from_data(data, &device), c_out, b, t),
    }
}

/// [`interleave_parities`] in tensor operations (any device): the even outputs are windows 0..T,
/// the odd ones 1..T+1, the two aligned by one copy along the outer dimension (a concatenation
/// along the inner one goes element by element in flex), then interleaved by one transposing
/// copy — three copies in all, as the shifted halves are made contiguous first.
pub fn interleave_parities_by_tensor_ops(product: Tensor<2>, c_out: usize, b: usize, t: usize) -> Tensor<3> {
    let out = product.reshape([2, c_out, b, t + 1]);
    let even = out.clone().narrow(0, 0, 1).narrow(3, 0, t);
    let odd = out.narrow(0, 1, 1).narrow(3, 1, t);
    Tensor::cat(vec![even, odd], 0).permute([1, 2, 3, 0]).reshape([c_out, b, 2 * t])
}

/// The smallest batch [`conv3_shifted_cbt`] is used for (the layers take [`conv1d_gemm_cbt`]
/// below it). Measured natively, one thread, on the AMD EPYC family 25 model 1 (Zen 3, AVX2) with
/// both paths in one process taking turns (bench/README.md): a 160-frame label-based batch
/// of 10 samples 4-7 % faster, of 4 the same, of 2 3-4 % slower and of 1 13 % slower (three
/// products of a few frames each cost more than the one column copy they save).
pub const SHIFTED_MIN_BATCH: usize = 4;

/// A kernel-3 convolution's taps one after another, `[3, C_out, C_in]` (tap `j` is
/// `weight[:, :, j]`), for [`conv3_shifted_cbt`]. Built on the weight's taps as rows (one
/// transposing copy; flex reshapes a transposed view by laying it out).
pub fn split_taps(conv: &Conv1d) -> Tensor<3> {
    let [c_out, c_in, k] = conv.weight.dims();
    assert_eq!(k, 3, "split_taps: a kernel of 3, got {k}");
    let n = c_out * c_in;
    // (Reshaping the transposed view lays it out: flex reshapes a strided view by copying it.)
    conv.weight.val().reshape([n, 3]).transpose().reshape([3 * n]).reshape([3, c_out, c_in])
}

/// `conv` (kernel 3, stride 1; `reflect`: the layer's reflection padding of 1 before a
/// convolution without padding, else the convolution's own zero padding of 1) on the batch-inner
/// layout `[C_in, B, T]` → `[C_out, B, T]`, inference only, with `taps` = [`split_taps`]`(conv)`:
/// no columns. The clips are padded side by side into one sequence, with a clip of zeros after
/// the last — reflection: `[x₁, x₀ … x_{T−1}, x_{T−2}]` per clip, `L = T + 2` frames; zero
/// padding: one zero frame before each clip, which is also the previous clip's right padding,
/// `L = T + 1` — and viewed as a matrix `[C_in, (B+1)·L]`. Output frame `t` of clip `b` is
/// column `p = b·L + t` of `Σⱼ Wⱼ · (columns j … j + B·L of that matrix)`: three products on
/// shifted views (flex hands their strides to gemm: nothing is copied), summed, then viewed as
/// `[C_out, B, L]` and cut to `T` frames. One copy of the input (the padding) instead of two, the
/// second of them the tap-by-tap column build (`copy_2d_tiled`, a fifth of the ten-sample batch's
/// time natively on an AVX2 machine); the same multiply-adds plus `2/T` for the padding columns.
/// The sums differ from [`conv1d_gemm_cbt`]'s by float rounding only (three partial sums).
/// Reflection needs `T ≥ 2`.
pub fn conv3_shifted_cbt(conv: &Conv1d, taps: &Tensor<3>, x: Tensor<3>, reflect: bool) -> Tensor<3> {
    let frames = x.dims()[2];
    conv3_shifted_padded_cbt(conv, taps, x, reflect).narrow(2, 0, frames)
}

/// [`conv3_shifted_cbt`] before its last step: `[C_out, B, L]` with every clip's `T` frames
/// first and `L − T` padding frames (values of no use) after them, contiguous.
fn conv3_shifted_padded_cbt(conv: &Conv1d, taps: &Tensor<3>, x: Tensor<3>, reflect: bool) -> Tensor<3> {
    let [_, c_out, c_in] = taps.dims();
    let b = x.dims()[1];
    let (flat, l) = shifted_input(x, reflect);
    let n = b * l;
    let tap = |j: usize| taps.clone().narrow(0, j, 1).reshape([c_out, c_in]);
    let shifted = |j: usize| tap(j).matmul(flat.clone().narrow(1, j, n));
    let mut out = shifted(0) + shifted(1);
    out = out + shifted(2);
    if let Some(bias) = &conv.bias {
        out = out + bias.val().reshape([c_out, 1]);
    }
    out.reshape([c_out, b, l])
}

/// The shifted products' input: the clips `[C_in, B, T]` padded side by side, with a clip of zeros
/// after the last, as a matrix `[C_in, (B+1)·L]` (see [`conv3_shifted_cbt`]), and `L`.
fn shifted_input(x: Tensor<3>, reflect: bool) -> (Tensor<2>, usize) {
    let [c_in, b, t] = x.dims();
    let device = x.device();
    let (padded, l) = if reflect {
        let l = t + 2;
        let padded = Tensor::<3>::zeros([c_in, b + 1, l], &device)
            .slice_assign([0..c_in, 0..b, 0..1], x.clone().narrow(2, 1, 1))
            .slice_assign([0..c_in, 0..b, t + 1..t + 2], x.clone().narrow(2, t - 2, 1))
            .slice_assign([0..c_in, 0..b, 1..t + 1], x);
        (padded, l)
    } else {
        // Batch: one clip of zeros after the last; time: one zero frame before each clip.
        (x.pad([(0, 1), (1, 0)], burn::tensor::ops::PadMode::Constant(0.0)), t + 1)
    };
    (padded.reshape([c_in, (b + 1) * l]), l)
}

/// [`conv3_shifted_cbt`] on flex with the taps as values ([`CpuTaps`]): the three products
/// accumulated into one buffer, the bias and (with `activate`) the LeakyReLU in one pass over it
/// ([`super::cpu_conv::shifted_products`]). Other sums than the tensor path's only where `gemm`
/// splits a product's input channels into blocks (within float rounding). `None` where the input
/// is not `f32` (the caller takes the tensor path).
pub fn conv3_shifted_on_cpu(taps: &CpuTaps, x: Tensor<3>, reflect: bool, activate: bool) -> Option<Tensor<3>> {
    let [_, b, t] = x.dims();
    let device = x.device();
    let (flat, l) = shifted_input(x, reflect);
    let ld = flat.dims()[1];
    let data = flat.into_data();
    let values = shifted_products(taps, data.as_slice::<f32>().ok()?, ld, b * l, activate)?;
    let out = Tensor::<3>::from_data(TensorData::new(values, [taps.c_out(), b, l]), &device);
    Some(out.narrow(2, 0, t))
}

/// Adaptive instance normalisation: `γ · IN(x) + β`, with `[γ ; β]` from one linear layer on the
/// conditioning vector `[style code ; one-hot label]`. The bias starts at γ = 1, β = 0, so an
/// untrained AdaIN is plain instance norm.
#[derive(Module, Debug)]
pub struct AdaIn {
    pub linear: Linear,
    pub channels: usize,
}

impl AdaIn {
    pub fn new(channels: usize, cond_dim: usize, device: &Device) -> Self {
        let mut linear = LinearConfig::new(cond_dim, 2 * channels)
            .with_bias(false)
            .with_initializer(Initializer::XavierNormal { gain: 1.0 })
            .init(device);
        let bias = Tensor::cat(vec![Tensor::<1>::ones([channels], device), Tensor::zeros([channels], device)], 0);
        linear.bias = Some(Param::from_tensor(bias));
        Self { linear, channels }
    }

    /// `x`: `[B, C, T]`, `cond`: `[B, cond_dim]`.
    pub fn forward(&self, x: Tensor<3>, cond: Tensor<2>) -> Tensor<3> {
        let c = self.channels;
        let gb = self.linear.forward(cond);
        let gamma = gb.clone().narrow(1, 0, c).unsqueeze_dim::<3>(2);
        let beta = gb.narrow(1, c, c).unsqueeze_dim::<3>(2);
        instance_norm(x) * gamma + beta
    }

    /// The same on the batch-inner layout: `x`: `[C, B, T]`, `cond`: `[B, cond_dim]`.
    pub fn forward_cbt(&self, x: Tensor<3>, cond: Tensor<2>) -> Tensor<3> {
        let c = self.channels;
        let gb = self.linear.forward(cond).swap_dims(0, 1);
        let gamma = gb.clone().narrow(0, 0, c).unsqueeze_dim::<3>(2);
        let beta = gb.narrow(0, c, c).unsqueeze_dim::<3>(2);
        instance_norm(x) * gamma + beta
    }
}
