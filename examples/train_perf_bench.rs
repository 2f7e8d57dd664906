//! Our side of `make bench-train` (bench/perf/train_run.mjs): one training step of each stage —
//! the autoencoder + global regressor ([`AeTrainer`]) and the supervised stylizer on the frozen
//! autoencoder ([`StylizerTrainer`]) — at batch 16 × 160 frames, seeded, for the PyTorch rebuild
//! (bench/perf/torch_train.py) to reproduce and to be timed against.
//!
//! ```text
//! train_perf_bench dump DIR [--width 0.5] [--steps 3]
//! train_perf_bench time [--width 0.5] [--repeats 3]      # threads: RAYON_NUM_THREADS
//! ```
//!
//! `dump` writes into DIR everything the PyTorch side needs for the same first steps:
//! - `meta.json`: the model config (dropout 0, so that both sides compute the same function), the
//!   training config, the stylizer's loss weights, batch, frames, steps, parameter counts;
//! - `ae.bpk` (an `AeNets`: autoencoder + regressor) and `stylizer.bpk` (content encoder, style
//!   encoder, generator): the initial weights, Burn's burnpack in f32 (`rundir::module_bytes`);
//!   the stylizer's frozen autoencoder is `ae.bpk`'s, i.e. the AeTrainer's own initial networks;
//! - `motion1.f32`, `motion2.f32` (`[16, 260, 160]`, little-endian f32): the batch (the
//!   autoencoder stage trains on `motion1`), the style labels in `meta.json`;
//! - `noise.f32` (`[steps, 5, 16, style_dim]`): the reparameterisation noise the stylizer steps
//!   draw, five `[B, style_dim]` draws per step in `stylizer_loss`'s order, replayed from a
//!   `NoiseRng` with the trainer's seed salt (the plain autoencoder draws none);
//! - `losses.json`: every term of the first `steps` steps of both stages (before each update),
//!   gradient norms included.
//!
//! `time` builds the same trainers and batch, runs one warm-up step of each stage, then times
//! `repeats` steps of each and prints one JSON line: seconds per step and per phase.

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("train_perf_bench needs `--features model`");
}

#[cfg(feature = "model")]
fn main() {
    if let Err(e) = bench::main() {
        eprintln!("train_perf_bench: {e:#}");
        std::process::exit(1);
    }
}

#[cfg(feature = "model")]
mod bench {
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use anyhow::{Context, bail};
    use burn::module::Module;
    use burn::prelude::*;
    use motion_stylizer::model::{ModelConfig, NoiseRng};
    use motion_stylizer::train::{
        AeTrainer, PhaseTimes, StepReport, StylizerBatch, StylizerTrainer, TrainConfig, Trainer,
    };
    use serde_json::{Value, json};

    const B: usize = 16;
    const T: usize = 160;
    const FEATURES: usize = 260;
    /// Seeds of the two trainers' weights and noise, and of the batch.
    const AE_SEED: u64 = 1;
    const STYLIZER_SEED: u64 = 2;
    const BATCH_SEED: u64 = 7;
    /// `StylizerTrainer::new` seeds its noise with `seed ^ NOISE_SALT`; the PyTorch side's parity
    /// check fails if this replay ever drifts from it.
    const STYLIZER_NOISE_SALT: u64 = motion_stylizer::train::stylizer::NOISE_SALT;
    /// `[B, style_dim]` draws per stylizer step (`stylizer_loss`: s¹, s², s³, s² again, sᵗ).
    const DRAWS_PER_STEP: usize = 5;

    struct Setup {
        config: ModelConfig,
        ae: AeTrainer,
        stylizer: StylizerTrainer,
        batch: StylizerBatch,
    }

