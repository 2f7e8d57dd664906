//! Progress display: an indicatif bar (loss, steps/s, ETA) when stderr is a terminal, otherwise
//! one plain line every N steps (for `nohup … > log`).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;

/// How to show progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ProgressMode {
    /// A bar on a terminal, plain lines otherwise.
    #[default]
    Auto,
    /// Plain lines.
    Plain,
    /// Nothing (tests).
    Quiet,
}

pub struct Progress {
    bar: Option<ProgressBar>,
    plain: bool,
    log_every: u64,
    total: u64,
    /// Names of the shown loss terms and their positions in a step's terms.
    shown: Vec<(&'static str, usize)>,
    sums: Vec<f64>,
    count: u64,
    since: Instant,
    since_step: u64,
    started: Instant,
    start_step: u64,
}

impl Progress {
    pub fn new(
        mode: ProgressMode,
        start_step: u64,
        total: u64,
        log_every: u64,
        shown: Vec<(&'static str, usize)>,
    ) -> Self {
        let bar = (mode == ProgressMode::Auto && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template(
                    "[{elapsed_precise}] {bar:30.cyan/blue} {pos}/{len} {per_sec:.2} ETA {eta} {msg}",
                )
                .expect("valid template")
                .progress_chars("=> "),
            );
            bar.set_position(start_step);
            bar.reset_eta();
            bar
        });
        let n = shown.len();
        Self {
            plain: bar.is_none() && mode != ProgressMode::Quiet,
            bar,
            log_every: log_every.max(1),
            total,
            shown,
            sums: vec![0.0; n],
            count: 0,
            since: Instant::now(),
            since_step: start_step,
            started: Instant::now(),
            start_step,
        }
    }

    /// A line above the bar (or on its own).
    pub fn println(&self, line: &str) {
        match &self.bar {
            Some(bar) => bar.println(line),
            None if self.plain => eprintln!("{line}"),
            None => {}
        }
    }

    /// After step `step` with loss terms `terms`.
    pub fn step(&mut self, step: u64, terms: &[f64]) {
        for (s, (_, i)) in self.sums.iter_mut().zip(&self.shown) {
            *s += terms[*i];
        }
        self.count += 1;
        if let Some(bar) = &self.bar {
            bar.set_position(step);
            if self.count >= 10 || step == self.total {
                bar.set_message(self.means());
                self.reset(step);
            }
        } else if self.plain && (step.is_multiple_of(self.log_every) || step == self.total) {
            let dt = self.since.elapsed().as_secs_f64();
            let per_step = dt / (step - self.since_step).max(1) as f64;
            let done = step - self.start_step;
            let avg = self.started.elapsed().as_secs_f64() / done.max(1) as f64;
            let eta = avg * (self.total - step) as f64;
            eprintln!(
                "step {step}/{} | {} | {per_step:.3} s/step ({:.2} steps/s) | ETA {}",
                self.total,
                self.means(),
                1.0 / per_step.max(1e-9),
                format_duration(eta)
            );
            self.reset(step);
        }
    }

    fn means(&self) -> String {
        let n = self.count.max(1) as f64;
        self.shown
            .iter()
            .zip(&self.sums)
            .map(|((name, _), s)| format!("{name} {:.4}", s / n))
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn reset(&mut self, step: u64) {
        self.sums.iter_mut().for_each(|s| *s = 0.0);
        self.count = 0;
        self.since = Instant::now();
        self.since_step = step;
    }

    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }
}

/// `1h02m`, `5m07s`, `42s`.
pub fn format_duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    if s >= 3600 {
        format!("{}h{:02}m", s / 3600, (s % 3600) / 60)
    } else if s >= 60 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{s}s")
    }
}
