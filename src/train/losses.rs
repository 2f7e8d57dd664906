//! Losses. All reductions are means over every element (PyTorch's default `reduction="mean"`;
//! the reference's KL terms are `sum / numel` too), so weights compare across widths and lengths.

use std::ops::Range;

use burn::prelude::*;
use burn::tensor::activation::log_softmax;

pub use super::recipe::{StylizerExtras, StylizerWeights};
use super::settings::TrainConfig;
pub use super::statistics::{StatsOffset, content_shape, style_statistics, style_statistics_moved};
use crate::model::autoencoder::{MotionAutoencoder, MotionDecoder, ae_input};
use crate::model::layers::one_hot;
use crate::model::{NoiseRng, StyleClassifier, StyleDistribution, Stylizer};

/// Smooth-L1 (Huber with β = 1, PyTorch's `SmoothL1Loss`), mean over elements:
/// `0.5 d²` where `|d| < 1`, `|d| − 0.5` elsewhere. Written as `0.5 q² + (|d| − q)` with
/// `q = min(|d|, 1)`, which is the same function and needs no mask.
pub fn smooth_l1<const D: usize>(pred: Tensor<D>, target: Tensor<D>) -> Tensor<1> {
    let d = (pred - target).abs();
    let q = d.clone().clamp_max(1.0);
    (q.clone().square() * 0.5 + (d - q)).mean()
}

/// Mean absolute error.
pub fn l1<const D: usize>(pred: Tensor<D>, target: Tensor<D>) -> Tensor<1> {
    (pred - target).abs().mean()
}

/// `KL(N(μ, σ²) ‖ N(0, I))` per element, `½(σ² + μ² − log σ² − 1)`, mean over elements.
pub fn kl_to_standard_normal<const D: usize>(mean: Tensor<D>, logvar: Tensor<D>) -> Tensor<1> {
    ((logvar.clone().exp() + mean.square() - logvar - 1.0) * 0.5).mean()
}

/// `KL(N(μ₁, σ₁²) ‖ N(μ₂, σ₂²))` between diagonal Gaussians, per element
/// `½(log σ₂² − log σ₁²) + (σ₁² + (μ₁ − μ₂)²) / (2σ₂²) − ½`, mean over elements.
pub fn kl_gaussians<const D: usize>(
    mean1: Tensor<D>,
    logvar1: Tensor<D>,
    mean2: Tensor<D>,
    logvar2: Tensor<D>,
) -> Tensor<1> {
    let half_log_ratio = (logvar2.clone() - logvar1.clone()) * 0.5;
    let num = logvar1.exp() + (mean1 - mean2).square();
    (half_log_ratio + num / (logvar2.exp() * 2.0) - 0.5).mean()
}

/// KL of a style posterior to the prior `N(0, I)`.
pub fn style_kl(dist: &StyleDistribution) -> Tensor<1> {
    kl_to_standard_normal(dist.mean.clone(), dist.logvar.clone())
}

/// Homo-style alignment `KL(N_s¹ ‖ N_s²)`.
pub fn style_alignment(first: &StyleDistribution, second: &StyleDistribution) -> Tensor<1> {
    kl_gaussians(first.mean.clone(), first.logvar.clone(), second.mean.clone(), second.logvar.clone())
}

/// L1 sparsity of an AE latent `[B, D, L]`: mean `|z|`.
pub fn latent_sparsity(z: Tensor<3>) -> Tensor<1> {
    z.abs().mean()
}

/// L1 smoothness of an AE latent `[B, D, L]` over time: mean `|z_{t+1} − z_t|` (0 for L = 1).
pub fn latent_smoothness(z: Tensor<3>) -> Tensor<1> {
    let len = z.dims()[2];
    if len < 2 {
        return z.sum() * 0.0;
    }
    let next = z.clone().narrow(2, 1, len - 1);
    let prev = z.narrow(2, 0, len - 1);
    (next - prev).abs().mean()
}

