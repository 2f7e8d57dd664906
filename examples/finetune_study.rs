//! Fine-tuning study (issue 18): what a new label learnt from a few clips gives, and what
//! fine-tuning costs the old labels.
//!
//! ```text
//! # 1. a folder of N takes of a style the weights do not know, with their `normal` originals
//! cargo run --release --features model --example finetune_study -- make --data data --clips 5 --out runs/ft5/data
//! # 2. fine-tune (README, "Train on your own data"); --from needs the classifier beside the weights
//! motion-stylizer train all --data runs/ft5/data --out runs/ft5 --from runs/ft-from --steps 300
//! # 3. per-label style shift and accuracy, before (the --from weights) and after
//! cargo run --release --features model --example finetune_study -- measure --data data \
//!     --weights runs/ft5/weights --classifier assets/eval/classifier.bin --json runs/ft5/after.json
//! ```
//!
//! **The new style** (`lean-back`) is made from real `normal` takes by a fixed change of posture
//! that no Bandai-Namco style has: the spine and chest tilted back by 10° each, the upper arms
//! held 30° out from the body. Being a function of the take, its real "takes" are known for every
//! content, so its direction is measured as the others' are ([`Directions::from_takes`]: its takes
//! minus the `normal` takes of the same content). `make` picks `--clips` `normal` takes of the
//! training split (set 2, one content after another, so five clips are five contents) and writes
//! each with its `lean-back` version and a `labels.csv` (`file,style,content`); `--rehearse K`
//! adds the K longest training takes of every other label (what a user who has the old data can
//! add so that the old labels keep being trained).
//!
//! **Measured** on the held-out takes (`--limit` of them, evenly spaced): for every label of the
//! weights, label-based stylization (one sample, seeds 0..`--repeats`), its style shift towards
//! the label (directions from every take of the data plus the `lean-back` versions of the
//! `normal` ones) and the classifier's accuracy (`--classifier`: the shipped one knows the old
//! labels only; the fine-tuned run's `classifier.bin` knows the new one too). Prints a table and
//! writes JSON.

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("finetune_study needs `--features model`");
}

#[cfg(feature = "model")]
fn main() {
    if let Err(e) = study::main() {
        eprintln!("finetune_study: {e:#}");
        std::process::exit(1);
    }
}

#[cfg(feature = "model")]
mod study {
    use std::collections::BTreeMap;
    use std::fmt::Write as _;
    use std::path::{Path, PathBuf};

    use anyhow::{Context, bail};
    use glam::DQuat;
    use motion_stylizer::Motion;
    use motion_stylizer::dataset::corpus::list_takes;
    use motion_stylizer::dataset::labels::{STYLES, Style};
    use motion_stylizer::dataset::{Split, TakeId};
    use motion_stylizer::eval::classify::Judge;
    use motion_stylizer::eval::shift::{Directions, Take, descriptors};
    use motion_stylizer::skeleton::{self, canonical::joint::*};
    use motion_stylizer::stylize::{self, Request, StyleSource, Weights};

    /// The new style's name.
    pub const NEW_STYLE: &str = "lean-back";

    /// The `lean-back` version of `m`: spine and chest tilted back 10° each (about the joints'
    /// lateral axis; +x tilts forward on the canonical rig, whose T-pose faces +z), the upper arms
    /// 30° further out from the body (about the forward axis, in the shoulder's frame).
    pub fn lean_back(m: &Motion) -> Motion {
        let back = DQuat::from_rotation_x(-10f64.to_radians());
        let (out_l, out_r) = (DQuat::from_rotation_z(30f64.to_radians()), DQuat::from_rotation_z(-30f64.to_radians()));
        let rotations = m
            .rotations()
            .iter()
            .map(|pose| {
                let mut p = *pose;
                p[SPINE] = p[SPINE] * back;
                p[CHEST] = p[CHEST] * back;
                p[UPPER_ARM_L] = out_l * p[UPPER_ARM_L];
                p[UPPER_ARM_R] = out_r * p[UPPER_ARM_R];
                p
            })
            .collect();
        Motion::new(m.root_positions().to_vec(), rotations).expect("rotations of a valid motion stay finite")
    }

    fn import(path: &Path) -> anyhow::Result<Motion> {
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
        Ok(skeleton::import_bvh(&text).with_context(|| format!("cannot import {}", path.display()))?.motion)
    }

