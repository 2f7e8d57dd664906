//! A folder of the user's own BVH files as training data (native only).
//!
//! `DIR` is searched recursively for `*.bvh` files (any rig the importer accepts). An optional
//! `DIR/labels.csv` labels some of them:
//!
//! ```text
//! file,style,content
//! walks/proud_01.bvh,proud,walk
//! walks/tired_01.bvh,tired,
//! ```
//!
//! The header names the columns (any order, any case): `file` and `style` are required, `content`
//! is optional (recorded, not trained on). `file` is relative to `DIR` (`/` or `\` separators;
//! no absolute paths, no `..`). Fields may be double-quoted (`""` inside quotes is a quote; a row
//! is one line).
//! Label names are compared without case (the first spelling is kept). Files not listed are
//! unlabelled: they train the autoencoder, the regressor and the unsupervised stylizer; labelled
//! ones also the supervised stylizer and the classifier. The label set, in one-hot order, is the
//! labels sorted by name.
//!
//! A malformed `labels.csv` is a [`LabelsError`] naming the line. Files that fail to import are
//! skipped and listed with their error ([`super::corpus::Corpus::failed`]).
//!
//! **Held-out files** ([`choose_heldout`]): a tenth of every label's files (at least one) where the
//! label has at least [`MIN_FILES_TO_HOLD_OUT`] files, and a tenth of the unlabelled files where
//! there are at least that many; chosen by a stable hash of the relative paths, so every stage of
//! a run (and a rerun) holds out the same files.

use super::corpus::{Clip, Corpus, par_map};
use super::labels::Style;
use crate::features::{self, Features};
use crate::skeleton;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The labels file at the folder's root.
pub const LABELS_CSV: &str = "labels.csv";
/// Most labels a folder may define (the manifest's limit: labels are stored as `u8`).
pub const MAX_LABELS: usize = 256;
/// Longest label name, characters.
pub const MAX_LABEL_CHARS: usize = 64;
/// Deepest folder nesting searched.
pub const MAX_DEPTH: usize = 32;
/// A label (or the unlabelled files) needs this many files before any is held out.
pub const MIN_FILES_TO_HOLD_OUT: usize = 5;
/// Salt of the held-out hash (fixed: every stage must agree).
const HELDOUT_SALT: u64 = 0x0f01_de20_2611;

/// A malformed `labels.csv`. Lines are 1-based, as an editor shows them.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum LabelsError {
    #[error("labels.csv is empty: its first line must be the header `file,style` (optional column `content`)")]
    Empty,
    #[error("labels.csv line 1: the header lacks the column `{column}` (found: {found})")]
    MissingColumn { column: &'static str, found: String },
    #[error("labels.csv line 1: unknown column `{column}` (the columns are file, style and optionally content)")]
    UnknownColumn { column: String },
    #[error("labels.csv line 1: the column `{column}` appears twice")]
    DuplicateColumn { column: String },
    #[error("labels.csv line {line}: {got} fields, the header has {expected}")]
    FieldCount { line: usize, expected: usize, got: usize },
    #[error("labels.csv line {line}: an unterminated or misplaced double quote")]
    BadQuote { line: usize },
    #[error("labels.csv line {line}: the `{column}` field is empty")]
    EmptyField { line: usize, column: &'static str },
    #[error("labels.csv line {line}: `{file}` must be a path relative to the data folder, without `..`")]
    BadPath { line: usize, file: String },
    #[error("labels.csv line {line}: `{file}` is not a .bvh file in the data folder")]
    NotFound { line: usize, file: String },
    #[error("labels.csv line {line}: `{file}` is already labelled on line {first}")]
    DuplicateFile { line: usize, file: String, first: usize },
    #[error(
        "labels.csv line {line}: the label `{label}` is not usable (1-{MAX_LABEL_CHARS} characters, no control \
         characters)"
    )]
    BadLabel { line: usize, label: String },
    #[error("labels.csv line {line}: more than {MAX_LABELS} labels")]
    TooManyLabels { line: usize },
    #[error("labels.csv is not UTF-8 text")]
    NotText,
}

