//! Inference passes on the CPU (flex) over plain `f32` values, where tensor operations cost
//! copies: the kernel-3 layers' shifted products computed into one buffer, and the upsampling
//! layers' parities interleaved, each with the bias and the activation in the same pass.
//!
//! [`super::conv::conv3_shifted_cbt`] convolves with three matrix products on shifted views of
//! the padded frames, then adds them and the bias, then (in the layer) applies the activation:
//! through Burn, each product gets an output buffer of its own (flex zero-fills it, then copies
//! it into an aligned allocation) and each addition and the activation is a pass over the
//! output. Here the three products accumulate into one buffer by the `gemm` crate Burn's flex
//! backend calls itself (the same crate and version, the same kernels), and the bias and the
//! LeakyReLU are one pass over it. Written by hand because Burn has no matrix product that
//! accumulates into an existing tensor.

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
    pub fn new(bias: Option<Tensor<1>>, c_out: usize) -> Option<Arc<Self>> {
        let values = match bias {
            Some(b) => Some(b.into_data().try_to_vec::<f32>().ok().filter(|v| v.len() == c_out)?),
            None => None,
        };
        Some(Arc::new(Self { values, c_out }))
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

/// A kernel-3 layer's taps and bias as values, taken once at load
/// ([`super::layers::ConvLayer::fold_for_inference`]).
#[derive(Debug)]
pub struct CpuTaps {
    /// `[3, C_out, C_in]`: tap `j` is `weight[:, :, j]`.
    taps: Vec<f32>,
    bias: Arc<CpuBias>,
    c_in: usize,
}

impl CpuTaps {
    /// From the taps one after another `[3, C_out, C_in]` ([`super::conv::split_taps`]) and the
    /// bias `[C_out]`; `None` where their values are not `f32` or not of those sizes.
    pub fn new(taps: Tensor<3>, bias: Option<Tensor<1>>) -> Option<Arc<Self>> {
        let [k, c_out, c_in] = taps.dims();
        let taps = taps.into_data().try_to_vec::<f32>().ok().filter(|v| k == 3 && v.len() == 3 * c_out * c_in)?;
        Some(Arc::new(Self { taps, bias: CpuBias::new(bias, c_out)?, c_in }))
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
        // SAFETY: `out` is `c_out × n` (row stride n), `tap` is `c_out × c_in` (row stride c_in),
        // and the right-hand side reads rows `0..c_in` of `x` at stride `ld`, columns `j..j + n`,
        // whose last element `(c_in − 1)·ld + j + n − 1 < c_in·ld` as `j ≤ 2 < ld − n + 1`: every
        // pointer stays inside its slice (checked above), and `out` is written only here.
        unsafe {
            gemm::gemm(
                c_out,
                n,
                c_in,
                out.as_mut_ptr(),
                1,
                n as isize,
                j > 0,
                tap.as_ptr(),
                1,
                c_in as isize,
                x.as_ptr().add(j),
                1,
                ld as isize,
                1.0f32,
                1.0f32,
                false,
                false,
                false,
                parallelism(c_out, n, c_in),
            );
        }
    }
    for (c, row) in out.chunks_exact_mut(n).enumerate() {
        taps.bias.finish(c, row, activate);
    }
    Some(out)
}

/// The two parities of an upsampling layer's product `[2·C_out, B·(T+1)]`
/// ([`super::conv::upsample2_conv1d_gemm_cbt`]) interleaved into `[C_out, B, 2T]` — output
/// `2s + p` of channel `c`, clip `b` is the product's row `p·C_out + c`, column `b·(T+1) + s + p`
/// — in one pass, then each row finished with `bias` ([`CpuBias`]; none: as it is). In tensor
/// operations the shift between the parities and the interleave take three copies
/// ([`super::conv::interleave_parities_by_tensor_ops`]), the bias and the activation two more
/// passes. `None` where `product` is not `2·C_out·B·(T+1)` values or there are no frames.
pub fn interleave_parities(
    product: &[f32],
    c_out: usize,
    b: usize,
    t: usize,
    bias: Option<&CpuBias>,
    activate: bool,
) -> Option<Vec<f32>> {
    let (row, half) = (b * (t + 1), c_out * b * (t + 1));
    if b == 0 || t == 0 || product.len() != 2 * half || bias.is_some_and(|bias| bias.c_out != c_out) {
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
        if let Some(bias) = bias {
            bias.finish(c, channel, activate);
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
