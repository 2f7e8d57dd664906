//! `bvh-parse-bench FILE.bvh [ITERATIONS]`: parses FILE ITERATIONS times with `Bvh::parse` (after a
//! warm-up), then writes it as many times with `Bvh::to_bvh_string`; prints MB/s and frames/s, and a
//! last line `RESULT ms_per_parse=…` for run.sh. Builds natively and for wasm32-wasip1.
use motion_stylizer::bvh::Bvh;
use std::hint::black_box;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: bvh-parse-bench FILE.bvh [ITERATIONS]");
        std::process::exit(2);
    };
    let iters: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(200);
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let bvh = Bvh::parse(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    let target = if cfg!(target_arch = "wasm32") { "wasm32" } else { "native" };

    for _ in 0..10 {
        black_box(Bvh::parse(black_box(&text)).ok());
    }
    let t0 = Instant::now();
    let mut frames = 0;
    for _ in 0..iters {
        let b = Bvh::parse(black_box(&text)).expect("parses");
        frames += b.frames;
        black_box(&b);
    }
    let parse_s = t0.elapsed().as_secs_f64() / iters as f64;

    let t0 = Instant::now();
    let mut bytes = 0;
    for _ in 0..iters {
        bytes += black_box(&bvh).to_bvh_string().len();
    }
    let write_s = t0.elapsed().as_secs_f64() / iters as f64;

    let mb = text.len() as f64 / 1e6;
    println!(
        "ours ({target}) parse: {} bytes, {} frames × {} channels, {iters} runs: {:.3} ms/parse, {:.0} MB/s, {:.0} frames/s",
        text.len(),
        bvh.frames,
        bvh.num_channels(),
        parse_s * 1e3,
        mb / parse_s,
        (frames / iters) as f64 / parse_s
    );
    println!(
        "ours ({target}) write: {:.3} ms/write, {:.0} MB/s of output",
        write_s * 1e3,
        (bytes / iters) as f64 / 1e6 / write_s
    );
    println!("RESULT ms_per_parse={}", parse_s * 1e3);
}
