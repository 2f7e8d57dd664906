//! The fixed train / held-out split, by take.
//!
//! About 10 % of the takes of every style are held out, and every content with at least three takes
//! has one held out, so evaluation sees every style and (nearly) every content while training keeps
//! them all too. The choice is a deterministic function of the take names and a seed; the result is
//! committed (`assets/split/heldout.txt`) so it never drifts, even if this function changes.

use super::labels::Style;
use std::collections::{BTreeMap, BTreeSet};
use thiserror::Error;

/// Fraction of each style's takes held out.
pub const HELDOUT_FRACTION: f64 = 0.1;

/// A Bandai-Namco take, from its file stem `dataset-{set}_{content}_{style}_{take}`.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TakeId {
    pub set: u8,
    pub content: String,
    /// The style as spelled in the file name (see [`Style::from_bandai`] for the unified label).
    pub style_raw: String,
    pub take: u32,
}

impl TakeId {
    /// Parses a file stem such as `dataset-1_walk_not-confident_003` (a trailing `.bvh` is ignored).
    pub fn parse(stem: &str) -> Option<TakeId> {
        let stem = stem.strip_suffix(".bvh").unwrap_or(stem);
        let mut parts = stem.split('_');
        let set = match parts.next()? {
            "dataset-1" => 1,
            "dataset-2" => 2,
            _ => return None,
        };
        let content = parts.next()?.to_string();
        let style_raw = parts.next()?.to_string();
        let take_str = parts.next()?;
        if parts.next().is_some() || content.is_empty() || take_str.is_empty() {
            return None;
        }
        let take = take_str.parse().ok()?;
        Style::from_bandai(set, &style_raw)?;
        Some(TakeId { set, content, style_raw, take })
    }

    /// The file stem this id was parsed from.
    pub fn stem(&self) -> String {
        format!("dataset-{}_{}_{}_{:03}", self.set, self.content, self.style_raw, self.take)
    }

    /// The unified style label.
    pub fn style(&self) -> Style {
        // `parse` only accepts takes whose style maps.
        Style::from_bandai(self.set, &self.style_raw).unwrap_or(Style(0))
    }

    /// `set/content`, the key of a content (contents of the two sets are different motions).
    pub fn content_key(&self) -> String {
        format!("{}/{}", self.set, self.content)
    }
}

#[derive(Debug, Error, PartialEq)]
pub enum SplitError {
    #[error("split file line {line}: {stem:?} is not a Bandai-Namco take name")]
    BadTake { line: usize, stem: String },
}

/// Which takes are held out; every other take is for training.
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    heldout: BTreeSet<String>,
}

impl Split {
    /// Chooses the held-out takes (see the module doc) deterministically from `takes` and `seed`.
    pub fn choose(takes: &[TakeId], seed: u64) -> Split {
        let mut order: Vec<&TakeId> = takes.iter().collect();
        order.sort_by_key(|t| (fnv1a(seed, &t.stem()), t.stem()));
        let mut per_style: BTreeMap<Style, usize> = BTreeMap::new();
        let mut per_content: BTreeMap<String, usize> = BTreeMap::new();
        for t in takes {
            *per_style.entry(t.style()).or_default() += 1;
            *per_content.entry(t.content_key()).or_default() += 1;
        }
        let quota: BTreeMap<Style, usize> = per_style
            .iter()
            .map(|(s, n)| (*s, ((*n as f64 * HELDOUT_FRACTION).round() as usize).max(1).min(n - 1)))
            .collect();
        let mut held: BTreeMap<Style, usize> = BTreeMap::new();
        let mut heldout = BTreeSet::new();
        // 1. one take of every content with ≥ 3 takes, from a style with quota left where possible.
        for (content, n) in &per_content {
            if *n < 3 {
                continue;
            }
            let candidates: Vec<&&TakeId> = order.iter().filter(|t| &t.content_key() == content).collect();
            let pick = candidates
                .iter()
                .find(|t| held.get(&t.style()).copied().unwrap_or(0) < quota[&t.style()])
                .or(candidates.first());
            if let Some(t) = pick {
                heldout.insert(t.stem());
                *held.entry(t.style()).or_default() += 1;
            }
        }
        // 2. fill every style up to its quota, in hash order, never taking a content's only takes.
        for t in &order {
            if per_content[&t.content_key()] < 3 {
                continue;
            }
            let h = held.entry(t.style()).or_default();
            if *h < quota[&t.style()] && heldout.insert(t.stem()) {
                *h += 1;
            }
        }
        Split { heldout }
    }

