//! `motion-stylizer export`: the shipped weights folder from three finished runs (the layout of
//! [`crate::stylize::manifest`]).
//!
//! - `shared.bin`: the autoencoder and regressor both stylizers were trained on (the copy in each
//!   stylizer run's `ae.bin`, so the weights are consistent even if the `ae` run went on training
//!   afterwards; the two copies must be the same checkpoint, or the supervised run's is taken with
//!   a warning), a part file ([`save_part`]).
//! - `supervised.bin`, `unsupervised.bin`: each stylizer run's latest checkpoint, its stylizer
//!   networks only.
//! - Large layers in the [`Encodings`] asked for (default f16; `--shared q8 --stylizer q4g64`...).
//! - `norm.json`: the normalisation statistics (identical in all three runs, or an error).
//! - `manifest.json`: provenance of each bundle, one [`StageRecord`] per stage. The `ae` record
//!   describes the `--ae` run up to the step the stylizer took its autoencoder from: command
//!   line(s) (resumed segments joined by ` && `), steps, seed, batch, window, wall seconds
//!   (prorated to that step if the run went further), seconds per training step, machine; final
//!   losses = means of the last 100 `loss.csv` rows (up to that step) of every loss term and
//!   gradient norm; held-out metrics = the last `eval.csv` row up to that step (its step as
//!   `eval_step`).

use anyhow::{Context, bail, ensure};
use burn::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

use super::ae::AeNets;
use super::rundir::load_module;
use super::rundir::{self, Checkpoint, CsvTable, RunConfig, RunLog};
use crate::dataset::{STYLES, Split};
use crate::features::NormStats;
use crate::model::weights::{PartEncoding, PartKind, SharedNets, float_params, fnv1a64, save_part};
use crate::model::{ModelConfig, MotionModel, Stylizer};
use crate::stylize::manifest::{FORMAT, FileRef, Manifest, ModelEntry, SharedEntry, StageRecord};
use crate::stylize::{Setting, Weights};

/// How the large layers of each file are stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Encodings {
    /// `shared.bin` (autoencoder, regressor).
    pub shared: PartEncoding,
    /// The supervised stylizer's files.
    pub supervised: PartEncoding,
    /// The unsupervised stylizer's files (fetched apart in a browser, so its budget is its own).
    pub unsupervised: PartEncoding,
}

impl Encodings {
    /// `shared` for `shared.bin`, `stylizer` for both stylizers' files.
    pub fn new(shared: PartEncoding, stylizer: PartEncoding) -> Encodings {
        Encodings { shared, supervised: stylizer.clone(), unsupervised: stylizer }
    }

    /// The encoding of a setting's files.
    pub fn stylizer(&self, setting: Setting) -> &PartEncoding {
        match setting {
            Setting::Supervised => &self.supervised,
            Setting::Unsupervised => &self.unsupervised,
        }
    }
}

impl Default for Encodings {
    fn default() -> Self {
        Encodings::new(PartEncoding::F16, PartEncoding::F16)
    }
}

/// The encodings asked of [`repack`] / [`replace_stylizers`]; a file not asked for keeps the
/// encoding the source folder's manifest records for it (f16 where it records none: formats 1 and
/// 2), so a fine-tune of 8-bit weights stays 8-bit and what it does not replace is written again
/// as it was.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EncodingChoice {
    pub shared: Option<PartEncoding>,
    pub supervised: Option<PartEncoding>,
    pub unsupervised: Option<PartEncoding>,
}

impl From<Encodings> for EncodingChoice {
    /// Every file in the given encoding, whatever the folder's.
    fn from(e: Encodings) -> Self {
        EncodingChoice { shared: Some(e.shared), supervised: Some(e.supervised), unsupervised: Some(e.unsupervised) }
    }
}

impl EncodingChoice {
    /// The chosen encodings, `base`'s for the files not chosen.
    pub fn over(self, base: Encodings) -> Encodings {
        Encodings {
            shared: self.shared.unwrap_or(base.shared),
            supervised: self.supervised.unwrap_or(base.supervised),
            unsupervised: self.unsupervised.unwrap_or(base.unsupervised),
        }
    }

