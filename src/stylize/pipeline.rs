//! The stylization pipeline: content motion + style source → stylized motions.
//!
//! 1. Content features ([`extract_placed`]), normalised with the weights' statistics, padded to a
//!    multiple of 8 frames by reflection ([`pad_features`]); encoder → motion latent → content code.
//! 2. Style codes, one row per sample ([`StyleSource`]).
//! 3. The content code repeated once per sample, the generator (AdaIN on each row's style code and
//!    label) → motion latents → decoder → features, all samples in one batch.
//! 4. Root: angular velocity (dim 0) from the content's features, ground velocity (dims 1..3) from
//!    the global motion regressor on the generated motion, height and everything else from the
//!    decoder; denormalised, trimmed to the content's length, rebuilt ([`reconstruct`]) and put
//!    where the content was ([`Placement`](crate::features::Placement)).

use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};

use super::StylizeError;
use super::source::{MAX_GUIDANCE, MAX_MIX_DEPTH, MAX_SAMPLES, MAX_STRENGTH, MAX_TEMPERATURE, Request, StyleSource};
use super::weights::{Setting, Weights};
use super::{feet, legs};
use crate::Motion;
use crate::dataset::Style;
use crate::features::{DIM, FeatureError, Features, MODEL_DIM, ROOT_ANG_VEL, View, extract_placed, reconstruct};
use crate::model::config::FRAME_MULTIPLE;
use crate::model::layers::{channels, one_hot};
use crate::model::{Model, NoiseRng, StyleDistribution};

/// Longest content or reference motion accepted, frames at 30 fps (5 minutes).
pub const MAX_FRAMES: usize = 9_000;

/// Samples × padded frames that go through the networks in one batch; more samples are split
/// into several batches (bounds the memory, e.g. in the browser). At 160 frames, 64 samples fit
/// in one batch.
const BATCH_FRAME_BUDGET: usize = 16_384;

/// The length a clip of `frames` frames is padded to: the next multiple of 8, at least 8.
pub fn padded_frames(frames: usize) -> usize {
    frames.div_ceil(FRAME_MULTIPLE).max(1) * FRAME_MULTIPLE
}

/// Index of the frame that padding frame `t` copies, for a clip of `n` frames: reflection without
/// repeating the edge (`… n−2, n−1, n−2, …, 0, 1, …`, periodic for long pads); a one-frame clip
/// repeats its frame.
fn reflect_index(t: usize, n: usize) -> usize {
    if n <= 1 {
        return 0;
    }
    let period = 2 * (n - 1);
    let i = t % period;
    if i < n { i } else { period - i }
}

/// `f` extended to `len ≥ f.frames()` frames by reflection in time (mirror without repeating the
/// edge frame, periodic for long pads; a one-frame clip repeats its frame).
pub fn pad_features(f: &Features, len: usize) -> Features {
    let n = f.frames();
    let mut data = Vec::with_capacity(len.max(n) * DIM);
    for t in 0..len.max(n) {
        data.extend_from_slice(f.frame(reflect_index(t, n)));
    }
    Features::new(len.max(n), data).unwrap_or_else(|_| f.clone())
}

/// A motion's normalised, padded features as a `[1, 260, T]` tensor, its frame count and where it
/// sat in the world.
struct Prepared {
    tensor: Tensor<3>,
    frames: usize,
    placement: crate::features::Placement,
}

fn prepare(
    norm: &crate::features::NormStats,
    motion: &Motion,
    what: &'static str,
    device: &Device,
) -> Result<Prepared, StylizeError> {
    let frames = motion.frames();
    if frames > MAX_FRAMES {
        return Err(StylizeError::TooLong { what, frames, max: MAX_FRAMES });
    }
    let (mut features, placement) = extract_placed(motion);
    if let Some((frame, dim)) = features.first_non_finite() {
        return Err(StylizeError::Features(FeatureError::NonFinite { frame, dim }));
    }
    norm.normalize(&mut features);
    let len = padded_frames(frames);
    let padded = pad_features(&features, len);
    let tensor = Tensor::from_data(TensorData::new(padded.view_channels_first(View::Full), [1, DIM, len]), device);
    Ok(Prepared { tensor, frames, placement })
}

