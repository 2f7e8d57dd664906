//! Style shift: how far a stylization moved its content towards a style, measured without any
//! network, on interpretable kinematic descriptors.
//!
//! - **Descriptors** ([`descriptors`]): per clip on the canonical rig, lengths divided by the leg
//!   length (the canonical rig's: every motion is on it), speeds per second: [`DESCRIPTORS`].
//! - **Spread**: each descriptor's standard deviation over the real takes; every difference below
//!   is in these units.
//! - **A style's direction** ([`Directions::from_takes`]): per content (Bandai's `set/content`
//!   key) that has takes of the style and `normal` takes, the mean over the style's takes of
//!   (take − mean of the content's `normal` takes); the direction is the mean of those over the
//!   contents (both sets pooled, each content counting once). A style whose direction is shorter
//!   than [`MIN_DIRECTION`] spreads — its real takes barely differ from `normal` on these
//!   descriptors — is reported, not scored.
//! - **Shift of an output** ([`Directions::shift`]): `(d(output) − d(content)) · dir / |dir|²`:
//!   1.0 = the output moved as far along the style's direction as a real take of the style is from
//!   a `normal` take of its content; 0 = unchanged; negative = away from the style.

use std::collections::BTreeMap;

use glam::DVec3;
use serde::Serialize;

use crate::Motion;
use crate::features::{CONTACT_HEIGHT, CONTACT_SPEED};
use crate::skeleton::canonical::{self, FPS, joint::*};

/// The descriptors, in [`descriptors`]' order.
pub const DESCRIPTORS: [&str; 12] = [
    "ground_speed",
    "hip_bounce",
    "hip_height",
    "trunk_lean",
    "head_height",
    "arm_swing",
    "hand_height",
    "elbow_extension",
    "knee_bend",
    "foot_lift",
    "joint_speed",
    "step_rate",
];

/// Number of descriptors.
pub const N: usize = DESCRIPTORS.len();

/// The descriptors of the lower body (root and legs: [`crate::stylize::BodyPart::Lower`]'s joints).
pub const LOWER_BODY: [usize; 6] = [0, 1, 2, 8, 9, 11];
/// The descriptors of the upper body (spine and arms: [`crate::stylize::BodyPart::Upper`]'s).
pub const UPPER_BODY: [usize; 4] = [3, 5, 6, 7];

/// Directions shorter than this (in spreads) are not scored.
pub const MIN_DIRECTION: f64 = 0.3;

/// A clip's descriptors.
pub type Descriptors = [f64; N];

fn mean(v: impl IntoIterator<Item = f64>) -> f64 {
    let (s, n) = v.into_iter().fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { 0.0 } else { s / n as f64 }
}

fn std(v: &[f64]) -> f64 {
    let m = mean(v.iter().copied());
    mean(v.iter().map(|x| (x - m) * (x - m))).sqrt()
}

fn horizontal(v: DVec3) -> DVec3 {
    DVec3::new(v.x, 0.0, v.z)
}

/// The angle at `b` between `a − b` and `c − b`, radians (π for a straight limb).
fn angle_at(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (u, v) = (a - b, c - b);
    let d = u.length() * v.length();
    if d > 0.0 { (u.dot(v) / d).clamp(-1.0, 1.0).acos() } else { std::f64::consts::PI }
}

fn percentile(v: &[f64], p: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(((s.len().saturating_sub(1)) as f64 * p).round() as usize).copied().unwrap_or(0.0)
}

