//! Seeded Gaussian noise generated on the Rust side, then turned into tensors.
//!
//! Burn's `Tensor::random` draws from a per-backend generator (seeded with `Device::seed`, shared
//! and possibly global), whose stream differs between backends and is not promised stable across
//! versions. Inference must give bit-identical style samples natively and in wasm, so the style
//! noise comes from a [`NoiseRng`] the caller owns: ChaCha8 words → uniforms (exact integer
//! arithmetic) → Box–Muller with the pure-Rust `libm` (the same bits on every target; `sqrt` is
//! IEEE-exact).

use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};

/// A seeded source of standard-normal noise. Same seed → same numbers on every platform.
#[derive(Clone, Debug)]
pub struct NoiseRng {
    rng: ChaCha8Rng,
    spare: Option<f64>,
}

impl NoiseRng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self { rng: ChaCha8Rng::seed_from_u64(seed), spare: None }
    }

    /// Uniform in (0, 1]: 53 random bits, never 0 (safe for `ln`).
    fn uniform_open0(&mut self) -> f64 {
        ((self.rng.next_u64() >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// One standard-normal sample (Box–Muller; the second value of each pair is kept for the
    /// next call).
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let r = (-2.0 * libm::log(self.uniform_open0())).sqrt();
        let theta = 2.0 * core::f64::consts::PI * self.uniform();
        self.spare = Some(r * libm::sin(theta));
        r * libm::cos(theta)
    }

    /// `n` standard-normal samples as `f32`.
    pub fn normals(&mut self, n: usize) -> Vec<f32> {
        (0..n).map(|_| self.normal() as f32).collect()
    }

    /// A `[rows, cols]` tensor of standard-normal samples (row-major fill order).
    pub fn normal_tensor(&mut self, rows: usize, cols: usize, device: &Device) -> Tensor<2> {
        Tensor::from_data(TensorData::new(self.normals(rows * cols), [rows, cols]), device)
    }
}