/// Style codes `[N, style_dim]` and, for the supervised model, (possibly soft) one-hot labels
/// `[N, num_styles]`.
struct Codes {
    code: Tensor<2>,
    label: Option<Tensor<2>>,
}

/// Checks a request against the model before any network runs.
fn validate(source: &StyleSource<'_>, model: &Model, depth: usize) -> Result<(), StylizeError> {
    let supervised = model.config.supervised;
    let check_label = |s: &Style| label_index(*s, model).map(|_| ());
    match source {
        StyleSource::Motion { motion, label } => {
            match (supervised, label) {
                (true, None) => return Err(StylizeError::MotionNeedsLabel),
                (false, Some(_)) => return Err(StylizeError::LabelWithUnsupervised),
                (true, Some(l)) => check_label(l)?,
                (false, None) => {}
            }
            if motion.frames() > MAX_FRAMES {
                return Err(StylizeError::TooLong { what: "reference", frames: motion.frames(), max: MAX_FRAMES });
            }
            Ok(())
        }
        StyleSource::Label(l) => {
            if !supervised {
                return Err(StylizeError::LabelNeedsSupervised);
            }
            check_label(l)
        }
        StyleSource::Prior => Ok(()),
        StyleSource::Mix { a, b, t } => {
            if depth >= MAX_MIX_DEPTH {
                return Err(StylizeError::MixTooDeep { max: MAX_MIX_DEPTH });
            }
            if !(t.is_finite() && (0.0..=1.0).contains(t)) {
                return Err(StylizeError::MixWeight { t: *t });
            }
            validate(a, model, depth + 1)?;
            validate(b, model, depth + 1)
        }
    }
}

fn label_index(style: Style, model: &Model) -> Result<usize, StylizeError> {
    let count = model.config.num_styles;
    if style.index() < count {
        Ok(style.index())
    } else {
        Err(StylizeError::LabelOutOfRange { index: style.index(), count })
    }
}

/// The random draws of one request: style noise and (supervised prior) labels, both from the seed.
struct Draws {
    noise: NoiseRng,
    labels: ChaCha8Rng,
}

impl Draws {
    fn new(seed: u64) -> Self {
        let mut labels = ChaCha8Rng::seed_from_u64(seed);
        // Another stream than the noise's (NoiseRng uses stream 0 of the same seed).
        labels.set_stream(1);
        Draws { noise: NoiseRng::new(seed), labels }
    }

    /// Uniform in `0..n` (`n ≥ 1`; multiply-shift, the same on every platform).
    fn label(&mut self, n: usize) -> usize {
        ((u64::from(self.labels.next_u32()) * n as u64) >> 32) as usize
    }
}

struct Resolver<'w> {
    weights: &'w Weights,
    model: &'w Model,
    samples: usize,
    /// Scale of the prior draws ([`Request::temperature`]).
    temperature: f32,
    draws: Draws,
}