impl LabelsError {
    /// A stable code for scripts.
    pub fn code(&self) -> &'static str {
        match self {
            LabelsError::Empty => "LABELS_EMPTY",
            LabelsError::MissingColumn { .. }
            | LabelsError::UnknownColumn { .. }
            | LabelsError::DuplicateColumn { .. } => "LABELS_HEADER",
            LabelsError::FieldCount { .. } | LabelsError::BadQuote { .. } | LabelsError::EmptyField { .. } => {
                "LABELS_ROW"
            }
            LabelsError::BadPath { .. } | LabelsError::NotFound { .. } | LabelsError::DuplicateFile { .. } => {
                "LABELS_FILE"
            }
            LabelsError::BadLabel { .. } | LabelsError::TooManyLabels { .. } => "LABELS_LABEL",
            LabelsError::NotText => "LABELS_NOT_TEXT",
        }
    }
}

/// Why a folder cannot be used as training data.
#[derive(Debug, Error)]
pub enum FolderError {
    #[error("cannot list {dir}: {error}")]
    List { dir: PathBuf, error: std::io::Error },
    #[error("cannot read {path}: {error}")]
    Read { path: PathBuf, error: std::io::Error },
    #[error("{path}: {error}")]
    Labels { path: PathBuf, error: LabelsError },
    #[error(
        "{0} is not a folder (the data: a folder of BVH files with an optional labels.csv, or the Bandai-Namco \
         archives unpacked into DIR/dataset-1 and DIR/dataset-2)"
    )]
    Missing(PathBuf),
    #[error("no .bvh files under {0} (nor the Bandai-Namco layout DIR/dataset-1, DIR/dataset-2)")]
    NoFiles(PathBuf),
    #[error("none of the .bvh files under {0} could be imported (see the skipped files above)")]
    NothingImported(PathBuf),
}

impl FolderError {
    /// A stable code for scripts.
    pub fn code(&self) -> &'static str {
        match self {
            FolderError::List { .. } | FolderError::Read { .. } | FolderError::Missing(_) => "DATA_READ",
            FolderError::Labels { error, .. } => error.code(),
            FolderError::NoFiles(_) => "DATA_EMPTY",
            FolderError::NothingImported(_) => "DATA_UNUSABLE",
        }
    }
}

/// Whether `dir` is the Bandai-Namco layout (`DIR/dataset-1/data` or `DIR/dataset-2/data`, and no
/// `labels.csv`): the data `train` read before folders of one's own files.
pub fn is_bandai_layout(dir: &Path) -> bool {
    !dir.join(LABELS_CSV).exists() && ["dataset-1", "dataset-2"].iter().any(|set| dir.join(set).join("data").is_dir())
}

/// One row of `labels.csv`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LabelRow {
    /// 1-based line.
    pub line: usize,
    /// Relative path with `/` separators.
    pub file: String,
    /// Index into the folder's label set.
    pub style: usize,
    pub content: Option<String>,
}

/// A parsed `labels.csv`: the label set (sorted by name) and the rows.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Labels {
    pub names: Vec<String>,
    pub rows: Vec<LabelRow>,
}

/// Splits one CSV line into fields (double quotes, `""` escapes).
fn split_fields(line: &str, number: usize) -> Result<Vec<String>, LabelsError> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut was_quoted = false;
    while let Some(c) = chars.next() {
        if quoted {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => quoted = false,
                _ => field.push(c),
            }
        } else {
            match c {
                ',' => {
                    fields.push(std::mem::take(&mut field));
                    was_quoted = false;
                }
                '"' if field.trim().is_empty() && !was_quoted => {
                    field.clear();
                    quoted = true;
                    was_quoted = true;
                }
                '"' => return Err(LabelsError::BadQuote { line: number }),
                _ if was_quoted && !c.is_whitespace() => return Err(LabelsError::BadQuote { line: number }),
                _ => field.push(c),
            }
        }
    }
    if quoted {
        return Err(LabelsError::BadQuote { line: number });
    }
    fields.push(field);
    Ok(fields.into_iter().map(|f| f.trim().to_string()).collect())
}

