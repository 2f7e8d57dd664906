//! Stage 2: the stylizer — content encoder, style encoder and generator ([`StylizerTrainer`]) — on
//! latents of a frozen autoencoder, with style-balanced homo-style pairs of windows.

use burn::module::Module;
use burn::optim::ModuleOptimizer;
use burn::prelude::*;

use super::data::TrainData;
use super::eval;
use super::losses::{
    Judges, LossShares, StatsOffset, StyleNoise, StylizerInputs, StylizerWeights, stylizer_loss_drawn,
};
use super::optim::{
    adam, clip_factor, clip_grad_norm, optimizers_from_bytes, optimizers_to_bytes, scale_grads, squared_norm_parts,
    total_norm,
};
use super::parallel::{Replica, map_parallel, row_groups, sum_grads, weighted_terms};
use super::rundir::{load_module, module_bytes};
use super::sampler::{SamplerRng, batch_tensor};
use super::settings::TrainConfig;
use super::trainer::{PhaseTimes, Trainer, step_report};
use crate::dataset::CONTENTS;
use crate::features::DIM;
use crate::model::autoencoder::ae_input;
use crate::model::init::seeded_xavier;
use crate::model::layers::one_hot;
use crate::model::weights::load_classifier;
use crate::model::{ModelConfig, ModelError, MotionAutoencoder, NoiseRng, StyleClassifier, Stylizer, check_features};
use std::time::Instant;

/// A stylizer batch: per row, two clips of the same sequence and (supervised) its style label.
#[derive(Clone, Debug)]
pub struct StylizerBatch {
    /// `[B, 260, T]`, normalised features.
    pub motion1: Tensor<3>,
    /// `[B, 260, T]`, another clip of the same sequence as `motion1`'s row.
    pub motion2: Tensor<3>,
    /// One label per row (supervised) or `None`.
    pub labels: Option<Vec<usize>>,
    /// Rows whose partner row (`partner_permutation`: 0↔1, 2↔3, …) holds a take of the same
    /// content in another style (the style-statistics loss judges their swaps).
    pub content_paired: Vec<usize>,
    /// The row whose style each row's swap takes (`None`: the partner row; see
    /// [`StylizerWeights::cross_content`](super::losses::StylizerWeights::cross_content)).
    pub style_source: Option<Vec<usize>>,
    /// Offsets of the content-paired rows' target statistics (`None`: the partners' own;
    /// [`StylizerWeights::cross_set_relative`]).
    pub stats_offset: Option<StatsOffset>,
    /// Each row's content class (empty: no content-class loss; [`StylizerInputs::content_classes`]).
    pub content_classes: Vec<Option<usize>>,
}

impl StylizerBatch {
    /// The paper's batch: two clips of one sequence per row and their labels (`None`:
    /// unsupervised), no content-paired rows (so none of the pair losses' extras).
    pub fn unpaired(motion1: Tensor<3>, motion2: Tensor<3>, labels: Option<Vec<usize>>) -> Self {
        StylizerBatch {
            motion1,
            motion2,
            labels,
            content_paired: Vec::new(),
            style_source: None,
            stats_offset: None,
            content_classes: Vec::new(),
        }
    }
}

step_report! {
    /// Losses of one stylizer step (before the update), unweighted terms as in
    /// [`StylizerLosses`](super::losses::StylizerLosses).
    pub struct StylizerStepReport {
        pub loss,
        pub rec_latent,
        pub rec_pose,
        pub cyc_latent,
        pub cyc_pose,
        pub kl,
        pub hsa,
        /// The style-statistics loss of the content-paired swaps (0 without them).
        pub style_stats,
        /// The content-shape loss of the swaps (0 without it).
        pub content_shape,
        /// The content judge's cross-entropy on the swaps (0 without it).
        pub content_class,
        /// The style judge's cross-entropy on the swaps (0 without it).
        pub style_class,
        /// Gradient norms before clipping: content + style encoders, generator.
        pub encoders_grad_norm,
        pub generator_grad_norm,
    }
}

/// The trainer's noise generator is seeded with `seed ^ NOISE_SALT` (the reparameterisation draws
/// of [`stylizer_loss`]; `examples/train_perf_bench.rs` replays them).
pub const NOISE_SALT: u64 = 0x5eed_57e0;