/// The descriptors of `m` ([`DESCRIPTORS`]; see the module docs).
///
/// - `ground_speed`: mean horizontal speed of the Hips, leg lengths per second;
/// - `hip_bounce`, `hip_height`: standard deviation and mean of the Hips' height;
/// - `trunk_lean`: mean forward offset of the Head from the Hips (facing direction of each frame,
///   from the hips and shoulders);
/// - `head_height`: mean height of the Head;
/// - `arm_swing`: per hand, the standard deviation of its forward offset from the Hips; mean of both;
/// - `hand_height`: mean height of the hands above the Hips;
/// - `elbow_extension`, `knee_bend`: mean elbow angle, and π minus the mean knee angle (radians);
/// - `foot_lift`: per ankle, its 95th minus 5th height percentile; mean of both;
/// - `joint_speed`: mean speed of all joints, leg lengths per second;
/// - `step_rate`: foot plants (an ankle coming into contact: slower than 60 cm/s and lower than
///   the feature's contact height) per second.
pub fn descriptors(m: &Motion) -> Descriptors {
    let l = canonical::leg_length();
    let pos = m.global_positions();
    let frames = pos.len();
    let forward: Vec<DVec3> = pos
        .iter()
        .map(|p| {
            let across = horizontal((p[UPPER_LEG_R] - p[UPPER_LEG_L]) + (p[UPPER_ARM_R] - p[UPPER_ARM_L]));
            DVec3::Y.cross(across).normalize_or_zero()
        })
        .collect();
    let over = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { (0..frames).map(f).collect() };
    let speeds = |f: &dyn Fn(usize) -> f64| -> f64 { mean((0..frames.saturating_sub(1)).map(f)) };
    let hips_y = over(&|t| pos[t][HIPS].y / l);
    let swing = |hand: usize| std(&over(&|t| horizontal(pos[t][hand] - pos[t][HIPS]).dot(forward[t]) / l));
    let lift = |foot: usize| {
        let y = over(&|t| pos[t][foot].y / l);
        percentile(&y, 0.95) - percentile(&y, 0.05)
    };
    let mut plants = 0usize;
    for (k, foot) in [(0, FOOT_L), (2, FOOT_R)] {
        let contact = |t: usize| {
            let next = (t + 1).min(frames - 1);
            (pos[next][foot] - pos[t][foot]).length() < CONTACT_SPEED && pos[t][foot].y < CONTACT_HEIGHT[k]
        };
        plants += (1..frames).filter(|&t| contact(t) && !contact(t - 1)).count();
    }
    let seconds = (frames.max(2) - 1) as f64 / FPS;
    [
        speeds(&|t| horizontal(pos[t + 1][HIPS] - pos[t][HIPS]).length() * FPS / l),
        std(&hips_y),
        mean(hips_y.iter().copied()),
        mean(over(&|t| horizontal(pos[t][HEAD] - pos[t][HIPS]).dot(forward[t]) / l)),
        mean(over(&|t| pos[t][HEAD].y / l)),
        (swing(HAND_L) + swing(HAND_R)) / 2.0,
        mean(over(&|t| ((pos[t][HAND_L].y + pos[t][HAND_R].y) / 2.0 - pos[t][HIPS].y) / l)),
        mean(over(&|t| {
            let a = angle_at(pos[t][UPPER_ARM_L], pos[t][LOWER_ARM_L], pos[t][HAND_L]);
            let b = angle_at(pos[t][UPPER_ARM_R], pos[t][LOWER_ARM_R], pos[t][HAND_R]);
            (a + b) / 2.0
        })),
        std::f64::consts::PI
            - mean(over(&|t| {
                let a = angle_at(pos[t][UPPER_LEG_L], pos[t][LOWER_LEG_L], pos[t][FOOT_L]);
                let b = angle_at(pos[t][UPPER_LEG_R], pos[t][LOWER_LEG_R], pos[t][FOOT_R]);
                (a + b) / 2.0
            })),
        (lift(FOOT_L) + lift(FOOT_R)) / 2.0,
        speeds(&|t| mean((0..pos[t].len()).map(|j| (pos[t + 1][j] - pos[t][j]).length())) * FPS / l),
        plants as f64 / seconds,
    ]
}

/// One style's direction, as [`Directions::from_takes`] found it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Direction {
    /// Style label index.
    pub style: usize,
    /// Contents that have both this style's takes and `normal` takes.
    pub contents: usize,
    /// Takes of the style over those contents.
    pub takes: usize,
    /// In spreads, per descriptor.
    pub vector: Vec<f64>,
    /// Its length in spreads.
    pub length: f64,
    /// Long enough to be scored ([`MIN_DIRECTION`]).
    pub scored: bool,
}

