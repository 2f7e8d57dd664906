//! One style-label set across Bandai-Namco sets 1 and 2.
//!
//! Set 1 has 15 styles, set 2 has 7; three of set 2's are set 1's under another name and are merged:
//! `elderly` → `old`, `exhausted` → `tired`, and set 1's `masculinity` → `masculine`. `normal`,
//! `feminine` and `active` are shared as spelled. `youthful` (set 2) and `childish` (set 1) are kept
//! apart: set 2's youthful takes are adults moving young and brisk, set 1's childish ones are
//! child-like, and merging them would blur both. That gives 16 labels.

/// The unified style labels, in label-index order (the model's one-hot order).
pub const STYLES: [&str; 16] = [
    "normal",
    "active",
    "feminine",
    "masculine",
    "old",
    "tired",
    "youthful",
    "childish",
    "happy",
    "sad",
    "angry",
    "proud",
    "not-confident",
    "musical",
    "giant",
    "chimpira",
];

/// A style label: an index into [`STYLES`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct Style(pub u8);

impl Style {
    /// The label for a unified name (`"old"`), case-insensitive.
    pub fn from_name(name: &str) -> Option<Style> {
        STYLES.iter().position(|s| s.eq_ignore_ascii_case(name)).map(|i| Style(i as u8))
    }

    /// The label for a style as spelled in Bandai-Namco set `set` (1 or 2), merging synonyms.
    pub fn from_bandai(set: u8, raw: &str) -> Option<Style> {
        let unified = match (set, raw) {
            (1, "masculinity") => "masculine",
            (2, "elderly") => "old",
            (2, "exhausted") => "tired",
            (1, "youthful") | (2, "childish") => return None,
            (1 | 2, other) => other,
            _ => return None,
        };
        Style::from_name(unified)
    }

    pub fn name(self) -> &'static str {
        STYLES[self.0 as usize]
    }

    pub fn index(self) -> usize {
        self.0 as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mirror_image_trades_left_and_right_contents() {
        let class = |name: &str, mirrored| content_class_as_seen(name, mirrored).map(|c| CONTENTS[c]);
        assert_eq!(class("walk-left", true), Some("walk-right"));
        assert_eq!(class("walk-turn-right", true), Some("walk-turn-left"));
        assert_eq!(class("raise-up-left-hand", true), Some("raise-up-right-hand"));
        assert_eq!(class("wave-right-hand", true), Some("wave-left-hand"));
        // Unchanged: the take itself, contents without a side, and contents without a class.
        assert_eq!(class("walk-left", false), Some("walk-left"));
        assert_eq!(class("wave-both-hands", true), Some("wave-both-hands"));
        assert_eq!(class("run", true), Some("run"));
        assert_eq!(class("kick", true), None);
        // Every side-specific class has its mirror among the classes.
        for name in CONTENTS {
            assert!(class(name, true).is_some(), "{name}");
        }
    }

    #[test]
    fn every_bandai_style_maps_and_merges_as_documented() {
        let set1 = [
            "normal",
            "happy",
            "sad",
            "angry",
            "proud",
            "not-confident",
            "masculinity",
            "feminine",
            "childish",
            "old",
            "tired",
            "active",
            "musical",
            "giant",
            "chimpira",
        ];
        let set2 = ["active", "normal", "feminine", "youthful", "masculine", "exhausted", "elderly"];
        let mut used = std::collections::BTreeSet::new();
        for s in set1 {
            used.insert(Style::from_bandai(1, s).expect(s));
        }
        for s in set2 {
            used.insert(Style::from_bandai(2, s).expect(s));
        }
        assert_eq!(used.len(), STYLES.len(), "every unified label is used");
        assert_eq!(Style::from_bandai(2, "elderly"), Style::from_bandai(1, "old"));
        assert_eq!(Style::from_bandai(2, "exhausted"), Style::from_bandai(1, "tired"));
        assert_eq!(Style::from_bandai(1, "masculinity"), Style::from_bandai(2, "masculine"));
        assert_ne!(Style::from_bandai(2, "youthful"), Style::from_bandai(1, "childish"));
        assert_eq!(Style::from_bandai(3, "normal"), None);
        assert_eq!(Style::from_name("OLD").map(Style::name), Some("old"));
    }
}

/// The content classes of the evaluation's content classifier: every Bandai-Namco content with at
/// least 10 takes, by name (set 1's and set 2's `walk` and `run` are one class each). Left out: the
/// set-1 contents with 1–2 takes (`call`, `dance-short`, `kick`, `punch`, `respond`, `slash`).
pub const CONTENTS: [&str; 18] = [
    "bow",
    "bye",
    "byebye",
    "dash",
    "guide",
    "run",
    "walk",
    "walk-back",
    "walk-left",
    "walk-right",
    "raise-up-both-hands",
    "raise-up-left-hand",
    "raise-up-right-hand",
    "walk-turn-left",
    "walk-turn-right",
    "wave-both-hands",
    "wave-left-hand",
    "wave-right-hand",
];

/// The content class of a take's content name (an index into [`CONTENTS`]), if it has one.
pub fn content_class(content: &str) -> Option<usize> {
    CONTENTS.iter().position(|c| *c == content)
}

/// The content class of a take's mirror image (`mirrored`) or of the take: a mirrored
/// `walk-left` walks to the right, a mirrored `raise-up-left-hand` raises the right hand, so
/// `left` and `right` trade places in the name; other contents keep theirs.
pub fn content_class_as_seen(content: &str, mirrored: bool) -> Option<usize> {
    if !mirrored {
        return content_class(content);
    }
    let swapped: Vec<&str> = content
        .split('-')
        .map(|w| match w {
            "left" => "right",
            "right" => "left",
            w => w,
        })
        .collect();
    content_class(&swapped.join("-"))
}