/// Cross-entropy of `logits` `[B, C]` against class indices, mean over the batch (the
/// evaluation classifier's training loss).
pub fn cross_entropy(logits: Tensor<2>, labels: &[usize]) -> Tensor<1> {
    let [_, c] = logits.dims();
    let target = one_hot(labels, c, &logits.device());
    cross_entropy_one_hot(logits, target)
}

/// [`cross_entropy`] against one-hot targets `[B, C]`.
pub fn cross_entropy_one_hot(logits: Tensor<2>, target: Tensor<2>) -> Tensor<1> {
    -(log_softmax(logits, 1) * target).sum_dim(1).mean()
}

// ---------------------------------------------------------------------------------------------
// Autoencoder stage.

/// The autoencoder's loss terms for one batch.
#[derive(Clone, Debug)]
pub struct AeLosses {
    pub total: Tensor<1>,
    /// Smooth-L1 between the reconstruction (260 dims) and the input features.
    pub reconstruction: Tensor<1>,
    /// AE only: L1 magnitude of the latent.
    pub sparsity: Tensor<1>,
    /// AE only: L1 of the latent's time differences.
    pub smoothness: Tensor<1>,
    /// VAE only: KL of the latent posterior to N(0, I).
    pub kl: Tensor<1>,
}

/// The VAE's reparameterisation noise for a batch of `batch` windows of `frames` frames: `[B,
/// latent_dim, frames / 4]` (the encoder halves time twice) drawn from `noise`; `None` for the
/// plain autoencoder, which draws nothing.
pub fn autoencoder_noise(
    ae: &MotionAutoencoder,
    batch: usize,
    frames: usize,
    noise: &mut NoiseRng,
    device: &Device,
) -> Option<Tensor<3>> {
    let d = ae.encoder.vae.then_some(ae.encoder.latent_dim)?;
    let l = frames / 4;
    Some(noise.normal_tensor(batch, d * l, device).reshape([batch, d, l]))
}

/// Autoencoder loss for features `[B, 260, T]`: smooth-L1 reconstruction of all 260 dims from
/// the 256 the encoder sees, plus (AE) `λ_l1 ‖z‖₁ + λ_sms ‖Δz‖₁` or (VAE) `λ_kl KL(z ‖ N(0,I))`,
/// each 0.001. The VAE decodes a reparameterised sample with the noise `eps`
/// ([`autoencoder_noise`]; a VAE without it is a bug of the caller's and panics).
pub fn autoencoder_loss(
    ae: &MotionAutoencoder,
    features: Tensor<3>,
    cfg: &TrainConfig,
    eps: Option<Tensor<3>>,
) -> AeLosses {
    let device = features.device();
    let dist = ae.encoder.forward(ae_input(features.clone()));
    let zero = || Tensor::<1>::zeros([1], &device);
    let (z, sparsity, smoothness, kl) = match &dist.logvar {
        Some(logvar) => {
            let eps = eps.expect("the VAE's noise (autoencoder_noise)");
            assert_eq!(eps.dims(), dist.mean.dims(), "the VAE's noise has the latent's shape");
            let z = dist.mean.clone() + (logvar.clone() * 0.5).exp() * eps;
            let kl = kl_to_standard_normal(dist.mean.clone(), logvar.clone());
            (z, zero(), zero(), kl)
        }
        None => {
            let z = dist.mean.clone();
            (z.clone(), latent_sparsity(z.clone()), latent_smoothness(z), zero())
        }
    };
    let reconstruction = smooth_l1(ae.decoder.forward(z), features);
    let total = reconstruction.clone()
        + sparsity.clone() * cfg.lambda_l1
        + smoothness.clone() * cfg.lambda_smooth
        + kl.clone() * cfg.lambda_ae_kl;
    AeLosses { total, reconstruction, sparsity, smoothness, kl }
}

// ---------------------------------------------------------------------------------------------
// Stylizer stage.

