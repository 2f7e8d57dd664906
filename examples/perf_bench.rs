//! Our side of `make bench-perf` (bench/perf/run.mjs), natively and compiled to wasm32-wasip1 (run
//! in Node's WASI, one thread): times the supervised network at the shipped weights on a 160-frame
//! content clip, and the whole BVH-text-in → BVH-text-out stylization, and optionally writes the
//! network's inputs and outputs for the parity check against PyTorch and onnxruntime.
//!
//! ```text
//! perf_bench WEIGHTS_DIR CONTENT.bvh STYLE.bvh REPEATS [DUMP_DIR]
//! ```
//!
//! The work timed (REPEATS times each, after two warm-up runs of all of it; every time in ms on
//! stdout as JSON):
//! - `net_motion`: supervised motion-based, the style reference's posterior mean with its label
//!   (`old`): encode content and reference, content encoder, style encoder, generator, decoder,
//!   global motion regressor, output read back — exactly the network calls of
//!   `stylize::stylize` (`src/stylize/pipeline.rs`), from normalised features to normalised features;
//! - `net_label1`, `net_label10`: label-based (`old`), 1 and 10 style codes
//!   (`temperature · N(0, I)` from `NoiseRng`, as the pipeline draws them): content encoded once,
//!   then the samples in one batch;
//! - `e2e_motion`, `e2e_label1`, `e2e_label10`: the same requests through `stylize::stylize` from
//!   BVH text (import and retarget) to BVH text on the content's rig.
//!
//! DUMP_DIR gets little-endian f32 files: `content.f32` and `style.f32` (`[1, 260, T]` normalised
//! features), `label1.f32` (`[1, 16]` one-hot), `codes10.f32` (`[10, style_dim]`), `labels10.f32`
//! (`[10, 16]`), `motion_out.f32` (`[1, 260, T]`), `label10_out.f32` (`[10, 260, T]`), and
//! `dims.json`.

use burn::prelude::*;
use motion_stylizer::features::{self, DIM, ROOT_ANG_VEL, View};
use motion_stylizer::model::layers::{channels, one_hot};
use motion_stylizer::model::{Model, NoiseRng};
use motion_stylizer::skeleton;
use motion_stylizer::stylize::{self, DEFAULT_TEMPERATURE, Request, Setting, StyleSource, WeightFiles, Weights};
use std::time::Instant;

type BoxResult<T> = Result<T, Box<dyn std::error::Error>>;

/// Normalised `[1, 260, T]` features of a BVH clip (T must be a multiple of 8: no padding here).
fn features_of(weights: &Weights, text: &str, device: &Device) -> BoxResult<(Tensor<3>, Vec<f32>)> {
    let motion = skeleton::import_bvh(text)?.motion;
    let mut f = features::extract(&motion);
    weights.norm().normalize(&mut f);
    let values = f.view_channels_first(View::Full);
    let t = f.frames();
    if !t.is_multiple_of(8) {
        return Err(format!("{t} frames: the benchmark clips must be a multiple of 8 frames").into());
    }
    Ok((Tensor::from_data(TensorData::new(values.clone(), [1, DIM, t]), device), values))
}

fn read_back(t: Tensor<3>) -> BoxResult<Vec<f32>> {
    t.try_into_vec_as::<f32>().map_err(|e| format!("reading a tensor: {e:?}").into())
}

/// Motion-based: the network calls of `stylize::stylize` with `samples = 1`.
fn net_motion(s: &Model, content: Tensor<3>, style: Tensor<3>, label: usize) -> BoxResult<Vec<f32>> {
    let code = s.content(s.encode(content.clone())?)?;
    let dist = s.style_distribution(s.encode(style)?, Some(&[label]))?;
    let latent = s.generate_with(code, dist.mean, Some(one_hot(&[label], s.config.num_styles, s.device())))?;
    finish(s, content, latent, 1)
}

