//! The stylizer's losses on the decoded motion's statistics over time (ours, not the paper's):
//! the style-statistics loss, which hands every feature's mean and spread over a window to the
//! style, and the content-shape loss, which keeps what is left — each feature's curve — the
//! content's. [`super::losses::stylizer_loss`] weighs them in.

use burn::prelude::*;

use super::losses::smooth_l1;

/// Per-row offsets of the style-statistics targets, `[B, 260]` each: a content-paired row's swap
/// is judged by its partner's per-feature mean and spread over time plus these (with
/// [`super::losses::StylizerWeights::cross_set_relative`]: the row's data set's `normal`
/// statistics of the content minus the partner's set's; zero within a set).
#[derive(Clone, Debug)]
pub struct StatsOffset {
    pub mean: Tensor<2>,
    pub spread: Tensor<2>,
}

impl StatsOffset {
    /// The rows `rows` (a row group, or the judged rows by index).
    pub(super) fn select(&self, rows: Tensor<1, Int>) -> Self {
        Self { mean: self.mean.clone().select(0, rows.clone()), spread: self.spread.clone().select(0, rows) }
    }
}

/// Per-channel mean and standard deviation over time of `[B, C, T]` features: `([B, C], [B, C])`.
fn time_statistics(x: Tensor<3>) -> (Tensor<2>, Tensor<2>) {
    let mean = x.clone().mean_dim(2);
    let var = (x - mean.clone()).square().mean_dim(2);
    let [b, c, _] = mean.dims();
    (mean.reshape([b, c]), (var + 1e-6).sqrt().reshape([b, c]))
}

/// Style-statistics loss (ours, not the paper's): a swap `G(c_A, s_B)` whose two clips are takes
/// of the same content in different styles should move the decoded motion's time statistics —
/// every feature's mean (posture: hip height, lean, hand height, …) and spread over the window
/// (swing, bounce, speed variation) — to those of `B`'s clip, since with the content shared
/// what differs between the takes' statistics is the style. Smooth-L1 on the means plus on the
/// standard deviations, `[B, 260, T]` decoded swaps against `[B, 260, T]` targets (the
/// windows' timing is free: nothing is compared frame by frame).
pub fn style_statistics(decoded: Tensor<3>, target: Tensor<3>) -> Tensor<1> {
    style_statistics_moved(decoded, target, None)
}

/// [`style_statistics`] against the target's statistics moved by `offset` (its spreads floored at
/// 0): `mean(target) + offset.mean`, `max(spread(target) + offset.spread, 0)`.
pub fn style_statistics_moved(decoded: Tensor<3>, target: Tensor<3>, offset: Option<StatsOffset>) -> Tensor<1> {
    let (m, s) = time_statistics(decoded);
    let (mut mt, mut st) = time_statistics(target);
    if let Some(o) = offset {
        mt = mt + o.mean;
        st = (st + o.spread).clamp_min(0.0);
    }
    smooth_l1(m, mt) + smooth_l1(s, st)
}

/// Spread floor of [`content_shape`]'s standardisation, in normalised feature units: a feature
/// that barely moves within a window is compared on its (damped) deviations, not blown up.
const SHAPE_SPREAD_FLOOR: f32 = 0.1;

