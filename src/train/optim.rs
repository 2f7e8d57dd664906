//! Adam and per-network global gradient-norm clipping, and the optimizers' state as bytes.
//!
//! Burn's own `GradientClipping::Norm` clips each parameter tensor on its own; the reference uses
//! `torch.nn.utils.clip_grad_norm_(network.parameters(), 0.5)`, one norm over all of a network's
//! gradients, so that is done here ([`clip_grad_norm`]) and no clipping is configured in Adam.
//! Adam: β = (0.9, 0.999), ε = 1e-8 (PyTorch's defaults; Burn's default ε is 1e-5).

use burn::module::{Module, ModuleVisitor, Param};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;

use crate::model::ModelError;

struct SquaredNorm<'a> {
    grads: &'a GradientsParams,
    parts: Vec<Tensor<1>>,
}

impl ModuleVisitor for SquaredNorm<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.grads.get::<D>(param.id) {
            self.parts.push(g.square().sum());
        }
    }
}

struct ScaleGrads<'a> {
    grads: &'a mut GradientsParams,
    factor: f32,
}

impl ModuleVisitor for ScaleGrads<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.grads.remove::<D>(param.id) {
            self.grads.register(param.id, g * self.factor);
        }
    }
}

/// Squared-gradient sums of `module`'s parameters found in `grads` (one tensor per parameter).
pub(super) fn squared_norm_parts<M: Module>(module: &M, grads: &GradientsParams) -> Vec<Tensor<1>> {
    let mut v = SquaredNorm { grads, parts: Vec::new() };
    module.visit(&mut v);
    v.parts
}

/// The L2 norm of gradients given as squared sums.
pub(super) fn total_norm(parts: Vec<Tensor<1>>) -> f32 {
    if parts.is_empty() {
        return 0.0;
    }
    Tensor::cat(parts, 0).sum().into_scalar::<f32>().sqrt()
}

/// The factor that brings a gradient of norm `norm` down to `max_norm`, if it is above.
pub(super) fn clip_factor(norm: f32, max_norm: f32) -> Option<f32> {
    let factor = max_norm / (norm + 1e-6);
    (factor < 1.0).then_some(factor)
}

/// Scales the gradients of `module`'s parameters in `grads` by `factor`.
pub(super) fn scale_grads<M: Module>(module: &M, grads: &mut GradientsParams, factor: f32) {
    module.visit(&mut ScaleGrads { grads, factor });
}

/// `clip_grad_norm_` for the parameters of `module`: if the global L2 norm of their gradients
/// exceeds `max_norm`, all are scaled by `max_norm / (norm + 1e-6)`. Returns the norm before
/// clipping.
pub fn clip_grad_norm<M: Module>(module: &M, grads: &mut GradientsParams, max_norm: f32) -> f32 {
    let norm = total_norm(squared_norm_parts(module, grads));
    if let Some(factor) = clip_factor(norm, max_norm) {
        scale_grads(module, grads, factor);
    }
    norm
}

/// Adam with PyTorch's ε.
pub fn adam() -> ModuleOptimizer {
    AdamConfig::new().with_epsilon(1e-8).init()
}

/// Adam states as bytes: per optimizer, its length (u64 LE) and its burnpack record (moments
/// and step counts keyed by parameter id, which module records keep).
pub fn optimizers_to_bytes(optims: &[&ModuleOptimizer]) -> Result<Vec<u8>, ModelError> {
    let mut out = Vec::new();
    for o in optims {
        let bytes = o.into_bytes().map_err(|e| ModelError::Weights(format!("optimizer state: {e}")))?;
        out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        out.extend_from_slice(&bytes);
    }
    Ok(out)
}

/// Inverse of [`optimizers_to_bytes`] for `N` optimizers.
pub fn optimizers_from_bytes<const N: usize>(bytes: &[u8]) -> Result<[ModuleOptimizer; N], ModelError> {
    let bad = |m: &str| ModelError::Weights(format!("optimizer state: {m}"));
    let mut rest = bytes;
    let mut out = Vec::with_capacity(N);
    for _ in 0..N {
        let (len, tail) = rest.split_first_chunk::<8>().ok_or_else(|| bad("truncated"))?;
        let len = usize::try_from(u64::from_le_bytes(*len)).map_err(|_| bad("length"))?;
        let (record, tail) = tail.split_at_checked(len).ok_or_else(|| bad("truncated"))?;
        let optim =
            adam().from_bytes(burn::tensor::Bytes::from_bytes_vec(record.to_vec())).map_err(|e| bad(&e.to_string()))?;
        out.push(optim);
        rest = tail;
    }
    if !rest.is_empty() {
        return Err(bad("trailing bytes"));
    }
    out.try_into().map_err(|_| bad("count"))
}

/// Reads several scalar losses with one device read.
pub(super) fn read_scalars<const N: usize>(values: [Tensor<1>; N]) -> [f32; N] {
    let values: Vec<Tensor<1>> = values.into_iter().map(|t| t.detach().inner()).collect();
    let read = Tensor::cat(values, 0).into_data().try_into_vec_as::<f32>().expect("f32 losses");
    read.try_into().unwrap_or_else(|v: Vec<f32>| panic!("{} losses read, {N} expected", v.len()))
}