/// One stylizer batch, already in latent space. `B` sequences; clip 1 and clip 2 of each row
/// come from the same sequence (homo-style).
#[derive(Clone, Debug)]
pub struct StylizerInputs {
    /// Features of clip 1, `[B, 260, T]` (the pose-space targets).
    pub motion1: Tensor<3>,
    /// Features of clip 2, `[B, 260, T]`.
    pub motion2: Tensor<3>,
    /// Latents of the clips from the frozen motion encoder, `[B, D_z, T/4]` (no gradient).
    pub latent1: Tensor<3>,
    pub latent2: Tensor<3>,
    /// One-hot style label of each sequence `[B, S]` (supervised), `None` (unsupervised).
    pub labels: Option<Tensor<2>>,
    /// The rows whose partner row ([`partner_permutation`]) is a take of the same content in
    /// another style: their swaps are judged by the style-statistics loss. Empty: no such loss.
    pub content_paired: Vec<usize>,
    /// The row whose style each row's swap takes (and whose clip 2 its cycle rebuilds), within
    /// the batch; `None`: the partner row ([`partner_permutation`]). See
    /// [`StylizerWeights::cross_content`].
    pub style_source: Option<Vec<usize>>,
    /// Offsets of the content-paired rows' target statistics (`None`: none).
    pub stats_offset: Option<StatsOffset>,
    /// The content class of each row's clips ([`crate::dataset::CONTENTS`]; `None`: a content
    /// without a class), which the content-class loss holds the row's swap to. Empty: no such
    /// loss.
    pub content_classes: Vec<Option<usize>>,
}

/// The stylizer's loss terms for one batch (unweighted, plus the weighted total).
#[derive(Clone, Debug)]
pub struct StylizerLosses {
    pub total: Tensor<1>,
    /// `L_rec`, latent part: `sl1(ẑ¹, z¹) + sl1(ẑ², z²)`.
    pub rec_latent: Tensor<1>,
    /// `L_rec`, pose part: `sl1(D(ẑ¹), P¹) + sl1(D(ẑ²), P²)`.
    pub rec_pose: Tensor<1>,
    /// `L_cyc`, latent part: `sl1(z̃², z²) + sl1(z̃³, z³)`.
    pub cyc_latent: Tensor<1>,
    /// `L_cyc`, pose part: `sl1(D(z̃²), P²) + sl1(D(z̃³), P³)`.
    pub cyc_pose: Tensor<1>,
    /// `L_kl`: `KL(N¹‖N) + KL(N²‖N) + KL(Nᵗ‖N)` (`N³` is a permutation of `N²`).
    pub kl: Tensor<1>,
    /// `L_hsa`: `KL(N¹ ‖ N²)`.
    pub hsa: Tensor<1>,
    /// `L_stats`: [`style_statistics`] of the content-paired swaps `D(zᵗ)` against `P³` (0 when
    /// the batch has none or its weight is 0).
    pub style_stats: Tensor<1>,
    /// `L_shape`: [`content_shape`] of every swap `D(zᵗ)` against `P²` (0 when its weight is 0).
    pub content_shape: Tensor<1>,
    /// `L_content_class`: the content judge's cross-entropy on the swaps `D(zᵗ)` of the rows with a
    /// content class, against that class (0 without a judge, classes or weight).
    pub content_class: Tensor<1>,
    /// The style judge's cross-entropy on every swap `D(zᵗ)` against its target label `sl³` (0
    /// without a judge, labels or weight).
    pub style_class: Tensor<1>,
}

impl StylizerLosses {
    /// The terms in the order of [`StylizerStepReport`](super::stylizer::StylizerStepReport)'s
    /// losses (total first), each with the share of the batch it is a mean over, of a row group's
    /// [`LossShares`]: the style statistics over the content-paired rows, the total its own.
    pub fn into_terms(self, shares: LossShares) -> [(Tensor<1>, f32); 11] {
        let LossShares { rows: r, paired } = shares;
        [
            (self.total, 1.0),
            (self.rec_latent, r),
            (self.rec_pose, r),
            (self.cyc_latent, r),
            (self.cyc_pose, r),
            (self.kl, r),
            (self.hsa, r),
            (self.style_stats, paired),
            (self.content_shape, r),
            (self.content_class, r),
            (self.style_class, r),
        ]
    }
}

