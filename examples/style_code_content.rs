//! Does a model's style code carry the take's content? Encodes training takes (all
//! of set 1, every `STRIDE`-th of set 2) and reports, by nearest centroid (leave one out):
//! the content class from the codes of `normal` takes, the content class from the codes of every
//! style's takes against the `normal` centroids, and the style from the codes as they are and
//! with their content's `normal` centroid taken away.
//!
//! ```text
//! cargo run --release --example style_code_content -- data [STRIDE] [CENTROIDS_OUT.json or -] [supervised|unsupervised] [DIRECTIONS_OUT.json]
//! ```
//!
//! The unsupervised model by default; `supervised`: the supervised one, each take encoded under
//! its own label.

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("style_code_content needs `--features model`");
}

#[cfg(feature = "model")]
fn main() -> anyhow::Result<()> {
    use motion_stylizer::dataset::{STYLES, Split, content_class};
    use motion_stylizer::eval::import_takes;
    use motion_stylizer::stylize::{Setting, Weights, style_code_of};
    use std::path::PathBuf;

    let args: Vec<String> = std::env::args().skip(1).collect();
    let data = PathBuf::from(args.first().map_or("data", String::as_str));
    let stride: u32 = args.get(1).map_or(Ok(4), |s| s.parse())?;
    let supervised = args.get(3).is_some_and(|s| s == "supervised");
    let split = Split::parse(&std::fs::read_to_string("assets/split/heldout.txt")?)?;
    let weights = Weights::load_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/weights"))?;
    let imported = import_takes(&data, 2, |t| !split.is_heldout(t) && (t.set == 1 || t.take % stride == 0))?;
    // (content class, style, code)
    let mut rows: Vec<(usize, usize, Vec<f32>)> = Vec::new();
    let mut sets: Vec<u8> = Vec::new();
    for (take, motion) in &imported {
        let (Ok(motion), Some(content)) = (motion, content_class(&take.content)) else { continue };
        let code = if supervised {
            style_code_of(&weights, Setting::Supervised, motion, Some(take.style()))?
        } else {
            style_code_of(&weights, Setting::Unsupervised, motion, None)?
        };
        rows.push((content, take.style().index(), code));
        sets.push(take.set);
    }
    let normal = STYLES.iter().position(|s| *s == "normal").unwrap_or(0);
    eprintln!("{} takes encoded", rows.len());
    let dim = rows[0].2.len();
    let dist = |a: &[f32], b: &[f64]| a.iter().zip(b).map(|(x, y)| (f64::from(*x) - y).powi(2)).sum::<f64>();
    // Centroids of `key` over `rows` selected by `keep`, leaving out row `skip`.
    let centroids = |key: &dyn Fn(&(usize, usize, Vec<f32>)) -> usize,
                     keep: &dyn Fn(&(usize, usize, Vec<f32>)) -> bool,
                     codes: &[Vec<f32>],
                     skip: Option<usize>,
                     n: usize| {
        let mut sums = vec![vec![0.0f64; dim]; n];
        let mut counts = vec![0usize; n];
        for (i, r) in rows.iter().enumerate() {
            if Some(i) == skip || !keep(r) {
                continue;
            }
            for (s, v) in sums[key(r)].iter_mut().zip(&codes[i]) {
                *s += f64::from(*v);
            }
            counts[key(r)] += 1;
        }
        for (s, c) in sums.iter_mut().zip(&counts) {
            for v in s.iter_mut() {
                *v /= (*c).max(1) as f64;
            }
        }
        (sums, counts)
    };
    let nearest = |code: &[f32], cents: &(Vec<Vec<f64>>, Vec<usize>)| {
        (0..cents.0.len())
            .filter(|&k| cents.1[k] > 0)
            .min_by(|&a, &b| dist(code, &cents.0[a]).total_cmp(&dist(code, &cents.0[b])))
            .unwrap_or(0)
    };
    let codes: Vec<Vec<f32>> = rows.iter().map(|r| r.2.clone()).collect();
    let n_content = motion_stylizer::dataset::CONTENTS.len();
    let by_content = |r: &(usize, usize, Vec<f32>)| r.0;
    let by_style = |r: &(usize, usize, Vec<f32>)| r.1;
    let is_normal = |r: &(usize, usize, Vec<f32>)| r.1 == normal;
    let all = |_: &(usize, usize, Vec<f32>)| true;
    // 1. Content of normal takes from normal centroids (leave one out).
    let (mut ok, mut n) = (0, 0);
    for (i, r) in rows.iter().enumerate().filter(|(_, r)| r.1 == normal) {
        let c = centroids(&by_content, &is_normal, &codes, Some(i), n_content);
        ok += usize::from(nearest(&r.2, &c) == r.0);
        n += 1;
    }
    println!("content of normal takes from normal centroids: {ok}/{n} = {:.3}", ok as f64 / n as f64);
    // 2. Content of other styles' takes from the normal centroids.
    let c = centroids(&by_content, &is_normal, &codes, None, n_content);
    let (mut ok, mut n) = (0, 0);
    for r in rows.iter().filter(|r| r.1 != normal) {
        ok += usize::from(nearest(&r.2, &c) == r.0);
        n += 1;
    }
    println!("content of styled takes from normal centroids: {ok}/{n} = {:.3}", ok as f64 / n as f64);
    if let Some(out) = args.get(2).filter(|s| *s != "-") {
        let kept: Vec<&Vec<f64>> = c.0.iter().zip(&c.1).filter(|(_, n)| **n > 0).map(|(v, _)| v).collect();
        std::fs::write(out, serde_json::to_string(&kept)?)?;
        eprintln!("{} normal centroids -> {out}", kept.len());
    }
    // 3. Style, raw codes vs codes minus their content's normal centroid (leave one out).
    for (name, residual) in [("raw codes", false), ("minus content's normal centroid", true)] {
        let resid: Vec<Vec<f32>> = rows
            .iter()
            .map(|r| {
                if residual {
                    r.2.iter().zip(&c.0[r.0]).map(|(v, m)| (f64::from(*v) - m) as f32).collect()
                } else {
                    r.2.clone()
                }
            })
            .collect();
        let (mut ok, mut n) = (0, 0);
        let mut per = vec![(0usize, 0usize); STYLES.len()];
        for (i, r) in rows.iter().enumerate() {
            let s = centroids(&by_style, &all, &resid, Some(i), STYLES.len());
            let hit = nearest(&resid[i], &s) == r.1;
            ok += usize::from(hit);
            n += 1;
            per[r.1].0 += usize::from(hit);
            per[r.1].1 += 1;
        }
        let mean_per: f64 = per.iter().filter(|p| p.1 > 0).map(|p| p.0 as f64 / p.1 as f64).sum::<f64>()
            / per.iter().filter(|p| p.1 > 0).count() as f64;
        println!(
            "style by nearest centroid, {name}: {ok}/{n} = {:.3} (mean per style {mean_per:.3})",
            ok as f64 / n as f64
        );
    }
    // Each style's direction in code space, paired by content: per (set, content) with takes of
    // the style and of `normal`, the mean code of the style's takes minus the `normal` takes';
    // averaged over those contents (what the kinematic style direction does with descriptors).
    if let Some(out) = args.get(4) {
        let mut deltas = Vec::with_capacity(STYLES.len());
        for style in 0..STYLES.len() {
            let mut sum = vec![0.0f64; dim];
            let mut pairs = 0usize;
            for set in [1u8, 2] {
                for content in 0..n_content {
                    let mean = |st: usize| {
                        let mut m = vec![0.0f64; dim];
                        let mut k = 0usize;
                        for (r, s) in rows.iter().zip(&sets) {
                            if *s == set && r.0 == content && r.1 == st {
                                for (a, v) in m.iter_mut().zip(&r.2) {
                                    *a += f64::from(*v);
                                }
                                k += 1;
                            }
                        }
                        (k > 0).then(|| m.into_iter().map(|v| v / k as f64).collect::<Vec<f64>>())
                    };
                    if let (Some(a), Some(b)) = (mean(style), mean(normal)) {
                        for ((s, x), y) in sum.iter_mut().zip(&a).zip(&b) {
                            *s += x - y;
                        }
                        pairs += 1;
                    }
                }
            }
            eprintln!("{}: {pairs} contents", STYLES[style]);
            deltas.push(sum.into_iter().map(|v| (v / pairs.max(1) as f64) as f32).collect::<Vec<f32>>());
        }
        std::fs::write(out, serde_json::to_string(&deltas)?)?;
        eprintln!("style directions -> {out}");
    }
    Ok(())
}
