//! Native side of the wasm benchmark (`bench/wasm/run.mjs`, `make bench-wasm`): times one
//! stylization of CONTENT (label-based, supervised, output BVH text on the content's rig) with 1
//! and with 10 samples, after one warm-up; prints one JSON line of median and best milliseconds.
//!
//! `cargo run --release --example stylize_bench -- CONTENT.bvh [REPEATS]` (threads: RAYON_NUM_THREADS)

use motion_stylizer::skeleton;
use motion_stylizer::stylize::{self, Request, StyleSource, Weights};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    motion_stylizer::memory::keep_freed_memory();
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: stylize_bench CONTENT.bvh [REPEATS]")?;
    let repeats: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(5);
    let t = Instant::now();
    let mut weights = Weights::load_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/weights"))?;
    weights.prepare_for_inference(); // as the CLI and the package load them
    let load_ms = t.elapsed().as_secs_f64() * 1e3;
    let content = skeleton::import_bvh(&std::fs::read_to_string(&path)?)?;
    let old = weights.style("old")?;

    // (median, best) of `repeats` runs after a warm-up.
    let time = |samples: usize| -> Result<(f64, f64), Box<dyn std::error::Error>> {
        let request = Request::new(StyleSource::Label(old)).with_samples(samples).with_seed(7);
        let once = || -> Result<f64, Box<dyn std::error::Error>> {
            let t = Instant::now();
            let texts: Vec<String> = stylize::stylize(&weights, &content.motion, &request)?
                .iter()
                .map(|m| content.rig.from_canonical(m).to_bvh_string())
                .collect();
            std::hint::black_box(texts);
            Ok(t.elapsed().as_secs_f64() * 1e3)
        };
        once()?;
        let mut ms = (0..repeats).map(|_| once()).collect::<Result<Vec<_>, _>>()?;
        ms.sort_by(f64::total_cmp);
        Ok((ms[ms.len() / 2], ms[0]))
    };
    let (one, one_best) = time(1)?;
    let (ten, ten_best) = time(10)?;
    println!(
        "{{\"frames\":{},\"load_ms\":{load_ms:.1},\"one_ms\":{one:.2},\"ten_ms\":{ten:.2},\"one_best_ms\":{one_best:.2},\"ten_best_ms\":{ten_best:.2}}}",
        content.motion.frames()
    );
    Ok(())
}