/// The frozen classifiers that judge the swaps ([`StylizerWeights::content_class`],
/// [`StylizerWeights::style_class`]); `None`: that loss is not used.
#[derive(Clone, Copy, Debug, Default)]
pub struct Judges<'a> {
    pub content: Option<&'a StyleClassifier>,
    pub style: Option<&'a StyleClassifier>,
}

impl StylizerInputs {
    /// The rows `rows` of the batch (a row group of [`super::parallel`]): `content_paired`
    /// keeps the paired rows inside it, renumbered.
    pub fn rows(&self, rows: Range<usize>) -> Self {
        let pick3 = |x: &Tensor<3>| x.clone().narrow(0, rows.start, rows.len());
        Self {
            motion1: pick3(&self.motion1),
            motion2: pick3(&self.motion2),
            latent1: pick3(&self.latent1),
            latent2: pick3(&self.latent2),
            labels: self.labels.as_ref().map(|l| l.clone().narrow(0, rows.start, rows.len())),
            content_paired: self.content_paired.iter().filter(|r| rows.contains(r)).map(|r| r - rows.start).collect(),
            // The caller keeps every source within its row group (`StylizerTrainer::step`).
            style_source: self.style_source.as_ref().map(|s| s[rows.clone()].iter().map(|r| r - rows.start).collect()),
            stats_offset: self.stats_offset.as_ref().map(|o| StatsOffset {
                mean: o.mean.clone().narrow(0, rows.start, rows.len()),
                spread: o.spread.clone().narrow(0, rows.start, rows.len()),
            }),
            content_classes: self.content_classes.get(rows).map(<[_]>::to_vec).unwrap_or_default(),
        }
    }
}

/// The five reparameterisation draws of one stylizer step, `[B, style_dim]` each, in the order
/// [`stylizer_loss`] uses them: s¹, s², s³, s² again (from the detached posterior), sᵗ.
#[derive(Clone, Debug)]
pub struct StyleNoise(pub [Tensor<2>; 5]);

impl StyleNoise {
    /// Five draws from `noise`, one after the other.
    pub fn draw(noise: &mut NoiseRng, batch: usize, style_dim: usize, device: &Device) -> Self {
        Self(std::array::from_fn(|_| noise.normal_tensor(batch, style_dim, device)))
    }

    /// The draws of the rows `rows`.
    pub fn rows(&self, rows: Range<usize>) -> Self {
        Self(self.0.clone().map(|e| e.narrow(0, rows.start, rows.len())))
    }
}

/// The share of a whole batch's loss that one row group's terms carry: `rows` for the terms
/// averaged over rows (the group's rows ÷ the batch's), `paired` for the style statistics
/// (the group's content-paired rows ÷ the batch's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LossShares {
    pub rows: f32,
    pub paired: f32,
}

impl LossShares {
    /// A whole batch.
    pub const WHOLE: Self = Self { rows: 1.0, paired: 1.0 };
}

/// The row permutation that picks "another clip" `z³` for every row: rows swapped in pairs
/// (0↔1, 2↔3, …, as the reference's `swap`) for an even batch; a rotation by one for an odd
/// batch, so every row still gets another row's clip. `B = 1` gives the identity.
pub fn partner_permutation(batch: usize) -> Vec<usize> {
    if batch.is_multiple_of(2) {
        (0..batch).map(|i| i ^ 1).collect()
    } else {
        (0..batch).map(|i| (i + 1) % batch).collect()
    }
}

