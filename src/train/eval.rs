//! Held-out evaluation on a fixed, deterministic set of windows.
//!
//! Every held-out take with at least `T` frames gives one autoencoder window (its middle `T`
//! frames) and one stylizer pair (its first and its last `T` frames: two clips of one sequence,
//! overlapping when the take is shorter than `2T`). No mirrors. When there are more than the
//! requested maximum, an evenly spaced subset (in take-name order) is kept.
//!
//! Autoencoder metrics (the decoded 260-D features are denormalised and rebuilt into a motion by
//! [`features::reconstruct`], joint positions by forward kinematics; distances in mm or cm, means
//! over joints, frames and windows):
//! - `reconstruction`: smooth-L1 of the decoded features against the input, normalised units
//!   (the training loss term, on held-out data);
//! - `mpjpe_mm`: pose error — joint positions relative to the Hips, each motion in its own facing
//!   frame (rotated by minus its integrated yaw), so root drift does not count;
//! - `mpjpe_global_mm`: full-trajectory error, every joint in world space, with the decoder's own
//!   root velocities;
//! - `mpjpe_pipeline_mm`: full-trajectory error as the stylization pipeline would produce it
//!   ([`crate::model::Model::stylize`]): the input's root angular velocity and the regressor's
//!   ground velocity predicted from the decoded motion;
//! - `root_end_cm`, `root_mean_cm`: the regressor alone, on the input motion: root ground path
//!   integrated from its predicted velocity (and the true yaw) against the true path, at the
//!   window's last frame and averaged over frames.
//!
//! Stylizer metrics: each loss term of [`super::losses::stylizer_loss`] on the held-out
//! pairs (latents are the frozen encoder's means; the style samples use a fixed seed, so the
//! numbers are comparable between evaluations).

use burn::prelude::*;
use glam::{DQuat, DVec3};

use super::losses::{StylizerInputs, StylizerWeights, stylizer_loss};
use super::sampler::{Window, batch_tensor};
use crate::dataset::corpus::Clip;
use crate::features::{self, DIM, Features, NormStats, ROOT_ANG_VEL, ROOT_LIN_VEL};
use crate::model::autoencoder::{MotionAutoencoder, ae_input};
use crate::model::layers::{channels, one_hot};
use crate::model::regressor::{GlobalRegressor, regressor_input, regressor_input_from};
use crate::model::{NoiseRng, Stylizer};
use crate::skeleton::canonical::joint;

/// Names of the autoencoder metrics, in `eval.csv` order.
pub const AE_METRICS: [&str; 6] =
    ["reconstruction", "mpjpe_mm", "mpjpe_global_mm", "mpjpe_pipeline_mm", "root_end_cm", "root_mean_cm"];
/// Names of the stylizer metrics, in `eval.csv` order.
pub const STYLIZER_METRICS: [&str; 7] = ["loss", "rec_latent", "rec_pose", "cyc_latent", "cyc_pose", "kl", "hsa"];

/// Seed of the style-sampling noise of every stylizer evaluation.
const EVAL_NOISE_SEED: u64 = 0xe7a1;

/// The fixed held-out windows.
#[derive(Clone, Debug)]
pub struct HeldoutSet {
    pub window: usize,
    /// Per autoencoder window: raw and normalised features (`T` frames).
    pub raw: Vec<Features>,
    pub normalized: Vec<Features>,
    /// Per stylizer pair: normalised features of both clips and the take's style label.
    pub pairs: Vec<(Features, Features, usize)>,
    /// Held-out takes shorter than the window.
    pub skipped: usize,
}

impl HeldoutSet {
    /// Windows of the held-out clips (see the module docs); at most `max` of each kind.
    pub fn new(clips: &[Clip], norm: &NormStats, window: usize, max: usize) -> HeldoutSet {
        let long: Vec<&Clip> = clips.iter().filter(|c| c.features.frames() >= window).collect();
        let skipped = clips.len() - long.len();
        let keep: Vec<&Clip> =
            if long.len() > max && max > 0 { (0..max).map(|i| long[i * long.len() / max]).collect() } else { long };
        let normalized_clip = |f: Features| {
            let mut f = f;
            norm.normalize(&mut f);
            f
        };
        let mut set = HeldoutSet { window, raw: Vec::new(), normalized: Vec::new(), pairs: Vec::new(), skipped };
        for c in keep {
            let n = c.features.frames();
            let mid = (n - window) / 2;
            let raw = c.features.slice(mid, mid + window);
            set.normalized.push(normalized_clip(raw.clone()));
            set.raw.push(raw);
            let first = normalized_clip(c.features.slice(0, window));
            let last = normalized_clip(c.features.slice(n - window, n));
            set.pairs.push((first, last, c.style.map_or(0, |s| s.index())));
        }
        set
    }