impl Resolver<'_> {
    fn one_hot_rows(&self, labels: &[usize]) -> Tensor<2> {
        one_hot(labels, self.model.config.num_styles, self.model.device())
    }

    /// Codes for `source` (validated by [`validate`]).
    fn resolve(&mut self, source: &StyleSource<'_>) -> Result<Codes, StylizeError> {
        let (n, d) = (self.samples, self.model.config.style_dim);
        let device = self.model.device().clone();
        let supervised = self.model.config.supervised;
        match source {
            StyleSource::Motion { motion, label } => {
                let label = label.map(|l| label_index(l, self.model)).transpose()?;
                let prepared = prepare(self.weights.norm(), motion, "reference", &device)?;
                let latent = self.model.encode(prepared.tensor)?;
                let dist = self.model.style_distribution(latent, label.map(|l| vec![l]).as_deref())?;
                let code = if n == 1 {
                    dist.mean
                } else {
                    let eps = self.draws.noise.normal_tensor(n, d, &device);
                    let rows =
                        StyleDistribution { mean: dist.mean.repeat_dim(0, n), logvar: dist.logvar.repeat_dim(0, n) };
                    rows.sample_with(eps)
                };
                Ok(Codes { code, label: label.map(|l| self.one_hot_rows(&vec![l; n])) })
            }
            StyleSource::Label(style) => {
                let l = label_index(*style, self.model)?;
                let spread = self.draws.noise.normal_tensor(n, d, &device) * self.temperature;
                let code = match self.weights.label_code(*style) {
                    Some(centre) => {
                        Tensor::<2>::from_data(TensorData::new(centre.to_vec(), [1, d]), &device).repeat_dim(0, n)
                            + spread
                    }
                    None => spread,
                };
                Ok(Codes { code, label: Some(self.one_hot_rows(&vec![l; n])) })
            }
            StyleSource::Prior => {
                let code = self.draws.noise.normal_tensor(n, d, &device) * self.temperature;
                let label = supervised.then(|| {
                    let count = self.model.config.num_styles;
                    let labels: Vec<usize> = (0..n).map(|_| self.draws.label(count)).collect();
                    self.one_hot_rows(&labels)
                });
                Ok(Codes { code, label })
            }
            StyleSource::Mix { a, b, t } => {
                let a = self.resolve(a)?;
                let b = self.resolve(b)?;
                let lerp = |x: Tensor<2>, y: Tensor<2>| x.clone() + (y - x) * *t;
                let label = match (a.label, b.label) {
                    (Some(x), Some(y)) => Some(lerp(x, y)),
                    _ => None,
                };
                Ok(Codes { code: lerp(a.code, b.code), label })
            }
        }
    }
}

/// How much of the content's own drift under the neutral style, `z_c − G(c, s_normal)`, the
/// guidance direction carries back (see [`Request::guidance`]). Measured on the quick protocol
/// (EVALUATION.md, "Guidance"): at guidance 1, 0.5 keeps the label-based style shift of the plain
/// difference (1.06 against 0.99) with content accuracy 0.27 instead of 0.16, geodesic distance
/// 0.35 instead of 0.42 and the classifier's accuracy 0.92; 0 is the plain difference.
const GUIDANCE_CONTENT: f32 = 0.5;

/// The label of the neutral style guidance measures a style against (the Bandai-Namco sets' own).
pub const NEUTRAL_LABEL: &str = "normal";

/// The neutral style's codes for [`Request::guidance`]: `normal`'s label code (with the same
/// draws as a label-based request of the same seed: its noise for label- and prior-based
/// sources, none for motion-based ones) in the supervised model. In the unsupervised one, for a
/// reference motion the `normal` takes' code ([`Weights::neutral_code`]; the prior's mean, 0,
/// for weights without one), and for prior draws the prior's mean they are drawn around.
/// Measured by `make eval` (EVALUATION.md, "The unsupervised model's neutral anchor"): against
/// `normal` instead of 0, references move 0.92 of a real take's change instead of 0.80 with the
/// same accuracy, less foot skating and more content; prior draws measured against `normal` lost
/// content (0.66 → 0.52 on the quick protocol), so they keep 0. `None` — guidance not applied — for a
/// label-based request of `normal` itself, and for supervised weights without a `normal` label
/// (a folder of one's own styles may have none: there is no neutral style to measure against).
fn neutral_codes(weights: &Weights, model: &Model, request: &Request<'_>) -> Result<Option<Codes>, StylizeError> {
    let n = request.samples;
    if !model.config.supervised {
        let d = model.config.style_dim;
        // A mix's anchor mixes its sources' anchors the same way.
        fn reference_share(source: &StyleSource<'_>) -> f32 {
            match source {
                StyleSource::Motion { .. } => 1.0,
                StyleSource::Label(_) | StyleSource::Prior => 0.0,
                StyleSource::Mix { a, b, t } => (1.0 - t) * reference_share(a) + t * reference_share(b),
            }
        }
        let share = reference_share(&request.source);
        let code = match weights.neutral_code() {
            Some(code) if share > 0.0 => {
                let anchor: Vec<f32> = code.iter().map(|v| v * share).collect();
                Tensor::<1>::from_data(TensorData::new(anchor, [d]), model.device()).reshape([1, d]).repeat_dim(0, n)
            }
            _ => Tensor::zeros([n, d], model.device()),
        };
        return Ok(Some(Codes { code, label: None }));
    }
    let Ok(normal) = weights.style(NEUTRAL_LABEL) else { return Ok(None) };
    let neutral_itself = match request.source {
        StyleSource::Label(s) | StyleSource::Motion { label: Some(s), .. } => s == normal,
        _ => false,
    };
    if neutral_itself {
        // The neutral style itself, by label or by a reference of it: no difference to amplify,
        // and the content term alone would only bring back the content's own style, which
        // `normal` is asked to replace (a `normal` reference's motion-based accuracy fell to
        // 0.78 with it on the posture weights: EVALUATION.md, "The neutral reference").
        return Ok(None);
    }
    let temperature = match request.source {
        StyleSource::Motion { .. } => 0.0,
        _ => request.temperature,
    };
    let mut resolver = Resolver { weights, model, samples: n, temperature, draws: Draws::new(request.seed) };
    resolver.resolve(&StyleSource::Label(normal)).map(Some)
}

