//! Per-dimension normalisation statistics over a training set, with one std per feature group.

use super::layout::{DIM, FeatureError, Features, GROUPS, View};
use serde::{Deserialize, Serialize};

/// Lower bound on every std after group averaging, so that a group that never varies in the data
/// (e.g. the yaw velocity of a set of straight walks) is not divided by ~0. Below every group's
/// spread on real data (the smallest, the yaw velocity, is ~0.005-0.05 rad/frame).
pub const STD_FLOOR: f32 = 1e-3;

/// Mean and std of each of the [`DIM`] dims: `normalize` maps x to (x − mean) / std.
///
/// Built by [`NormStats::compute`] (or a [`NormAccumulator`]); the std of a dim is the mean over its
/// group ([`GROUPS`]) of the per-dim population stds, at least [`STD_FLOOR`]. Serialises as
/// `{"mean": [...], "std": [...]}`; deserialising checks the lengths and values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawNormStats", into = "RawNormStats")]
pub struct NormStats {
    mean: Vec<f32>,
    std: Vec<f32>,
}

#[derive(Clone, Serialize, Deserialize)]
struct RawNormStats {
    mean: Vec<f32>,
    std: Vec<f32>,
}

impl TryFrom<RawNormStats> for NormStats {
    type Error = FeatureError;
    fn try_from(r: RawNormStats) -> Result<NormStats, FeatureError> {
        NormStats::new(r.mean, r.std)
    }
}

impl From<NormStats> for RawNormStats {
    fn from(s: NormStats) -> RawNormStats {
        RawNormStats { mean: s.mean, std: s.std }
    }
}

impl NormStats {
    /// Statistics from explicit values: [`DIM`] finite means and [`DIM`] finite positive stds.
    pub fn new(mean: Vec<f32>, std: Vec<f32>) -> Result<NormStats, FeatureError> {
        let ok = mean.len() == DIM
            && std.len() == DIM
            && mean.iter().all(|m| m.is_finite())
            && std.iter().all(|s| s.is_finite() && *s > 0.0);
        if !ok {
            return Err(FeatureError::BadStats { mean: mean.len(), std: std.len() });
        }
        Ok(NormStats { mean, std })
    }

    /// Statistics over every frame of `clips` (streaming: one clip in memory at a time).
    /// Errors: no frames ([`FeatureError::Empty`]), a non-finite value.
    pub fn compute<'a>(clips: impl IntoIterator<Item = &'a Features>) -> Result<NormStats, FeatureError> {
        let mut acc = NormAccumulator::new();
        for f in clips {
            acc.push(f)?;
        }
        acc.finish()
    }

    /// Per-dim means.
    pub fn mean(&self) -> &[f32] {
        &self.mean
    }

    /// Per-dim stds (shared within each group).
    pub fn std(&self) -> &[f32] {
        &self.std
    }

    /// (x − mean) / std on every value.
    pub fn normalize(&self, f: &mut Features) {
        for row in f.data_mut().chunks_exact_mut(DIM) {
            for ((x, m), s) in row.iter_mut().zip(&self.mean).zip(&self.std) {
                *x = (*x - m) / s;
            }
        }
    }

    /// x · std + mean on every value: the inverse of [`NormStats::normalize`].
    pub fn denormalize(&self, f: &mut Features) {
        for row in f.data_mut().chunks_exact_mut(DIM) {
            for ((x, m), s) in row.iter_mut().zip(&self.mean).zip(&self.std) {
                *x = *x * s + m;
            }
        }
    }

    /// [`NormStats::normalize`] on frame-major values of a view (`frames × view.width()`), e.g. a model's
    /// input batch.
    pub fn normalize_view(&self, view: View, values: &mut [f32]) -> Result<(), FeatureError> {
        self.map_view(view, values, |x, m, s| (x - m) / s)
    }

    /// [`NormStats::denormalize`] on frame-major values of a view, e.g. a model's output batch.
    pub fn denormalize_view(&self, view: View, values: &mut [f32]) -> Result<(), FeatureError> {
        self.map_view(view, values, |x, m, s| x * s + m)
    }

    fn map_view(&self, view: View, values: &mut [f32], op: impl Fn(f32, f32, f32) -> f32) -> Result<(), FeatureError> {
        let width = view.width();
        if !values.len().is_multiple_of(width) {
            return Err(FeatureError::BadLength { len: values.len(), frames: values.len() / width, width });
        }
        let dims: Vec<usize> = view.dims().collect();
        for row in values.chunks_exact_mut(width) {
            for (x, &d) in row.iter_mut().zip(&dims) {
                *x = op(*x, self.mean[d], self.std[d]);
            }
        }
        Ok(())
    }
}

/// Streaming accumulator of [`NormStats`]: exact per-dim mean and variance in f64, each clip by two
/// passes, clips merged with Chan et al.'s pairwise update (no cancellation over ~10⁶ frames).
#[derive(Clone, Debug)]
pub struct NormAccumulator {
    count: u64,
    mean: Vec<f64>,
    m2: Vec<f64>,
}

impl Default for NormAccumulator {
    fn default() -> Self {
        Self::new()
    }
}

impl NormAccumulator {
    pub fn new() -> NormAccumulator {
        NormAccumulator { count: 0, mean: vec![0.0; DIM], m2: vec![0.0; DIM] }
    }

    /// Frames accumulated so far.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Adds every frame of `f`. Non-finite values are refused (nothing is added).
    pub fn push(&mut self, f: &Features) -> Result<(), FeatureError> {
        if let Some((frame, dim)) = f.first_non_finite() {
            return Err(FeatureError::NonFinite { frame, dim });
        }
        let n = f.frames() as f64;
        let mut mean = vec![0.0f64; DIM];
        for row in f.rows() {
            for (m, &x) in mean.iter_mut().zip(row) {
                *m += x as f64;
            }
        }
        mean.iter_mut().for_each(|m| *m /= n);
        let mut m2 = vec![0.0f64; DIM];
        for row in f.rows() {
            for ((s, &x), m) in m2.iter_mut().zip(row).zip(&mean) {
                let d = x as f64 - m;
                *s += d * d;
            }
        }
        let na = self.count as f64;
        let total = na + n;
        for d in 0..DIM {
            let delta = mean[d] - self.mean[d];
            self.mean[d] += delta * n / total;
            self.m2[d] += m2[d] + delta * delta * na * n / total;
        }
        self.count += f.frames() as u64;
        Ok(())
    }

    /// The statistics: per-dim mean; per-dim population std averaged over each group, floored.
    pub fn finish(&self) -> Result<NormStats, FeatureError> {
        if self.count == 0 {
            return Err(FeatureError::Empty);
        }
        let n = self.count as f64;
        let per_dim: Vec<f64> = self.m2.iter().map(|m2| (m2 / n).max(0.0).sqrt()).collect();
        let mut std = vec![0.0f32; DIM];
        for g in GROUPS {
            let group_std = per_dim[g.clone()].iter().sum::<f64>() / g.len() as f64;
            let s = (group_std as f32).max(STD_FLOOR);
            std[g].iter_mut().for_each(|x| *x = s);
        }
        let mean = self.mean.iter().map(|&m| m as f32).collect();
        NormStats::new(mean, std)
    }
}