    fn setup(width: f64) -> Setup {
        let device = Device::flex();
        let mut config = ModelConfig::scaled(width);
        config.dropout = 0.0;
        let train = TrainConfig::default();
        let ae = AeTrainer::new(config.clone(), train.clone(), &device, AE_SEED);
        // The frozen autoencoder of the stylizer stage: the AeTrainer's own (initial) networks.
        let stylizer = StylizerTrainer::new(config.clone(), train, ae.autoencoder.clone(), &device, STYLIZER_SEED);
        let mut rng = NoiseRng::new(BATCH_SEED);
        let mut features = || rng.normal_tensor(B, FEATURES * T, &device).reshape([B, FEATURES, T]);
        let motion1 = features();
        let motion2 = features();
        let labels: Vec<usize> = (0..B).map(|i| (5 * i + 3) % config.num_styles).collect();
        let batch = StylizerBatch::unpaired(motion1, motion2, Some(labels));
        Setup { config, ae, stylizer, batch }
    }

    fn f32_bytes(t: &Tensor<3>) -> Vec<u8> {
        let v = t.clone().into_data().try_into_vec_as::<f32>().expect("f32 features");
        v.iter().flat_map(|x| x.to_le_bytes()).collect()
    }

    fn report<R: StepReport>(r: &R) -> Value {
        let map: serde_json::Map<String, Value> =
            R::TERMS.iter().zip(r.values()).map(|(k, v)| ((*k).to_string(), json!(v))).collect();
        Value::Object(map)
    }

    fn write(dir: &Path, name: &str, bytes: &[u8]) -> anyhow::Result<()> {
        let path = dir.join(name);
        std::fs::write(&path, bytes).with_context(|| format!("cannot write {}", path.display()))
    }

    fn dump(dir: PathBuf, width: f64, steps: usize) -> anyhow::Result<()> {
        std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let Setup { config, mut ae, mut stylizer, batch } = setup(width);
        write(&dir, "ae.bpk", &ae.weights()?)?;
        write(&dir, "stylizer.bpk", &stylizer.weights()?)?;
        write(&dir, "motion1.f32", &f32_bytes(&batch.motion1))?;
        write(&dir, "motion2.f32", &f32_bytes(&batch.motion2))?;
        let mut noise = NoiseRng::new(STYLIZER_SEED ^ STYLIZER_NOISE_SALT);
        let noise: Vec<u8> = (0..steps * DRAWS_PER_STEP)
            .flat_map(|_| noise.normals(B * config.style_dim))
            .flat_map(|x| x.to_le_bytes())
            .collect();
        write(&dir, "noise.f32", &noise)?;

        let mut ae_losses = Vec::new();
        let mut stylizer_losses = Vec::new();
        for _ in 0..steps {
            ae_losses.push(report(&ae.step(batch.motion1.clone())?));
            stylizer_losses.push(report(&stylizer.step(&batch)?));
        }
        let meta = json!({
            "width": width,
            "batch": B,
            "frames": T,
            "features": FEATURES,
            "steps": steps,
            "draws_per_step": DRAWS_PER_STEP,
            "labels": batch.labels,
            "config": config,
            "train": ae.train,
            "stylizer_weights": stylizer.weights,
            "params": {
                "autoencoder": ae.autoencoder.num_params(),
                "regressor": ae.regressor.num_params(),
                "stylizer": stylizer.net.num_params(),
            },
        });
        write(&dir, "meta.json", serde_json::to_string_pretty(&meta)?.as_bytes())?;
        write(
            &dir,
            "losses.json",
            serde_json::to_string_pretty(&json!({ "ae": ae_losses, "stylizer": stylizer_losses }))?.as_bytes(),
        )?;
        println!(
            "{}",
            json!({ "dir": dir, "width": width, "steps": steps, "ae": ae_losses, "stylizer": stylizer_losses })
        );
        Ok(())
    }

    fn phases(p: &PhaseTimes) -> Value {
        let n = p.steps.max(1) as f64;
        json!({ "forward": p.forward / n, "backward": p.backward / n, "clip": p.clip / n, "update": p.update / n })
    }

