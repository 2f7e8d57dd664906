//! Seeded weight initialisation independent of Burn's generator.
//!
//! Burn initialises parameters lazily (at first use) from a per-backend generator that all
//! threads share, so "seed the device, build the model" is reproducible only in a single-threaded
//! program that uses the model right away. [`seeded_xavier`] instead draws every weight from a
//! [`NoiseRng`] in the module's (fixed) traversal order: same config + same seed → the same
//! weights, on any thread, backend or target.
//!
//! Every weight of these networks is Xavier-normal (the reference's `init_weight`): rank-3 conv
//! weights `[out, in, k]` get std `sqrt(2 / ((in + out) k))`, rank-2 linear weights `[in, out]`
//! std `sqrt(2 / (in + out))`. Rank-1 parameters (biases: zeros, AdaIN's γ = 1 / β = 0) keep
//! their deterministic initialisers.

use burn::module::{Module, ModuleMapper, Param, ParamId};
use burn::prelude::*;

use super::rng::NoiseRng;

struct SeededXavier {
    rng: NoiseRng,
}

impl ModuleMapper for SeededXavier {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let shape = param.lazy_shape();
        let dims = shape.clone().to_vec();
        let std = match D {
            3 => (2.0 / ((dims[0] + dims[1]) * dims[2]) as f64).sqrt(),
            2 => (2.0 / (dims[0] + dims[1]) as f64).sqrt(),
            _ => return param,
        };
        let n = shape.num_elements();
        let data: Vec<f32> = (0..n).map(|_| (self.rng.normal() * std) as f32).collect();
        let data = TensorData::new(data, shape.clone());
        let device = param.lazy_device();
        let id: ParamId = param.id;
        Param::uninitialized(
            id,
            move |device, require_grad| {
                let t = Tensor::from_data(data, device);
                if require_grad { t.require_grad() } else { t }
            },
            device,
            true,
            shape,
        )
    }
}

/// `module` with every rank-2/3 weight replaced by seeded Xavier-normal values (see the module
/// docs). Parameter ids are kept.
pub fn seeded_xavier<M: Module>(module: M, seed: u64) -> M {
    module.map(&mut SeededXavier { rng: NoiseRng::new(seed) })
}
