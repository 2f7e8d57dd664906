//! Filmstrips for EVALUATION.md: one content under every style label, each next to a real take of
//! that label, drawn from the side (the walking direction to the right, up is up) with a pose
//! every few frames, as one SVG (text labels, no raster library; GitHub shows it inline).
//!
//! ```text
//! cargo run --release --example filmstrip -- --data data --out assets/eval/filmstrips/walk.svg \
//!     [--content tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh] [--strength 1] [--seed 0] \
//!     [--weights assets/weights]
//! ```
//!
//! Stylized: label-based with the shipped weights (assets/weights, or a candidate's folder), the default temperature, one
//! sample. Real: the first `walk` take of the label in the Bandai-Namco data (set 2 where it has
//! the label, else set 1), cut to the content's length. Poses every `EVERY` frames, each at its
//! own slot, root-relative in the walking direction so that walks and in-place motions read alike.

#[cfg(not(feature = "model"))]
fn main() {
    eprintln!("filmstrip needs `--features model`");
}

#[cfg(feature = "model")]
fn main() {
    if let Err(e) = strip::main() {
        eprintln!("filmstrip: {e:#}");
        std::process::exit(1);
    }
}

#[cfg(feature = "model")]
mod strip {
    use std::fmt::Write as _;
    use std::path::{Path, PathBuf};

    use anyhow::{Context, bail};
    use motion_stylizer::Motion;
    use motion_stylizer::dataset::TakeId;
    use motion_stylizer::dataset::corpus::list_takes;
    use motion_stylizer::skeleton::{self, canonical::PARENTS};
    use motion_stylizer::stylize::{self, Request, StyleSource, Weights};

    /// Frames between two drawn poses (1/3 s at 30 fps).
    const EVERY: usize = 10;
    /// Pixels per cm, horizontal slot per pose, row height.
    const SCALE: f64 = 0.42;
    const SLOT: f64 = 44.0;
    const ROW: f64 = 96.0;
    const LEFT: f64 = 110.0;
    const GAP: f64 = 40.0;

    struct Args {
        data: PathBuf,
        content: PathBuf,
        out: PathBuf,
        weights: PathBuf,
        strength: f32,
        seed: u64,
    }

