//! The convolutions as matrix products (layout `[C, B, T]`, see [`super::layers::to_cbt`]): the
//! taps stacked into columns (inference and training), and the inference-only paths a
//! [`super::layers::ConvLayer`] prepares at load — the upsampling layers' folded taps and the
//! kernel-3 layers' shifted products, in tensor operations on any device and on the CPU in plain
//! passes over the values ([`super::cpu_conv`]).

use burn::nn::PaddingConfig1d;
use burn::nn::conv::Conv1d;
use burn::prelude::*;

use super::cpu_conv::{self, CpuTaps, CpuUpsampling, WINOGRAD_MIN_PAIRS, shifted_products, winograd_products};
use super::layers::{from_cbt, leaky_relu, to_cbt, upsample_nearest2};

/// The zero padding `conv1d_gemm_cbt` applies itself, or `None` for the shapes it leaves to
/// `conv.forward` (dilation, groups, kernels other than 1 and 3, asymmetric padding).
pub(crate) fn gemm_padding(conv: &Conv1d) -> Option<usize> {
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
    upsampling_foldable(conv).then(|| fold_split_taps(split_taps(conv)))
}

/// Whether `conv` has folded upsampling taps ([`fold_upsampling_taps`]): kernel 3, stride 1, zero
/// padding 1.
pub fn upsampling_foldable(conv: &Conv1d) -> bool {
    conv.weight.dims()[2] == 3 && conv.stride == 1 && gemm_padding(conv) == Some(1)
}