    /// Reads a split file: one held-out take stem per line; `#` starts a comment.
    pub fn parse(text: &str) -> Result<Split, SplitError> {
        let mut heldout = BTreeSet::new();
        for (i, line) in text.lines().enumerate() {
            let stem = line.split('#').next().unwrap_or("").trim();
            if stem.is_empty() {
                continue;
            }
            if TakeId::parse(stem).is_none() {
                return Err(SplitError::BadTake { line: i + 1, stem: stem.to_string() });
            }
            heldout.insert(stem.to_string());
        }
        Ok(Split { heldout })
    }

    /// The split file's text, with a header saying how it was made.
    pub fn to_text(&self, header: &str) -> String {
        let mut s = String::new();
        for line in header.lines() {
            s.push_str("# ");
            s.push_str(line);
            s.push('\n');
        }
        for stem in &self.heldout {
            s.push_str(stem);
            s.push('\n');
        }
        s
    }

    pub fn is_heldout(&self, take: &TakeId) -> bool {
        self.heldout.contains(&take.stem())
    }

    pub fn heldout(&self) -> impl Iterator<Item = &str> {
        self.heldout.iter().map(String::as_str)
    }

    pub fn len(&self) -> usize {
        self.heldout.len()
    }

    pub fn is_empty(&self) -> bool {
        self.heldout.is_empty()
    }
}

/// FNV-1a over the seed and a name: a stable hash (std's hashers may change between releases).
fn fnv1a(seed: u64, name: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in seed.to_le_bytes().iter().chain(name.as_bytes()) {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fake_takes() -> Vec<TakeId> {
        let mut v = Vec::new();
        for (set, styles, contents, per) in [
            (1u8, &["normal", "happy", "old", "masculinity"][..], &["walk", "bow", "kick"][..], 3u32),
            (2u8, &["normal", "elderly", "exhausted"][..], &["walk", "run"][..], 20u32),
        ] {
            for s in styles {
                for c in contents {
                    let n = match (*c, *s) {
                        ("kick", "happy") => 1,
                        ("kick", _) => 0,
                        _ => per,
                    };
                    for k in 1..=n {
                        v.push(TakeId::parse(&format!("dataset-{set}_{c}_{s}_{k:03}")).unwrap());
                    }
                }
            }
        }
        v
    }

    #[test]
    fn parses_take_names() {
        let t = TakeId::parse("dataset-1_walk_not-confident_003.bvh").unwrap();
        assert_eq!((t.set, t.content.as_str(), t.style_raw.as_str(), t.take), (1, "walk", "not-confident", 3));
        assert_eq!(t.stem(), "dataset-1_walk_not-confident_003");
        assert_eq!(t.style().name(), "not-confident");
        for bad in ["dataset-3_walk_normal_001", "dataset-1_walk_normal", "dataset-1_walk_nosuch_001", "x", ""] {
            assert_eq!(TakeId::parse(bad), None, "{bad}");
        }
    }

    #[test]
    fn split_holds_out_about_a_tenth_of_every_style_and_every_content() {
        let takes = fake_takes();
        let split = Split::choose(&takes, 7);
        let styles: BTreeSet<Style> = takes.iter().map(TakeId::style).collect();
        for s in &styles {
            let all = takes.iter().filter(|t| t.style() == *s).count();
            let held = takes.iter().filter(|t| t.style() == *s && split.is_heldout(t)).count();
            assert!(held >= 1 && held < all, "{}: {held} of {all}", s.name());
        }
        for c in ["1/walk", "1/bow", "2/walk", "2/run"] {
            assert!(takes.iter().any(|t| t.content_key() == c && split.is_heldout(t)), "{c}");
            assert!(takes.iter().any(|t| t.content_key() == c && !split.is_heldout(t)), "{c}");
        }
        assert!(!takes.iter().any(|t| t.content == "kick" && split.is_heldout(t)), "single takes stay in training");
        let frac = split.len() as f64 / takes.len() as f64;
        assert!((0.08..0.2).contains(&frac), "{frac}");
        // Deterministic, and a file round trip keeps it.
        assert_eq!(Split::choose(&takes, 7), split);
        assert_ne!(Split::choose(&takes, 8), split);
        assert_eq!(Split::parse(&split.to_text("made by a test\nseed 7")).unwrap(), split);
        assert_eq!(
            Split::parse("dataset-1_walk_normal_001\nnonsense\n"),
            Err(SplitError::BadTake { line: 2, stem: "nonsense".into() })
        );
    }
}
