//! Inference passes on the CPU (flex) over plain `f32` values, where tensor operations cost
//! copies or multiply-adds: the kernel-3 layers' products computed into one buffer — by
//! Winograd's minimal filtering F(2, 3) where there are enough frames ([`winograd_products`]:
//! ⅔ of the multiply-adds), else the three shifted products accumulated ([`shifted_products`]) —
//! and the upsampling layers' three products ([`upsampling_products`]: ¾ of the folded taps'),
//! each finished with the bias and the activation in the pass that writes the output.
//!
//! [`super::conv::conv3_shifted_cbt`] convolves with three matrix products on shifted views of
//! the padded frames, then adds them and the bias, then (in the layer) applies the activation:
//! through Burn, each product gets an output buffer of its own (flex zero-fills it, then copies
//! it into an aligned allocation) and each addition and the activation is a pass over the
//! output. Here the products go into plain buffers by the `gemm` crate Burn's flex backend calls
//! itself (the same crate and version, the same kernels), and the transforms, the bias and the
//! LeakyReLU are passes of plain Rust. Written by hand because Burn has no matrix product that
//! accumulates into an existing tensor, and no Winograd convolution.
//!
//! Winograd's transforms regroup the convolution's sums (the weights' and the inputs' sums and
//! differences are formed first), so its outputs differ from the direct convolution's by float
//! rounding: within 1e-5 of values of order one in `tests/model_networks.rs`, and the stylized
//! motions' evaluation unchanged (EVALUATION.md, bench/README.md).

use std::sync::Arc;

use burn::prelude::*;

use super::layers::LEAKY_SLOPE;

/// A layer's bias as values (or none) and what the passes on the CPU finish each output row
/// with: the bias added, then the LeakyReLU if asked — the operations, in the order, of the
/// tensor path (`out + bias`, then [`super::layers::leaky_relu`]), so the same bytes.
#[derive(Debug)]
pub struct CpuBias {
    values: Option<Vec<f32>>,
    c_out: usize,
}

impl CpuBias {
    /// From a layer's bias `[C_out]` (or none); `None` where its values are not `C_out` `f32`s.
    pub fn new(bias: Option<Tensor<1>>, c_out: usize) -> Option<Self> {
        let values = match bias {
            Some(b) => Some(b.into_data().try_to_vec::<f32>().ok().filter(|v| v.len() == c_out)?),
            None => None,
        };
        Some(Self { values, c_out })
    }

    pub fn c_out(&self) -> usize {
        self.c_out
    }

    /// Output channel `c`'s row: the bias added, then the LeakyReLU if `activate`.
    fn finish(&self, c: usize, row: &mut [f32], activate: bool) {
        if let Some(bias) = &self.values {
            let b = bias[c];
            row.iter_mut().for_each(|v| *v += b);
        }
        if activate {
            // As Burn's flex LeakyReLU computes it.
            let slope = LEAKY_SLOPE as f32;
            row.iter_mut().for_each(|v| *v = if *v >= 0.0 { *v } else { slope * *v });
        }
    }
}

/// The taps one after another `[3, C_out, C_in]` as values, with `C_out` and `C_in`; `None` where
/// they are not three taps of `f32`.
fn tap_values(taps: Tensor<3>) -> Option<(Vec<f32>, usize, usize)> {
    let [k, c_out, c_in] = taps.dims();
    let values = taps.into_data().try_to_vec::<f32>().ok().filter(|v| k == 3 && v.len() == 3 * c_out * c_in)?;
    Some((values, c_out, c_in))
}

/// `W₀`, `W₁`, `W₂` of [`tap_values`]' values, `len` = `C_out·C_in` each.
fn three_taps(taps: &[f32], len: usize) -> [&[f32]; 3] {
    [&taps[..len], &taps[len..2 * len], &taps[2 * len..3 * len]]
}

/// A kernel-3 layer's taps and bias as values, taken once at load
/// ([`super::layers::ConvLayer::fold_for_inference`]).
#[derive(Debug)]
pub struct CpuTaps {
    /// `[3, C_out, C_in]`: tap `j` is `weight[:, :, j]`.
    taps: Vec<f32>,
    /// `[4, C_out, C_in]`: the taps transformed for [`winograd_products`] — `W₀`, `(W₀ + W₁ + W₂)/2`,
    /// `(W₀ − W₁ + W₂)/2`, `W₂`.
    winograd: Vec<f32>,
    bias: CpuBias,
    c_in: usize,
}

