//! `make bench-gpu`: the wgpu device against the CPU (flex) in one run — seconds per training
//! step of each stage (autoencoder + regressor; supervised stylizer on a frozen autoencoder) at
//! batch 16 × 160 frames, width 0.5 (shipped) and 1.0 (paper), and milliseconds per 160-frame
//! label-based stylization with the shipped weights, 1 and 10 samples (BVH text out).
//!
//! ```text
//! cargo run --release --features wgpu --example gpu_bench [-- --steps 2 --repeats 3 --widths 0.5,1]
//! ```
//!
//! Steps: the mean of `--steps` timed steps after one warm-up (which also compiles the wgpu
//! kernels); every step reads its losses back, so the device has finished it. Stylization: the
//! median of `--repeats` runs after one warm-up. CPU threads: RAYON_NUM_THREADS.

#[cfg(not(all(feature = "wgpu", not(target_arch = "wasm32"))))]
fn main() {
    eprintln!("gpu_bench needs `--features wgpu`");
}

#[cfg(all(feature = "wgpu", not(target_arch = "wasm32")))]
fn main() {
    if let Err(e) = bench::main() {
        eprintln!("gpu_bench: {e:#}");
        std::process::exit(1);
    }
}

#[cfg(all(feature = "wgpu", not(target_arch = "wasm32")))]
mod bench {
    use std::time::Instant;

    use anyhow::{Context, bail};
    use burn::prelude::*;
    use motion_stylizer::Motion;
    use motion_stylizer::model::device::{self, DeviceName};
    use motion_stylizer::model::{ModelConfig, NoiseRng};
    use motion_stylizer::skeleton;
    use motion_stylizer::stylize::{self, Request, StyleSource, Weights};
    use motion_stylizer::train::{AeTrainer, StylizerBatch, StylizerTrainer, TrainConfig};

    const B: usize = 16;
    const T: usize = 160;

    struct Options {
        steps: usize,
        repeats: usize,
        widths: Vec<f64>,
    }

    fn options() -> anyhow::Result<Options> {
        let mut o = Options { steps: 2, repeats: 3, widths: vec![0.5, 1.0] };
        let args: Vec<String> = std::env::args().skip(1).collect();
        for pair in args.chunks(2) {
            let value = pair.get(1).with_context(|| format!("{} needs a value", pair[0]))?;
            match pair[0].as_str() {
                "--steps" => o.steps = value.parse().context("--steps N")?,
                "--repeats" => o.repeats = value.parse().context("--repeats N")?,
                "--widths" => {
                    o.widths =
                        value.split(',').map(|w| w.parse()).collect::<Result<_, _>>().context("--widths 0.5,1")?
                }
                other => bail!("unknown argument {other} (--steps N, --repeats N, --widths W,W)"),
            }
        }
        anyhow::ensure!(o.steps >= 1 && o.repeats >= 1, "--steps and --repeats must be at least 1");
        Ok(o)
    }

    /// Mean seconds of `steps` calls after one warm-up call.
    fn time_steps(steps: usize, mut step: impl FnMut() -> anyhow::Result<()>) -> anyhow::Result<f64> {
        step()?;
        let start = Instant::now();
        for _ in 0..steps {
            step()?;
        }
        Ok(start.elapsed().as_secs_f64() / steps as f64)
    }

    /// Seconds per step of (autoencoder + regressor, stylizer) at `width` on `device`.
    fn train_steps(device: &Device, width: f64, steps: usize) -> anyhow::Result<(f64, f64)> {
        let mut config = ModelConfig::scaled(width);
        config.dropout = 0.0;
        let mut rng = NoiseRng::new(7);
        let mut features = || rng.normal_tensor(B, 260 * T, device).reshape([B, 260, T]);
        let (motion1, motion2) = (features(), features());
        let labels: Vec<usize> = (0..B).map(|i| (5 * i + 3) % config.num_styles).collect();
        let mut ae = AeTrainer::new(config.clone(), TrainConfig::default(), device, 1);
        let ae_s = time_steps(steps, || {
            ae.step(motion1.clone())?;
            Ok(())
        })?;
        let mut st = StylizerTrainer::new(config, TrainConfig::default(), ae.autoencoder.clone(), device, 2);
        drop(ae);
        let batch = StylizerBatch::unpaired(motion1, motion2, Some(labels));
        let st_s = time_steps(steps, || {
            st.step(&batch)?;
            Ok(())
        })?;
        Ok((ae_s, st_s))
    }

