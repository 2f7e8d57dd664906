//! The training loop, the same for every stage: steps, `loss.csv`, held-out evaluations
//! (`eval.csv`), checkpoints, progress.

use anyhow::{Context, ensure};
use std::path::Path;
use std::time::Instant;

use super::data::TrainData;
use super::progress::{Progress, format_duration};
use super::rundir::{self, Checkpoint, CheckpointMeta, CsvLog, RunConfig, RunLog};
use super::sampler::SamplerRng;
use super::settings::TrainOptions;
use super::trainer::{StepReport, Trainer};
use super::{SAMPLER_SALT, TrainSummary};

/// Where a segment of a run starts: the checkpoint it resumes (none for a new run), the run log
/// to extend, and when the invocation started.
pub struct Start<'a> {
    pub resume_from: Option<&'a Checkpoint>,
    pub log: RunLog,
    pub started: Instant,
}

/// Loads `optimizer.bin` into the trainer when it belongs to the checkpoint being resumed.
fn restore_optimizer<T: Trainer>(
    trainer: &mut T,
    out: &Path,
    ckpt: &Checkpoint,
    say: &dyn Fn(String),
) -> anyhow::Result<()> {
    let path = out.join(rundir::OPTIMIZER);
    let bytes = if ckpt.meta.optimizer_state { std::fs::read(&path).ok() } else { None };
    match bytes.as_deref().and_then(|b| b.split_first_chunk::<8>()) {
        Some((step, state)) if u64::from_le_bytes(*step) == ckpt.meta.step => {
            trainer.load_optimizer_state(state).with_context(|| format!("cannot restore {}", path.display()))?;
            say(format!("resumed Adam's state of step {}", ckpt.meta.step));
        }
        _ => eprintln!(
            "warning: no optimizer state for step {} (a checkpoint from an older version?): Adam restarts with fresh moments",
            ckpt.meta.step
        ),
    }
    Ok(())
}