/// Label-based with the given codes `[N, style_dim]` and one-hot labels `[N, S]`, one batch.
fn net_label(s: &Model, content: Tensor<3>, codes: Tensor<2>, labels: Tensor<2>) -> BoxResult<Vec<f32>> {
    let n = codes.dims()[0];
    let code = s.content(s.encode(content.clone())?)?;
    let latent = s.generate_with(code.repeat_dim(0, n), codes, Some(labels))?;
    finish(s, content, latent, n)
}

/// Decoder, regressor (with the content's angular velocity) and the output assembly, read back.
fn finish(s: &Model, content: Tensor<3>, latent: Tensor<3>, n: usize) -> BoxResult<Vec<f32>> {
    let angular = channels(content, ROOT_ANG_VEL).repeat_dim(0, n);
    read_back(s.with_root(s.decode(latent)?, angular)?)
}

fn write_f32(path: &std::path::Path, values: &[f32]) -> BoxResult<()> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes)?;
    Ok(())
}

/// Median and all times (ms) of `repeats` runs of `f` (after the warm-up of `main`).
fn time(repeats: usize, mut f: impl FnMut() -> BoxResult<()>) -> BoxResult<(f64, Vec<f64>)> {
    let mut ms = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let t = Instant::now();
        f()?;
        ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mut sorted = ms.clone();
    sorted.sort_by(f64::total_cmp);
    Ok((sorted[sorted.len() / 2], ms))
}