    /// The 120-frame walk fixture played forward, then backward from frame 118, to 160 frames (as
    /// bench/wasm/clip.mjs does to the BVH text).
    fn walk160() -> anyhow::Result<skeleton::Imported> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh");
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {path}"))?;
        let mut imported = skeleton::import_bvh(&text).with_context(|| format!("cannot import {path}"))?;
        let m = &imported.motion;
        let n = m.frames();
        let order: Vec<usize> = (0..n).chain((0..n.saturating_sub(1)).rev()).cycle().take(T).collect();
        let root = order.iter().map(|&f| m.root_positions()[f]).collect();
        let rotations = order.iter().map(|&f| m.rotations()[f]).collect();
        imported.motion = Motion::new(root, rotations)?;
        Ok(imported)
    }

    /// Median milliseconds of a label-based stylization of `content` with 1 and with 10 samples.
    fn stylize_ms(device: &Device, content: &skeleton::Imported, repeats: usize) -> anyhow::Result<(f64, f64)> {
        let weights = Weights::load_dir_on(device, concat!(env!("CARGO_MANIFEST_DIR"), "/assets/weights"))?;
        let old = weights.style("old")?;
        let time = |samples: usize| -> anyhow::Result<f64> {
            let request = Request::new(StyleSource::Label(old)).with_samples(samples).with_seed(7);
            let once = || -> anyhow::Result<f64> {
                let t = Instant::now();
                let texts: Vec<String> = stylize::stylize(&weights, &content.motion, &request)?
                    .iter()
                    .map(|m| content.rig.from_canonical(m).to_bvh_string())
                    .collect();
                std::hint::black_box(texts);
                Ok(t.elapsed().as_secs_f64() * 1e3)
            };
            once()?;
            let mut ms = (0..repeats).map(|_| once()).collect::<anyhow::Result<Vec<_>>>()?;
            ms.sort_by(f64::total_cmp);
            Ok(ms[ms.len() / 2])
        };
        Ok((time(1)?, time(10)?))
    }

    fn cpu_model() -> String {
        std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
            })
            .unwrap_or_else(|| "?".into())
    }

    pub fn main() -> anyhow::Result<()> {
        motion_stylizer::memory::keep_freed_memory();
        let o = options()?;
        let gpu = device::open(DeviceName::Wgpu)?;
        let adapter = device::adapter_name(&gpu).unwrap_or_else(|| "? (see vulkaninfo --summary)".into());
        let threads = std::env::var("RAYON_NUM_THREADS")
            .unwrap_or_else(|_| std::thread::available_parallelism().map_or(1, |n| n.get()).to_string());
        println!("CPU: {} ({threads} threads for flex); wgpu adapter: {adapter}", cpu_model());
        println!("training: B = {B}, T = {T}, dropout 0, mean of {} steps after 1 warm-up, s/step", o.steps);
        println!("{:<6} {:>6} {:>12} {:>12}", "device", "width", "ae+regr s", "stylizer s");
        let devices = [("cpu", Device::flex()), ("wgpu", gpu)];
        let mut json = Vec::new();
        for &w in &o.widths {
            for (name, device) in &devices {
                let (ae_s, st_s) = train_steps(device, w, o.steps)?;
                println!("{name:<6} {w:>6} {ae_s:>12.3} {st_s:>12.3}");
                json.push(format!(
                    "{{\"device\":\"{name}\",\"width\":{w},\"ae_step_s\":{ae_s:.4},\"stylizer_step_s\":{st_s:.4}}}"
                ));
            }
        }
        let content = walk160()?;
        println!(
            "stylization: {} frames, label-based, median of {} after 1 warm-up, ms",
            content.motion.frames(),
            o.repeats
        );
        println!("{:<6} {:>10} {:>10}", "device", "1 sample", "10 samples");
        for (name, device) in &devices {
            let (one, ten) = stylize_ms(device, &content, o.repeats)?;
            println!("{name:<6} {one:>10.1} {ten:>10.1}");
            json.push(format!("{{\"device\":\"{name}\",\"stylize_one_ms\":{one:.2},\"stylize_ten_ms\":{ten:.2}}}"));
        }
        println!("{{\"adapter\":{:?},\"results\":[{}]}}", adapter, json.join(","));
        Ok(())
    }
}