/// [`fold_upsampling_taps`] from the layer's taps one after another ([`split_taps`],
/// `[3, C_out, C_in]`), for a caller that needs those taps too.
pub fn fold_split_taps(taps: Tensor<3>) -> Tensor<2> {
    let [_, c_out, c_in] = taps.dims();
    // Built on the weight's taps as rows `[3, C_out·C_in]` ([`split_taps`]: one transposing copy,
    // then every slice, sum and stack is of whole rows), turned back to `[C_out, C_in·2]` per
    // parity by one transposing copy and stacked even over odd. (Slicing the taps out of the
    // weight as stored, `narrow` on its last dimension then `cat`, goes element by element in
    // flex: 3x slower.)
    let taps = taps.reshape([3, c_out * c_in]);
    let tap = |j: usize| taps.clone().narrow(0, j, 1);
    let parity = |a: Tensor<2>, b: Tensor<2>| Tensor::cat(vec![a, b], 0).transpose().reshape([c_out, c_in * 2]);
    let even = parity(tap(0), tap(1) + tap(2));
    let odd = parity(tap(0) + tap(1), tap(2));
    Tensor::cat(vec![even, odd], 0)
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

/// [`upsample2_conv1d_gemm_cbt`] on flex with the taps as values ([`CpuUpsampling`]): three
/// products instead of the folded taps' four multiply-adds a frame, combined into the frames in
/// order with the bias and (with `activate`) the LeakyReLU
/// ([`super::cpu_conv::upsampling_products`]). Other sums than the folded taps' (float
/// rounding). `None` where the input is not `f32` (the caller takes the tensor path).
pub fn upsample2_conv1d_on_cpu(up: &CpuUpsampling, x: Tensor<3>, activate: bool) -> Option<Tensor<3>> {
    let [_, b, t] = x.dims();
    let device = x.device();
    let data = x.into_data();
    let values = cpu_conv::upsampling_products(up, data.as_slice::<f32>().ok()?, b, t, activate)?;
    Some(Tensor::from_data(TensorData::new(values, [up.c_out(), b, 2 * t]), &device))
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
    let values = data.as_slice::<f32>().ok().and_then(|v| cpu_conv::interleave_parities(v, c_out, b, t));
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
/// below it; in wasm Winograd's products go below it too, [`shifted_pays`]). Measured natively,
/// one thread, on the AMD EPYC family 25 model 1 (Zen 3, AVX2) with both paths in one process
/// taking turns (bench/README.md): a 160-frame label-based batch
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

/// [`conv3_shifted_cbt`] on flex with the taps as values ([`CpuTaps`]): from
/// [`WINOGRAD_MIN_PAIRS`] pairs of output columns on ([`winograd_pays`]) Winograd's four products
/// ([`super::cpu_conv::winograd_products`]: ⅔ of the multiply-adds, other sums within float
/// rounding), below it the three products accumulated into one buffer
/// ([`super::cpu_conv::shifted_products`]: other sums than the tensor path's only where `gemm`
/// splits a product's input channels into blocks); either way the bias and (with `activate`) the
/// LeakyReLU in the pass that writes the output. `None` where the input is not `f32` (the caller
/// takes the tensor path).
pub fn conv3_shifted_on_cpu(taps: &CpuTaps, x: Tensor<3>, reflect: bool, activate: bool) -> Option<Tensor<3>> {
    let [_, b, t] = x.dims();
    let device = x.device();
    let (flat, l) = shifted_input(x, reflect);
    let ld = flat.dims()[1];
    let data = flat.into_data();
    let (x, n) = (data.as_slice::<f32>().ok()?, b * l);
    let values = if winograd_pays(b, t, reflect) {
        winograd_products(taps, x, ld, n, activate)?
    } else {
        shifted_products(taps, x, ld, n, activate)?
    };
    let out = Tensor::<3>::from_data(TensorData::new(values, [taps.c_out(), b, l]), &device);
    Some(out.narrow(2, 0, t))
}

/// Whether a kernel-3, stride-1 layer takes its prepared products ([`conv3_shifted_prepared`])
/// rather than the columns ([`conv1d_gemm_cbt`]) for `B` clips of `T` frames: from
/// [`SHIFTED_MIN_BATCH`] clips on; in wasm, with the taps as values on the CPU (`on_cpu`), also
/// fewer clips where Winograd's products apply ([`winograd_pays`]). Natively one or two clips stay
/// on the columns: there the one product over `3·C_in` is 1–2 % faster than four narrow ones (the
/// `gemm` crate's packing weighs more against an AVX-512 kernel than against wasm's SIMD128 one).
pub fn shifted_pays(on_cpu: bool, b: usize, t: usize, reflect: bool) -> bool {
    b >= SHIFTED_MIN_BATCH || (cfg!(target_arch = "wasm32") && on_cpu && winograd_pays(b, t, reflect))
}

/// Whether [`conv3_shifted_on_cpu`] takes Winograd's products for `B` clips of `T` frames (padded
/// with reflection or zeros): at least [`WINOGRAD_MIN_PAIRS`] pairs of output columns.
pub fn winograd_pays(b: usize, t: usize, reflect: bool) -> bool {
    let l = if reflect { t + 2 } else { t + 1 };
    (b * l).div_ceil(2) >= WINOGRAD_MIN_PAIRS
}

/// An upsampling layer's prepared convolution ([`super::layers::ConvLayer::fold_for_inference`]):
/// on the CPU Winograd's three products with the bias and (with `activate`) the activation in
/// the pass that combines them ([`upsample2_conv1d_on_cpu`]), elsewhere
/// [`upsample2_conv1d_gemm_cbt`] then the activation.
pub fn upsample2_conv1d_prepared(
    conv: &Conv1d,
    folded: &Tensor<2>,
    on_cpu: Option<&CpuUpsampling>,
    x: Tensor<3>,
    activate: bool,
) -> Tensor<3> {
    if let Some(out) = on_cpu.and_then(|up| upsample2_conv1d_on_cpu(up, x.clone(), activate)) {
        return out;
    }
    let out = upsample2_conv1d_gemm_cbt(conv, Some(folded.clone()), x);
    if activate { leaky_relu(out) } else { out }
}

/// A kernel-3 layer's prepared convolution: on the CPU the products into plain buffers
/// ([`conv3_shifted_on_cpu`]), elsewhere [`conv3_shifted_cbt`]'s products; with `activate`, the
/// activation over the whole product before the frames are cut.
pub fn conv3_shifted_prepared(
    conv: &Conv1d,
    taps: &Tensor<3>,
    on_cpu: Option<&CpuTaps>,
    x: Tensor<3>,
    reflect: bool,
    activate: bool,
) -> Tensor<3> {
    if let Some(out) = on_cpu.and_then(|cpu| conv3_shifted_on_cpu(cpu, x.clone(), reflect, activate)) {
        return out;
    }
    let frames = x.dims()[2];
    let padded = conv3_shifted_padded_cbt(conv, taps, x, reflect);
    let padded = if activate { leaky_relu(padded) } else { padded };
    padded.narrow(2, 0, frames)
}