/// A tensor's values on the host. Asynchronous, the one way a browser's WebGPU device can be
/// read; on the CPU backends (and natively on wgpu, under [`complete`]) it is ready at once.
async fn read_back<const D: usize>(t: Tensor<D>) -> Result<Vec<f32>, StylizeError> {
    let data = t.into_data_async().await.map_err(|e| StylizeError::Model(format!("reading a tensor: {e:?}")))?;
    data.try_into_vec_as::<f32>().map_err(|e| StylizeError::Model(format!("reading a tensor: {e:?}")))
}

/// Runs one of the pipeline's async functions to its end, for the synchronous API. Natively the
/// thread waits for the device (woken by it, or every millisecond where a runtime does not wake
/// it); in wasm nothing may block, so a device that is not ready at once (WebGPU) is an error
/// naming the async call to use instead: the CPU backends always are.
///
/// Written here rather than taken from an executor crate: these ten lines are all the pipeline
/// needs (no spawning, no I/O), and the wasm build must never block.
pub(crate) fn complete<T>(future: impl Future<Output = Result<T, StylizeError>>) -> Result<T, StylizeError> {
    use std::task::{Context, Poll};
    let mut future = std::pin::pin!(future);
    #[cfg(not(target_arch = "wasm32"))]
    {
        struct Unpark(std::thread::Thread);
        impl std::task::Wake for Unpark {
            fn wake(self: std::sync::Arc<Self>) {
                self.0.unpark();
            }
        }
        let waker = std::sync::Arc::new(Unpark(std::thread::current())).into();
        let mut cx = Context::from_waker(&waker);
        loop {
            match future.as_mut().poll(&mut cx) {
                Poll::Ready(v) => return v,
                Poll::Pending => std::thread::park_timeout(std::time::Duration::from_millis(1)),
            }
        }
    }
    #[cfg(target_arch = "wasm32")]
    {
        match future.as_mut().poll(&mut Context::from_waker(std::task::Waker::noop())) {
            Poll::Ready(v) => v,
            Poll::Pending => Err(StylizeError::Model(
                "this device reads its results asynchronously (WebGPU): use the async call".into(),
            )),
        }
    }
}

/// Stylizes `content` as `request` asks: `request.samples` motions, each as long as `content`, on
/// the canonical rig, where `content` was in the world (same start, facing and floor).
///
/// Deterministic: the same weights, content and request give the same motions, bit for bit.
/// Errors: see [`StylizeError`]; nothing panics on any motion or request.
pub fn stylize(weights: &Weights, content: &Motion, request: &Request<'_>) -> Result<Vec<Motion>, StylizeError> {
    complete(stylize_async(weights, content, request))
}

