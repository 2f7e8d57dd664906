//! Throughput of the import pipeline on a Bandai clip: BVH parse, retarget to the canonical rig at
//! 30 fps, and 260-D features — each stage timed alone and together, in frames per second.
//!
//! `cargo run --release --example pipeline_throughput [FILE.bvh] [REPEATS]`

use motion_stylizer::bvh::Bvh;
use motion_stylizer::{features, skeleton};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| "tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh".into());
    let repeats: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(200);
    let text = std::fs::read_to_string(&path)?;
    let bvh = Bvh::parse(&text)?;
    let motion = skeleton::import(&bvh)?.motion;
    let frames = bvh.frames;
    println!("{path}: {frames} frames, {} bytes, {repeats} repeats", text.len());

    let time = |label: &str, f: &mut dyn FnMut()| {
        f(); // warm-up
        let t = Instant::now();
        for _ in 0..repeats {
            f();
        }
        let s = t.elapsed().as_secs_f64() / repeats as f64;
        println!("{label:<28} {:>9.3} ms/clip {:>12.0} frames/s", s * 1e3, frames as f64 / s);
    };
    time("parse", &mut || {
        std::hint::black_box(Bvh::parse(&text).ok());
    });
    time("retarget (import from Bvh)", &mut || {
        std::hint::black_box(skeleton::import(&bvh).ok());
    });
    time("features", &mut || {
        std::hint::black_box(features::extract(&motion));
    });
    time("parse + retarget + features", &mut || {
        let m = Bvh::parse(&text).ok().and_then(|b| skeleton::import(&b).ok()).map(|i| features::extract(&i.motion));
        std::hint::black_box(m);
    });
    Ok(())
}
