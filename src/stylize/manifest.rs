//! `assets/weights/manifest.json`: what the shipped weights are and how they were made.
//!
//! The folder holds `manifest.json`, `norm.json` (the training split's [`NormStats`]) and the
//! networks. **Format 2** (what `motion-stylizer export` writes): `shared.bin`, the networks both
//! stylizers share (autoencoder and global motion regressor, [`Manifest::shared`]), and one file
//! per stylizer setting holding only its stylizer (`supervised.bin`, `unsupervised.bin`), each a
//! part file ([`crate::model::weights::save_part`]: every tensor by name in f16 or, for the large
//! layers, integers with scales); every file listed with its size and FNV-1a 64 fingerprint, which
//! the loaders check. **Format 3** (what `motion-stylizer export` writes now) is format 2 with each
//! stylizer in two files: `supervised.bin` holds the content encoder and generator (all that label-
//! and prior-based stylization need), `supervised-style.bin` its style encoder
//! ([`ModelEntry::style_encoder`]), which a browser fetches only when a reference motion is first
//! used. **Format 1** (still read): no shared file, each setting's file a whole f16
//! bundle ([`crate::model::weights::save_bundle`]).
//!
//! This is the one reader of the manifest: the npm package asks the engine which files to fetch
//! ([`WeightFileList`]).
//!
//! [`NormStats`]: crate::features::NormStats

use serde::{Deserialize, Serialize};

/// The manifest format `export` writes.
pub const FORMAT: u32 = 3;
/// The formats this build reads.
pub const FORMATS: [u32; 3] = [1, 2, 3];

/// A weight file of format 2: name (relative to the manifest), size and fingerprint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileRef {
    pub file: String,
    pub bytes: u64,
    /// FNV-1a 64 of the file's bytes, 16 hex digits ([`crate::model::weights::fnv1a64`]).
    pub fnv1a64: String,
}

/// The shared networks' file (format 2) and how its large layers are encoded.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SharedEntry {
    #[serde(flatten)]
    pub file: FileRef,
    /// The networks it holds: `["autoencoder", "regressor"]`.
    pub holds: Vec<String>,
    /// `"f16"`, `"q8"`, `"q4g64"`, ... ([`crate::model::weights::PartEncoding::name`]).
    pub encoding: String,
}

/// Which files a manifest names, for a loader (the npm package) to fetch: what
/// [`Manifest::file_list`] gives.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct WeightFileList {
    pub format: u32,
    pub norm: ListedFile,
    /// Format 2: the shared networks, needed by every setting.
    pub shared: Option<ListedFile>,
    /// Per setting, its file.
    pub models: Vec<ListedModel>,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ListedFile {
    pub file: String,
    /// Its size (0 where the manifest does not say, format 1).
    pub bytes: u64,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ListedModel {
    pub setting: String,
    pub file: String,
    pub bytes: u64,
    /// Format 3: the style encoder's file, needed only for reference motions.
    pub style_encoder: Option<ListedFile>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: u32,
    /// Licence of the weights (trained on CC BY-NC 4.0 data).
    pub licence: String,
    /// Style labels in one-hot order (the unified label set, [`crate::dataset::STYLES`]).
    pub styles: Vec<String>,
    /// File name of the normalisation statistics, relative to the manifest.
    pub norm: String,
    /// Format 2: the statistics file's size and FNV-1a 64 (so that the manifest's own bytes
    /// identify every file of the folder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub norm_bytes: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub norm_fnv1a64: Option<String>,
    /// Training window, frames.
    pub window: usize,
    /// The held-out split file the training used (repository path) and its held-out take count.
    pub split: String,
    pub heldout_takes: usize,
    /// Format 2: the networks every setting shares (required there, absent in format 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shared: Option<SharedEntry>,
    /// Per setting: `"supervised"`, `"unsupervised"`.
    pub models: Vec<ModelEntry>,
}

impl Manifest {
    /// The entry of `setting`, if the manifest lists one: the one lookup every reader and writer
    /// of a manifest uses.
    pub fn entry(&self, setting: super::Setting) -> Option<&ModelEntry> {
        self.models.iter().find(|m| m.setting == setting.as_str())
    }

    /// [`Manifest::entry`], to change it.
    pub fn entry_mut(&mut self, setting: super::Setting) -> Option<&mut ModelEntry> {
        self.models.iter_mut().find(|m| m.setting == setting.as_str())
    }

    /// The manifest as `manifest.json` holds it: pretty JSON with every array of plain numbers on
    /// one line (the label codes: 16 lines, not 4,000), ending in a newline.
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        Ok(compact_number_arrays(&serde_json::to_string_pretty(self)?) + "\n")
    }

    /// The files to fetch: statistics, shared networks (format 2), one file per setting.
    pub fn file_list(&self) -> WeightFileList {
        WeightFileList {
            format: self.format,
            norm: ListedFile { file: self.norm.clone(), bytes: self.norm_bytes.unwrap_or(0) },
            shared: self.shared.as_ref().map(|s| ListedFile { file: s.file.file.clone(), bytes: s.file.bytes }),
            models: self
                .models
                .iter()
                .map(|m| ListedModel {
                    setting: m.setting.clone(),
                    file: m.file.clone(),
                    bytes: m.bytes.unwrap_or(0),
                    style_encoder: m
                        .style_encoder
                        .as_ref()
                        .map(|f| ListedFile { file: f.file.clone(), bytes: f.bytes }),
                })
                .collect(),
        }
    }
}