/// Stage 2: content encoder, style encoder and generator on latents of a frozen autoencoder.
pub struct StylizerTrainer {
    pub config: ModelConfig,
    pub train: TrainConfig,
    pub weights: StylizerWeights,
    /// Frozen (no gradients, dropout off), on the autodiff device so gradients flow through the
    /// decoder into the generator.
    pub autoencoder: MotionAutoencoder,
    /// On the autodiff device.
    pub net: Stylizer,
    /// The frozen content classifier of the content-class loss
    /// ([`StylizerWeights::content_class`]), on the autodiff device.
    content_judge: Option<StyleClassifier>,
    /// The frozen style classifier of the style-class loss ([`StylizerWeights::style_class`]).
    style_judge: Option<StyleClassifier>,
    optim: ModuleOptimizer,
    noise: NoiseRng,
    device: Device,
    /// Time per phase of the steps, when measured.
    pub phases: Option<PhaseTimes>,
}

impl StylizerTrainer {
    /// Fresh stylizer networks on `device.autodiff()` (weights from `seed`) over the given
    /// (trained) autoencoder, which may live on the plain or the autodiff device of the same
    /// backend.
    pub fn new(
        config: ModelConfig,
        train: TrainConfig,
        autoencoder: MotionAutoencoder,
        device: &Device,
        seed: u64,
    ) -> Self {
        let device = device.clone().autodiff();
        device.seed(seed);
        let autoencoder = autoencoder.valid().train().freeze();
        let net = seeded_xavier(Stylizer::new(&config, &device), seed);
        let weights = train.stylizer_weights.unwrap_or_else(|| StylizerWeights::paper(config.supervised));
        Self {
            config,
            train,
            weights,
            autoencoder,
            net,
            content_judge: None,
            style_judge: None,
            optim: adam(),
            noise: NoiseRng::new(seed ^ NOISE_SALT),
            device,
            phases: None,
        }
    }

    /// Sets the content classifier of the content-class loss from its file's bytes
    /// ([`save_classifier`](crate::model::weights::save_classifier)); frozen, on the training
    /// device (`device`: its plain side, as given to [`StylizerTrainer::new`]). It must classify
    /// [`CONTENTS`]' classes.
    pub fn set_content_judge(&mut self, bytes: &[u8], device: &Device) -> Result<(), ModelError> {
        self.content_judge = Some(frozen_on(read_judge(bytes, Judged::Content, &self.config)?, device));
        Ok(())
    }

    /// Sets the style classifier of the style-class loss from its file's bytes, as
    /// [`StylizerTrainer::set_content_judge`]. It must classify the run's style labels, and the
    /// run must be supervised (the swaps' target labels).
    pub fn set_style_judge(&mut self, bytes: &[u8], device: &Device) -> Result<(), ModelError> {
        self.style_judge = Some(frozen_on(read_judge(bytes, Judged::Style, &self.config)?, device));
        Ok(())
    }

    /// The training device (autodiff).
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// Latent of features through the frozen encoder (a sample for the VAE, as the reference),
    /// without gradient.
    fn latent(&mut self, features: Tensor<3>) -> Tensor<3> {
        let dist = self.autoencoder.encoder.forward(ae_input(features));
        let z = match dist.logvar {
            Some(logvar) => {
                let [b, d, l] = dist.mean.dims();
                let eps: Tensor<3> = self.noise.normal_tensor(b, d * l, &self.device).reshape([b, d, l]);
                dist.mean + (logvar * 0.5).exp() * eps
            }
            None => dist.mean,
        };
        z.detach()
    }