impl CpuTaps {
    /// From the taps one after another `[3, C_out, C_in]` ([`super::conv::split_taps`]) and the
    /// bias `[C_out]`; `None` where their values are not `f32` or not of those sizes.
    pub fn new(taps: Tensor<3>, bias: Option<Tensor<1>>) -> Option<Arc<Self>> {
        let (taps, c_out, c_in) = tap_values(taps)?;
        let [w0, w1, w2] = three_taps(&taps, c_out * c_in);
        let mut winograd = Vec::with_capacity(4 * c_out * c_in);
        winograd.extend_from_slice(w0);
        winograd.extend(w0.iter().zip(w1).zip(w2).map(|((a, b), c)| (a + b + c) * 0.5));
        winograd.extend(w0.iter().zip(w1).zip(w2).map(|((a, b), c)| (a - b + c) * 0.5));
        winograd.extend_from_slice(w2);
        Some(Arc::new(Self { taps, winograd, bias: CpuBias::new(bias, c_out)?, c_in }))
    }

    pub fn c_out(&self) -> usize {
        self.bias.c_out
    }
}

/// An upsampling layer's taps for [`upsampling_products`] and its bias, taken once at load
/// ([`super::layers::ConvLayer::fold_for_inference`]).
#[derive(Debug)]
pub struct CpuUpsampling {
    /// `[3, C_out, C_in]`: `W₀`, `W₀ + W₁ + W₂`, `W₂`.
    winograd: Vec<f32>,
    bias: CpuBias,
    c_in: usize,
}

impl CpuUpsampling {
    /// From the layer's taps one after another `[3, C_out, C_in]` ([`super::conv::split_taps`])
    /// and its bias `[C_out]`; `None` where their values are not `f32` or not of those sizes.
    pub fn new(taps: Tensor<3>, bias: Option<Tensor<1>>) -> Option<Arc<Self>> {
        let (taps, c_out, c_in) = tap_values(taps)?;
        let [w0, w1, w2] = three_taps(&taps, c_out * c_in);
        let mut winograd = Vec::with_capacity(3 * c_out * c_in);
        winograd.extend_from_slice(w0);
        winograd.extend(w0.iter().zip(w1).zip(w2).map(|((a, b), c)| a + b + c));
        winograd.extend_from_slice(w2);
        let bias = CpuBias::new(bias, c_out)?;
        Some(Arc::new(Self { winograd, bias, c_in }))
    }

    pub fn c_out(&self) -> usize {
        self.bias.c_out
    }
}

/// `Σⱼ Wⱼ · X[:, j … j + n]` (+ bias, then LeakyReLU if `activate`) for the padded frames `x`
/// `[C_in, ld]` (row-major, `ld ≥ n + 2`): `[C_out, n]`, row-major. The products accumulate in
/// the order [`super::conv::conv3_shifted_cbt`] adds them (tap 0, + tap 1, + tap 2; then the
/// bias), each product's own sum over the input channels in `gemm`'s blocks. `None` where the
/// sizes do not fit.
pub fn shifted_products(taps: &CpuTaps, x: &[f32], ld: usize, n: usize, activate: bool) -> Option<Vec<f32>> {
    let (c_out, c_in) = (taps.c_out(), taps.c_in);
    if n == 0 || ld < n + 2 || x.len() < c_in * ld || taps.taps.len() != 3 * c_out * c_in {
        return None;
    }
    let mut out = vec![0.0f32; c_out * n];
    for j in 0..3 {
        let tap = &taps.taps[j * c_out * c_in..(j + 1) * c_out * c_in];
        // Columns `j … j + n` of the rows at stride `ld`: inside `x` as `j ≤ 2 ≤ ld − n`.
        product(&mut out, tap, &x[j..], c_out, n, c_in, ld, j > 0);
    }
    for (c, row) in out.chunks_exact_mut(n).enumerate() {
        taps.bias.finish(c, row, activate);
    }
    Some(out)
}

/// Output column pairs at least this many for [`winograd_products`] to pay: below it the four
/// products are too narrow for `gemm`'s blocks and the transforms cost more than they save.
pub const WINOGRAD_MIN_PAIRS: usize = 16;