    fn args() -> anyhow::Result<Args> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut a = Args {
            data: root.join("data"),
            content: root.join("tests/fixtures/bandai/dataset-2_walk_normal_001_f120.bvh"),
            out: root.join("assets/eval/filmstrips/walk.svg"),
            weights: root.join("assets/weights"),
            strength: 1.0,
            seed: 0,
        };
        let mut it = std::env::args().skip(1);
        while let Some(flag) = it.next() {
            let mut value = || it.next().with_context(|| format!("{flag} needs a value"));
            match flag.as_str() {
                "--data" => a.data = value()?.into(),
                "--content" => a.content = value()?.into(),
                "--out" => a.out = value()?.into(),
                "--weights" => a.weights = value()?.into(),
                "--strength" => a.strength = value()?.parse()?,
                "--seed" => a.seed = value()?.parse()?,
                other => bail!("unknown argument {other}"),
            }
        }
        Ok(a)
    }

    fn import(path: &Path) -> anyhow::Result<Motion> {
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
        Ok(skeleton::import_bvh(&text).with_context(|| format!("cannot import {}", path.display()))?.motion)
    }

    /// One motion's poses as SVG path data, its row's top at `top`, slots from `left`.
    fn poses(m: &Motion, left: f64, top: f64) -> String {
        let positions = m.global_positions();
        let mut d = String::new();
        for (slot, frame) in (0..m.frames()).step_by(EVERY).enumerate() {
            let p = &positions[frame];
            let (cx, floor) = (left + SLOT * (slot as f64 + 0.5), top + ROW - 8.0);
            let at = |j: usize| (cx + (p[j].z - p[0].z) * SCALE, floor - p[j].y * SCALE);
            for (j, parent) in PARENTS.iter().enumerate() {
                if let Some(q) = parent {
                    let ((x0, y0), (x1, y1)) = (at(*q), at(j));
                    let _ = write!(d, "M{x0:.1} {y0:.1}L{x1:.1} {y1:.1}");
                }
            }
        }
        d
    }

    pub fn main() -> anyhow::Result<()> {
        let a = args()?;
        let weights = Weights::load_dir(&a.weights)
            .with_context(|| format!("cannot load the weights in {}", a.weights.display()))?;
        let content = import(&a.content)?;
        let takes = list_takes(&a.data).with_context(|| format!("cannot list the takes in {}", a.data.display()))?;
        let real_take = |label: usize| -> Option<&(TakeId, PathBuf)> {
            let walks = |set: u8| {
                takes.iter().filter(move |(t, _)| t.set == set && t.content == "walk" && t.style().index() == label)
            };
            walks(2).min_by_key(|(t, _)| t.take).or_else(|| walks(1).min_by_key(|(t, _)| t.take))
        };

        let slots = content.frames().div_ceil(EVERY) as f64;
        let half = SLOT * slots;
        let styles = weights.styles().to_vec();
        let (width, height) = (LEFT + 2.0 * half + GAP + 10.0, 40.0 + ROW * (styles.len() + 1) as f64);
        let mut svg = String::new();
        let _ = writeln!(
            svg,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" \
             viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"13\">"
        );
        let _ = writeln!(svg, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
        let name = a.content.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let _ = writeln!(
            svg,
            "<text x=\"{LEFT}\" y=\"22\">stylized: label-based, strength {}, guidance {}, seed {}</text>\
             <text x=\"{:.0}\" y=\"22\">a real walk take of the label</text>",
            a.strength,
            stylize::DEFAULT_GUIDANCE,
            a.seed,
            LEFT + half + GAP
        );
        let row = |svg: &mut String, i: usize, label: &str, left: &str, right: Option<(&str, String)>| {
            let top = 30.0 + ROW * i as f64;
            let _ = writeln!(svg, "<text x=\"8\" y=\"{:.0}\" font-weight=\"bold\">{label}</text>", top + ROW / 2.0);
            let _ = writeln!(
                svg,
                "<line x1=\"{LEFT}\" x2=\"{:.0}\" y1=\"{y:.0}\" y2=\"{y:.0}\" stroke=\"#ccc\"/>",
                width - 10.0,
                y = top + ROW - 8.0
            );
            let _ = writeln!(svg, "<path d=\"{left}\" stroke=\"#1f4e9c\" stroke-width=\"1.6\" fill=\"none\"/>");
            if let Some((take, path)) = right {
                let _ = writeln!(svg, "<path d=\"{path}\" stroke=\"#333\" stroke-width=\"1.6\" fill=\"none\"/>");
                let _ = writeln!(
                    svg,
                    "<text x=\"{:.0}\" y=\"{:.0}\" font-size=\"10\" fill=\"#666\">{take}</text>",
                    LEFT + half + GAP,
                    top + 12.0
                );
            }
        };
        row(&mut svg, 0, "content", &poses(&content, LEFT, 30.0), None);
        let _ = writeln!(
            svg,
            "<text x=\"{LEFT}\" y=\"42\" font-size=\"10\" fill=\"#666\">{name} (a pose every {EVERY} frames)</text>"
        );
        for (i, label) in styles.iter().enumerate() {
            let style = weights.style(label)?;
            let request = Request::new(StyleSource::Label(style)).with_seed(a.seed).with_strength(a.strength);
            let out = stylize::stylize(&weights, &content, &request)?.remove(0);
            let top = 30.0 + ROW * (i + 1) as f64;
            let real = match real_take(i) {
                Some((take, path)) => {
                    let m = import(path)?;
                    let m = m.slice(0, m.frames().min(content.frames()));
                    Some((take.stem(), poses(&m, LEFT + half + GAP, top)))
                }
                None => None,
            };
            let right = real.as_ref().map(|(t, p)| (t.as_str(), p.clone()));
            row(&mut svg, i + 1, label, &poses(&out, LEFT, top), right);
            eprintln!("{label}");
        }
        svg.push_str("</svg>\n");
        if let Some(dir) = a.out.parent() {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(&a.out, svg).with_context(|| format!("cannot write {}", a.out.display()))?;
        eprintln!("filmstrip -> {}", a.out.display());
        Ok(())
    }
}
