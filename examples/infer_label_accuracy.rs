//! How often `stylize::infer_label` (the supervised model's reconstruction under each label)
//! finds a held-out take's own style label, overall and per style.
//!
//! ```text
//! cargo run --release --example infer_label_accuracy -- data [assets/split/heldout.txt]
//! ```

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("infer_label_accuracy needs `--features model`");
}

#[cfg(feature = "model")]
fn main() -> anyhow::Result<()> {
    use motion_stylizer::dataset::{STYLES, Split};
    use motion_stylizer::eval::load_heldout;
    use motion_stylizer::stylize::{Weights, infer_label};
    use std::path::PathBuf;

    let args: Vec<String> = std::env::args().skip(1).collect();
    let data = PathBuf::from(args.first().map_or("data", String::as_str));
    let split_path = args.get(1).map_or("assets/split/heldout.txt", String::as_str);
    let split = Split::parse(&std::fs::read_to_string(split_path)?)?;
    let weights = Weights::load_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/weights"))?;
    let takes = load_heldout(&data, &split)?;
    let mut per_style = vec![(0usize, 0usize); STYLES.len()];
    for take in &takes {
        let Some(truth) = take.style else { continue };
        let (found, _) = infer_label(&weights, &take.motion)?;
        per_style[truth].0 += usize::from(found.index() == truth);
        per_style[truth].1 += 1;
    }
    let (correct, total) = per_style.iter().fold((0, 0), |(c, t), (a, b)| (c + a, t + b));
    println!("held-out takes: {correct}/{total} = {:.3}", correct as f64 / total.max(1) as f64);
    for (name, (c, t)) in STYLES.iter().zip(&per_style) {
        if *t > 0 {
            println!("  {name:<14} {c}/{t}");
        }
    }
    Ok(())
}