    /// One Adam step.
    pub fn step(&mut self, batch: &StylizerBatch) -> Result<StylizerStepReport, ModelError> {
        check_features("clip 1 features", &batch.motion1)?;
        check_features("clip 2 features", &batch.motion2)?;
        let [b, _, t] = batch.motion1.dims();
        if let Some(&bad) = batch.content_paired.iter().find(|&&r| r >= b) {
            return Err(ModelError::BatchSize {
                what: "content-paired row (below the batch size)",
                expected: b,
                got: bad,
            });
        }
        let groups = row_groups(&self.device, b, self.train.batch_chunks);
        if let Some(source) = &batch.style_source {
            if source.len() != b {
                return Err(ModelError::BatchSize {
                    what: "style sources (one a row)",
                    expected: b,
                    got: source.len(),
                });
            }
            // Row groups run apart: a swap's style source must be in its own group.
            if let Some((row, &bad)) =
                source.iter().enumerate().find(|&(r, s)| !groups.iter().any(|g| g.contains(&r) && g.contains(s)))
            {
                return Err(ModelError::BatchSize {
                    what: "style source of a row (a row of the same row group)",
                    expected: row,
                    got: bad,
                });
            }
        }
        if let Some(o) = &batch.stats_offset
            && (o.mean.dims() != [b, DIM] || o.spread.dims() != [b, DIM])
        {
            let got = o.mean.dims()[0];
            return Err(ModelError::BatchSize { what: "statistics offsets ([B, 260] each)", expected: b, got });
        }
        if !batch.content_classes.is_empty() && batch.content_classes.len() != b {
            let got = batch.content_classes.len();
            return Err(ModelError::BatchSize { what: "content classes (one a row)", expected: b, got });
        }
        if let Some(bad) = batch.content_classes.iter().flatten().find(|&&c| c >= CONTENTS.len()) {
            return Err(ModelError::Label(format!("content class {bad} out of range {}", CONTENTS.len())));
        }
        if batch.motion2.dims() != [b, DIM, t] {
            let got = batch.motion2.dims()[0];
            return Err(ModelError::BatchSize { what: "clip 2 (same shape as clip 1)", expected: b, got });
        }
        let labels = match (self.config.supervised, &batch.labels) {
            (false, _) => None,
            (true, None) => return Err(ModelError::Label("supervised training needs style labels".into())),
            (true, Some(labels)) => {
                if labels.len() != b {
                    return Err(ModelError::BatchSize { what: "style labels", expected: b, got: labels.len() });
                }
                if let Some(&bad) = labels.iter().find(|&&l| l >= self.config.num_styles) {
                    return Err(ModelError::Label(format!("label {bad} out of range {}", self.config.num_styles)));
                }
                Some(one_hot(labels, self.config.num_styles, &self.device))
            }
        };
        let t0 = Instant::now();
        let motion1 = batch.motion1.clone().to_device(&self.device).autodiff();
        let motion2 = batch.motion2.clone().to_device(&self.device).autodiff();
        let inputs = StylizerInputs {
            latent1: self.latent(motion1.clone()),
            latent2: self.latent(motion2.clone()),
            motion1,
            motion2,
            labels,
            content_paired: batch.content_paired.clone(),
            style_source: batch.style_source.clone(),
            stats_offset: batch.stats_offset.as_ref().map(|o| StatsOffset {
                mean: o.mean.clone().to_device(&self.device).autodiff(),
                spread: o.spread.clone().to_device(&self.device).autodiff(),
            }),
            content_classes: batch.content_classes.clone(),
        };
        let eps = StyleNoise::draw(&mut self.noise, b, self.net.style_encoder.style_dim, &self.device);
        // The batch's row groups side by side on the CPU's threads (`super::parallel`), each its
        // share of the whole batch's loss; one group on a GPU or with `batch_chunks` 1.
        let paired_total = batch.content_paired.len().max(1) as f32;
        let shares: Vec<LossShares> = groups
            .iter()
            .map(|g| LossShares {
                rows: g.len() as f32 / b as f32,
                paired: batch.content_paired.iter().filter(|r| g.contains(r)).count() as f32 / paired_total,
            })
            .collect();
        let (net, decoder, weights) = (&self.net, &self.autoencoder.decoder, &self.weights);
        let judges = Judges { content: self.content_judge.as_ref(), style: self.style_judge.as_ref() };
        let replicas: Vec<Replica<Stylizer>> = groups.iter().map(|_| Replica::of(net)).collect();
        let losses = map_parallel(groups.len(), |i| {
            let group = inputs.rows(groups[i].clone());
            let eps = eps.rows(groups[i].clone());
            stylizer_loss_drawn(&replicas[i].module, decoder, judges, &group, weights, eps, shares[i])
        });

        let t1 = Instant::now();
        let grads = map_parallel(losses.len(), |i| replicas[i].grads(&mut losses[i].total.backward()));
        let mut g = sum_grads(&self.net, grads);
        let t2 = Instant::now();
        // As the reference: one norm over both encoders, one over the generator.
        let clip = self.train.grad_clip_norm;
        let mut enc_parts = squared_norm_parts(&self.net.content_encoder, &g);
        enc_parts.extend(squared_norm_parts(&self.net.style_encoder, &g));
        let encoders_grad_norm = total_norm(enc_parts);
        if let Some(factor) = clip_factor(encoders_grad_norm, clip) {
            scale_grads(&self.net.content_encoder, &mut g, factor);
            scale_grads(&self.net.style_encoder, &mut g, factor);
        }
        let generator_grad_norm = clip_grad_norm(&self.net.generator, &mut g, clip);
        let t3 = Instant::now();

        // The batch's terms: each group's means weighted by its shares (the totals carry theirs).
        let [
            loss,
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
        ] = weighted_terms(shares.iter().zip(losses).map(|(&shares, l)| {
            let terms = l.into_terms(shares);
            (terms.clone().map(|(value, _)| value), terms.map(|(_, share)| share))
        }));
        self.net = self.optim.step(self.train.lr, self.net.clone(), g);
        if let Some(p) = &mut self.phases {
            p.add([t0, t1, t2, t3, Instant::now()]);
        }
        Ok(StylizerStepReport {
            loss,
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
            encoders_grad_norm,
            generator_grad_norm,
        })
    }
}