/// What [`shifted_products`] computes, by Winograd's minimal filtering F(2, 3): two output
/// columns from four input columns `d₀ … d₃` take four matrix products instead of six —
/// `M₁ = W₀(d₀ − d₂)`, `M₂ = ½(W₀ + W₁ + W₂)(d₁ + d₂)`, `M₃ = ½(W₀ − W₁ + W₂)(d₂ − d₁)`,
/// `M₄ = W₂(d₁ − d₃)`; `y₀ = M₁ + M₂ + M₃`, `y₁ = M₂ − M₃ − M₄` — so the layer's multiply-adds are
/// ⅔ of the direct convolution's, for a pass over the input that builds the four differences and
/// one over the products that combines them (with the bias and the LeakyReLU). The sums are the
/// direct ones regrouped: they differ from [`shifted_products`]' by float rounding (relative
/// ~1e-7 a layer). `None` where the sizes do not fit.
pub fn winograd_products(taps: &CpuTaps, x: &[f32], ld: usize, n: usize, activate: bool) -> Option<Vec<f32>> {
    let (c_out, c_in) = (taps.c_out(), taps.c_in);
    if n == 0 || ld < n + 2 || x.len() < c_in * ld || taps.winograd.len() != 4 * c_out * c_in {
        return None;
    }
    let pairs = n.div_ceil(2);
    // The four transformed inputs, each `[C_in, pairs]`. Pair `q` reads columns `2q … 2q + 3`; the
    // last one of an odd `n` may reach past the padded row (its second output is not kept).
    let mut u = vec![0.0f32; 4 * c_in * pairs];
    {
        let (u1, rest) = u.split_at_mut(c_in * pairs);
        let (u2, rest) = rest.split_at_mut(c_in * pairs);
        let (u3, u4) = rest.split_at_mut(c_in * pairs);
        for r in 0..c_in {
            let row = &x[r * ld..(r + 1) * ld];
            let at = r * pairs..(r + 1) * pairs;
            let (u1, u2, u3, u4) = (&mut u1[at.clone()], &mut u2[at.clone()], &mut u3[at.clone()], &mut u4[at]);
            let whole = if 2 * pairs + 2 <= ld { pairs } else { pairs - 1 };
            for q in 0..whole {
                let d = &row[2 * q..2 * q + 4];
                u1[q] = d[0] - d[2];
                u2[q] = d[1] + d[2];
                u3[q] = d[2] - d[1];
                u4[q] = d[1] - d[3];
            }
            for q in whole..pairs {
                let (d0, d1, d2) = (row[2 * q], row[2 * q + 1], row[2 * q + 2]);
                u1[q] = d0 - d2;
                u2[q] = d1 + d2;
                u3[q] = d2 - d1;
                u4[q] = d1;
            }
        }
    }
    let mut m = vec![0.0f32; 4 * c_out * pairs];
    for i in 0..4 {
        let g = &taps.winograd[i * c_out * c_in..(i + 1) * c_out * c_in];
        let rhs = &u[i * c_in * pairs..(i + 1) * c_in * pairs];
        product(&mut m[i * c_out * pairs..(i + 1) * c_out * pairs], g, rhs, c_out, pairs, c_in, pairs, false);
    }
    let mut out = vec![0.0f32; c_out * n];
    let plane = c_out * pairs;
    for (c, row) in out.chunks_exact_mut(n).enumerate() {
        let at = c * pairs..(c + 1) * pairs;
        let (m1, m2, m3, m4) = (
            &m[at.clone()],
            &m[plane + c * pairs..][..pairs],
            &m[2 * plane + c * pairs..][..pairs],
            &m[3 * plane + c * pairs..][..pairs],
        );
        let mut pairs_out = row.chunks_exact_mut(2);
        for (q, pair) in (&mut pairs_out).enumerate() {
            pair[0] = m1[q] + m2[q] + m3[q];
            pair[1] = m2[q] - m3[q] - m4[q];
        }
        if let [last] = pairs_out.into_remainder() {
            let q = pairs - 1;
            *last = m1[q] + m2[q] + m3[q];
        }
        taps.bias.finish(c, row, activate);
    }
    Some(out)
}

/// A kernel-3, zero-padded convolution of `x` `[C_in, B, T]` (row-major) upsampled ×2 by
/// repeating each frame, `[C_out, B, 2T]`, without the upsampled frames: output `2s` reads
/// `(x[s−1], x[s], x[s])` and `2s + 1` reads `(x[s], x[s], x[s+1])` (zeros past either end), which
/// is Winograd's F(2, 3) with its middle inputs equal — one of its four products vanishes:
/// `M₁ = W₀(x[s−1] − x[s])`, `M₂ = (W₀ + W₁ + W₂)x[s]`, `M₄ = W₂(x[s] − x[s+1])`,
/// `y[2s] = M₁ + M₂`, `y[2s+1] = M₂ − M₄`. Three products of `C_out × C_in` per input frame against
/// four for the folded taps ([`super::conv::upsample2_conv1d_gemm_cbt`]), the input as it is for
/// the middle one and no interleaving pass of its own: the combination writes the frames in
/// order, with the bias and (with `activate`) the LeakyReLU. Other sums than the folded taps'
/// (float rounding). `None` where `x` is not `C_in·B·T` values or there are no frames.
pub fn upsampling_products(up: &CpuUpsampling, x: &[f32], b: usize, t: usize, activate: bool) -> Option<Vec<f32>> {
    let (c_out, c_in, n) = (up.c_out(), up.c_in, b * t);
    if n == 0 || x.len() != c_in * n || up.winograd.len() != 3 * c_out * c_in {
        return None;
    }
    // `x[s−1] − x[s]` and `x[s] − x[s+1]` per clip, `[C_in, B·T]` each.
    let mut d = vec![0.0f32; 2 * c_in * n];
    let (before, after) = d.split_at_mut(c_in * n);
    for ((clip, d1), d4) in x.chunks_exact(t).zip(before.chunks_exact_mut(t)).zip(after.chunks_exact_mut(t)) {
        d1[0] = -clip[0];
        for s in 1..t {
            d1[s] = clip[s - 1] - clip[s];
        }
        for s in 0..t - 1 {
            d4[s] = clip[s] - clip[s + 1];
        }
        d4[t - 1] = clip[t - 1];
    }
    let mut m = vec![0.0f32; 3 * c_out * n];
    for (i, rhs) in [&d[..c_in * n], x, &d[c_in * n..]].into_iter().enumerate() {
        let g = &up.winograd[i * c_out * c_in..(i + 1) * c_out * c_in];
        product(&mut m[i * c_out * n..(i + 1) * c_out * n], g, rhs, c_out, n, c_in, n, false);
    }
    let mut out = vec![0.0f32; c_out * 2 * n];
    let plane = c_out * n;
    for (c, row) in out.chunks_exact_mut(2 * n).enumerate() {
        let (m1, m2, m4) = (&m[c * n..][..n], &m[plane + c * n..][..n], &m[2 * plane + c * n..][..n]);
        for (((pair, &p1), &p2), &p4) in row.chunks_exact_mut(2).zip(m1).zip(m2).zip(m4) {
            pair[0] = p1 + p2;
            pair[1] = p2 - p4;
        }
        up.bias.finish(c, row, activate);
    }
    Some(out)
}

