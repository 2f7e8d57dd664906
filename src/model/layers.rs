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

use super::conv::{
    conv1d_gemm_cbt, conv3_shifted_prepared, fold_split_taps, gemm_padding, shifted_pays, split_taps,
    upsample2_conv1d_prepared, upsampling_foldable,
};
use super::cpu_conv::{CpuTaps, CpuUpsampling};

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
    /// CPU also its taps and bias as values for Winograd's three products
    /// ([`super::cpu_conv::upsampling_products`]).
    Upsampling(Tensor<2>, Option<Arc<CpuUpsampling>>),
    /// A kernel-3, stride-1 layer's taps one after another ([`split_taps`]), `[3, C_out, C_in]`;
    /// on the CPU also as values with the bias (and transformed for Winograd's F(2, 3)), for the
    /// products into plain buffers ([`super::cpu_conv`]).
    Shifted(Tensor<3>, Option<Arc<CpuTaps>>),
}

impl ConvLayer {
    /// Inference only: computes once the taps the layer's forward then convolves with, for the
    /// layers where that saves copies: an upsampling layer's folded taps
    /// ([`fold_upsampling_taps`]: it convolves the frames as they are, [`upsample2_conv1d_gemm_cbt`],
    /// 2/3 of the multiply-adds, without the upsampled copy), and a kernel-3, stride-1 layer's taps
    /// one after another ([`split_taps`]: three products on shifted views of the padded frames,
    /// [`conv3_shifted_cbt`], without building columns); on the CPU both also as values for
    /// Winograd's products ([`super::cpu_conv`]: ¾ and ⅔ of those multiply-adds). Computing them
    /// on every call costs more than it saves at one sample (the folded taps: 1.5-1.8x slower), so
    /// without this the layer upsamples and builds columns. The taps are a copy of the weights as they are now: a layer
    /// that is trained or gets other weights afterwards must not have them
    /// (`stylize::Weights::prepare_for_inference` calls this; trainers never do). Other layers
    /// (stride 2, kernel 1): nothing.
    pub fn fold_for_inference(&mut self) {
        let [_, _, k] = self.conv.weight.dims();
        self.prepared = if self.upsample && self.reflect_pad == 0 {
            upsampling_foldable(&self.conv).then(|| {
                // Split once: the folded taps and the CPU's Winograd taps are both made from them.
                let taps = split_taps(&self.conv);
                let on_cpu = (taps.device() == Device::flex())
                    .then(|| CpuUpsampling::new(taps.clone(), self.conv.bias.as_ref().map(|b| b.val())))
                    .flatten();
                PreparedTaps::Upsampling(fold_split_taps(taps), on_cpu)
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
        // Without a norm or dropout, the prepared paths apply the activation themselves, over the
        // whole product before the frames are cut (on the cut view flex would go value by value).
        let fuse = !self.instance_norm && self.dropout.is_none() && self.activate;
        let (mut x, activated) = match (prepared, self.padding()) {
            // Inference: the upsampling and the convolution in one, on the frames as they are.
            (Some(PreparedTaps::Upsampling(folded, on_cpu)), _) if folded.device() == x.device() => {
                (upsample2_conv1d_prepared(&self.conv, folded, on_cpu.as_deref(), x, fuse), fuse)
            }
            // Inference: products on shifted views of the padded frames, no columns (on the CPU
            // by Winograd's F(2, 3) where there are enough frames; in wasm then for one clip too).
            (Some(PreparedTaps::Shifted(taps, on_cpu)), Some(reflect))
                if taps.device() == x.device()
                    && shifted_pays(on_cpu.is_some(), x.dims()[1], x.dims()[2], reflect)
                    && (!reflect || x.dims()[2] >= 2) =>
            {
                (conv3_shifted_prepared(&self.conv, taps, on_cpu.as_deref(), x, reflect, fuse), fuse)
            }
            _ => {
                let x = if self.upsample { upsample_nearest2(x) } else { x };
                let x = reflect_pad_time(x, self.reflect_pad);
                // The convolution as one matrix product for the batch on the weights as stored, in
                // inference and in training (there differentiated as plain tensor ops: its backward is
                // two matrix products, 1.3-1.9x faster than Burn's convolution backward on flex;
                // `examples/conv_train_bench.rs`).
                (conv1d_gemm_cbt(&self.conv, x), false)
            }
        };
        if self.instance_norm {
            x = instance_norm(x);
        }
        if let Some(dropout) = &self.dropout {
            x = dropout.forward(x);
        }
        if self.activate && !activated {
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
