//! Data parallelism inside one training step on the CPU (issue 13).
//!
//! Burn's flex backend runs its matrix products on every core but most of the rest of a step —
//! copies, element-wise kernels, the autodiff bookkeeping — on the calling thread, so a second
//! core bought a training step only 1.1–1.3× (bench/README.md). Here the batch is cut into row
//! groups ([`row_chunks`]) whose forward and backward passes run side by side on rayon's threads
//! ([`map_parallel`]); every network works per sample, so the groups' graphs are independent.
//! Burn's autodiff keeps one graph per connected component and runs a backward pass holding its
//! graph's lock, and a parameter joins every graph that uses it: each group therefore runs on a
//! [`Replica`] of the trained network (the same tensors as new leaves, no copy), and the
//! replicas' gradients are summed under the network's own parameter ids ([`sum_grads`]). The
//! loss of a group is its share of the whole batch's mean, so the summed gradient is the whole
//! batch's, up to float rounding.
//!
//! The number of groups is a setting ([`super::settings::TrainConfig::batch_chunks`]), not the
//! number of threads: a run gives the same numbers on one core and on two (one core runs the
//! groups one after the other).

use std::ops::Range;

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param, ParamId};
use burn::optim::GradientsParams;
use burn::prelude::*;
use burn::tensor::Gradients;

/// `chunks` contiguous row ranges covering `0..batch`, as equal as possible, each starting on an
/// even row (the loss pairs rows 0↔1, 2↔3, …: a pair never straddles two groups). One range
/// (the whole batch) when `chunks ≤ 1` or the batch is odd (its pairing is a rotation).
pub fn row_chunks(batch: usize, chunks: usize) -> Vec<Range<usize>> {
    if chunks <= 1 || batch < 4 || !batch.is_multiple_of(2) {
        return std::iter::once(0..batch).collect();
    }
    let pairs = batch / 2;
    let n = chunks.min(pairs);
    (0..n).map(|i| 2 * (i * pairs / n)..2 * ((i + 1) * pairs / n)).collect()
}

/// The row groups of a training step's batch on `device`: [`row_chunks`] on the CPU backends,
/// the whole batch on a GPU (it runs a whole batch's kernels at once; groups would only make
/// them smaller).
pub fn row_groups(device: &Device, batch: usize, chunks: usize) -> Vec<Range<usize>> {
    row_chunks(batch, if splits_batches(device) { chunks } else { 1 })
}

fn splits_batches(device: &Device) -> bool {
    let inner = device.clone().inner();
    #[cfg(feature = "ndarray")]
    #[allow(deprecated)]
    if inner == Device::ndarray() {
        return true;
    }
    inner == Device::flex()
}

/// `f(0), …, f(n − 1)`, on rayon's threads where the build has them; results in order.
pub fn map_parallel<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        (0..n).into_par_iter().map(f).collect()
    }
    #[cfg(not(feature = "rayon"))]
    {
        (0..n).map(f).collect()
    }
}

/// A module whose trainable parameters are new leaves over the same values (a graph of their
/// own), with the ids of the module they came from.
pub struct Replica<M> {
    pub module: M,
    /// The original parameters' ids, in visiting order.
    ids: Vec<ParamId>,
}

struct Replicate {
    ids: Vec<ParamId>,
}

impl ModuleMapper for Replicate {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        if !param.is_require_grad() {
            return param;
        }
        self.ids.push(param.id);
        Param::initialized(ParamId::new(), param.val().detach().require_grad())
    }
}

struct ReplicaGrads<'a> {
    ids: std::slice::Iter<'a, ParamId>,
    grads: &'a mut Gradients,
    out: GradientsParams,
}

impl ModuleVisitor for ReplicaGrads<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if !param.is_require_grad() {
            return;
        }
        let id = *self.ids.next().expect("a replica has the parameters it was made with");
        if let Some(grad) = param.val().grad_remove(self.grads) {
            self.out.register(id, grad);
        }
    }
}

impl<M: Module> Replica<M> {
    /// `module` with its trainable parameters as new leaves.
    pub fn of(module: &M) -> Self {
        let mut mapper = Replicate { ids: Vec::new() };
        let module = module.clone().map(&mut mapper);
        Self { module, ids: mapper.ids }
    }

    /// The gradients of the replica's parameters in `grads`, under the original module's ids.
    pub fn grads(&self, grads: &mut Gradients) -> GradientsParams {
        let mut visitor = ReplicaGrads { ids: self.ids.iter(), grads, out: GradientsParams::new() };
        self.module.visit(&mut visitor);
        visitor.out
    }
}

/// The batch's loss terms from its groups' own: each group's scalars (read back) times its
/// shares, summed in the groups' order (one group with shares of 1 gives its scalars as they are).
pub fn weighted_terms<const N: usize>(groups: impl IntoIterator<Item = ([Tensor<1>; N], [f32; N])>) -> [f32; N] {
    let mut terms = [0f32; N];
    for (values, shares) in groups {
        for ((t, v), s) in terms.iter_mut().zip(super::optim::read_scalars(values)).zip(shares) {
            *t += v * s;
        }
    }
    terms
}

struct AddGrads<'a> {
    into: &'a mut GradientsParams,
    from: &'a mut GradientsParams,
}

impl ModuleVisitor for AddGrads<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.from.remove::<D>(param.id) {
            let sum = match self.into.remove::<D>(param.id) {
                Some(acc) => acc + g,
                None => g,
            };
            self.into.register(param.id, sum);
        }
    }
}

/// The sum of the groups' gradients of `module`'s parameters, added in the groups' order.
pub fn sum_grads<M: Module>(module: &M, parts: Vec<GradientsParams>) -> GradientsParams {
    let mut parts = parts.into_iter();
    let mut total = parts.next().unwrap_or_default();
    for mut part in parts {
        module.visit(&mut AddGrads { into: &mut total, from: &mut part });
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_chunks_cover_the_batch_on_even_rows() {
        assert_eq!(row_chunks(16, 2), vec![0..8, 8..16]);
        assert_eq!(row_chunks(16, 1), vec![0..16]);
        assert_eq!(row_chunks(12, 4), vec![0..2, 2..6, 6..8, 8..12]);
        // More groups than pairs: one pair each.
        assert_eq!(row_chunks(4, 8), vec![0..2, 2..4]);
        // Odd batches and tiny ones stay whole.
        assert_eq!(row_chunks(15, 2), vec![0..15]);
        assert_eq!(row_chunks(2, 2), vec![0..2]);
        for (batch, chunks) in [(16, 3), (32, 5), (10, 4)] {
            let r = row_chunks(batch, chunks);
            assert_eq!(r.first().unwrap().start, 0);
            assert_eq!(r.last().unwrap().end, batch);
            assert!(r.windows(2).all(|w| w[0].end == w[1].start && w[1].start % 2 == 0 && !w[0].is_empty()));
        }
    }
}