    fn flag<'a>(args: &'a [String], name: &str) -> Option<&'a str> {
        args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).map(String::as_str)
    }

    fn number<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> anyhow::Result<T> {
        match flag(args, name) {
            None => Ok(default),
            Some(v) => v.parse().map_err(|_| anyhow::anyhow!("{name} {v}: not a number")),
        }
    }

    fn split(args: &[String]) -> anyhow::Result<Split> {
        let path = flag(args, "--split").unwrap_or(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/split/heldout.txt"));
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {path}"))?;
        Ok(Split::parse(&text)?)
    }

    pub fn main() -> anyhow::Result<()> {
        let args: Vec<String> = std::env::args().skip(1).collect();
        let data = PathBuf::from(flag(&args, "--data").unwrap_or("data"));
        match args.first().map(String::as_str) {
            Some("make") => make(&data, &args),
            Some("measure") => measure(&data, &args),
            _ => bail!("usage: finetune_study make|measure --data DIR [...] (see the file's docs)"),
        }
    }

    /// `make`: the fine-tuning folder.
    fn make(data: &Path, args: &[String]) -> anyhow::Result<()> {
        let clips: usize = number(args, "--clips", 5)?;
        let out = PathBuf::from(flag(args, "--out").context("make needs --out DIR")?);
        let split = split(args)?;
        let takes = list_takes(data).with_context(|| format!("cannot list the takes in {}", data.display()))?;
        let mut by_content: BTreeMap<String, Vec<&(TakeId, PathBuf)>> = BTreeMap::new();
        for t in takes.iter().filter(|(t, _)| t.set == 2 && t.style().name() == "normal" && !split.is_heldout(t)) {
            by_content.entry(t.0.content.clone()).or_default().push(t);
        }
        // Round-robin over the contents, `walk` first: clip k is the (k / contents)-th take of
        // content k % contents.
        let mut contents: Vec<&String> = by_content.keys().collect();
        contents.sort_by_key(|c| (c.as_str() != "walk", c.as_str()));
        let mut chosen = Vec::new();
        for round in 0.. {
            let before = chosen.len();
            for c in &contents {
                if chosen.len() < clips
                    && let Some(t) = by_content[*c].get(round)
                {
                    chosen.push(*t);
                }
            }
            if chosen.len() == clips || chosen.len() == before {
                break;
            }
        }
        std::fs::create_dir_all(out.join("takes")).with_context(|| format!("cannot create {}", out.display()))?;
        let mut csv = String::from("file,style,content\n");
        for (take, path) in &chosen {
            let m = import(path)?;
            let stem = take.stem();
            for (name, style, motion) in [
                (format!("{stem}.bvh"), "normal", m.clone()),
                (format!("{stem}_{NEW_STYLE}.bvh"), NEW_STYLE, lean_back(&m)),
            ] {
                std::fs::write(out.join("takes").join(&name), motion.to_bvh().to_bvh_string())?;
                let _ = writeln!(csv, "takes/{name},{style},{}", take.content);
            }
        }
        // Rehearsal: `--rehearse K` training-split takes of every other label, as they are (the
        // longest ones: a window is 64 frames).
        let rehearse: usize = number(args, "--rehearse", 0)?;
        if rehearse > 0 {
            let mut by_label: BTreeMap<usize, Vec<(usize, &(TakeId, PathBuf))>> = BTreeMap::new();
            for t in takes.iter().filter(|(t, _)| !split.is_heldout(t) && t.style().name() != "normal") {
                let len = std::fs::metadata(&t.1).map_or(0, |m| m.len() as usize);
                by_label.entry(t.0.style().index()).or_default().push((len, t));
            }
            for group in by_label.values_mut() {
                group.sort_by(|a, b| b.0.cmp(&a.0).then_with(|| a.1.0.stem().cmp(&b.1.0.stem())));
                for (_, (take, path)) in group.iter().take(rehearse) {
                    let name = format!("{}.bvh", take.stem());
                    std::fs::write(out.join("takes").join(&name), import(path)?.to_bvh().to_bvh_string())?;
                    let _ = writeln!(csv, "takes/{name},{},{}", take.style().name(), take.content);
                }
            }
        }
        std::fs::write(out.join("labels.csv"), &csv)?;
        eprintln!("{} clips of {NEW_STYLE} (and their normal takes) in {}", chosen.len(), out.display());
        print!("{csv}");
        Ok(())
    }

    /// `measure`: per-label shift and accuracy on the held-out takes.
    fn measure(data: &Path, args: &[String]) -> anyhow::Result<()> {
        let weights_dir =
            PathBuf::from(flag(args, "--weights").unwrap_or(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/weights")));
        let classifiers: Vec<PathBuf> =
            args.windows(2).filter(|w| w[0] == "--classifier").map(|w| PathBuf::from(&w[1])).collect();
        anyhow::ensure!(!classifiers.is_empty(), "measure needs --classifier FILE (one or more)");
        let limit: usize = number(args, "--limit", 40)?;
        let repeats: u64 = number(args, "--repeats", 2)?;
        let weights =
            Weights::load_dir(&weights_dir).with_context(|| format!("cannot load {}", weights_dir.display()))?;
        // Each classifier's label set: the weights' first `num_styles()` labels (a classifier
        // trained before the fine-tune knows only the old ones).
        let judges = classifiers
            .iter()
            .map(|c| {
                let bytes = std::fs::read(c).with_context(|| format!("cannot read {}", c.display()))?;
                Ok(Judge::from_bytes(&bytes, weights.norm().clone())?)
            })
            .collect::<anyhow::Result<Vec<Judge>>>()?;
        let labels: Vec<String> = weights.styles().to_vec();
        let split = split(args)?;

        // Directions: every take of the data, and the lean-back version of every normal take.
        let takes = list_takes(data).with_context(|| format!("cannot list the takes in {}", data.display()))?;
        let new_index = STYLES.len();
        let mut real = Vec::new();
        let mut heldout = Vec::new();
        eprintln!("importing {} takes", takes.len());
        for (take, path) in &takes {
            let m = import(path)?;
            let style = take.style().index();
            real.push(Take { content: take.content_key(), style, descriptors: descriptors(&m) });
            if take.style().name() == "normal" {
                real.push(Take {
                    content: take.content_key(),
                    style: new_index,
                    descriptors: descriptors(&lean_back(&m)),
                });
            }
            if split.is_heldout(take) {
                heldout.push((take.stem(), m));
            }
        }
        // The old labels' directions from the real takes only (as `eval` has them); lean-back's
        // from the real takes and the lean-back versions.
        let normal = 0;
        let old_directions =
            Directions::from_takes(&real.iter().filter(|t| t.style != new_index).cloned().collect::<Vec<_>>(), normal);
        let new_directions = Directions::from_takes(&real, normal);
        if let Some(d) = new_directions.get(new_index) {
            eprintln!(
                "{NEW_STYLE}: direction {:.2} spreads, {:?}",
                d.length,
                d.vector.iter().map(|v| (v * 100.0).round() / 100.0).collect::<Vec<_>>()
            );
        }
        let chosen: Vec<&(String, Motion)> = if limit == 0 || limit >= heldout.len() {
            heldout.iter().collect()
        } else {
            (0..limit).map(|i| &heldout[i * heldout.len() / limit]).collect()
        };

        let mut rows = Vec::new();
        let mut table = format!(
            "| label | direction (spreads) | shift |{}\n|---|---:|---:|{}\n",
            classifiers.iter().map(|c| format!(" accuracy ({}) |", c.display())).collect::<String>(),
            "---:|".repeat(classifiers.len())
        );
        for (i, label) in labels.iter().enumerate() {
            let style = weights.style(label)?;
            // The label's index among the directions: Bandai's for the old labels, one past them for
            // lean-back.
            let (dir_index, directions) = match Style::from_name(label) {
                Some(s) => (s.index(), &old_directions),
                None => (new_index, &new_directions),
            };
            let (mut shifts, mut hits, mut n) = (Vec::new(), vec![0usize; judges.len()], 0usize);
            for (c, (_, content)) in chosen.iter().enumerate() {
                let d_content = descriptors(content);
                for r in 0..repeats {
                    let request = Request::new(StyleSource::Label(style)).with_seed(r * 1000 + c as u64);
                    let out = stylize::stylize(&weights, content, &request)?.remove(0);
                    if let Some(s) = directions.shift(dir_index, &d_content, &descriptors(&out)) {
                        shifts.push(s);
                    }
                    for (judge, hits) in judges.iter().zip(&mut hits) {
                        *hits += usize::from(i < judge.num_styles() && judge.judge(&out).predicted == i);
                    }
                    n += 1;
                }
            }
            let shift = (!shifts.is_empty()).then(|| shifts.iter().sum::<f64>() / shifts.len() as f64);
            let accuracy: Vec<Option<f64>> = judges
                .iter()
                .zip(&hits)
                .map(|(j, &h)| (n > 0 && i < j.num_styles()).then(|| h as f64 / n as f64))
                .collect();
            let length = directions.get(dir_index).map(|d| d.length);
            let fmt = |v: Option<f64>, p: usize| v.map_or("–".to_string(), |v| format!("{v:.p$}"));
            let accuracies: String = accuracy.iter().map(|a| format!(" {} |", fmt(*a, 3))).collect();
            let _ = writeln!(table, "| {label} | {} | {} |{accuracies}", fmt(length, 2), fmt(shift, 2));
            eprintln!("{label}: shift {} accuracy{accuracies}", fmt(shift, 3));
            rows.push(serde_json::json!({"label": label, "direction": length, "shift": shift, "accuracy": accuracy}));
        }
        // The old labels' means (shift over the scored ones).
        let old_rows: Vec<&serde_json::Value> =
            rows.iter().filter(|r| Style::from_name(r["label"].as_str().unwrap_or("")).is_some()).collect();
        let mean_of = |f: &dyn Fn(&serde_json::Value) -> Option<f64>| {
            let v: Vec<f64> = old_rows.iter().filter_map(|r| f(r)).collect();
            (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
        };
        let fmt = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.3}"));
        let _ = write!(table, "| old labels' mean | | {} |", fmt(mean_of(&|r| r["shift"].as_f64())));
        for k in 0..judges.len() {
            let _ = write!(table, " {} |", fmt(mean_of(&|r| r["accuracy"][k].as_f64())));
        }
        table.push('\n');
        print!("{table}");
        if let Some(json) = flag(args, "--json") {
            let value = serde_json::json!({
                "weights": weights_dir, "classifiers": classifiers, "contents": chosen.len(), "repeats": repeats,
                "labels": rows,
            });
            std::fs::write(json, serde_json::to_string_pretty(&value)?)?;
        }
        Ok(())
    }
}