/// A `labels.csv` path in the one spelling used everywhere (`/` separators, no `./`); `None`
/// for absolute paths and paths with `..`.
pub fn normalize_rel(file: &str) -> Option<String> {
    let unified = file.replace('\\', "/");
    if unified.starts_with('/') || unified.contains(':') {
        return None;
    }
    let mut parts = Vec::new();
    for part in unified.split('/') {
        match part {
            "" | "." => {}
            ".." => return None,
            p => parts.push(p),
        }
    }
    (!parts.is_empty()).then(|| parts.join("/"))
}

fn usable_label(name: &str) -> bool {
    let n = name.chars().count();
    (1..=MAX_LABEL_CHARS).contains(&n) && !name.chars().any(char::is_control)
}

/// Parses `labels.csv` text. `exists(rel)` says whether a relative path is one of the folder's
/// BVH files.
pub fn parse_labels(text: &str, exists: impl Fn(&str) -> bool) -> Result<Labels, LabelsError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let (header_line, header) = lines.next().ok_or(LabelsError::Empty)?;
    let columns = split_fields(header, header_line)?;
    let (mut file_col, mut style_col, mut content_col) = (None, None, None);
    for (i, c) in columns.iter().enumerate() {
        let slot = match c.to_ascii_lowercase().as_str() {
            "file" => &mut file_col,
            "style" => &mut style_col,
            "content" => &mut content_col,
            _ => return Err(LabelsError::UnknownColumn { column: c.clone() }),
        };
        if slot.replace(i).is_some() {
            return Err(LabelsError::DuplicateColumn { column: c.clone() });
        }
    }
    let found = columns.join(",");
    let file_col = file_col.ok_or_else(|| LabelsError::MissingColumn { column: "file", found: found.clone() })?;
    let style_col = style_col.ok_or(LabelsError::MissingColumn { column: "style", found })?;

    // (line, file, label as written, content)
    let mut raw: Vec<(usize, String, String, Option<String>)> = Vec::new();
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    // Lower-case label -> first spelling.
    let mut spelling: BTreeMap<String, String> = BTreeMap::new();
    for (line, text) in lines {
        let fields = split_fields(text, line)?;
        if fields.len() != columns.len() {
            return Err(LabelsError::FieldCount { line, expected: columns.len(), got: fields.len() });
        }
        let file = &fields[file_col];
        if file.is_empty() {
            return Err(LabelsError::EmptyField { line, column: "file" });
        }
        let label = &fields[style_col];
        if label.is_empty() {
            return Err(LabelsError::EmptyField { line, column: "style" });
        }
        if !usable_label(label) {
            return Err(LabelsError::BadLabel { line, label: label.clone() });
        }
        let rel = normalize_rel(file).ok_or_else(|| LabelsError::BadPath { line, file: file.clone() })?;
        if !exists(&rel) {
            return Err(LabelsError::NotFound { line, file: file.clone() });
        }
        if let Some(&first) = seen.get(&rel) {
            return Err(LabelsError::DuplicateFile { line, file: file.clone(), first });
        }
        seen.insert(rel.clone(), line);
        let key = label.to_lowercase();
        if !spelling.contains_key(&key) {
            if spelling.len() == MAX_LABELS {
                return Err(LabelsError::TooManyLabels { line });
            }
            spelling.insert(key.clone(), label.clone());
        }
        let content = content_col.map(|c| fields[c].clone()).filter(|c| !c.is_empty());
        raw.push((line, rel, key, content));
    }
    let mut names: Vec<String> = spelling.values().cloned().collect();
    names.sort_by_key(|n| (n.to_lowercase(), n.clone()));
    let index: BTreeMap<String, usize> = names.iter().enumerate().map(|(i, n)| (n.to_lowercase(), i)).collect();
    let rows = raw
        .into_iter()
        .map(|(line, file, key, content)| LabelRow { line, file, style: index[&key], content })
        .collect();
    Ok(Labels { names, rows })
}