    pub fn len(&self) -> usize {
        self.raw.len()
    }

    pub fn is_empty(&self) -> bool {
        self.raw.is_empty()
    }
}

fn whole(n: usize) -> Vec<Window> {
    (0..n).map(|clip| Window { clip, start: 0 }).collect()
}

fn to_vec(t: Tensor<3>) -> Vec<f32> {
    t.try_into_vec_as::<f32>().expect("f32 tensor")
}

/// Channels-first `[C, T]` values of one batch row → row-major `T × C`.
fn rows_of(cf: &[f32], channels: usize, t: usize) -> Vec<f32> {
    let mut out = vec![0f32; cf.len()];
    for c in 0..channels {
        for k in 0..t {
            out[k * channels + c] = cf[c * t + k];
        }
    }
    out
}

fn smooth_l1_sum(a: &[f32], b: &[f32]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (*x as f64 - *y as f64).abs();
            if d < 1.0 { 0.5 * d * d } else { d - 0.5 }
        })
        .sum()
}

/// Yaw of every frame, integrated from 0 as [`features::reconstruct`] does.
fn yaws(f: &Features) -> Vec<f64> {
    let mut yaw = 0.0f64;
    f.rows()
        .map(|row| {
            let y = yaw;
            yaw += row[ROOT_ANG_VEL.start] as f64;
            y
        })
        .collect()
}

/// Joint positions relative to the Hips, in each frame's facing frame.
fn local_positions(f: &Features) -> Option<Vec<[DVec3; 21]>> {
    let motion = features::reconstruct(f).ok()?;
    let yaw = yaws(f);
    Some(
        motion
            .global_positions()
            .into_iter()
            .zip(yaw)
            .map(|(p, y)| {
                let (inv, hips) = (DQuat::from_rotation_y(-y), p[joint::HIPS]);
                p.map(|q| inv * (q - hips))
            })
            .collect(),
    )
}

fn global_positions(f: &Features) -> Option<Vec<[DVec3; 21]>> {
    features::reconstruct(f).ok().map(|m| m.global_positions())
}

/// Mean joint distance (cm) between two position sequences; NaN if either is missing.
fn mean_distance(a: Option<Vec<[DVec3; 21]>>, b: &Option<Vec<[DVec3; 21]>>) -> f64 {
    match (a, b) {
        (Some(a), Some(b)) => {
            let n = (a.len() * 21) as f64;
            a.iter().zip(b).flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| x.distance(*y))).sum::<f64>() / n
        }
        _ => f64::NAN,
    }
}

/// Overwrites the root ground velocity (dims 1..3) of `f` with normalised values `v` (`T × 2`,
/// row-major), denormalised.
fn set_velocity(f: &mut Features, v_norm: &[f32], norm: &NormStats) {
    let (m, s) = (norm.mean(), norm.std());
    let d0 = ROOT_LIN_VEL.start;
    for (t, v) in v_norm.chunks_exact(2).enumerate() {
        let row = f.frame_mut(t);
        row[d0] = v[0] * s[d0] + m[d0];
        row[d0 + 1] = v[1] * s[d0 + 1] + m[d0 + 1];
    }
}