/// `dst` (`m × n`, row stride `n`) = or += `lhs` (`m × k`, row stride `k`) · `rhs` (`k` rows of
/// `n` at row stride `ld`), by the `gemm` crate.
///
/// # Panics
/// Where a slice is shorter than its matrix (a bug of the caller: the sizes are checked there).
#[allow(clippy::too_many_arguments)]
fn product(dst: &mut [f32], lhs: &[f32], rhs: &[f32], m: usize, n: usize, k: usize, ld: usize, accumulate: bool) {
    assert!(dst.len() >= m * n && lhs.len() >= m * k && k > 0 && n <= ld && rhs.len() >= (k - 1) * ld + n);
    // SAFETY: checked above — `dst` holds `m × n` at row stride `n`, `lhs` `m × k` at row stride
    // `k`, and `rhs`'s last element `(k − 1)·ld + n − 1` is inside it.
    unsafe {
        gemm::gemm(
            m,
            n,
            k,
            dst.as_mut_ptr(),
            1,
            n as isize,
            accumulate,
            lhs.as_ptr(),
            1,
            k as isize,
            rhs.as_ptr(),
            1,
            ld as isize,
            1.0f32,
            1.0f32,
            false,
            false,
            false,
            parallelism(m, n, k),
        );
    }
}

/// The two parities of an upsampling layer's product `[2·C_out, B·(T+1)]` with the folded taps
/// ([`super::conv::upsample2_conv1d_gemm_cbt`], on flex where a layer has no [`CpuUpsampling`])
/// interleaved into `[C_out, B, 2T]` — output `2s + p` of channel `c`, clip `b` is the product's
/// row `p·C_out + c`, column `b·(T+1) + s + p` — in one pass. In tensor operations the shift
/// between the parities and the interleave take three copies
/// ([`super::conv::interleave_parities_by_tensor_ops`]). `None` where `product` is not
/// `2·C_out·B·(T+1)` values or there are no frames.
pub fn interleave_parities(product: &[f32], c_out: usize, b: usize, t: usize) -> Option<Vec<f32>> {
    let (row, half) = (b * (t + 1), c_out * b * (t + 1));
    if b == 0 || t == 0 || product.len() != 2 * half {
        return None;
    }
    let mut dst = vec![0.0f32; c_out * b * 2 * t];
    for (c, channel) in dst.chunks_exact_mut(b * 2 * t).enumerate() {
        for (clip, frames) in channel.chunks_exact_mut(2 * t).enumerate() {
            let at = c * row + clip * (t + 1);
            let (even, odd) = (&product[at..at + t], &product[half + at + 1..half + at + 1 + t]);
            for ((pair, &e), &o) in frames.chunks_exact_mut(2).zip(even).zip(odd) {
                pair[0] = e;
                pair[1] = o;
            }
        }
    }
    Some(dst)
}

/// Threads for one product, as flex picks them for its own (all of the pool's from 192³
/// multiply-adds on; one below, and always in wasm).
fn parallelism(m: usize, n: usize, k: usize) -> gemm::Parallelism {
    #[cfg(feature = "rayon")]
    if m.saturating_mul(n).saturating_mul(k) >= 192 * 192 * 192 {
        return gemm::Parallelism::Rayon(0);
    }
    let _ = (m, n, k);
    gemm::Parallelism::None
}
