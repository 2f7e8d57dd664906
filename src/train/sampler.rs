//! Training windows: which take and which frames each batch row sees, from a seeded generator
//! whose position is saved in every checkpoint (so a resumed run draws exactly the batches a
//! straight run would have drawn).
//!
//! - **Window**: `T` consecutive frames of one clip (a take or its mirror image). Clips shorter
//!   than `T` are skipped (counted and reported); no padding.
//! - **Autoencoder** ([`WindowSampler::window`]): uniform over every window of every eligible
//!   clip, i.e. a clip is drawn with probability ∝ its number of window starts (`frames − T + 1`),
//!   then the start uniformly. Every frame of the training set is (nearly) equally likely to be
//!   seen, whatever its style: the autoencoder and the regressor should model *all* motion, and
//!   Bandai set 2's many short takes then weigh what they hold.
//! - **Stylizer** ([`WindowSampler::pair`]): *style-balanced*. A style label is drawn uniformly
//!   among the labels that have an eligible clip, then a clip of that style uniformly, then two
//!   windows of it at independent uniform offsets. Set 1's styles have ~11 takes each against
//!   several hundred for set 2's, so sampling by take (or by frame) would show the style encoder
//!   and the AdaIN label embedding little but `normal`/`active`/`feminine`…; uniform styles give
//!   every label the same share of the batches, at the price of showing set 1's few takes (and
//!   their mirrors) far more often than set 2's.
//! - **Homo-style pairs**: the two windows of a pair come from the SAME clip (same style by
//!   construction; the paper takes two clips of one sequence). They are drawn independently, so
//!   they may overlap — always when the clip is shorter than `2T` — and are occasionally
//!   identical (the chance is `1 / (frames − T + 1)`). A mirrored clip is a different clip with the
//!   same label.

use crate::features::Features;
use burn::prelude::*;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use serde::{Deserialize, Serialize};

/// A ChaCha8 stream that can be saved ([`SamplerRng::state`]) and restored exactly.
#[derive(Clone, Debug)]
pub struct SamplerRng {
    seed: u64,
    rng: ChaCha8Rng,
}

/// The saved position of a [`SamplerRng`]: its seed and ChaCha word position (a decimal string:
/// the position is a `u128`, which JSON numbers do not carry exactly).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RngState {
    pub seed: u64,
    pub word_pos: String,
}

impl SamplerRng {
    /// A fresh stream for `seed`.
    pub fn new(seed: u64) -> Self {
        Self { seed, rng: ChaCha8Rng::seed_from_u64(seed) }
    }

    /// The stream at a saved position.
    pub fn from_state(state: &RngState) -> Result<Self, String> {
        let pos: u128 = state.word_pos.parse().map_err(|_| format!("bad sampler position {:?}", state.word_pos))?;
        let mut rng = Self::new(state.seed);
        rng.rng.set_word_pos(pos);
        Ok(rng)
    }

    /// The current position.
    pub fn state(&self) -> RngState {
        RngState { seed: self.seed, word_pos: self.rng.get_word_pos().to_string() }
    }

    /// Uniform in `0..n` (`n > 0`), unbiased (rejection of the top partial range).
    pub fn below(&mut self, n: u64) -> u64 {
        assert!(n > 0, "empty range");
        let threshold = n.wrapping_neg() % n;
        loop {
            let v = self.rng.next_u64();
            if v >= threshold {
                return v % n;
            }
        }
    }
}

/// `T` frames of clip `clip` from frame `start`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    pub clip: usize,
    pub start: usize,
}

/// Draws windows of `T` frames from a set of clips (see the module docs).
#[derive(Clone, Debug)]
pub struct WindowSampler {
    window: usize,
    frames: Vec<usize>,
    /// Indices of clips with at least `T` frames.
    eligible: Vec<usize>,
    /// Running total of window starts over `eligible` (inclusive).
    cumulative: Vec<u64>,
    /// Per style with an eligible clip: its eligible clips.
    by_style: Vec<(usize, Vec<usize>)>,
    /// Every clip's style label.
    styles: Vec<usize>,
}

impl WindowSampler {
    /// Clips given by their frame counts and style labels (same order as the clips).
    pub fn new(frames: &[usize], styles: &[usize], window: usize) -> Self {
        assert_eq!(frames.len(), styles.len());
        let eligible: Vec<usize> = (0..frames.len()).filter(|&i| frames[i] >= window).collect();
        let mut total = 0u64;
        let cumulative = eligible
            .iter()
            .map(|&i| {
                total += (frames[i] - window + 1) as u64;
                total
            })
            .collect();
        let mut by_style: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for &i in &eligible {
            by_style.entry(styles[i]).or_default().push(i);
        }
        Self {
            window,
            frames: frames.to_vec(),
            eligible,
            cumulative,
            by_style: by_style.into_iter().collect(),
            styles: styles.to_vec(),
        }
    }