/// Trains `trainer` on `data` from the start's step to `opts.steps` (see the module docs of
/// [`super`]).
pub fn run<T: Trainer>(
    mut trainer: T,
    data: &TrainData,
    config: &RunConfig,
    opts: &TrainOptions,
    start: Start<'_>,
    say: &dyn Fn(String),
) -> anyhow::Result<TrainSummary> {
    let out = &opts.out;
    let Start { resume_from, mut log, started } = start;
    let start_step = resume_from.map_or(0, |c| c.meta.step);
    if let Some(ckpt) = resume_from {
        trainer.load_weights(&ckpt.weights)?;
        restore_optimizer(&mut trainer, out, ckpt, say)?;
    }
    let mut rng = match resume_from {
        Some(c) => SamplerRng::from_state(&c.meta.sampler).map_err(anyhow::Error::msg)?,
        None => SamplerRng::new(config.settings.seed ^ SAMPLER_SALT),
    };
    let elapsed0 = resume_from.map_or(0.0, |c| c.meta.elapsed_s);
    let lrs = trainer.learning_rates();
    let terms = T::Report::TERMS;
    let loss_columns: Vec<&str> =
        ["step", "elapsed_s"].iter().chain(terms).copied().chain(lrs.iter().map(|(n, _)| *n)).collect();
    let eval_columns: Vec<&str> = ["step", "elapsed_s"].iter().chain(T::METRICS).copied().collect();
    let mut loss_csv = CsvLog::open(&out.join(rundir::LOSS_CSV), &loss_columns, start_step)?;
    let mut eval_csv = CsvLog::open(&out.join(rundir::EVAL_CSV), &eval_columns, start_step)?;

    let s = &config.settings;
    say(format!(
        "{} run {}: steps {start_step} -> {}, width {}, batch {}, window {}, seed {}{}",
        config.stage,
        out.display(),
        opts.steps,
        s.width,
        s.batch,
        s.window,
        s.seed,
        match config.supervised {
            Some(true) => ", supervised",
            Some(false) => ", unsupervised",
            None => "",
        }
    ));
    let shown: Vec<(&'static str, usize)> = T::SHOWN
        .iter()
        .map(|(label, term)| (*label, terms.iter().position(|t| t == term).expect("a shown term is a term")))
        .collect();
    let mut progress = Progress::new(opts.progress, start_step, opts.steps, opts.log_every, shown);
    let t_loop = Instant::now();
    let (mut step_s, mut eval_s) = (0.0f64, 0.0f64);
    let mut last_terms = Vec::new();
    let mut last_eval: Option<Vec<f64>> = None;
    for step in start_step + 1..=opts.steps {
        let t = Instant::now();
        let values = trainer.train_step(data, &mut rng).with_context(|| format!("step {step}"))?.values();
        step_s += t.elapsed().as_secs_f64();
        ensure!(
            values[0].is_finite(),
            "step {step}: the loss is not finite ({}); stopping without checkpointing it",
            values[0]
        );
        let elapsed = elapsed0 + t_loop.elapsed().as_secs_f64();
        let row: Vec<f64> =
            [elapsed].into_iter().chain(values.iter().copied()).chain(lrs.iter().map(|(_, v)| *v)).collect();
        loss_csv.row(step, &row)?;
        progress.step(step, &values);
        last_terms = values;

        let last = step == opts.steps;
        if last || (opts.eval_every > 0 && step.is_multiple_of(opts.eval_every)) {
            let t = Instant::now();
            let metrics = trainer.evaluate(data);
            eval_s += t.elapsed().as_secs_f64();
            let row: Vec<f64> =
                [elapsed0 + t_loop.elapsed().as_secs_f64()].into_iter().chain(metrics.iter().copied()).collect();
            eval_csv.row(step, &row)?;
            let text: Vec<String> = T::METRICS.iter().zip(&metrics).map(|(n, v)| format!("{n} {v:.4}")).collect();
            progress.println(&format!("held-out @ {step}: {}", text.join(" ")));
            last_eval = Some(metrics);
        }
        if last || step.is_multiple_of(opts.checkpoint_every) {
            loss_csv.flush()?;
            eval_csv.flush()?;
            let elapsed = elapsed0 + t_loop.elapsed().as_secs_f64();
            let mut optimizer = step.to_le_bytes().to_vec();
            optimizer.extend(trainer.optimizer_state()?);
            rundir::write_atomic(&out.join(rundir::OPTIMIZER), &optimizer)?;
            let ckpt = Checkpoint {
                meta: CheckpointMeta {
                    stage: config.stage.clone(),
                    step,
                    elapsed_s: elapsed,
                    sampler: rng.state(),
                    optimizer_state: true,
                },
                weights: trainer.weights()?,
            };
            rundir::write_atomic(&out.join(rundir::CHECKPOINT), &ckpt.to_bytes()?)?;
            for (name, bytes) in trainer.artifacts()? {
                rundir::write_atomic(&out.join(name), &bytes)?;
            }
            let seg = log.segments.last_mut().expect("a segment");
            seg.to_step = step;
            seg.step_s = step_s;
            seg.eval_s = eval_s;
            seg.wall_s = started.elapsed().as_secs_f64();
            rundir::write_json(&out.join(rundir::RUN_LOG), &log)?;
        }
    }
    progress.finish();
    let done = opts.steps - start_step;
    say(format!(
        "{}: step {} reached; {done} steps in {} ({:.3} s/step training, {} held-out evaluation)",
        out.display(),
        opts.steps,
        format_duration(t_loop.elapsed().as_secs_f64()),
        step_s / done.max(1) as f64,
        format_duration(eval_s)
    ));
    Ok(TrainSummary {
        step: opts.steps,
        losses: terms.iter().map(|s| s.to_string()).zip(last_terms).collect(),
        heldout: T::METRICS.iter().map(|s| s.to_string()).zip(last_eval.unwrap_or_default()).collect(),
    })
}