    /// The encodings for a folder with `manifest`: the chosen ones, the folder's for the rest.
    fn over_folder(self, manifest: &Manifest) -> anyhow::Result<Encodings> {
        let recorded = |what: &str, spec: Option<&str>| match spec {
            None => Ok(PartEncoding::F16),
            Some(spec) => PartEncoding::parse(spec)
                .with_context(|| format!("the manifest's {what} encoding {spec:?} is not one (f16, q8, q4g64, ...)")),
        };
        let model = |setting: Setting| {
            let entry = manifest.entry(setting);
            recorded(setting.as_str(), entry.and_then(|e| e.encoding.as_deref()))
        };
        let folder = Encodings {
            shared: recorded("shared", manifest.shared.as_ref().map(|s| s.encoding.as_str()))?,
            supervised: model(Setting::Supervised)?,
            unsupervised: model(Setting::Unsupervised)?,
        };
        Ok(self.over(folder))
    }
}

/// Licence of the exported weights.
pub const LICENCE: &str = "CC BY-NC 4.0 (trained on the Bandai-Namco Research Motion dataset); code MIT OR Apache-2.0";

/// Rows of `loss.csv` averaged for the final losses.
const FINAL_ROWS: usize = 100;

/// Licence of weights exported from a folder of the user's own files.
pub const FOLDER_LICENCE: &str = "the licence of the training data (your own files); code MIT OR Apache-2.0";

/// Writes the weights folder `out` from the runs; returns the manifest written.
pub fn export(sup: &Path, unsup: &Path, ae: &Path, out: &Path, encodings: Encodings) -> anyhow::Result<Manifest> {
    export_runs(ae, Some(sup), Some(unsup), out, encodings)
}

/// [`export`] with either stylizer run optional (at least one): a folder without labels has no
/// supervised model. The labels come from the stylizer runs (the Bandai-Namco label set, or a
/// folder's).
pub fn export_runs(
    ae: &Path,
    sup: Option<&Path>,
    unsup: Option<&Path>,
    out: &Path,
    encodings: Encodings,
) -> anyhow::Result<Manifest> {
    ensure!(sup.is_some() || unsup.is_some(), "nothing to export: neither a supervised nor an unsupervised run");
    let ae_config: RunConfig = rundir::read_json(&ae.join(rundir::CONFIG))
        .with_context(|| format!("--ae {}: not a training run folder", ae.display()))?;
    ensure!(ae_config.stage == "ae", "--ae {}: a {} run, not an `ae` run", ae.display(), ae_config.stage);
    let norm: NormStats = rundir::read_json(&ae.join(rundir::NORM))?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;

    let mut models = Vec::new();
    let mut nets = Vec::new();
    let mut window = None;
    let mut split = None;
    let mut ae_weights: Option<Vec<u8>> = None;
    let mut labels: Option<Vec<String>> = None;
    let runs = [("supervised", sup, true), ("unsupervised", unsup, false)];
    for (setting, dir, supervised) in runs.into_iter().filter_map(|(s, d, sup)| d.map(|d| (s, d, sup))) {
        let flag = if supervised { "--sup" } else { "--unsup" };
        let config: RunConfig = rundir::read_json(&dir.join(rundir::CONFIG))
            .with_context(|| format!("{flag} {}: not a training run folder", dir.display()))?;
        ensure!(config.stage == "stylizer", "{flag} {}: a {} run, not a stylizer run", dir.display(), config.stage);
        ensure!(
            config.supervised == Some(supervised) && config.model.supervised == supervised,
            "{flag} {}: not a{} {setting} run",
            dir.display(),
            if supervised { "" } else { "n" }
        );
        let run_norm: NormStats = rundir::read_json(&dir.join(rundir::NORM))?;
        ensure!(
            run_norm == norm,
            "{flag} {}: its normalisation statistics differ from the autoencoder run's",
            dir.display()
        );
        if let Some(w) = window
            && w != config.settings.window
        {
            bail!("the stylizer runs use different windows ({w} and {})", config.settings.window);
        }
        window = Some(config.settings.window);
        split.get_or_insert_with(|| config.split.clone());
        match &labels {
            Some(l) if *l != config.labels() => bail!("the stylizer runs were trained on different label sets"),
            Some(_) => {}
            None => labels = Some(config.labels()),
        }
        let ckpt = Checkpoint::read(&dir.join(rundir::CHECKPOINT))?;
        let ae_ckpt = Checkpoint::read(&dir.join(rundir::AE_COPY))?;
        match &ae_weights {
            Some(w) if *w != ae_ckpt.weights => {
                eprintln!("warning: the two stylizer runs were trained on different autoencoder checkpoints")
            }
            _ => ae_weights = Some(ae_ckpt.weights.clone()),
        }
        if let Some(recorded) = &config.ae_run
            && !same_path(Path::new(recorded), ae)
        {
            eprintln!(
                "warning: {flag} {} was trained on the autoencoder of {recorded}, not of --ae {}",
                dir.display(),
                ae.display()
            );
        }

        let device = Device::flex();
        let ae_nets = load_module(AeNets::new(&config.model, &device), &ae_ckpt.weights)?;
        let stylizer = load_module(Stylizer::new(&config.model, &device), &ckpt.weights)?;
        nets.push((
            config.model.clone(),
            MotionModel { autoencoder: ae_nets.autoencoder, stylizer, regressor: ae_nets.regressor },
        ));

        models.push(ModelEntry {
            setting: setting.into(),
            file: format!("{setting}.bin"),
            bytes: None,
            fnv1a64: None,
            encoding: None,
            style_encoder: None,
            width: config.settings.width,
            stages: vec![stage_record(ae, &ae_config, ae_ckpt.meta.step)?, stage_record(dir, &config, ckpt.meta.step)?],
            // New networks: `motion-stylizer label-codes` computes them for these.
            label_codes: None,
            neutral_code: None,
        });
    }

    let (split, heldout_takes, licence) = match &ae_config.folder {
        Some(folder) => (
            "labels.csv folder: held-out files chosen by dataset::folder".to_string(),
            folder.heldout.len(),
            FOLDER_LICENCE.to_string(),
        ),
        None => {
            let split = split.context("a stylizer run")?;
            let split_text =
                std::fs::read_to_string(&split).with_context(|| format!("cannot read the runs' split file {split}"))?;
            let heldout = Split::parse(&split_text).with_context(|| format!("split file {split}"))?.len();
            (split, heldout, LICENCE.to_string())
        }
    };
    // Fine-tuned weights carry the licence of the weights they started from too.
    let licence = match ae_config.from.as_deref().map(|f| Path::new(f).join("manifest.json")) {
        Some(path) => match rundir::read_json::<Manifest>(&path) {
            Ok(old) if old.licence != licence => format!("{licence}; fine-tuned from weights under: {}", old.licence),
            _ => licence,
        },
        None => licence,
    };
    let manifest = Manifest {
        format: FORMAT,
        licence,
        styles: labels.unwrap_or_else(|| STYLES.iter().map(|s| s.to_string()).collect()),
        norm: rundir::NORM.into(),
        window: window.context("a stylizer run")?,
        split,
        heldout_takes,
        norm_bytes: None,
        norm_fnv1a64: None,
        shared: None,
        models,
    };
    rundir::write_json(&out.join(rundir::NORM), &norm)?;
    write_folder(out, manifest, nets, encodings)
}