/// The stylizer's training loss (paper §3.2 "Learning Scheme"; structure as the authors' code).
///
/// With `sl` the label (supervised only) and `s ~ N_s` reparameterised samples (noise from
/// `noise`):
/// - Clips: `z¹`, `z²` from the same sequence; `z³ = perm(z²)` another sequence's clip
///   ([`partner_permutation`]), with its label, features and — instead of re-encoding — its
///   content code and style posterior permuted the same way (they are `E_c(z³)`, `E_s(z³)`).
/// - Autoencoding: `ẑⁱ = G(E_c(zⁱ), sⁱ, slⁱ)`, `sⁱ ~ E_s(zⁱ, slⁱ)`, i ∈ {1, 2}.
/// - Swap: `zᵗ = G(c², s³, sl³)` — the content of clip 2 (detached, as the reference) with the
///   style of clip 3.
/// - Cycle: `cᵗ = E_c(zᵗ)`, `Nᵗ = E_s(zᵗ, sl³)`;
///   `z̃² = G(cᵗ, s ~ N²(detached), sl²)` (content back from the transfer, clip 2's own style),
///   `z̃³ = G(c³ (detached), s ~ Nᵗ, sl³)` (clip 3's content, the style read back from zᵗ).
/// - Pose space: every reconstruction is decoded by the frozen decoder `D` and compared with the
///   clip's 260-D features.
/// - `L = λ_rec L_rec + λ_cyc L_cyc + λ_kl L_kl + λ_hsa L_hsa (+ λ_stats L_stats)` (see
///   [`StylizerLosses`]; ours: `L_stats` on the rows of `inputs.content_paired`,
///   [`style_statistics`]`(D(zᵗ), P³)`, and `L_shape` on every row, [`content_shape`]`(D(zᵗ), P²)`).
pub fn stylizer_loss(
    net: &Stylizer,
    decoder: &MotionDecoder,
    inputs: &StylizerInputs,
    weights: &StylizerWeights,
    noise: &mut NoiseRng,
) -> StylizerLosses {
    let eps = StyleNoise::draw(noise, inputs.latent1.dims()[0], net.style_encoder.style_dim, &inputs.latent1.device());
    stylizer_loss_drawn(net, decoder, Judges::default(), inputs, weights, eps, LossShares::WHOLE)
}

