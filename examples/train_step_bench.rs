//! Seconds per training step, B = 16 clips of T = 160 frames (the paper's batch), for
//! (a) the autoencoder + regressor stage and (b) the stylizer stage, at several width factors, on
//! the CPU backends compiled in.
//!
//! ```text
//! cargo run --release --features model --example train_step_bench [-- --steps 3 --widths 1,0.5,0.25]
//! cargo run --release --features ndarray --example train_step_bench   # flex and ndarray
//! ```

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("train_step_bench needs `--features model`");
}

#[cfg(feature = "model")]
fn main() {
    bench::main();
}

#[cfg(feature = "model")]
mod bench {
    use std::time::Instant;

    use burn::prelude::*;
    use motion_stylizer::model::{ModelConfig, MotionAutoencoder, NoiseRng};
    use motion_stylizer::train::{AeTrainer, PhaseTimes, StylizerBatch, StylizerTrainer, TrainConfig};

    const B: usize = 16;
    const T: usize = 160;

    fn features(rng: &mut NoiseRng, device: &Device) -> Tensor<3> {
        rng.normal_tensor(B, 260 * T, device).reshape([B, 260, T])
    }

    /// Mean seconds over `steps` timed calls after one warm-up call.
    fn time_steps(steps: usize, mut step: impl FnMut()) -> f64 {
        step();
        let start = Instant::now();
        for _ in 0..steps {
            step();
        }
        start.elapsed().as_secs_f64() / steps as f64
    }

    fn backends() -> Vec<(&'static str, Device)> {
        #[allow(unused_mut)]
        let mut v = vec![("flex", Device::flex())];
        #[cfg(feature = "ndarray")]
        #[allow(deprecated)]
        v.push(("ndarray", Device::ndarray()));
        v
    }

    pub fn main() {
        motion_stylizer::memory::keep_freed_memory();
        let mut steps = 3usize;
        let mut widths = vec![1.0, 0.5, 0.25];
        let args: Vec<String> = std::env::args().skip(1).collect();
        let mut i = 0;
        while i < args.len() {
            match args[i].as_str() {
                "--steps" => steps = args[i + 1].parse().expect("--steps N"),
                "--widths" => widths = args[i + 1].split(',').map(|w| w.parse().expect("--widths 1,0.5")).collect(),
                other => panic!("unknown argument {other}"),
            }
            i += 2;
        }
        println!("B = {B}, T = {T}, {steps} timed steps after 1 warm-up; seconds per step");
        println!("{:<8} {:>6} {:>12} {:>12} {:>10}", "backend", "width", "ae+regr s", "stylizer s", "params M");
        for (name, device) in backends() {
            for &w in &widths {
                let cfg = ModelConfig::scaled(w);
                let mut rng = NoiseRng::new(1);
                let x1 = features(&mut rng, &device);
                let x2 = features(&mut rng, &device);
                let labels: Vec<usize> = (0..B).map(|i| i % cfg.num_styles).collect();

                let mut ae = AeTrainer::new(cfg.clone(), TrainConfig::default(), &device, 1);
                let params = (ae.autoencoder.num_params() + ae.regressor.num_params()) as f64 / 1e6;
                let ae_s = time_steps(steps, || {
                    ae.phases = Some(PhaseTimes::default());
                    ae.step(x1.clone()).unwrap();
                });
                let ae_phases = ae.phases.unwrap_or_default();
                drop(ae);

                let frozen = MotionAutoencoder::new(&cfg, &device);
                let mut st = StylizerTrainer::new(cfg.clone(), TrainConfig::default(), frozen, &device, 2);
                let params = params + st.net.num_params() as f64 / 1e6;
                let batch = StylizerBatch::unpaired(x1.clone(), x2.clone(), Some(labels));
                let st_s = time_steps(steps, || {
                    st.phases = Some(PhaseTimes::default());
                    st.step(&batch).unwrap();
                });
                let st_phases = st.phases.unwrap_or_default();
                println!("{name:<8} {w:>6} {ae_s:>12.3} {st_s:>12.3} {params:>10.2}");
                for (stage, p) in [("ae+regr", ae_phases), ("stylizer", st_phases)] {
                    let n = p.steps.max(1) as f64; // 1: the phases are reset before each step
                    println!(
                        "  {stage:<9} last step: forward {:.3} s, backward {:.3} s, clip {:.3} s, update {:.3} s",
                        p.forward / n,
                        p.backward / n,
                        p.clip / n,
                        p.update / n
                    );
                }
            }
        }
    }
}