/// Every `*.bvh` (any case) under `dir`, as sorted relative paths with `/` separators.
pub fn list_bvh(dir: &Path) -> Result<Vec<String>, FolderError> {
    fn walk(dir: &Path, rel: &str, depth: usize, out: &mut Vec<String>) -> Result<(), FolderError> {
        let list_err = |error| FolderError::List { dir: dir.to_path_buf(), error };
        for entry in std::fs::read_dir(dir).map_err(list_err)? {
            let entry = entry.map_err(list_err)?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let child = if rel.is_empty() { name.clone() } else { format!("{rel}/{name}") };
            // Not followed through symbolic links to folders (no loops).
            let kind = entry.file_type().map_err(list_err)?;
            if kind.is_dir() {
                if depth < MAX_DEPTH && !name.starts_with('.') {
                    walk(&entry.path(), &child, depth + 1, out)?;
                }
            } else if name.to_ascii_lowercase().ends_with(".bvh") && entry.path().is_file() {
                out.push(child);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, "", 0, &mut out)?;
    out.sort();
    Ok(out)
}

/// A folder's files and labels, before anything is imported.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FolderListing {
    /// Relative paths of every BVH file, sorted.
    pub files: Vec<String>,
    /// From `labels.csv` (empty when there is none).
    pub labels: Labels,
}

impl FolderListing {
    /// Lists `dir` and reads its `labels.csv`, if any.
    pub fn read(dir: &Path) -> Result<FolderListing, FolderError> {
        if !dir.is_dir() {
            return Err(FolderError::Missing(dir.to_path_buf()));
        }
        let files = list_bvh(dir)?;
        if files.is_empty() {
            return Err(FolderError::NoFiles(dir.to_path_buf()));
        }
        let path = dir.join(LABELS_CSV);
        let labels = if path.is_file() {
            let bytes = std::fs::read(&path).map_err(|error| FolderError::Read { path: path.clone(), error })?;
            let text = String::from_utf8(bytes)
                .map_err(|_| FolderError::Labels { path: path.clone(), error: LabelsError::NotText })?;
            let set: BTreeSet<&str> = files.iter().map(String::as_str).collect();
            parse_labels(&text, |rel| set.contains(rel)).map_err(|error| FolderError::Labels { path, error })?
        } else {
            Labels::default()
        };
        Ok(FolderListing { files, labels })
    }

    /// The listing with its labels indexing `names` (a superset of its own labels, compared
    /// without case: a fine-tuned run's label set); `None` if a label is not in `names`.
    pub fn relabelled(&self, names: &[String]) -> Option<FolderListing> {
        let map: Vec<usize> = self
            .labels
            .names
            .iter()
            .map(|n| names.iter().position(|m| m.eq_ignore_ascii_case(n)))
            .collect::<Option<_>>()?;
        let rows = self.labels.rows.iter().map(|r| LabelRow { style: map[r.style], ..r.clone() }).collect();
        Some(FolderListing { files: self.files.clone(), labels: Labels { names: names.to_vec(), rows } })
    }

    /// Each file's label and content (`None`: unlabelled), in `files` order.
    pub fn annotations(&self) -> Vec<(Option<usize>, Option<String>)> {
        let by_file: BTreeMap<&str, &LabelRow> = self.labels.rows.iter().map(|r| (r.file.as_str(), r)).collect();
        self.files
            .iter()
            .map(|f| by_file.get(f.as_str()).map_or((None, None), |r| (Some(r.style), r.content.clone())))
            .collect()
    }
}

/// FNV-1a of a salt and a name (stable across releases).
fn stable_hash(salt: u64, name: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in salt.to_le_bytes().iter().chain(name.as_bytes()) {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The held-out files of a listing (see the module docs), sorted.
pub fn choose_heldout(listing: &FolderListing) -> Vec<String> {
    let mut groups: BTreeMap<Option<usize>, Vec<&str>> = BTreeMap::new();
    for (file, (style, _)) in listing.files.iter().zip(listing.annotations()) {
        groups.entry(style).or_default().push(file);
    }
    let mut out = Vec::new();
    for files in groups.values_mut() {
        if files.len() < MIN_FILES_TO_HOLD_OUT {
            continue;
        }
        files.sort_by_key(|f| (stable_hash(HELDOUT_SALT, f), f.to_string()));
        let n = ((files.len() as f64 * super::split::HELDOUT_FRACTION).round() as usize).max(1);
        out.extend(files[..n].iter().map(|f| f.to_string()));
    }
    out.sort();
    out
}

/// One file's fate in a load.
#[derive(Clone, Debug, PartialEq)]
pub struct FileReport {
    pub file: String,
    pub style: Option<usize>,
    pub heldout: bool,
    /// Frames at 30 fps, or the import error.
    pub result: Result<usize, String>,
}

/// Loads the folder's files as features, `heldout` (relative paths) held out, on `threads`
/// threads; training files get a mirrored copy. The corpus' `labels` is the folder's label set.
pub fn load(
    dir: &Path,
    listing: &FolderListing,
    heldout: &BTreeSet<String>,
    threads: usize,
    progress: impl FnMut(usize, usize),
) -> Result<(Corpus, Vec<FileReport>), FolderError> {
    let paths: Vec<PathBuf> = listing.files.iter().map(|f| dir.join(f)).collect();
    let results = par_map(&paths, threads, |p| load_one(p), progress);
    let mut corpus = Corpus { labels: listing.labels.names.clone(), ..Corpus::default() };
    let mut report = Vec::new();
    for (((file, path), (style, content)), r) in listing.files.iter().zip(paths).zip(listing.annotations()).zip(results)
    {
        let held = heldout.contains(file);
        let style_id = style.map(|s| Style(s as u8));
        report.push(FileReport {
            file: file.clone(),
            style,
            heldout: held,
            result: r.as_ref().map(Features::frames).map_err(Clone::clone),
        });
        let clip = |features: Features, mirrored: bool| Clip {
            take: None,
            name: file.clone(),
            content: content.clone(),
            style: style_id,
            mirrored,
            features,
        };
        match r {
            Ok(f) if held => corpus.heldout.push(clip(f, false)),
            Ok(f) => {
                let m = features::mirror(&f);
                corpus.train.push(clip(f, false));
                corpus.train.push(clip(m, true));
            }
            Err(e) => corpus.failed.push((path, e)),
        }
    }
    if corpus.train.is_empty() {
        return Err(FolderError::NothingImported(dir.to_path_buf()));
    }
    Ok((corpus, report))
}

fn load_one(path: &Path) -> Result<Features, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let imported = skeleton::import_bvh(&text).map_err(|e| format!("{} ({})", e, e.code()))?;
    Ok(features::extract(&imported.motion))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Labels, LabelsError> {
        parse_labels(text, |f| ["a.bvh", "sub/b.bvh", "c.bvh"].contains(&f))
    }

    #[test]
    fn parses_columns_in_any_order_quotes_and_merges_label_case() {
        let l = parse(
            "\u{feff}Style,FILE,content\nproud,a.bvh,walk\n\n\"Tired\", \"sub\\b.bvh\" ,\nTIRED,./c.bvh,\"a, b\"\n",
        )
        .unwrap();
        assert_eq!(l.names, ["proud", "Tired"]);
        assert_eq!(l.rows.len(), 3);
        assert_eq!((l.rows[1].line, l.rows[1].file.as_str(), l.rows[1].style), (4, "sub/b.bvh", 1));
        assert_eq!(l.rows[2].style, 1);
        assert_eq!(l.rows[0].content.as_deref(), Some("walk"));
        assert_eq!(l.rows[1].content, None);
        assert_eq!(l.rows[2].content.as_deref(), Some("a, b"));
        assert_eq!(parse("file,style\n").unwrap(), Labels::default());
    }

    #[test]
    fn malformed_labels_name_the_line_and_what_is_wrong() {
        use LabelsError::*;
        let cases: Vec<(&str, LabelsError)> = vec![
            ("", Empty),
            ("\n \n", Empty),
            ("file\na.bvh\n", MissingColumn { column: "style", found: "file".into() }),
            ("file,style,take\n", UnknownColumn { column: "take".into() }),
            ("file,style,file\n", DuplicateColumn { column: "file".into() }),
            ("file,style\na.bvh\n", FieldCount { line: 2, expected: 2, got: 1 }),
            ("file,style\na.bvh,old,x\n", FieldCount { line: 2, expected: 2, got: 3 }),
            ("file,style\n\"a.bvh,old\n", BadQuote { line: 2 }),
            ("file,style\na\"x.bvh,old\n", BadQuote { line: 2 }),
            ("file,style\n,old\n", EmptyField { line: 2, column: "file" }),
            ("file,style\na.bvh,\n", EmptyField { line: 2, column: "style" }),
            ("file,style\n../a.bvh,old\n", BadPath { line: 2, file: "../a.bvh".into() }),
            ("file,style\n/a.bvh,old\n", BadPath { line: 2, file: "/a.bvh".into() }),
            ("file,style\nC:\\a.bvh,old\n", BadPath { line: 2, file: "C:\\a.bvh".into() }),
            ("file,style\nnope.bvh,old\n", NotFound { line: 2, file: "nope.bvh".into() }),
            ("file,style\na.bvh,old\n\na.bvh,new\n", DuplicateFile { line: 4, file: "a.bvh".into(), first: 2 }),
            ("file,style\na.bvh,o\u{7}ld\n", BadLabel { line: 2, label: "o\u{7}ld".into() }),
        ];
        for (text, want) in cases {
            let got = parse(text).expect_err(text);
            assert_eq!(got, want, "{text:?}");
            assert!(got.code().starts_with("LABELS_"));
            // Every row error starts with its line number.
            if !matches!(got, Empty) {
                let text = got.to_string();
                let rest = text.strip_prefix("labels.csv line ").unwrap_or_else(|| panic!("{text}"));
                assert!(rest.starts_with(|c: char| c.is_ascii_digit()), "{text}");
            }
        }
        let long = format!("file,style\na.bvh,{}\n", "x".repeat(MAX_LABEL_CHARS + 1));
        assert!(matches!(parse(&long), Err(BadLabel { line: 2, .. })));
    }

    #[test]
    fn heldout_is_a_tenth_of_groups_with_enough_files_and_stable() {
        let files: Vec<String> = (0..30).map(|i| format!("f{i:02}.bvh")).collect();
        let rows = (0..12)
            .map(|i| LabelRow { line: i + 2, file: files[i].clone(), style: usize::from(i >= 6), content: None })
            .collect();
        let listing = FolderListing { files, labels: Labels { names: vec!["a".into(), "b".into()], rows } };
        let held = choose_heldout(&listing);
        // a: 6 files -> 1, b: 6 -> 1, unlabelled: 18 -> 2.
        assert_eq!(held.len(), 4, "{held:?}");
        assert_eq!(held, choose_heldout(&listing));
        let small = FolderListing { files: listing.files[..4].to_vec(), labels: Labels::default() };
        assert!(choose_heldout(&small).is_empty());
    }
}