/// `motion-stylizer export --from DIR`: an existing weights folder (format 1, 2 or 3) written
/// again in format 3 with `encodings` (the folder's own for the files not chosen): the same provenance and label codes, the statistics file copied
/// byte for byte, one shared file for the networks both settings carry (they must be the same
/// numbers; if not, the supervised model's are shared, with a warning).
pub fn repack(from: &Path, out: &Path, encodings: impl Into<EncodingChoice>) -> anyhow::Result<Manifest> {
    let weights = Weights::load_dir(from).with_context(|| format!("cannot load the weights at {}", from.display()))?;
    let mut manifest = weights.manifest().clone();
    let encodings = encodings.into().over_folder(&manifest)?;
    let norm = std::fs::read(from.join(&manifest.norm)).with_context(|| format!("cannot read {}", manifest.norm))?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    rundir::write_atomic(&out.join(&manifest.norm), &norm)?;
    let mut nets = Vec::new();
    for entry in &manifest.models {
        let setting =
            Setting::from_name(&entry.setting).with_context(|| format!("unknown setting {:?}", entry.setting))?;
        let model = weights.model(setting)?;
        nets.push((model.config.clone(), model.nets.clone()));
    }
    manifest.format = FORMAT;
    write_folder(out, manifest, nets, encodings)
}