/// What a judge of the swaps names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Judged {
    /// The content classes ([`CONTENTS`]): the content-class loss.
    Content,
    /// The run's style labels (supervised runs): the style-class loss.
    Style,
}

/// A judge's classifier from its file's bytes (on flex), checked against what it must name for a
/// stylizer of `config` (`train` checks this before it writes a run folder).
pub fn read_judge(bytes: &[u8], judged: Judged, config: &ModelConfig) -> Result<StyleClassifier, ModelError> {
    if judged == Judged::Style && !config.supervised {
        return Err(ModelError::Label("a style judge needs a supervised run (the swaps' target labels)".into()));
    }
    let (judge_config, judge) = load_classifier(bytes, &Device::flex())?;
    let classes = judge_config.num_styles;
    match judged {
        Judged::Content if classes != CONTENTS.len() => Err(ModelError::Label(format!(
            "the content judge classifies {classes} classes, not the {} content classes (a style classifier?)",
            CONTENTS.len()
        ))),
        Judged::Style if classes != config.num_styles => Err(ModelError::Label(format!(
            "the style judge classifies {classes} classes, not the run's {} style labels",
            config.num_styles
        ))),
        _ => Ok(judge),
    }
}

/// A judge read on flex (its file is f16), moved to `device` (not every device has f16 tensors),
/// frozen on its autodiff side.
fn frozen_on(judge: StyleClassifier, device: &Device) -> StyleClassifier {
    let judge = if *device == Device::flex() { judge } else { judge.to_device(device) };
    judge.train().freeze()
}

/// `[B, 260]` mean and spread offsets: `+offset` on each listed row, `−offset` on the row after
/// it (its partner), zero elsewhere.
fn stats_offsets(offsets: &[(usize, Vec<f32>, Vec<f32>)], batch: usize, device: &Device) -> StatsOffset {
    let (mut mean, mut spread) = (vec![0f32; batch * DIM], vec![0f32; batch * DIM]);
    for (row, m, s) in offsets {
        for (c, (&m, &s)) in m.iter().zip(s).enumerate() {
            mean[row * DIM + c] = m;
            spread[row * DIM + c] = s;
            mean[(row + 1) * DIM + c] = -m;
            spread[(row + 1) * DIM + c] = -s;
        }
    }
    let tensor = |v: Vec<f32>| Tensor::from_data(TensorData::new(v, [batch, DIM]), device);
    StatsOffset { mean: tensor(mean), spread: tensor(spread) }
}