/// The autoencoder metrics ([`AE_METRICS`] order) of inference copies of the networks.
pub fn evaluate_ae(
    autoencoder: &MotionAutoencoder,
    regressor: &GlobalRegressor,
    set: &HeldoutSet,
    norm: &NormStats,
    batch: usize,
    device: &Device,
) -> Vec<f64> {
    let t = set.window;
    let mut sums = [0f64; 6];
    let mut count = 0usize;
    let indices: Vec<usize> = (0..set.len()).collect();
    for chunk in indices.chunks(batch.max(1)) {
        let clips: Vec<Features> = chunk.iter().map(|&i| set.normalized[i].clone()).collect();
        let x = batch_tensor(&clips, &whole(clips.len()), t, device);
        let y = autoencoder.decoder.forward(autoencoder.encoder.forward(ae_input(x.clone())).mean);
        let v_true = regressor.forward(regressor_input(x.clone()));
        let v_pipe = regressor.forward(regressor_input_from(channels(x, ROOT_ANG_VEL), y.clone()));
        let (y, v_true, v_pipe) = (to_vec(y), to_vec(v_true), to_vec(v_pipe));
        for (b, &i) in chunk.iter().enumerate() {
            let y_rows = rows_of(&y[b * DIM * t..(b + 1) * DIM * t], DIM, t);
            sums[0] += smooth_l1_sum(&y_rows, set.normalized[i].data()) / (DIM * t) as f64;
            let mut decoded = Features::new(t, y_rows).expect("T frames");
            norm.denormalize(&mut decoded);
            let raw = &set.raw[i];
            sums[1] += mean_distance(local_positions(&decoded), &local_positions(raw)) * 10.0;
            let truth = global_positions(raw);
            sums[2] += mean_distance(global_positions(&decoded), &truth) * 10.0;
            let mut pipeline = decoded;
            for k in 0..t {
                pipeline.frame_mut(k)[ROOT_ANG_VEL.start] = raw.frame(k)[ROOT_ANG_VEL.start];
            }
            set_velocity(&mut pipeline, &rows_of(&v_pipe[b * 2 * t..(b + 1) * 2 * t], 2, t), norm);
            sums[3] += mean_distance(global_positions(&pipeline), &truth) * 10.0;
            let mut regressed = raw.clone();
            set_velocity(&mut regressed, &rows_of(&v_true[b * 2 * t..(b + 1) * 2 * t], 2, t), norm);
            let (end, mean) = match (features::reconstruct(&regressed), features::reconstruct(raw)) {
                (Ok(p), Ok(q)) => {
                    let d: Vec<f64> =
                        p.root_positions().iter().zip(q.root_positions()).map(|(a, b)| a.distance(*b)).collect();
                    (d[d.len() - 1], d.iter().sum::<f64>() / d.len() as f64)
                }
                _ => (f64::NAN, f64::NAN),
            };
            sums[4] += end;
            sums[5] += mean;
            count += 1;
        }
    }
    sums.iter().map(|s| s / count.max(1) as f64).collect()
}

/// The stylizer metrics ([`STYLIZER_METRICS`] order): the loss terms on the held-out pairs,
/// with inference copies of the networks. `num_styles` is `Some` for a supervised model.
pub fn evaluate_stylizer(
    net: &Stylizer,
    autoencoder: &MotionAutoencoder,
    weights: &StylizerWeights,
    num_styles: Option<usize>,
    set: &HeldoutSet,
    batch: usize,
    device: &Device,
) -> Vec<f64> {
    let t = set.window;
    let mut noise = NoiseRng::new(EVAL_NOISE_SEED);
    let mut sums = [0f64; 7];
    let mut count = 0usize;
    for chunk in set.pairs.chunks(batch.max(1)) {
        let first: Vec<Features> = chunk.iter().map(|p| p.0.clone()).collect();
        let second: Vec<Features> = chunk.iter().map(|p| p.1.clone()).collect();
        let motion1 = batch_tensor(&first, &whole(chunk.len()), t, device);
        let motion2 = batch_tensor(&second, &whole(chunk.len()), t, device);
        let labels: Vec<usize> = chunk.iter().map(|p| p.2).collect();
        let inputs = StylizerInputs {
            latent1: autoencoder.encoder.forward(ae_input(motion1.clone())).mean,
            latent2: autoencoder.encoder.forward(ae_input(motion2.clone())).mean,
            motion1,
            motion2,
            labels: num_styles.map(|n| one_hot(&labels, n, device)),
            content_paired: Vec::new(),
            style_source: None,
            stats_offset: None,
            content_classes: Vec::new(),
        };
        let l = stylizer_loss(net, &autoencoder.decoder, &inputs, weights, &mut noise);
        let terms = vec![l.total, l.rec_latent, l.rec_pose, l.cyc_latent, l.cyc_pose, l.kl, l.hsa];
        let v = Tensor::cat(terms, 0).try_into_vec_as::<f32>().expect("f32 losses");
        for (s, x) in sums.iter_mut().zip(v) {
            *s += x as f64 * chunk.len() as f64;
        }
        count += chunk.len();
    }
    sums.iter().map(|s| s / count.max(1) as f64).collect()
}