/// `motion-stylizer export --from DIR --sup RUN [--unsup RUN]`: the weights folder `from` with
/// the stylizer of each given run (a run fine-tuned from `from` with `train stylizer --from`, so
/// on its autoencoder and regressor: checked, as are the label set and the normalisation
/// statistics) in place of that setting's; the rest as [`repack`]. A replaced model's manifest
/// entry keeps its earlier stages and gains the run's; its label codes are dropped (new
/// networks: `motion-stylizer label-codes` computes them).
pub fn replace_stylizers(
    from: &Path,
    runs: &[(Setting, &Path)],
    out: &Path,
    encodings: impl Into<EncodingChoice>,
) -> anyhow::Result<Manifest> {
    let weights = Weights::load_dir(from).with_context(|| format!("cannot load the weights at {}", from.display()))?;
    let mut manifest = weights.manifest().clone();
    let encodings = encodings.into().over_folder(&manifest)?;
    let mut nets = Vec::new();
    for entry in &manifest.models {
        let setting =
            Setting::from_name(&entry.setting).with_context(|| format!("unknown setting {:?}", entry.setting))?;
        let model = weights.model(setting)?;
        nets.push((setting, model.config.clone(), model.nets.clone()));
    }
    for &(setting, dir) in runs {
        let flag = if setting == Setting::Supervised { "--sup" } else { "--unsup" };
        let config: RunConfig = rundir::read_json(&dir.join(rundir::CONFIG))
            .with_context(|| format!("{flag} {}: not a training run folder", dir.display()))?;
        ensure!(config.stage == "stylizer", "{flag} {}: a {} run, not a stylizer run", dir.display(), config.stage);
        ensure!(
            config.supervised == Some(setting == Setting::Supervised),
            "{flag} {}: not a {setting} run",
            dir.display()
        );
        ensure!(
            config.labels() == manifest.styles,
            "{flag} {}: trained on other labels than {}'s",
            dir.display(),
            from.display()
        );
        let run_norm: NormStats = rundir::read_json(&dir.join(rundir::NORM))?;
        ensure!(
            run_norm == *weights.norm(),
            "{flag} {}: its normalisation statistics differ from {}'s",
            dir.display(),
            from.display()
        );
        let (i, entry) = manifest
            .models
            .iter_mut()
            .enumerate()
            .find(|(_, e)| e.setting == setting.as_str())
            .with_context(|| format!("{} has no {setting} model to replace", from.display()))?;
        let (_, model_config, old) = &nets[i];
        let device = Device::flex();
        let ae_ckpt = Checkpoint::read(&dir.join(rundir::AE_COPY))?;
        let ae_nets = load_module(AeNets::new(&config.model, &device), &ae_ckpt.weights)?;
        let theirs = float_params(&SharedNets { autoencoder: ae_nets.autoencoder, regressor: ae_nets.regressor })?;
        let ours =
            float_params(&SharedNets { autoencoder: old.autoencoder.clone(), regressor: old.regressor.clone() })?;
        ensure!(
            theirs == ours,
            "{flag} {}: trained on another autoencoder than {}'s (fine-tune with `train stylizer --from {}`)",
            dir.display(),
            from.display(),
            from.display()
        );
        let ckpt = Checkpoint::read(&dir.join(rundir::CHECKPOINT))?;
        let stylizer = load_module(Stylizer::new(&config.model, &device), &ckpt.weights)?;
        entry.stages.push(stage_record(dir, &config, ckpt.meta.step)?);
        entry.label_codes = None;
        entry.neutral_code = None;
        let new = MotionModel { stylizer, ..old.clone() };
        // The run's architecture options (the posture path) go with its networks.
        let model_config = model_config.clone().with_content_posture(config.model.content_posture);
        nets[i] = (setting, model_config, new);
    }
    let norm = std::fs::read(from.join(&manifest.norm)).with_context(|| format!("cannot read {}", manifest.norm))?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    rundir::write_atomic(&out.join(&manifest.norm), &norm)?;
    manifest.format = FORMAT;
    write_folder(out, manifest, nets.into_iter().map(|(_, c, n)| (c, n)).collect(), encodings)
}

