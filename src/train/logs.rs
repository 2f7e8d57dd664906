//! The logs of a run folder: `run.json` ([`RunLog`], one [`Segment`] per invocation) and the CSV
//! logs `loss.csv` / `eval.csv` ([`CsvLog`] to append, [`CsvTable`] to read back).

use anyhow::{Context, bail};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

use super::rundir::write_atomic;

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
    /// The compute device and its adapter when not the CPU (`wgpu (llvmpipe ...)`); absent: flex.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub device: Option<String>,
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
            let old = lines.next().unwrap_or_default();
            // A log written before columns were added (new loss terms, which the run did not use
            // then): its rows are carried over with 0 in the new columns. Any other difference
            // is refused.
            let old_columns: Vec<&str> = old.split(',').collect();
            let from_old: Vec<Option<usize>> =
                columns.iter().map(|c| old_columns.iter().position(|o| o == c)).collect();
            let same = old == header;
            if !same && (from_old.iter().flatten().count() != old_columns.len() || from_old[0] != Some(0)) {
                bail!("{} has another header than expected ({header})", path.display());
            }
            let mut kept = header.clone();
            kept.push('\n');
            for line in lines {
                let step: u64 = line.split(',').next().and_then(|s| s.parse().ok()).unwrap_or(u64::MAX);
                if step > keep_to_step {
                    continue;
                }
                if same {
                    kept.push_str(line);
                } else {
                    let fields: Vec<&str> = line.split(',').collect();
                    let row: Vec<&str> =
                        from_old.iter().map(|i| i.and_then(|i| fields.get(i).copied()).unwrap_or("0")).collect();
                    kept.push_str(&row.join(","));
                }
                kept.push('\n');
            }
            if kept != text {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_from_before_a_column_was_added_is_carried_over_and_another_is_refused() {
        let dir = std::env::temp_dir().join(format!("ms-csvlog-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("loss.csv");
        std::fs::write(&path, "step,loss,hsa\n1,0.5,0.1\n2,0.4,0.2\n3,0.3,0.3\n").unwrap();
        let mut log = CsvLog::open(&path, &["step", "loss", "stats", "hsa"], 2).unwrap();
        log.row(3, &[0.25, 0.05, 0.15]).unwrap();
        drop(log);
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "step,loss,stats,hsa\n1,0.5,0,0.1\n2,0.4,0,0.2\n3,0.25,0.05,0.15\n"
        );
        // A column renamed or dropped is not an older layout of this log.
        for header in ["step,loss,kl\n1,0.5,0.1\n", "step,loss\n1,0.5\n"] {
            std::fs::write(&path, header).unwrap();
            let columns: &[&str] = if header.contains("kl") { &["step", "loss", "hsa"] } else { &["step"] };
            assert!(CsvLog::open(&path, columns, 1).is_err(), "{header}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