fn main() -> BoxResult<()> {
    motion_stylizer::memory::keep_freed_memory();
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err("usage: perf_bench WEIGHTS_DIR CONTENT.bvh STYLE.bvh REPEATS [DUMP_DIR]".into());
    }
    let dir = std::path::Path::new(&args[0]);
    let content_text = std::fs::read_to_string(&args[1])?;
    let style_text = std::fs::read_to_string(&args[2])?;
    let repeats: usize = args[3].parse()?;
    let dump = args.get(4).map(std::path::PathBuf::from);

    let t = Instant::now();
    let read = |name: &str| std::fs::read(dir.join(name));
    // Formats 2 and 3: the shared networks' file beside the supervised stylizer's (format 1:
    // none); format 3: the style encoder in a file of its own.
    let shared = read("shared.bin").ok();
    let supervised_style = read("supervised-style.bin").ok();
    let (manifest, norm, supervised) = (read("manifest.json")?, read("norm.json")?, read("supervised.bin")?);
    let mut weights = Weights::from_files(WeightFiles {
        manifest: &manifest,
        norm: &norm,
        shared: shared.as_deref(),
        supervised: Some(&supervised),
        supervised_style: supervised_style.as_deref(),
        ..Default::default()
    })?;
    // As the CLI and the package load them: inference only (the upsampling layers' folded taps).
    weights.prepare_for_inference();
    let load_ms = t.elapsed().as_secs_f64() * 1e3;
    let s = weights.model(Setting::Supervised)?;
    let device = s.device().clone();
    let old = weights.style("old")?;
    let label = old.index();
    let num_styles = s.config.num_styles;

    let (content, content_values) = features_of(&weights, &content_text, &device)?;
    let (style, style_values) = features_of(&weights, &style_text, &device)?;
    let frames = content.dims()[2];
    let draw = |n: usize| {
        let mut rng = NoiseRng::new(7);
        rng.normals(n * s.config.style_dim).into_iter().map(|v| v * DEFAULT_TEMPERATURE).collect::<Vec<f32>>()
    };
    let codes = |n: usize| Tensor::<2>::from_data(TensorData::new(draw(n), [n, s.config.style_dim]), &device);
    let labels = |n: usize| one_hot(&vec![label; n], num_styles, &device);

    if let Some(dump) = &dump {
        std::fs::create_dir_all(dump)?;
        write_f32(&dump.join("content.f32"), &content_values)?;
        write_f32(&dump.join("style.f32"), &style_values)?;
        write_f32(&dump.join("label1.f32"), &read_back(labels(1).unsqueeze_dim(0))?)?;
        write_f32(&dump.join("codes10.f32"), &draw(10))?;
        write_f32(&dump.join("labels10.f32"), &read_back(labels(10).unsqueeze_dim(0))?)?;
        write_f32(&dump.join("motion_out.f32"), &net_motion(s, content.clone(), style.clone(), label)?)?;
        write_f32(&dump.join("label10_out.f32"), &net_label(s, content.clone(), codes(10), labels(10))?)?;
        std::fs::write(
            dump.join("dims.json"),
            format!(
                "{{\"frames\":{frames},\"features\":{DIM},\"style_dim\":{},\"num_styles\":{num_styles},\"label\":{label}}}",
                s.config.style_dim
            ),
        )?;
    }

    // BVH text in (the content, and the reference for motion-based) → BVH text out.
    let e2e = |by_motion: bool, samples: usize| -> BoxResult<()> {
        let content = skeleton::import_bvh(&content_text)?;
        let reference = if by_motion { Some(skeleton::import_bvh(&style_text)?) } else { None };
        let source = match &reference {
            Some(r) => StyleSource::Motion { motion: &r.motion, label: Some(old) },
            None => StyleSource::Label(old),
        };
        let request = Request::new(source).with_samples(samples).with_seed(7);
        let texts: Vec<String> = stylize::stylize(&weights, &content.motion, &request)?
            .iter()
            .map(|m| content.rig.from_canonical(m).to_bvh_string())
            .collect();
        std::hint::black_box(texts);
        Ok(())
    };
    // Warm-up: every piece of work twice before any is timed (in wasm, V8 first runs baseline
    // code and tiers hot functions up to optimised code in the background).
    for _ in 0..2 {
        net_motion(s, content.clone(), style.clone(), label)?;
        net_label(s, content.clone(), codes(10), labels(10))?;
        e2e(true, 1)?;
        e2e(false, 10)?;
    }
    let (net_motion_ms, net_motion_all) =
        time(repeats, || net_motion(s, content.clone(), style.clone(), label).map(drop))?;
    let (net_label1_ms, net_label1_all) =
        time(repeats, || net_label(s, content.clone(), codes(1), labels(1)).map(drop))?;
    let (net_label10_ms, net_label10_all) =
        time(repeats, || net_label(s, content.clone(), codes(10), labels(10)).map(drop))?;

    let (e2e_motion_ms, e2e_motion_all) = time(repeats, || e2e(true, 1))?;
    let (e2e_label1_ms, e2e_label1_all) = time(repeats, || e2e(false, 1))?;
    let (e2e_label10_ms, e2e_label10_all) = time(repeats, || e2e(false, 10))?;

    let list = |v: &[f64]| v.iter().map(|x| format!("{x:.3}")).collect::<Vec<_>>().join(",");
    println!(
        "{{\"frames\":{frames},\"load_ms\":{load_ms:.2},\
         \"net_motion_ms\":{net_motion_ms:.3},\"net_label1_ms\":{net_label1_ms:.3},\"net_label10_ms\":{net_label10_ms:.3},\
         \"e2e_motion_ms\":{e2e_motion_ms:.3},\"e2e_label1_ms\":{e2e_label1_ms:.3},\"e2e_label10_ms\":{e2e_label10_ms:.3},\
         \"all\":{{\"net_motion\":[{}],\"net_label1\":[{}],\"net_label10\":[{}],\"e2e_motion\":[{}],\"e2e_label1\":[{}],\"e2e_label10\":[{}]}}}}",
        list(&net_motion_all),
        list(&net_label1_all),
        list(&net_label10_all),
        list(&e2e_motion_all),
        list(&e2e_label1_all),
        list(&e2e_label10_all),
    );
    Ok(())
}