/// Writes `shared.bin` (from the first model), one stylizer file per entry of `manifest.models`
/// (in the same order as `nets`), then the manifest with every file's size and fingerprint.
fn write_folder(
    out: &Path,
    mut manifest: Manifest,
    nets: Vec<(ModelConfig, MotionModel)>,
    encodings: Encodings,
) -> anyhow::Result<Manifest> {
    ensure!(!nets.is_empty() && nets.len() == manifest.models.len(), "one network set per manifest entry");
    let (first_config, first) = &nets[0];
    let shared = SharedNets { autoencoder: first.autoencoder.clone(), regressor: first.regressor.clone() };
    let reference = float_params(&shared)?;
    for ((_, other), entry) in nets.iter().zip(&manifest.models).skip(1) {
        let theirs =
            float_params(&SharedNets { autoencoder: other.autoencoder.clone(), regressor: other.regressor.clone() })?;
        if theirs != reference {
            eprintln!(
                "warning: the {} model's autoencoder/regressor differ from the {}'s; the {}'s are shared",
                entry.setting, manifest.models[0].setting, manifest.models[0].setting
            );
        }
    }
    let file_ref =
        |file: &str, bytes: &[u8]| FileRef { file: file.into(), bytes: bytes.len() as u64, fnv1a64: fnv1a64(bytes) };
    let norm = std::fs::read(out.join(&manifest.norm)).with_context(|| format!("cannot read {}", manifest.norm))?;
    manifest.norm_bytes = Some(norm.len() as u64);
    manifest.norm_fnv1a64 = Some(fnv1a64(&norm));
    // The posture path is a stylizer's option: the shared part's header leaves it out, so that
    // shared.bin stays byte for byte the same (and cached in browsers) when a stylizer gains it.
    let shared_config = first_config.clone().with_content_posture(false);
    let bytes = save_part(PartKind::Shared, &shared_config, shared, &encodings.shared)?;
    rundir::write_atomic(&out.join("shared.bin"), &bytes)?;
    manifest.shared = Some(SharedEntry {
        file: file_ref("shared.bin", &bytes),
        holds: vec!["autoencoder".into(), "regressor".into()],
        encoding: encodings.shared.name(),
    });
    // Format 3: per setting the networks every mode needs, and its style encoder apart (needed
    // only for reference motions, so a browser fetches it when one is first used).
    for ((config, model), entry) in nets.into_iter().zip(manifest.models.iter_mut()) {
        let (core, style) = model.stylizer.split();
        let setting =
            Setting::from_name(&entry.setting).with_context(|| format!("unknown setting {:?}", entry.setting))?;
        let encoding = encodings.stylizer(setting);
        let file = format!("{}.bin", entry.setting);
        let bytes = save_part(PartKind::StylizerCore, &config, core, encoding)?;
        rundir::write_atomic(&out.join(&file), &bytes)?;
        let r = file_ref(&file, &bytes);
        entry.file = r.file;
        entry.bytes = Some(r.bytes);
        entry.fnv1a64 = Some(r.fnv1a64);
        entry.encoding = Some(encoding.name());
        let file = format!("{}-style.bin", entry.setting);
        let bytes = save_part(PartKind::StyleEncoder, &config, style, encoding)?;
        rundir::write_atomic(&out.join(&file), &bytes)?;
        entry.style_encoder = Some(file_ref(&file, &bytes));
    }
    rundir::write_atomic(&out.join("manifest.json"), manifest.to_json()?.as_bytes())?;
    Ok(manifest)
}

fn same_path(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// How the run in `dir` ran up to `step` (see the module docs).
pub fn stage_record(dir: &Path, config: &RunConfig, step: u64) -> anyhow::Result<StageRecord> {
    let log: RunLog = rundir::read_json(&dir.join(rundir::RUN_LOG))?;
    let (total_steps, wall, per_step) = log.totals();
    let seconds = if total_steps > step && total_steps > 0 { wall * step as f64 / total_steps as f64 } else { wall };

    let losses = CsvTable::read(&dir.join(rundir::LOSS_CSV))?;
    let rows = losses.up_to(step);
    let tail = &rows[rows.len().saturating_sub(FINAL_ROWS)..];
    let mut final_losses = BTreeMap::new();
    for (i, name) in losses.columns.iter().enumerate() {
        if name == "step" || name == "elapsed_s" || name.ends_with("lr") || tail.is_empty() {
            continue;
        }
        let mean = tail.iter().map(|r| r.get(i).copied().unwrap_or(f64::NAN)).sum::<f64>() / tail.len() as f64;
        final_losses.insert(name.clone(), mean);
    }

    let evals = CsvTable::read(&dir.join(rundir::EVAL_CSV))?;
    let mut heldout = BTreeMap::new();
    if let Some(row) = evals.up_to(step).last() {
        for (name, v) in evals.columns.iter().zip(row.iter()) {
            match name.as_str() {
                "step" => {
                    heldout.insert("eval_step".to_string(), *v);
                }
                "elapsed_s" => {}
                _ => {
                    heldout.insert(name.clone(), *v);
                }
            }
        }
    }

    Ok(StageRecord {
        stage: config.stage.clone(),
        command: log.command(),
        steps: step,
        seed: config.settings.seed,
        batch: config.settings.batch,
        window: config.settings.window,
        seconds,
        seconds_per_step: per_step,
        machine: log.machine.clone(),
        final_losses,
        heldout,
    })
}