/// [`stylizer_loss`] with its reparameterisation noise drawn beforehand, and its total weighted
/// as `shares` of a larger batch (a row group of [`super::parallel`]; the terms it reports are
/// the group's own means), and `judges` the frozen classifiers of the content- and style-class
/// losses.
pub fn stylizer_loss_drawn(
    net: &Stylizer,
    decoder: &MotionDecoder,
    judges: Judges,
    inputs: &StylizerInputs,
    weights: &StylizerWeights,
    eps: StyleNoise,
    shares: LossShares,
) -> StylizerLosses {
    let device = inputs.latent1.device();
    let batch = inputs.latent1.dims()[0];
    let partner = partner_permutation(batch);
    let source = inputs.style_source.clone().unwrap_or_else(|| partner.clone());
    assert_eq!(source.len(), batch, "one style source a row");
    let index = |rows: Vec<usize>| {
        let n = rows.len();
        Tensor::<1, Int>::from_data(TensorData::new(rows.into_iter().map(|i| i as i64).collect(), [n]), &device)
    };
    let perm = index(source);
    let StyleNoise([eps1, eps2, eps3, eps2b, eps_t]) = eps;

    let z1 = inputs.latent1.clone();
    let z2 = inputs.latent2.clone();
    let z3 = z2.clone().select(0, perm.clone());
    let m3 = inputs.motion2.clone().select(0, perm.clone());
    let sl = inputs.labels.clone();
    let sl3 = inputs.labels.clone().map(|l| l.select(0, perm.clone()));
    // Networks run on stacked batches (same math, fewer and larger matrix products): every layer
    // works per sample (conv, instance norm, AdaIN), so stacking changes nothing but speed.
    let stack3 = |v: Vec<Tensor<3>>| Tensor::cat(v, 0);
    let stack2 = |v: Vec<Tensor<2>>| Tensor::cat(v, 0);
    let rows = |x: Tensor<3>, i: usize| x.narrow(0, i * batch, batch);
    let stack_labels = |v: Vec<&Option<Tensor<2>>>| -> Option<Tensor<2>> {
        v.into_iter().cloned().collect::<Option<Vec<_>>>().map(|v| Tensor::cat(v, 0))
    };

    // Encoders on [z¹; z²].
    let z12 = stack3(vec![z1.clone(), z2.clone()]);
    let c12 = net.content_encoder.forward(z12.clone());
    let n12 = net.style_encoder.forward(z12, stack_labels(vec![&sl, &sl]));
    let c1 = rows(c12.clone(), 0);
    let c2 = rows(c12, 1);
    let pick = |d: &StyleDistribution, i: usize| StyleDistribution {
        mean: d.mean.clone().narrow(0, i * batch, batch),
        logvar: d.logvar.clone().narrow(0, i * batch, batch),
    };
    let n1 = pick(&n12, 0);
    let n2 = pick(&n12, 1);
    let c3 = c2.clone().select(0, perm.clone());
    let n3 = n2.select(perm);

    // Autoencoding ẑ¹, ẑ² and the swap zᵗ = G(c² (detached), s³, sl³), in one generator pass.
    let s1 = n1.sample_with(eps1);
    let s2 = n2.sample_with(eps2);
    let s3 = n3.sample_with(eps3);
    let g = net.generator.forward(
        stack3(vec![c1, c2.clone(), c2.detach()]),
        stack2(vec![s1, s2, s3]),
        stack_labels(vec![&sl, &sl, &sl3]),
    );
    let (r1, r2, zt) = (rows(g.clone(), 0), rows(g.clone(), 1), rows(g, 2));
    // Cycle: encode zᵗ, then z̃² = G(cᵗ, s ~ N²(detached), sl²), z̃³ = G(c³ (detached), s ~ Nᵗ, sl³).
    let ct = net.content_encoder.forward(zt.clone());
    let nt = net.style_encoder.forward(zt.clone(), sl3.clone());
    let s2b = n2.detach().sample_with(eps2b);
    let st = nt.sample_with(eps_t);
    let g = net.generator.forward(stack3(vec![ct, c3.detach()]), stack2(vec![s2b, st]), stack_labels(vec![&sl, &sl3]));
    let (rr2, rr3) = (rows(g.clone(), 0), rows(g, 1));

    // Pose space: one pass of the frozen decoder over [ẑ¹; ẑ²; z̃²; z̃³] and the swaps zᵗ the
    // extra losses judge: every row for the content-shape loss, else the content-paired rows.
    let paired =
        (weights.style_stats > 0.0 && !inputs.content_paired.is_empty()).then(|| index(inputs.content_paired.clone()));
    // The content-class loss judges the rows with a content class.
    let classed: Vec<(usize, usize)> = match judges.content {
        Some(_) if weights.content_class > 0.0 => {
            inputs.content_classes.iter().enumerate().filter_map(|(r, c)| c.map(|c| (r, c))).collect()
        }
        _ => Vec::new(),
    };
    // The style-class loss judges every swap against its target label.
    let style_judged = match (judges.style, &sl3) {
        (Some(judge), Some(target)) if weights.style_class > 0.0 => Some((judge, target.clone())),
        _ => None,
    };
    // Every swap is decoded when a loss judges them all.
    let shape = weights.content_shape > 0.0 || !classed.is_empty() || style_judged.is_some();
    let mut decoded = vec![r1.clone(), r2.clone(), rr2.clone(), rr3.clone()];
    let swaps = match (&paired, shape) {
        (_, true) => batch,
        (Some(rows), false) => rows.dims()[0],
        (None, false) => 0,
    };
    if shape {
        decoded.push(zt);
    } else if let Some(rows) = &paired {
        decoded.push(zt.select(0, rows.clone()));
    }
    let poses = decoder.forward(stack3(decoded));
    let swap_poses = (swaps > 0).then(|| poses.clone().narrow(0, 4 * batch, swaps));
    let style_stats = match (&paired, &swap_poses) {
        (Some(rows), Some(p)) => {
            let judged = if shape { p.clone().select(0, rows.clone()) } else { p.clone() };
            // The content partner's statistics (the style source's too, unless cross-content).
            let partners = index(inputs.content_paired.iter().map(|&r| partner[r]).collect());
            let offset = inputs.stats_offset.as_ref().map(|o| o.select(rows.clone()));
            style_statistics_moved(judged, inputs.motion2.clone().select(0, partners), offset)
        }
        _ => Tensor::zeros([1], &device),
    };
    let content_shape = match (&swap_poses, weights.content_shape > 0.0) {
        (Some(p), true) => self::content_shape(p.clone(), inputs.motion2.clone()),
        _ => Tensor::zeros([1], &device),
    };
    let content_class = match (&swap_poses, judges.content) {
        (Some(p), Some(judge)) if !classed.is_empty() => {
            let rows = index(classed.iter().map(|&(r, _)| r).collect());
            let classes: Vec<usize> = classed.iter().map(|&(_, c)| c).collect();
            cross_entropy(judge.forward(ae_input(p.clone().select(0, rows))).logits, &classes)
        }
        _ => Tensor::zeros([1], &device),
    };
    let style_class = match (&swap_poses, style_judged) {
        (Some(p), Some((judge, target))) => cross_entropy_one_hot(judge.forward(ae_input(p.clone())).logits, target),
        _ => Tensor::zeros([1], &device),
    };
    let rec_latent = smooth_l1(r1, z1) + smooth_l1(r2, z2.clone());
    let rec_pose = smooth_l1(rows(poses.clone(), 0), inputs.motion1.clone())
        + smooth_l1(rows(poses.clone(), 1), inputs.motion2.clone());
    let cyc_latent = smooth_l1(rr2, z2) + smooth_l1(rr3, z3);
    let cyc_pose = smooth_l1(rows(poses.clone(), 2), inputs.motion2.clone()) + smooth_l1(rows(poses, 3), m3);
    let kl = style_kl(&n1) + style_kl(&n2) + style_kl(&nt);
    let hsa = style_alignment(&n1, &n2);

    // Every term is a mean over the rows (the style statistics: over the content-paired rows);
    // a row group's total is its share of the whole batch's (`w × 1` is `w`: a whole batch's
    // total is the same to the bit).
    let LossShares { rows: share, paired } = shares;
    let total = (rec_latent.clone() + rec_pose.clone()) * (weights.rec * share)
        + (cyc_latent.clone() + cyc_pose.clone()) * (weights.cyc * share)
        + kl.clone() * (weights.kl * share)
        + hsa.clone() * (weights.hsa * share)
        + style_stats.clone() * (weights.style_stats * paired)
        + content_shape.clone() * (weights.content_shape * share)
        + content_class.clone() * (weights.content_class * share)
        + style_class.clone() * (weights.style_class * share);
    StylizerLosses {
        total,
        rec_latent,
        rec_pose,
        cyc_latent,
        cyc_pose,
        kl,
        hsa,
        style_stats,
        content_shape,
        content_class,
        style_class,
    }
}