/// One shipped bundle and its provenance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelEntry {
    /// `"supervised"` or `"unsupervised"`.
    pub setting: String,
    /// Bundle file name, relative to the manifest.
    pub file: String,
    /// Format 2: the file's size and fingerprint, and how its large layers are encoded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bytes: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fnv1a64: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoding: Option<String>,
    /// Format 3: the file of the style encoder (`file` then holds the content encoder and the
    /// generator), in the same encoding.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub style_encoder: Option<FileRef>,
    /// Width factor relative to the paper's sizes.
    pub width: f64,
    /// Training stages that produced it, in order (autoencoder first, then the stylizer).
    pub stages: Vec<StageRecord>,
    /// Supervised model: where each label's real takes sit in its style space, the centre that
    /// label-based codes are drawn around (written by `motion-stylizer label-codes`). Absent:
    /// label-based codes are drawn around 0, the prior's mean.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label_codes: Option<LabelCodes>,
    /// Unsupervised model: where the `normal` training takes sit in its style space, what
    /// guidance measures a reference's style against (written by `motion-stylizer
    /// label-codes`). Absent: the prior's mean, 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub neutral_code: Option<NeutralCode>,
}

/// The mean of the unsupervised style encoder's posterior means over the `normal` training takes
/// (each data set weighted equally: set 1 has 19, set 2 ~400).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NeutralCode {
    /// The exact command that wrote it.
    pub command: String,
    /// Training takes encoded.
    pub takes: usize,
    /// `[style_dim]`.
    pub code: Vec<f32>,
}

/// Per label, the mean of the style encoder's posterior means over the label's training takes
/// (each data set weighted equally where it has the label: set 1 has ~11 takes a style, set 2
/// ~400), in one-hot order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LabelCodes {
    /// The exact command that wrote them.
    pub command: String,
    /// Training takes encoded, per label (one-hot order).
    pub takes: Vec<usize>,
    /// `[num_styles][style_dim]`.
    pub codes: Vec<Vec<f32>>,
}

/// How one training stage ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageRecord {
    /// `"ae"` or `"stylizer"`.
    pub stage: String,
    /// The exact command line.
    pub command: String,
    pub steps: u64,
    pub seed: u64,
    pub batch: usize,
    pub window: usize,
    /// Wall-clock training time, seconds, and seconds per step on the machine it ran on.
    pub seconds: f64,
    pub seconds_per_step: f64,
    pub machine: String,
    /// Final training losses (moving averages) by name, and held-out metrics by name.
    pub final_losses: std::collections::BTreeMap<String, f64>,
    pub heldout: std::collections::BTreeMap<String, f64>,
}

/// Pretty JSON with every array of plain numbers on one line (the label codes: 16 lines, not
/// 4,000); the same JSON value.
pub fn compact_number_arrays(pretty: &str) -> String {
    let mut out: Vec<String> = Vec::new();
    // The lines of an array that may hold only numbers: its opening line, then its elements.
    let mut held: Vec<&str> = Vec::new();
    for line in pretty.lines() {
        let t = line.trim();
        if !held.is_empty() {
            if t.trim_end_matches(',').parse::<f64>().is_ok() {
                held.push(line);
                continue;
            }
            if t.starts_with(']') && held.len() > 1 {
                let items: Vec<&str> = held[1..].iter().map(|l| l.trim()).collect();
                out.push(format!("{}{}{t}", held[0], items.join(" ")));
                held.clear();
                continue;
            }
            out.extend(held.drain(..).map(str::to_string));
        }
        if t.ends_with('[') {
            held.push(line);
        } else {
            out.push(line.to_string());
        }
    }
    out.extend(held.into_iter().map(str::to_string));
    out.join("\n")
}

#[cfg(test)]
mod tests {
    use super::compact_number_arrays;

    #[test]
    fn number_arrays_go_on_one_line_and_the_value_is_kept() {
        let value = serde_json::json!({"a": [1.5, -2, 3e-4], "b": [{"c": [1, 2]}, []], "d": [["x", 1]], "e": "["});
        let pretty = serde_json::to_string_pretty(&value).unwrap();
        let compact = compact_number_arrays(&pretty);
        assert!(compact.contains("\"a\": [1.5, -2, 0.0003]"), "{compact}");
        assert!(compact.contains("\"c\": [1, 2]"), "{compact}");
        assert_eq!(serde_json::from_str::<serde_json::Value>(&compact).unwrap(), value);
        assert!(compact.lines().count() < pretty.lines().count());
    }
}