    /// Number of clips long enough for a window.
    pub fn eligible(&self) -> usize {
        self.eligible.len()
    }

    /// Number of clips shorter than the window (never drawn).
    pub fn skipped(&self) -> usize {
        self.frames.len() - self.eligible.len()
    }

    /// Number of distinct windows (start positions) over all eligible clips.
    pub fn windows(&self) -> u64 {
        self.cumulative.last().copied().unwrap_or(0)
    }

    /// The style labels that can be drawn, with their number of eligible clips.
    pub fn styles(&self) -> Vec<(usize, usize)> {
        self.by_style.iter().map(|(s, v)| (*s, v.len())).collect()
    }

    fn start_in(&self, clip: usize, rng: &mut SamplerRng) -> Window {
        let starts = (self.frames[clip] - self.window + 1) as u64;
        Window { clip, start: rng.below(starts) as usize }
    }

    /// Autoencoder: a window uniformly among all windows of all eligible clips. Panics if no clip
    /// is eligible (checked by the caller).
    pub fn window(&self, rng: &mut SamplerRng) -> Window {
        let k = rng.below(self.windows());
        let idx = self.cumulative.partition_point(|&c| c <= k);
        let clip = self.eligible[idx];
        let before = if idx == 0 { 0 } else { self.cumulative[idx - 1] };
        Window { clip, start: (k - before) as usize }
    }

    /// Stylizer: a style uniformly, a clip of it uniformly, two windows of that clip at
    /// independent offsets (they may overlap). Returns the pair and the clip's style label.
    pub fn pair(&self, rng: &mut SamplerRng) -> (Window, Window, usize) {
        let (style, clips) = &self.by_style[rng.below(self.by_style.len() as u64) as usize];
        let clip = clips[rng.below(clips.len() as u64) as usize];
        self.pair_of(clip, *style, rng)
    }

    fn pair_of(&self, clip: usize, style: usize, rng: &mut SamplerRng) -> (Window, Window, usize) {
        (self.start_in(clip, rng), self.start_in(clip, rng), style)
    }

    /// A partner for `clip`: an eligible clip of the same content group (`groups[i]`: e.g. the
    /// data set, content and mirroring of clip `i`; `None`: no group) in another style — a style
    /// uniformly among the group's other styles, then a clip of it uniformly — as a pair of
    /// windows like [`pair`](Self::pair). `None` when the group has no other style.
    pub fn content_partner(
        &self,
        clip: usize,
        groups: &[Option<u32>],
        rng: &mut SamplerRng,
    ) -> Option<(Window, Window, usize)> {
        let group = groups.get(clip).copied().flatten()?;
        let own = self.styles[clip];
        let mut by_style: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for &i in &self.eligible {
            if groups.get(i).copied().flatten() == Some(group) && self.styles[i] != own {
                by_style.entry(self.styles[i]).or_default().push(i);
            }
        }
        if by_style.is_empty() {
            return None;
        }
        let (style, clips) = by_style.iter().nth(rng.below(by_style.len() as u64) as usize)?;
        let partner = clips[rng.below(clips.len() as u64) as usize];
        Some(self.pair_of(partner, *style, rng))
    }

    /// A clip of `style` whose content (`contents[i]`) is not `content` — a clip uniformly among
    /// them — as a pair of windows like [`pair`](Self::pair). `None` when the style has no clip
    /// of another content.
    pub fn style_clip_elsewhere(
        &self,
        style: usize,
        content: Option<u32>,
        contents: &[Option<u32>],
        rng: &mut SamplerRng,
    ) -> Option<(Window, Window, usize)> {
        let (_, clips) = self.by_style.iter().find(|(s, _)| *s == style)?;
        let elsewhere = |i: usize| content.is_none() || contents.get(i).copied().flatten() != content;
        let others: Vec<usize> = clips.iter().copied().filter(|&i| elsewhere(i)).collect();
        if others.is_empty() {
            return None;
        }
        let clip = others[rng.below(others.len() as u64) as usize];
        Some(self.pair_of(clip, style, rng))
    }
}

