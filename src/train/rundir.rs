//! The files of a run directory and how they are written.
//!
//! | file | what |
//! |---|---|
//! | `config.json` | [`RunConfig`]: stage, settings, network sizes; fixed for the life of the run |
//! | `run.json` | [`RunLog`]: one segment per invocation (exact command line, steps, timings), machine |
//! | `norm.json` | the normalisation statistics the run trains on |
//! | `checkpoint.bin` | latest checkpoint: [`CheckpointMeta`] + burnpack bytes of the networks (f32) |
//! | `ae.bin` | stylizer runs: the frozen autoencoder + regressor checkpoint it trains on (a copy) |
//! | `loss.csv` | one row per step: step, elapsed_s, every loss term of the step report, lr |
//! | `eval.csv` | one row per evaluation: step, elapsed_s, held-out metrics |
//!
//! Files that must never be seen half-written (`checkpoint.bin`, `run.json`, `config.json`,
//! `norm.json`, `ae.bin`) are written to a temporary name in the same folder, synced, then renamed
//! over the old one.

use anyhow::{Context, bail};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

use super::sampler::RngState;
use crate::model::{ModelConfig, TrainConfig};

pub const CONFIG: &str = "config.json";
pub const RUN_LOG: &str = "run.json";
pub const NORM: &str = "norm.json";
pub const CHECKPOINT: &str = "checkpoint.bin";
pub const AE_COPY: &str = "ae.bin";
/// Adam's state at the checkpoint's step: the step (u64 LE), then the trainer's optimizer bytes.
pub const OPTIMIZER: &str = "optimizer.bin";
pub const LOSS_CSV: &str = "loss.csv";
pub const EVAL_CSV: &str = "eval.csv";

const CHECKPOINT_MAGIC: &[u8; 8] = b"MSTCKPT1";

/// Settings of a run, written once when it starts; a resumed run takes them from here.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunConfig {
    /// `"ae"` or `"stylizer"`.
    pub stage: String,
    /// Stylizer: supervised (style labels) or not; `None` for the autoencoder.
    pub supervised: Option<bool>,
    pub seed: u64,
    pub width: f64,
    pub batch: usize,
    pub window: usize,
    pub model: ModelConfig,
    pub train: TrainConfig,
    /// Held-out split file, as given.
    pub split: String,
    /// Stylizer: the autoencoder run it was started on (as given) and that run's step.
    pub ae_run: Option<String>,
    pub ae_step: Option<u64>,
    /// How windows are drawn ([`super::sampler`]).
    pub sampler: String,
    /// Training clips (takes + mirrors) used and skipped as shorter than the window; held-out
    /// windows evaluated and held-out takes skipped.
    pub train_clips: usize,
    pub train_clips_skipped: usize,
    pub eval_windows: usize,
    pub heldout_skipped: usize,
}

/// One invocation of `train` on this run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// `std::env::args` joined by spaces.
    pub command: String,
    /// Unix time (s) the invocation started.
    pub started_unix: u64,
    /// Step the segment started from (0, or the checkpoint it resumed) and the last step it
    /// checkpointed.
    pub from_step: u64,
    pub to_step: u64,
    /// Seconds: data loading; training steps (sampling + forward + backward + update); held-out
    /// evaluations; the whole segment up to its last checkpoint.
    pub load_s: f64,
    pub step_s: f64,
    pub eval_s: f64,
    pub wall_s: f64,
}

/// Provenance and timing of a run, updated at every checkpoint.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunLog {
    /// Processor model and core count of the machine (of the latest segment).
    pub machine: String,
    /// Rayon threads of the latest segment (the flex kernels' pool).
    pub threads: usize,
    pub segments: Vec<Segment>,
}

impl RunLog {
    /// The command lines, in order; one string when the run was not resumed.
    pub fn command(&self) -> String {
        self.segments.iter().map(|s| s.command.as_str()).collect::<Vec<_>>().join(" && ")
    }

    /// Total steps trained, total wall seconds of the training segments, seconds per step
    /// (training steps only, without evaluation, checkpoints and data loading).
    pub fn totals(&self) -> (u64, f64, f64) {
        let steps = self.segments.last().map_or(0, |s| s.to_step);
        let wall: f64 = self.segments.iter().map(|s| s.wall_s).sum();
        let step_s: f64 = self.segments.iter().map(|s| s.step_s).sum();
        let done: u64 = self.segments.iter().map(|s| s.to_step.saturating_sub(s.from_step)).sum();
        (steps, wall, if done > 0 { step_s / done as f64 } else { 0.0 })
    }
}

/// What a checkpoint holds besides the network weights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckpointMeta {
    pub stage: String,
    /// Steps done.
    pub step: u64,
    /// Wall seconds of training so far (all segments), for `elapsed_s` in the logs.
    pub elapsed_s: f64,
    /// Position of the window sampler's generator after `step` steps.
    pub sampler: RngState,
    /// Whether `optimizer.bin` holds Adam's state of this step (`false` in checkpoints written
    /// before it existed: such a run resumes with fresh moments).
    pub optimizer_state: bool,
}