/// Every style's direction and the descriptors' spreads.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Directions {
    /// Standard deviation of each descriptor over the real takes.
    pub spread: Vec<f64>,
    /// By style index (styles without any paired content are absent).
    pub styles: Vec<Direction>,
}

/// A real take for [`Directions::from_takes`]: its content key (`set/content`), style index and
/// descriptors.
#[derive(Clone, Debug)]
pub struct Take {
    pub content: String,
    pub style: usize,
    pub descriptors: Descriptors,
}

impl Directions {
    /// The directions of every style from real takes, `normal` being style index `normal`.
    pub fn from_takes(takes: &[Take], normal: usize) -> Directions {
        let spread: Vec<f64> = (0..N)
            .map(|k| {
                let v: Vec<f64> = takes.iter().map(|t| t.descriptors[k]).collect();
                let s = std(&v);
                if s > 1e-12 { s } else { 1.0 }
            })
            .collect();
        let mut by_content: BTreeMap<&str, Vec<&Take>> = BTreeMap::new();
        for t in takes {
            by_content.entry(t.content.as_str()).or_default().push(t);
        }
        let mut sums: BTreeMap<usize, (Vec<f64>, usize, usize)> = BTreeMap::new();
        for group in by_content.values() {
            let normals: Vec<&&Take> = group.iter().filter(|t| t.style == normal).collect();
            if normals.is_empty() {
                continue;
            }
            let base: Vec<f64> = (0..N).map(|k| mean(normals.iter().map(|t| t.descriptors[k])) / spread[k]).collect();
            let mut per_style: BTreeMap<usize, (Vec<f64>, usize)> = BTreeMap::new();
            for t in group.iter().filter(|t| t.style != normal) {
                let e = per_style.entry(t.style).or_insert_with(|| (vec![0.0; N], 0));
                for k in 0..N {
                    e.0[k] += t.descriptors[k] / spread[k] - base[k];
                }
                e.1 += 1;
            }
            for (style, (sum, n)) in per_style {
                let e = sums.entry(style).or_insert_with(|| (vec![0.0; N], 0, 0));
                for (acc, v) in e.0.iter_mut().zip(&sum) {
                    *acc += v / n as f64;
                }
                e.1 += 1;
                e.2 += n;
            }
        }
        let styles = sums
            .into_iter()
            .map(|(style, (sum, contents, takes))| {
                let vector: Vec<f64> = sum.iter().map(|v| v / contents as f64).collect();
                let length = vector.iter().map(|v| v * v).sum::<f64>().sqrt();
                Direction { style, contents, takes, vector, length, scored: length >= MIN_DIRECTION }
            })
            .collect();
        Directions { spread, styles }
    }

    /// The direction of `style`, if it has one.
    pub fn get(&self, style: usize) -> Option<&Direction> {
        self.styles.iter().find(|d| d.style == style)
    }

    /// The shift of `output` from `content` towards `style` (see the module docs); `None` if the
    /// style has no direction or is not scored.
    pub fn shift(&self, style: usize, content: &Descriptors, output: &Descriptors) -> Option<f64> {
        let d = self.get(style).filter(|d| d.scored)?;
        let dot: f64 = (0..N).map(|k| (output[k] - content[k]) / self.spread[k] * d.vector[k]).sum();
        Some(dot / (d.length * d.length))
    }