/// [`stylize`] for a device whose results are read asynchronously (WebGPU in a browser); the
/// same motions, bit for bit, on the same device.
pub async fn stylize_async(
    weights: &Weights,
    content: &Motion,
    request: &Request<'_>,
) -> Result<Vec<Motion>, StylizeError> {
    if !(1..=MAX_SAMPLES).contains(&request.samples) {
        return Err(StylizeError::Samples { got: request.samples, max: MAX_SAMPLES });
    }
    let model = weights.model(request.setting)?;
    if content.frames() > MAX_FRAMES {
        return Err(StylizeError::TooLong { what: "content", frames: content.frames(), max: MAX_FRAMES });
    }
    validate(&request.source, model, 0)?;

    let n = request.samples;
    if !(request.temperature.is_finite() && (0.0..=MAX_TEMPERATURE).contains(&request.temperature)) {
        return Err(StylizeError::Temperature { got: request.temperature, max: MAX_TEMPERATURE });
    }
    let strength = request.strength;
    if !(strength.is_finite() && (0.0..=MAX_STRENGTH).contains(&strength)) {
        return Err(StylizeError::Strength { got: strength, max: MAX_STRENGTH });
    }
    let guidance = request.guidance;
    if !(guidance.is_finite() && (0.0..=MAX_GUIDANCE).contains(&guidance)) {
        return Err(StylizeError::Guidance { got: guidance, max: MAX_GUIDANCE });
    }

    let device = model.device().clone();
    let prepared = prepare(weights.norm(), content, "content", &device)?;
    if strength == 0.0 {
        // No style at all: the content itself (features extracted only to check it).
        return Ok(vec![content.clone(); n]);
    }
    let padded = prepared.tensor.dims()[2];
    let content_latent = model.encode(prepared.tensor.clone())?;
    let content_code = model.content(content_latent.clone())?;
    let angular = channels(prepared.tensor.clone(), ROOT_ANG_VEL);
    let mut resolver =
        Resolver { weights, model, samples: n, temperature: request.temperature, draws: Draws::new(request.seed) };
    let codes = resolver.resolve(&request.source)?;
    if codes.label.is_some() != model.config.supervised {
        return Err(StylizeError::Model("style labels do not match the model's setting".into()));
    }
    let neutral = if guidance > 0.0 { neutral_codes(weights, model, request)? } else { None };

    let per_batch = (BATCH_FRAME_BUDGET / padded).clamp(1, n);
    let mut out = Vec::with_capacity(n);
    let mut start = 0;
    while start < n {
        let rows = per_batch.min(n - start);
        let code = codes.code.clone().narrow(0, start, rows);
        let label = codes.label.as_ref().map(|l| l.clone().narrow(0, start, rows));
        // The content's code and latent, one row per sample of this batch (the latent is what
        // guidance and strength measure the style against).
        let content_rows = content_code.clone().repeat_dim(0, rows);
        let own = content_latent.clone().repeat_dim(0, rows);
        let latent = model.generate_with(content_rows.clone(), code, label)?;
        let latent = match &neutral {
            Some(n) => {
                let code = n.code.clone().narrow(0, start, rows);
                let label = n.label.as_ref().map(|l| l.clone().narrow(0, start, rows));
                let base = model.generate_with(content_rows, code, label)?;
                // G_s + g·((G_s − G_n) + c·(z_c − G_n)), c = GUIDANCE_CONTENT.
                let direction = (latent.clone() - base.clone()) + (own.clone() - base) * GUIDANCE_CONTENT;
                latent + direction * guidance
            }
            None => latent,
        };
        let latent = if strength == 1.0 { latent } else { own.clone() + (latent - own) * strength };
        let features = model.with_root(model.decode(latent)?, angular.clone().repeat_dim(0, rows))?;
        let values = read_back(features).await?;
        for sample in values.chunks_exact(DIM * padded) {
            out.push(to_motion(weights, sample, padded, prepared.frames, &prepared.placement)?);
        }
        start += rows;
    }
    Ok(out)
}