/// A checkpoint: metadata and the burnpack bytes of the networks.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    pub meta: CheckpointMeta,
    pub weights: Vec<u8>,
}

impl Checkpoint {
    pub fn to_bytes(&self) -> anyhow::Result<Vec<u8>> {
        let json = serde_json::to_vec(&self.meta)?;
        let mut out = Vec::with_capacity(12 + json.len() + self.weights.len());
        out.extend_from_slice(CHECKPOINT_MAGIC);
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(&json);
        out.extend_from_slice(&self.weights);
        Ok(out)
    }

    pub fn from_bytes(bytes: &[u8]) -> anyhow::Result<Checkpoint> {
        if bytes.len() < 12 || &bytes[..8] != CHECKPOINT_MAGIC {
            bail!("not a motion-stylizer training checkpoint");
        }
        let len = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes")) as usize;
        let json = bytes.get(12..12 + len).context("truncated checkpoint")?;
        let meta = serde_json::from_slice(json).context("checkpoint metadata")?;
        Ok(Checkpoint { meta, weights: bytes[12 + len..].to_vec() })
    }

    pub fn read(path: &Path) -> anyhow::Result<Checkpoint> {
        let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
        Checkpoint::from_bytes(&bytes).with_context(|| format!("{}", path.display()))
    }
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, synced, renamed over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let tmp = tmp_path(path);
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}

fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

pub fn write_json<T: Serialize>(path: &Path, value: &T) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

pub fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> anyhow::Result<T> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("cannot parse {}", path.display()))
}

/// A CSV log with a fixed header, appended to across resumes.
pub struct CsvLog {
    path: PathBuf,
    columns: Vec<String>,
    out: std::io::BufWriter<std::fs::File>,
}

impl CsvLog {
    /// Opens `path` for appending rows of `columns`. A new file gets the header. An existing one
    /// must have the same header; its rows with a step (first column) above `keep_to_step` are
    /// dropped (written after the checkpoint being resumed).
    pub fn open(path: &Path, columns: &[&str], keep_to_step: u64) -> anyhow::Result<CsvLog> {
        let header = columns.join(",");
        if path.exists() {
            let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
            let mut lines = text.lines();
            if lines.next() != Some(header.as_str()) {
                bail!("{} has another header than expected ({header})", path.display());
            }
            let mut kept = header.clone();
            kept.push('\n');
            for line in lines {
                let step: u64 = line.split(',').next().and_then(|s| s.parse().ok()).unwrap_or(u64::MAX);
                if step <= keep_to_step {
                    kept.push_str(line);
                    kept.push('\n');
                }
            }
            if kept.len() != text.len() {
                write_atomic(path, kept.as_bytes())?;
            }
        } else {
            write_atomic(path, format!("{header}\n").as_bytes())?;
        }
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .with_context(|| format!("cannot open {}", path.display()))?;
        Ok(CsvLog {
            path: path.to_path_buf(),
            columns: columns.iter().map(|s| s.to_string()).collect(),
            out: std::io::BufWriter::new(file),
        })
    }

    /// Appends one row (step first; values in [`CsvLog::open`]'s column order after the step).
    pub fn row(&mut self, step: u64, values: &[f64]) -> anyhow::Result<()> {
        debug_assert_eq!(values.len() + 1, self.columns.len());
        let mut line = step.to_string();
        for v in values {
            line.push(',');
            line.push_str(&format_value(*v));
        }
        line.push('\n');
        self.out.write_all(line.as_bytes()).with_context(|| format!("cannot write {}", self.path.display()))
    }

    pub fn flush(&mut self) -> anyhow::Result<()> {
        self.out.flush().with_context(|| format!("cannot write {}", self.path.display()))
    }
}

/// Shortest text of the value as an f32 (losses are f32; seconds to the millisecond).
fn format_value(v: f64) -> String {
    if v.is_finite() {
        let mut b = ryu::Buffer::new();
        let s = b.format(v as f32);
        s.strip_suffix(".0").unwrap_or(s).to_string()
    } else {
        "NaN".to_string()
    }
}

/// A CSV log read back: header and numeric rows (unparsable cells become NaN).
#[derive(Clone, Debug, PartialEq)]
pub struct CsvTable {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl CsvTable {
    pub fn read(path: &Path) -> anyhow::Result<CsvTable> {
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
        let mut lines = text.lines();
        let columns = lines.next().context("empty CSV")?.split(',').map(str::to_string).collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(|c| c.trim().parse().unwrap_or(f64::NAN)).collect())
            .collect();
        Ok(CsvTable { columns, rows })
    }

    /// Rows whose step (first column) is at most `step`.
    pub fn up_to(&self, step: u64) -> Vec<&Vec<f64>> {
        self.rows.iter().filter(|r| r.first().is_some_and(|s| *s <= step as f64)).collect()
    }
}

/// The processor's model name and the number of logical cores, e.g.
/// `"AMD EPYC 7B13, 2 cores (Linux x86_64)"`.
pub fn machine_description() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{model}, {cores} cores ({} {})", std::env::consts::OS, std::env::consts::ARCH)
}

/// Seconds since the Unix epoch.
pub fn unix_now() -> u64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs())
}