/// Content-shape loss (ours, not the paper's): the swap `G(c_A, s_B)` keeps clip `A`'s timing,
/// so after removing each feature's mean and spread over the window — what the style-statistics
/// loss hands to the style — what is left, the shape of every feature's curve over time, should
/// be `A`'s. Smooth-L1 of the time-standardised `[B, 260, T]` decoded swaps against the
/// time-standardised content clips (spreads floored at [`SHAPE_SPREAD_FLOOR`]).
pub fn content_shape(decoded: Tensor<3>, content: Tensor<3>) -> Tensor<1> {
    let standardise = |x: Tensor<3>| {
        let mean = x.clone().mean_dim(2);
        let centred = x - mean;
        let spread = (centred.clone().square().mean_dim(2) + 1e-6).sqrt().clamp_min(SHAPE_SPREAD_FLOOR);
        centred / spread
    };
    smooth_l1(standardise(decoded), standardise(content))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[1, 2, 64]`: a sine of amplitude `amp` around `offset` and a constant, from phase `phase`.
    fn wave(amp: f32, offset: f32, phase: usize) -> Tensor<3> {
        let t = 64;
        let mut v: Vec<f32> =
            (0..t).map(|k| offset + amp * (std::f32::consts::TAU * ((k + phase) % 16) as f32 / 16.0).sin()).collect();
        v.extend(std::iter::repeat_n(0.5, t));
        Tensor::from_data(TensorData::new(v, [1, 2, t]), &Device::flex())
    }

    #[test]
    fn style_statistics_ignore_timing_and_see_posture_and_swing() {
        let loss = |a: Tensor<3>, b: Tensor<3>| style_statistics(a, b).into_scalar::<f32>();
        // The same periodic motion at another phase: same statistics.
        assert!(loss(wave(1.0, 0.0, 0), wave(1.0, 0.0, 5)) < 1e-6);
        // Larger swing, or another posture: the loss sees it, and more of it more.
        let swing = loss(wave(1.0, 0.0, 0), wave(1.5, 0.0, 3));
        let posture = loss(wave(1.0, 0.0, 0), wave(1.0, 0.4, 0));
        assert!(swing > 0.01 && posture > 0.01, "swing {swing}, posture {posture}");
        assert!(loss(wave(1.0, 0.0, 0), wave(1.0, 0.8, 0)) > 2.0 * posture);
    }

    #[test]
    fn moved_style_statistics_judge_against_the_target_plus_the_offset() {
        let offset = |mean: [f32; 2], spread: [f32; 2]| {
            let t = |v: [f32; 2]| Tensor::from_data(TensorData::new(v.to_vec(), [1, 2]), &Device::flex());
            StatsOffset { mean: t(mean), spread: t(spread) }
        };
        let moved = |a: Tensor<3>, b: Tensor<3>, o| style_statistics_moved(a, b, o).into_scalar::<f32>();
        // No offset, or a zero one: the plain loss.
        let plain = style_statistics(wave(1.0, 0.4, 0), wave(1.0, 0.0, 0)).into_scalar::<f32>();
        assert_eq!(moved(wave(1.0, 0.4, 0), wave(1.0, 0.0, 0), None), plain);
        assert_eq!(moved(wave(1.0, 0.4, 0), wave(1.0, 0.0, 0), Some(offset([0.0; 2], [0.0; 2]))), plain);
        // The target's posture moved by +0.4 on the first feature: the output at +0.4 is on target.
        assert!(moved(wave(1.0, 0.4, 0), wave(1.0, 0.0, 0), Some(offset([0.4, 0.0], [0.0; 2]))) < 1e-6);
        // A larger swing asked for through the spread offset (a sine's spread is amp / √2).
        let wider = offset([0.0; 2], [0.5 / 2f32.sqrt(), 0.0]);
        assert!(moved(wave(1.5, 0.0, 3), wave(1.0, 0.0, 0), Some(wider.clone())) < 1e-4);
        assert!(moved(wave(1.0, 0.0, 3), wave(1.0, 0.0, 0), Some(wider)) > 0.01);
    }

    #[test]
    fn content_shape_ignores_posture_and_swing_and_sees_timing() {
        let loss = |a: Tensor<3>, b: Tensor<3>| content_shape(a, b).into_scalar::<f32>();
        // Another posture or a larger swing of the same curve: the same shape.
        assert!(loss(wave(1.0, 0.0, 0), wave(1.5, 0.4, 0)) < 1e-6);
        // The same curve at another phase: the content's timing is lost, and the loss sees it.
        let shifted = loss(wave(1.0, 0.0, 0), wave(1.0, 0.0, 4));
        assert!(shifted > 0.3, "phase shift {shifted}");
        // A feature that barely moves is not blown up into a full curve.
        assert!(loss(wave(0.001, 0.0, 0), wave(0.001, 0.0, 8)) < 1e-3);
    }
}