    fn time(width: f64, repeats: usize) -> anyhow::Result<()> {
        let Setup { mut ae, mut stylizer, batch, .. } = setup(width);
        let threads = std::env::var("RAYON_NUM_THREADS").ok();
        // Warm-up: one step of each (first touches of the weights, allocator, thread pool).
        ae.step(batch.motion1.clone())?;
        stylizer.step(&batch)?;
        ae.phases = Some(PhaseTimes::default());
        stylizer.phases = Some(PhaseTimes::default());
        let (mut ae_s, mut stylizer_s) = (Vec::with_capacity(repeats), Vec::with_capacity(repeats));
        let (mut ae_cpu_s, mut stylizer_cpu_s) = (Vec::with_capacity(repeats), Vec::with_capacity(repeats));
        for _ in 0..repeats {
            let (t, c) = (Instant::now(), cpu_seconds());
            ae.step(batch.motion1.clone())?;
            ae_s.push(t.elapsed().as_secs_f64());
            ae_cpu_s.push(cpu_seconds() - c);
            let (t, c) = (Instant::now(), cpu_seconds());
            stylizer.step(&batch)?;
            stylizer_s.push(t.elapsed().as_secs_f64());
            stylizer_cpu_s.push(cpu_seconds() - c);
        }
        let out = json!({
            "width": width,
            "rayon_num_threads": threads,
            "ae_s": ae_s,
            "stylizer_s": stylizer_s,
            "ae_cpu_s": ae_cpu_s,
            "stylizer_cpu_s": stylizer_cpu_s,
            "ae_phases_s": phases(&ae.phases.unwrap_or_default()),
            "stylizer_phases_s": phases(&stylizer.phases.unwrap_or_default()),
        });
        println!("{out}");
        Ok(())
    }

    /// CPU seconds (user + system, every thread) the process has used: `/proc/self/stat`'s utime
    /// and stime in clock ticks (100 a second on Linux); 0 where it cannot be read. On a shared
    /// machine this moves less than wall time (what `time.process_time()` gives PyTorch's side).
    fn cpu_seconds() -> f64 {
        let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else { return 0.0 };
        // Fields after the command name (which is in parentheses and may hold spaces).
        let Some(rest) = stat.rsplit_once(')').map(|(_, r)| r) else { return 0.0 };
        let fields: Vec<&str> = rest.split_whitespace().collect();
        let ticks = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).unwrap_or(0.0);
        // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name.
        (ticks(11) + ticks(12)) / 100.0
    }

    pub fn main() -> anyhow::Result<()> {
        motion_stylizer::memory::keep_freed_memory();
        let args: Vec<String> = std::env::args().skip(1).collect();
        let Some(mode) = args.first().cloned() else {
            bail!("usage: train_perf_bench dump DIR [--width W] [--steps N] | time [--width W] [--repeats N]");
        };
        let mut rest = args[1..].to_vec();
        let dir = if mode == "dump" {
            if rest.is_empty() {
                bail!("dump needs an output folder");
            }
            Some(PathBuf::from(rest.remove(0)))
        } else {
            None
        };
        let (mut width, mut steps, mut repeats) = (0.5f64, 3usize, 3usize);
        let mut i = 0;
        while i < rest.len() {
            let value = rest.get(i + 1).with_context(|| format!("{} needs a value", rest[i]))?;
            match rest[i].as_str() {
                "--width" => width = value.parse().context("--width W")?,
                "--steps" => steps = value.parse().context("--steps N")?,
                "--repeats" => repeats = value.parse().context("--repeats N")?,
                other => bail!("unknown argument {other}"),
            }
            i += 2;
        }
        match (mode.as_str(), dir) {
            ("dump", Some(dir)) => dump(dir, width, steps),
            ("time", _) => time(width, repeats.max(1)),
            (other, _) => bail!("unknown mode {other} (dump or time)"),
        }
    }
}