/// `[B, 260, T]` tensor of the windows (each clip's features already normalised), channels first.
pub fn batch_tensor(clips: &[Features], windows: &[Window], t: usize, device: &Device) -> Tensor<3> {
    let dim = crate::features::DIM;
    let mut data = vec![0f32; windows.len() * dim * t];
    for (b, w) in windows.iter().enumerate() {
        let out = &mut data[b * dim * t..(b + 1) * dim * t];
        for k in 0..t {
            let row = clips[w.clip].frame(w.start + k);
            for (c, &v) in row.iter().enumerate() {
                out[c * t + k] = v;
            }
        }
    }
    Tensor::from_data(TensorData::new(data, [windows.len(), dim, t]), device)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_state_round_trips() {
        let mut a = SamplerRng::new(7);
        for _ in 0..13 {
            a.below(1000);
        }
        let mut b = SamplerRng::from_state(&a.state()).unwrap();
        let xs: Vec<u64> = (0..50).map(|_| a.below(97)).collect();
        let ys: Vec<u64> = (0..50).map(|_| b.below(97)).collect();
        assert_eq!(xs, ys);
    }

    #[test]
    fn windows_are_in_range_and_short_clips_skipped() {
        let frames = [10, 64, 100, 63, 64];
        let styles = [0, 0, 1, 2, 3];
        let s = WindowSampler::new(&frames, &styles, 64);
        assert_eq!((s.eligible(), s.skipped(), s.windows()), (3, 2, 1 + 37 + 1));
        assert_eq!(s.styles(), vec![(0, 1), (1, 1), (3, 1)]);
        let mut rng = SamplerRng::new(1);
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..2000 {
            let w = s.window(&mut rng);
            assert!(frames[w.clip] >= 64 && w.start + 64 <= frames[w.clip]);
            seen.insert((w.clip, w.start));
            let (a, b, style) = s.pair(&mut rng);
            assert_eq!(a.clip, b.clip);
            assert_eq!(styles[a.clip], style);
            assert!(a.start + 64 <= frames[a.clip] && b.start + 64 <= frames[b.clip]);
        }
        assert_eq!(seen.len() as u64, s.windows(), "every window is drawn");
    }

    #[test]
    fn a_content_partner_is_the_same_content_in_another_style() {
        // Clips 0–3: content group 0 in styles 0, 0, 1, 2 (clip 3 too short); clip 4: group 1,
        // style 1; clip 5: no group.
        let frames = [80, 80, 80, 10, 80, 80];
        let styles = [0, 0, 1, 2, 1, 1];
        let groups = [Some(0), Some(0), Some(0), Some(0), Some(1), None];
        let s = WindowSampler::new(&frames, &styles, 64);
        let mut rng = SamplerRng::new(3);
        for _ in 0..200 {
            let (a, b, style) = s.content_partner(0, &groups, &mut rng).expect("clip 2 is a partner");
            assert_eq!((a.clip, b.clip, style), (2, 2, 1), "the only eligible clip of group 0 in another style");
            let (a, _, style) = s.content_partner(2, &groups, &mut rng).unwrap();
            assert!(a.clip < 2 && style == 0);
        }
        assert!(s.content_partner(4, &groups, &mut rng).is_none(), "group 1 has one style");
        assert!(s.content_partner(5, &groups, &mut rng).is_none(), "no group");
    }

    #[test]
    fn a_style_clip_elsewhere_has_the_style_and_another_content() {
        // Style 1: clips 2 (content 0), 4 (content 1), 5 (no content), 6 (content 1, too short).
        let frames = [80, 80, 80, 10, 80, 80, 10];
        let styles = [0, 0, 1, 2, 1, 1, 1];
        let contents = [Some(0), Some(0), Some(0), Some(0), Some(1), None, Some(1)];
        let s = WindowSampler::new(&frames, &styles, 64);
        let mut rng = SamplerRng::new(5);
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..200 {
            let (a, b, style) = s.style_clip_elsewhere(1, Some(0), &contents, &mut rng).expect("clips 4 and 5");
            assert_eq!((a.clip, style), (b.clip, 1));
            seen.insert(a.clip);
            let (a, _, _) = s.style_clip_elsewhere(1, Some(1), &contents, &mut rng).unwrap();
            assert!(a.clip == 2 || a.clip == 5, "not content 1: {}", a.clip);
        }
        assert_eq!(seen, [4, 5].into(), "both clips of another content, never content 0's");
        assert!(s.style_clip_elsewhere(0, Some(0), &contents, &mut rng).is_none(), "style 0 has only content 0");
        assert!(s.style_clip_elsewhere(2, None, &contents, &mut rng).is_none(), "style 2 has no eligible clip");
    }
}