/// One sample's channel-first normalised features `[260, padded]` → the motion, trimmed to the
/// content's length, denormalised, rebuilt and placed.
fn to_motion(
    weights: &Weights,
    sample: &[f32],
    padded: usize,
    frames: usize,
    placement: &crate::features::Placement,
) -> Result<Motion, StylizeError> {
    let mut data = Vec::with_capacity(frames * DIM);
    for t in 0..frames {
        data.extend((0..DIM).map(|c| sample[c * padded + t]));
    }
    let mut features = Features::new(frames, data)?;
    weights.norm().denormalize(&mut features);
    let motion = reconstruct(&features)?;
    let contacts = feet::contacts(&features);
    let motion = feet::pin_feet(&motion, &contacts).map_err(|e| StylizeError::Features(e.into()))?;
    let motion = legs::lock_legs(&motion, &contacts).map_err(|e| StylizeError::Features(e.into()))?;
    placement.from_canonical_motion(&motion).map_err(|e| StylizeError::Features(e.into()))
}

/// The style encoder's posterior mean for `motion` (`style_dim` numbers): where the motion sits
/// in the style space of `setting`'s model. `label` as for [`StyleSource::Motion`] (required by
/// the supervised model, refused by the unsupervised one). For evaluation: a stylized output
/// should land nearer the codes of its style reference than its content does.
pub fn style_code_of(
    weights: &Weights,
    setting: Setting,
    motion: &Motion,
    label: Option<Style>,
) -> Result<Vec<f32>, StylizeError> {
    complete(style_code_of_async(weights, setting, motion, label))
}

/// [`style_code_of`], read asynchronously.
pub async fn style_code_of_async(
    weights: &Weights,
    setting: Setting,
    motion: &Motion,
    label: Option<Style>,
) -> Result<Vec<f32>, StylizeError> {
    let model = weights.model(setting)?;
    let source = StyleSource::Motion { motion, label };
    validate(&source, model, 0)?;
    let label = label.map(|l| label_index(l, model)).transpose()?;
    let prepared = prepare(weights.norm(), motion, "reference", model.device())?;
    let latent = model.encode(prepared.tensor)?;
    let dist = model.style_distribution(latent, label.map(|l| vec![l]).as_deref())?;
    read_back(dist.mean).await
}

/// Frames of a reference the label inference looks at (its first 34 s): 16 labels × this fill
/// one batch of [`BATCH_FRAME_BUDGET`].
const INFER_FRAMES: usize = 1024;

/// The style label of `motion` for the supervised model, when the user gives none: the label
/// under which the model reconstructs the motion best — each label's posterior mean of the
/// motion's own style, through the generator with the motion's own content and that label,
/// decoded and compared with the motion (mean absolute error of the normalised features the
/// autoencoder sees, over the real frames). The supervised stylizer is trained to reconstruct a
/// clip from its content and its style under its true label, so the true label fits best.
/// Returns the label and each label's error (one batch: all labels at once, at most the first
/// [`INFER_FRAMES`] frames).
pub fn infer_label(weights: &Weights, motion: &Motion) -> Result<(Style, Vec<f32>), StylizeError> {
    complete(infer_label_async(weights, motion))
}

/// [`infer_label`], read asynchronously.
pub async fn infer_label_async(weights: &Weights, motion: &Motion) -> Result<(Style, Vec<f32>), StylizeError> {
    let model = weights.model(Setting::Supervised)?;
    let n = model.config.num_styles;
    let motion = if motion.frames() > INFER_FRAMES { motion.slice(0, INFER_FRAMES) } else { motion.clone() };
    let prepared = prepare(weights.norm(), &motion, "reference", model.device())?;
    let frames = prepared.frames;
    let latent = model.encode(prepared.tensor.clone())?;
    let content = model.content(latent.clone())?;
    let labels: Vec<usize> = (0..n).collect();
    let dist = model.style_distribution(latent.repeat_dim(0, n), Some(&labels))?;
    let rows = one_hot(&labels, n, model.device());
    let decoded = model.decode(model.generate_with(content.repeat_dim(0, n), dist.mean, Some(rows))?)?;
    let target = channels(prepared.tensor, 0..MODEL_DIM).narrow(2, 0, frames).repeat_dim(0, n);
    let error = (channels(decoded, 0..MODEL_DIM).narrow(2, 0, frames) - target).abs().mean_dim(2).mean_dim(1);
    let errors = read_back(error).await?;
    let best = errors
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
        .ok_or_else(|| StylizeError::Model("no style labels".into()))?;
    Ok((Style(best as u8), errors))
}