    /// [`Directions::shift`] on a subset of the descriptors (e.g. [`UPPER_BODY`]): the output's
    /// move along the style direction's part on those descriptors, ÷ that part's squared length;
    /// `None` where the part of the direction is shorter than [`MIN_DIRECTION`].
    pub fn shift_on(&self, style: usize, content: &Descriptors, output: &Descriptors, subset: &[usize]) -> Option<f64> {
        let d = self.get(style).filter(|d| d.scored)?;
        let length2: f64 = subset.iter().map(|&k| d.vector[k] * d.vector[k]).sum();
        if length2.sqrt() < MIN_DIRECTION {
            return None;
        }
        let dot: f64 = subset.iter().map(|&k| (output[k] - content[k]) / self.spread[k] * d.vector[k]).sum();
        Some(dot / length2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    /// A stick figure walking forward (+Z) at `speed` cm/frame with knees bent by `bend` radians.
    fn walk(frames: usize, speed: f64, bend: f64) -> Motion {
        let root = (0..frames).map(|f| DVec3::new(0.0, 90.0, speed * f as f64)).collect();
        let pose = |f: usize| {
            let mut p = [DQuat::IDENTITY; canonical::NUM_JOINTS];
            let swing = 0.4 * (f as f64 * 0.3).sin();
            p[UPPER_LEG_L] = DQuat::from_rotation_x(swing - bend / 2.0);
            p[UPPER_LEG_R] = DQuat::from_rotation_x(-swing - bend / 2.0);
            p[LOWER_LEG_L] = DQuat::from_rotation_x(bend);
            p[LOWER_LEG_R] = DQuat::from_rotation_x(bend);
            p
        };
        Motion::new(root, (0..frames).map(pose).collect()).unwrap()
    }

    #[test]
    fn descriptors_follow_speed_and_knee_bend() {
        let (slow, fast) = (descriptors(&walk(60, 1.0, 0.1)), descriptors(&walk(60, 3.0, 0.1)));
        let l = canonical::leg_length();
        assert!((slow[0] - 30.0 / l).abs() < 1e-9 && (fast[0] - 90.0 / l).abs() < 1e-9);
        let bent = descriptors(&walk(60, 1.0, 0.8));
        assert!(bent[8] > slow[8] + 0.3, "knee bend {} vs {}", bent[8], slow[8]);
        assert!(descriptors(&walk(1, 1.0, 0.1)).iter().all(|v| v.is_finite()));
    }

    #[test]
    fn shift_is_one_for_a_real_take_and_zero_for_the_content() {
        let take =
            |content: &str, style, m: &Motion| Take { content: content.into(), style, descriptors: descriptors(m) };
        let (normal, fast, bent) = (walk(60, 1.0, 0.1), walk(60, 2.0, 0.1), walk(60, 1.0, 0.6));
        let takes = [take("1/walk", 0, &normal), take("1/walk", 1, &fast), take("1/walk", 2, &bent)];
        let dirs = Directions::from_takes(&takes, 0);
        let (dn, df) = (descriptors(&normal), descriptors(&fast));
        assert!((dirs.shift(1, &dn, &df).unwrap() - 1.0).abs() < 1e-9);
        assert!(dirs.shift(1, &dn, &dn).unwrap().abs() < 1e-12);
        // Halfway is a half; the other style's change does not count as this one's.
        let half = walk(60, 1.5, 0.1);
        let h = dirs.shift(1, &dn, &descriptors(&half)).unwrap();
        assert!(h > 0.2 && h < 0.8, "halfway: {h}");
        assert!(dirs.shift(2, &dn, &df).unwrap() < 0.5);
        assert_eq!(dirs.get(1).unwrap().contents, 1);
        assert!(dirs.shift(5, &dn, &df).is_none(), "no direction for a style without takes");
    }

    #[test]
    fn the_shift_on_a_part_sees_only_that_part() {
        let take =
            |content: &str, style, m: &Motion| Take { content: content.into(), style, descriptors: descriptors(m) };
        // A style that bends the knees: its direction lies in the lower body's descriptors.
        let (normal, bent) = (walk(60, 1.0, 0.1), walk(60, 1.0, 0.6));
        let dirs = Directions::from_takes(&[take("1/walk", 0, &normal), take("1/walk", 1, &bent)], 0);
        let (dn, db) = (descriptors(&normal), descriptors(&bent));
        let lower = dirs.shift_on(1, &dn, &db, &LOWER_BODY).unwrap();
        assert!((lower - 1.0).abs() < 0.2, "the real take on the legs: {lower}");
        assert!(dirs.shift_on(1, &dn, &dn, &LOWER_BODY).unwrap().abs() < 1e-12);
        // The arms did not move: the direction's upper-body part is too short to score.
        assert!(dirs.shift_on(1, &dn, &db, &UPPER_BODY).is_none());
    }
}