impl Trainer for StylizerTrainer {
    type Report = StylizerStepReport;
    const SHOWN: &'static [(&'static str, &'static str)] =
        &[("loss", "loss"), ("rec_pose", "rec_pose"), ("hsa", "hsa")];
    const METRICS: &'static [&'static str] = &eval::STYLIZER_METRICS;

    fn train_step(&mut self, data: &TrainData, rng: &mut SamplerRng) -> anyhow::Result<StylizerStepReport> {
        // With the style-statistics loss, every other pair of rows (0↔1, 4↔5, …) is a take and a
        // take of the same content in another style, when the data has one; the other rows are
        // drawn as always, so the swaps still cross contents half of the time. Cross-content:
        // rows 4k+2 and 4k+3 are then a take of row 4k+1's style and one of row 4k's, both of
        // another content, and the pair's swaps take their styles from them.
        let paired_rows = self.weights.style_stats > 0.0;
        let cross = paired_rows && self.weights.cross_content;
        let groups = if self.weights.cross_set { &data.groups_across_sets } else { &data.groups };
        let mut pairs = Vec::with_capacity(data.batch);
        let mut content_paired = Vec::new();
        let mut source: Vec<usize> = super::losses::partner_permutation(data.batch);
        let relative = paired_rows && self.weights.cross_set_relative;
        // (row, mean, spread): row's target moves by +offset, its partner row's by −offset.
        let mut offsets: Vec<(usize, Vec<f32>, Vec<f32>)> = Vec::new();
        while pairs.len() < data.batch {
            let row = pairs.len();
            let first = data.sampler.pair(rng);
            let quad = cross && row % 4 == 0 && row + 3 < data.batch;
            let partner = (paired_rows && row % 4 == 0 && row + 1 < data.batch)
                .then(|| data.sampler.content_partner(first.0.clip, groups, rng))
                .flatten();
            let sources = match (&partner, quad) {
                (Some(p), true) => {
                    let content = data.contents[first.0.clip];
                    let mut elsewhere = |style| data.sampler.style_clip_elsewhere(style, content, &data.contents, rng);
                    elsewhere(p.2).zip(elsewhere(first.2))
                }
                _ => None,
            };
            if let (true, Some(p)) = (relative, &partner) {
                // Zero within a set (one group, one baseline) and where a set lacks `normal` takes.
                let base = |clip: usize| data.baseline_of[clip].map(|i| &data.baselines[i]);
                if let (Some(own), Some(theirs)) = (base(first.0.clip), base(p.0.clip)) {
                    let (mean, spread) = own.minus(theirs);
                    offsets.push((row, mean, spread));
                }
            }
            pairs.push(first);
            if let Some(p) = partner {
                content_paired.extend([row, row + 1]);
                pairs.push(p);
            }
            if let Some((for_first, for_partner)) = sources {
                pairs.extend([for_first, for_partner]);
                source[row..row + 4].copy_from_slice(&[row + 2, row + 3, row + 3, row + 2]);
            }
        }
        let first: Vec<_> = pairs.iter().map(|p| p.0).collect();
        let second: Vec<_> = pairs.iter().map(|p| p.1).collect();
        debug_assert!(pairs.iter().all(|p| data.labels[p.0.clip] == p.2));
        let batch = StylizerBatch {
            motion1: batch_tensor(&data.clips, &first, data.window, &data.device),
            motion2: batch_tensor(&data.clips, &second, data.window, &data.device),
            labels: self.config.supervised.then(|| pairs.iter().map(|p| p.2).collect()),
            content_paired,
            style_source: cross.then_some(source),
            stats_offset: relative.then(|| stats_offsets(&offsets, data.batch, &data.device)),
            content_classes: match self.content_judge {
                Some(_) => pairs.iter().map(|p| data.content_class[p.0.clip]).collect(),
                None => Vec::new(),
            },
        };
        Ok(self.step(&batch)?)
    }

    fn evaluate(&self, data: &TrainData) -> Vec<f64> {
        let net = self.net.clone().valid();
        let ae = self.autoencoder.clone().valid();
        let styles = self.config.supervised.then_some(self.config.num_styles);
        eval::evaluate_stylizer(&net, &ae, &self.weights, styles, &data.heldout, data.batch, &data.device)
    }

    fn learning_rates(&self) -> Vec<(&'static str, f64)> {
        vec![("lr", self.train.lr)]
    }

    fn weights(&self) -> anyhow::Result<Vec<u8>> {
        module_bytes(self.net.clone().valid())
    }

    fn load_weights(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        self.net = load_module(Stylizer::new(&self.config, &self.device), bytes)?;
        Ok(())
    }

    fn optimizer_state(&self) -> Result<Vec<u8>, ModelError> {
        optimizers_to_bytes(&[&self.optim])
    }

    fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        [self.optim] = optimizers_from_bytes(bytes)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_offsets_move_a_pair_in_opposite_directions_and_leave_other_rows_alone() {
        let (m, s) = (vec![0.5; DIM], vec![-0.25; DIM]);
        let o = stats_offsets(&[(2, m, s)], 6, &Device::flex());
        let rows = |t: Tensor<2>| -> Vec<f32> {
            let v = t.into_data().try_to_vec::<f32>().expect("f32");
            (0..6).map(|r| v[r * DIM + DIM - 1]).collect()
        };
        assert_eq!(rows(o.mean), vec![0.0, 0.0, 0.5, -0.5, 0.0, 0.0]);
        assert_eq!(rows(o.spread), vec![0.0, 0.0, -0.25, 0.25, 0.0, 0.0]);
    }
}