#[cfg(test)]
mod tests {
    use super::StylizerExtras;

    #[test]
    fn extras_refuse_negative_or_nan_weights_and_cross_pairs_without_the_statistics() {
        assert_eq!(StylizerExtras::default().validate(), Ok(()));
        let stats = StylizerExtras { style_stats: 5.0, cross_content: true, cross_set: true, ..Default::default() };
        assert_eq!(stats.validate(), Ok(()));
        let negative = StylizerExtras { content_shape: -1.0, ..Default::default() };
        assert!(negative.validate().is_err_and(|e| e.starts_with("--content-shape -1")));
        let nan = StylizerExtras { hsa: Some(f32::NAN), ..Default::default() };
        assert!(nan.validate().is_err_and(|e| e.starts_with("--hsa NaN")));
        let unjudged = StylizerExtras { content_class: 1.0, ..Default::default() };
        assert!(unjudged.validate().is_err_and(|e| e.starts_with("--content-class needs --content-judge")));
        let idle = StylizerExtras { content_judge: Some("judge.bin".into()), ..Default::default() };
        assert!(idle.validate().is_err_and(|e| e.starts_with("--content-judge is used only with")));
        let judged =
            StylizerExtras { content_class: 1.0, content_judge: Some("judge.bin".into()), ..Default::default() };
        assert_eq!(judged.validate(), Ok(()));
        assert!(judged.any());
        let cross = StylizerExtras { cross_set: true, ..Default::default() };
        assert!(cross.validate().is_err_and(|e| e.starts_with("--cross-set needs --style-stats above 0")));
    }
}
