//! [`Weights`]: the shipped-weights folder (see [`super::manifest`]) loaded from bytes, so that the
//! browser can fetch the files and hand them over; [`Weights::load_dir`] reads the folder natively.

use burn::prelude::*;

use super::StylizeError;
use super::manifest::{self, Manifest};
use crate::dataset::Style;
use crate::features::NormStats;
use crate::model::weights::{
    PartKind, SharedNets, bundle_config, fnv1a64, load_bundle, load_shared, load_style_encoder, load_stylizer,
    load_stylizer_core, part_header,
};
use crate::model::{Model, ModelConfig, ModelError, MotionModel, StyleEncoder, Stylizer};

/// Which of the two stylizers (paper §3.4): trained with style labels or without.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Setting {
    /// Style encoder and generator conditioned on the style label: motion-based (with the
    /// reference's label) and label-based stylization.
    #[default]
    Supervised,
    /// No labels anywhere: motion-based and prior-based stylization.
    Unsupervised,
}

impl Setting {
    /// The manifest's name of the setting (`"supervised"`, `"unsupervised"`).
    pub fn as_str(self) -> &'static str {
        match self {
            Setting::Supervised => "supervised",
            Setting::Unsupervised => "unsupervised",
        }
    }

    /// The setting a manifest names, if any.
    pub fn from_name(name: &str) -> Option<Setting> {
        match name {
            "supervised" => Some(Setting::Supervised),
            "unsupervised" => Some(Setting::Unsupervised),
            _ => None,
        }
    }
}

impl core::fmt::Display for Setting {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Largest width (channels) a bundle's config may ask for: far above the paper's 1024, far below
/// an allocation that would abort.
const MAX_WIDTH: usize = 8192;

/// The bytes of a weights folder's files, for [`Weights::from_files`]: `manifest.json`, the
/// statistics, and (formats 2 and 3) the shared networks, with the file of each setting to load
/// now and (format 3) its style encoder's, if it is needed now.
#[derive(Clone, Copy, Debug, Default)]
pub struct WeightFiles<'a> {
    pub manifest: &'a [u8],
    pub norm: &'a [u8],
    /// The shared networks (`shared.bin`) of formats 2 and 3; `None` for format 1.
    pub shared: Option<&'a [u8]>,
    pub supervised: Option<&'a [u8]>,
    pub unsupervised: Option<&'a [u8]>,
    /// Format 3: the style encoders' files (`supervised-style.bin`, `unsupervised-style.bin`),
    /// each with its setting's file; without one, that model serves no reference motion until
    /// [`Weights::add_style_encoder`].
    pub supervised_style: Option<&'a [u8]>,
    pub unsupervised_style: Option<&'a [u8]>,
}

/// The trained models and what goes with them: the manifest, the normalisation statistics and
/// one [`Model`] per loaded setting (format 2: both on the same shared networks, and a setting
/// can be added later, [`Weights::add_setting`]).
#[derive(Debug)]
pub struct Weights {
    manifest: Manifest,
    norm: NormStats,
    /// Format 2: the shared networks (the autoencoder and regressor every setting's model uses).
    shared: Option<(ModelConfig, SharedNets)>,
    device: Device,
    supervised: Option<Model>,
    unsupervised: Option<Model>,
    /// The supervised model's label centres ([`manifest::LabelCodes`]), `num_styles × style_dim`
    /// row-major, checked against the model.
    label_codes: Option<Vec<f32>>,
    /// The unsupervised model's neutral code ([`manifest::NeutralCode`]), `style_dim` numbers,
    /// checked against the model.
    neutral_code: Option<Vec<f32>>,
    /// Whether [`Weights::prepare_for_inference`] was called: models added later get it too.
    inference_only: bool,
}

fn bad(message: impl Into<String>) -> StylizeError {
    StylizeError::BadWeights(message.into())
}

impl Weights {
    /// The weights from the bytes of a format-1 folder's files (`manifest.json`, `norm.json`,
    /// `supervised.bin`, `unsupervised.bin`), on the CPU (`flex`) device: [`Weights::from_files`]
    /// without a shared file.
    pub fn from_bytes(
        manifest_json: &[u8],
        norm_json: &[u8],
        supervised: Option<&[u8]>,
        unsupervised: Option<&[u8]>,
    ) -> Result<Weights, StylizeError> {
        Self::from_files(WeightFiles {
            manifest: manifest_json,
            norm: norm_json,
            supervised,
            unsupervised,
            ..Default::default()
        })
    }

    /// [`Weights::from_bytes`] on a given device.
    pub fn from_bytes_on(
        device: &Device,
        manifest_json: &[u8],
        norm_json: &[u8],
        supervised: Option<&[u8]>,
        unsupervised: Option<&[u8]>,
    ) -> Result<Weights, StylizeError> {
        let files =
            WeightFiles { manifest: manifest_json, norm: norm_json, supervised, unsupervised, ..Default::default() };
        Self::from_files_on(device, files)
    }

    /// The weights from the bytes of the folder's files, on the CPU (`flex`) device. At least one
    /// setting's file is needed (format 2: and the shared one). Errors
    /// ([`StylizeError::BadWeights`]): malformed JSON, a manifest of another format or without
    /// labels, statistics of the wrong size, files that are not ours, of the other setting, not
    /// the size or fingerprint the manifest lists, or whose label count disagrees with it.
    pub fn from_files(files: WeightFiles<'_>) -> Result<Weights, StylizeError> {
        Self::from_files_on(&Device::flex(), files)
    }

    /// [`Weights::from_files`] on a given device.
    pub fn from_files_on(device: &Device, files: WeightFiles<'_>) -> Result<Weights, StylizeError> {
        let manifest = parse_manifest(files.manifest)?;
        check_file(&manifest.norm, manifest.norm_bytes, manifest.norm_fnv1a64.as_deref(), files.norm)?;
        let norm: NormStats = serde_json::from_slice(files.norm).map_err(|e| bad(format!("norm.json: {e}")))?;
        if files.supervised.is_none() && files.unsupervised.is_none() {
            return Err(bad("no model: neither a supervised nor an unsupervised file"));
        }
        let shared = match (&manifest.shared, files.shared) {
            (None, None) => None,
            (None, Some(_)) => return Err(bad("a shared file was given, but the manifest (format 1) lists none")),
            (Some(entry), None) => {
                return Err(bad(format!(
                    "the shared networks' file {} is needed (manifest format 2)",
                    entry.file.file
                )));
            }
            (Some(entry), Some(bytes)) => {
                check_file(&entry.file.file, Some(entry.file.bytes), Some(&entry.file.fnv1a64), bytes)?;
                let (config, nets) =
                    load_shared(bytes, device).map_err(|e| bad(format!("shared file {}: {e}", entry.file.file)))?;
                Some((config, nets))
            }
        };
        let mut weights = Weights {
            manifest,
            norm,
            shared,
            device: device.clone(),
            supervised: None,
            unsupervised: None,
            label_codes: None,
            neutral_code: None,
            inference_only: false,
        };
        for (setting, bytes, style) in [
            (Setting::Supervised, files.supervised, files.supervised_style),
            (Setting::Unsupervised, files.unsupervised, files.unsupervised_style),
        ] {
            if let Some(bytes) = bytes {
                weights.add_setting(setting, bytes)?;
            }
            if let Some(style) = style {
                if bytes.is_none() {
                    return Err(bad(format!(
                        "the {setting} style encoder's file was given without the {setting} file"
                    )));
                }
                weights.add_style_encoder(setting, style)?;
            }
        }
        Ok(weights)
    }

    /// Loads the file of `setting` (the one the manifest lists for it) next to the models already
    /// loaded: the unsupervised model fetched only when it is first used. Format 2 builds it on
    /// the shared networks already loaded; format 1 files are whole bundles. Errors as
    /// [`Weights::from_files`]; on an error nothing changes.
    pub fn add_setting(&mut self, setting: Setting, bytes: &[u8]) -> Result<(), StylizeError> {
        let entry = self.manifest.entry(setting).ok_or(StylizeError::SettingUnavailable { setting })?;
        let context = |e: StylizeError| match e {
            StylizeError::BadWeights(m) => bad(format!("{setting} file {}: {m}", entry.file)),
            other => other,
        };
        let labels = self.manifest.styles.len();
        let mut model = match &self.shared {
            None => {
                check_config(&bundle_header(bytes).map_err(context)?, setting, labels).map_err(context)?;
                // The bundle's f16 tensors are read on flex (which casts them to f32) and the f32
                // networks then moved to the device: burn-ndarray has no f16 tensors and panics on them.
                let (config, model) = load_bundle(bytes, &Device::flex()).map_err(|e| context(e.into()))?;
                Model::new(config, model.to_device(&self.device))
            }
            Some((shared_config, shared)) => {
                check_file(&entry.file, entry.bytes, entry.fnv1a64.as_deref(), bytes).map_err(context)?;
                let (header, _) = part_header(bytes).map_err(|e| context(bad(e.to_string())))?;
                check_config(&header.config, setting, labels).map_err(context)?;
                check_shared_fits(shared_config, &header.config).map_err(context)?;
                let load_error = |e: crate::model::weights::PartError| context(bad(e.to_string()));
                let (config, stylizer, whole) = if entry.style_encoder.is_some() {
                    // Format 3: the style encoder comes from its own file (add_style_encoder);
                    // until then a placeholder the model refuses to use.
                    let (config, core) = load_stylizer_core(bytes, &self.device).map_err(load_error)?;
                    let placeholder = StyleEncoder::new(&config, &self.device);
                    (config, Stylizer::from_parts(core, placeholder), false)
                } else {
                    let (config, stylizer) = load_stylizer(bytes, &self.device).map_err(load_error)?;
                    (config, stylizer, true)
                };
                let nets = MotionModel {
                    autoencoder: shared.autoencoder.clone(),
                    stylizer,
                    regressor: shared.regressor.clone(),
                };
                if whole { Model::new(config, nets) } else { Model::without_style_encoder(config, nets) }
            }
        };
        if setting == Setting::Supervised {
            self.label_codes = match label_codes_of(&self.manifest) {
                Some(codes) => Some(check_label_codes(codes, &model)?),
                None => None,
            };
        } else {
            self.neutral_code = match neutral_code_of(&self.manifest) {
                Some(code) => Some(check_neutral_code(code, &model)?),
                None => None,
            };
        }
        if self.inference_only {
            model.nets.fold_for_inference();
        }
        match setting {
            Setting::Supervised => self.supervised = Some(model),
            Setting::Unsupervised => self.unsupervised = Some(model),
        }
        Ok(())
    }

    /// For weights that only stylize and evaluate (the CLI's `stylize` and `eval`, the wasm
    /// engine), never trained: the upsampling layers' folded taps computed once
    /// ([`MotionModel::fold_for_inference`]), here and for every model loaded later. The networks
    /// then convolve the un-upsampled frames: the same outputs up to float rounding (within 6e-6
    /// of the motion), 8-15 % less time for one to ten samples (`bench/README.md`). Trainers that
    /// start from these weights must not call it.
    pub fn prepare_for_inference(&mut self) {
        self.inference_only = true;
        for model in [self.supervised.as_mut(), self.unsupervised.as_mut()].into_iter().flatten() {
            model.nets.fold_for_inference();
        }
    }

    /// Loads the style encoder of `setting` (format 3: the file the manifest lists as its
    /// `style_encoder`) into that setting's model, loaded before: what motion-based stylization
    /// and label inference need. A no-op where it is loaded (formats 1 and 2 load it with the
    /// model). Errors: [`StylizeError::SettingUnavailable`] (no such model loaded),
    /// [`StylizeError::BadWeights`] (a file that is not this model's style encoder); on an error
    /// nothing changes.
    pub fn add_style_encoder(&mut self, setting: Setting, bytes: &[u8]) -> Result<(), StylizeError> {
        let entry = self.manifest.entry(setting).ok_or(StylizeError::SettingUnavailable { setting })?;
        let model = match setting {
            Setting::Supervised => self.supervised.as_mut(),
            Setting::Unsupervised => self.unsupervised.as_mut(),
        }
        .ok_or(StylizeError::SettingUnavailable { setting })?;
        if model.has_style_encoder() {
            return Ok(());
        }
        let file =
            entry.style_encoder.as_ref().ok_or_else(|| bad(format!("the {setting} entry lists no style encoder")))?;
        let context = |m: String| bad(format!("{setting} style encoder file {}: {m}", file.file));
        check_file(&file.file, Some(file.bytes), Some(&file.fnv1a64), bytes).map_err(|e| match e {
            StylizeError::BadWeights(m) => context(m),
            other => other,
        })?;
        let (header, _) = part_header(bytes).map_err(|e| context(e.to_string()))?;
        if header.part != PartKind::StyleEncoder {
            return Err(context(format!("it holds the {} networks, not the style encoder", header.part)));
        }
        if header.config != model.config {
            return Err(context("its config is not its model's".into()));
        }
        let (_, style_encoder) = load_style_encoder(bytes, model.device()).map_err(|e| context(e.to_string()))?;
        model.set_style_encoder(style_encoder);
        Ok(())
    }

    /// Whether the model of `setting` is loaded with its style encoder (see
    /// [`Weights::add_style_encoder`]).
    pub fn has_style_encoder(&self, setting: Setting) -> bool {
        self.model(setting).is_ok_and(Model::has_style_encoder)
    }

    /// Reads the weights folder `dir` (native builds only): `manifest.json`, the statistics file
    /// it names, the shared networks' file (format 2), and the file of each setting it lists; on
    /// the CPU (`flex`) device.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load_dir(dir: impl AsRef<std::path::Path>) -> Result<Weights, StylizeError> {
        Self::load_dir_on(&Device::flex(), dir)
    }

    /// [`Weights::load_dir`] on a given device (e.g. [`crate::model::device::open`]'s).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load_dir_on(device: &Device, dir: impl AsRef<std::path::Path>) -> Result<Weights, StylizeError> {
        let dir = dir.as_ref();
        let read = |name: &str| {
            let path = dir.join(name);
            std::fs::read(&path)
                .map_err(|e| StylizeError::Read { path: path.display().to_string(), message: e.to_string() })
        };
        let manifest_json = read("manifest.json")?;
        let manifest = parse_manifest(&manifest_json)?;
        let list = manifest.file_list();
        let norm_json = read(&list.norm.file)?;
        let shared = list.shared.as_ref().map(|s| read(&s.file)).transpose()?;
        let (mut supervised, mut unsupervised) = (None, None);
        let (mut supervised_style, mut unsupervised_style) = (None, None);
        for entry in &list.models {
            let (slot, style_slot) = match Setting::from_name(&entry.setting) {
                Some(Setting::Supervised) => (&mut supervised, &mut supervised_style),
                Some(Setting::Unsupervised) => (&mut unsupervised, &mut unsupervised_style),
                None => return Err(bad(format!("the manifest lists an unknown setting {:?}", entry.setting))),
            };
            *slot = Some(read(&entry.file)?);
            *style_slot = entry.style_encoder.as_ref().map(|f| read(&f.file)).transpose()?;
        }
        Self::from_files_on(
            device,
            WeightFiles {
                manifest: &manifest_json,
                norm: &norm_json,
                shared: shared.as_deref(),
                supervised: supervised.as_deref(),
                unsupervised: unsupervised.as_deref(),
                supervised_style: supervised_style.as_deref(),
                unsupervised_style: unsupervised_style.as_deref(),
            },
        )
    }

    /// The settings the manifest lists (loaded or not).
    pub fn listed(&self) -> Vec<Setting> {
        let listed: Vec<Setting> = self.manifest.models.iter().filter_map(|m| Setting::from_name(&m.setting)).collect();
        [Setting::Supervised, Setting::Unsupervised].into_iter().filter(|s| listed.contains(s)).collect()
    }

    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The training set's normalisation statistics.
    pub fn norm(&self) -> &NormStats {
        &self.norm
    }

    /// The style labels, in one-hot order.
    pub fn styles(&self) -> &[String] {
        &self.manifest.styles
    }

    /// The label called `name` (case-insensitive); the error lists the valid ones.
    pub fn style(&self, name: &str) -> Result<Style, StylizeError> {
        self.manifest
            .styles
            .iter()
            .position(|s| s.eq_ignore_ascii_case(name.trim()))
            .map(|i| Style(i as u8))
            .ok_or_else(|| StylizeError::UnknownLabel { name: name.to_string(), valid: self.manifest.styles.clone() })
    }

    /// The name of a label (`None` if out of range).
    pub fn style_name(&self, style: Style) -> Option<&str> {
        self.manifest.styles.get(style.index()).map(String::as_str)
    }

    /// Whether the model of `setting` is loaded.
    pub fn has(&self, setting: Setting) -> bool {
        self.model(setting).is_ok()
    }

    /// The settings loaded.
    pub fn settings(&self) -> Vec<Setting> {
        [Setting::Supervised, Setting::Unsupervised].into_iter().filter(|&s| self.has(s)).collect()
    }

    /// Where label `style`'s real takes sit in the supervised model's style space (the centre
    /// label-based codes are drawn around), if the manifest has the label codes.
    pub fn label_code(&self, style: Style) -> Option<&[f32]> {
        let codes = self.label_codes.as_deref()?;
        let dim = self.supervised.as_ref()?.config.style_dim;
        codes.get(style.index() * dim..(style.index() + 1) * dim)
    }

    /// Where the `normal` training takes sit in the unsupervised model's style space (what
    /// guidance measures a reference's style against), if the manifest has it.
    pub fn neutral_code(&self) -> Option<&[f32]> {
        self.unsupervised.as_ref()?;
        self.neutral_code.as_deref()
    }

    /// The inference model of `setting`.
    pub fn model(&self, setting: Setting) -> Result<&Model, StylizeError> {
        match setting {
            Setting::Supervised => self.supervised.as_ref(),
            Setting::Unsupervised => self.unsupervised.as_ref(),
        }
        .ok_or(StylizeError::SettingUnavailable { setting })
    }
}

/// The supervised entry's label codes, if the manifest has them.
fn label_codes_of(manifest: &Manifest) -> Option<&manifest::LabelCodes> {
    manifest.entry(Setting::Supervised)?.label_codes.as_ref()
}

/// The unsupervised entry's neutral code, if the manifest has it.
fn neutral_code_of(manifest: &Manifest) -> Option<&manifest::NeutralCode> {
    manifest.entry(Setting::Unsupervised)?.neutral_code.as_ref()
}

/// The neutral code after checking it against the model: `style_dim` finite numbers.
fn check_neutral_code(code: &manifest::NeutralCode, model: &Model) -> Result<Vec<f32>, StylizeError> {
    let dim = model.config.style_dim;
    if code.code.len() != dim {
        return Err(bad(format!(
            "the neutral code has {} numbers, not {dim} (the unsupervised model's style size)",
            code.code.len()
        )));
    }
    if code.code.iter().any(|v| !v.is_finite()) {
        return Err(bad("the neutral code holds a number that is not finite"));
    }
    Ok(code.code.clone())
}

/// The label codes flattened, after checking them against the model: one finite row of
/// `style_dim` numbers per label.
fn check_label_codes(codes: &manifest::LabelCodes, model: &Model) -> Result<Vec<f32>, StylizeError> {
    let (labels, dim) = (model.config.num_styles, model.config.style_dim);
    if codes.codes.len() != labels || codes.codes.iter().any(|row| row.len() != dim) {
        return Err(bad(format!("the label codes are not {labels} rows of {dim} numbers (the supervised model's)")));
    }
    let flat: Vec<f32> = codes.codes.concat();
    if flat.iter().any(|v| !v.is_finite()) {
        return Err(bad("the label codes hold a number that is not finite"));
    }
    Ok(flat)
}

/// A manifest this build reads: JSON of a known format with 1–256 labels.
pub fn parse_manifest(json: &[u8]) -> Result<Manifest, StylizeError> {
    let manifest: Manifest = serde_json::from_slice(json).map_err(|e| bad(format!("manifest.json: {e}")))?;
    if !manifest::FORMATS.contains(&manifest.format) {
        return Err(bad(format!(
            "manifest format {} (this build reads formats {:?})",
            manifest.format,
            manifest::FORMATS
        )));
    }
    // Weights trained on a folder without labels have no supervised model and no labels.
    let supervised = manifest.entry(Setting::Supervised).is_some();
    if (manifest.styles.is_empty() && supervised) || manifest.styles.len() > usize::from(u8::MAX) + 1 {
        return Err(bad(format!("the manifest lists {} style labels", manifest.styles.len())));
    }
    if manifest.format >= 2 {
        if manifest.shared.is_none() {
            return Err(bad("a format-2 manifest needs its shared networks' file (\"shared\")"));
        }
        if let Some(m) = manifest.models.iter().find(|m| m.bytes.is_none() || m.fnv1a64.is_none()) {
            return Err(bad(format!("the {} entry lacks its file's size or fingerprint", m.setting)));
        }
    }
    // Format 3 keeps every style encoder in its own file; earlier formats in the model's.
    if let Some(m) = manifest.models.iter().find(|m| m.style_encoder.is_some() != (manifest.format >= 3)) {
        return Err(bad(if manifest.format >= 3 {
            format!("the {} entry lacks its style encoder's file (manifest format 3)", m.setting)
        } else {
            format!("the {} entry lists a style encoder's file, which format {} has not", m.setting, manifest.format)
        }));
    }
    Ok(manifest)
}

/// A file's bytes against the manifest's size and fingerprint (where it lists them).
fn check_file(name: &str, bytes: Option<u64>, fingerprint: Option<&str>, data: &[u8]) -> Result<(), StylizeError> {
    if let Some(expected) = bytes
        && expected != data.len() as u64
    {
        return Err(bad(format!("{name}: {} bytes, the manifest lists {expected}", data.len())));
    }
    if let Some(expected) = fingerprint
        && !expected.eq_ignore_ascii_case(&fnv1a64(data))
    {
        return Err(bad(format!("{name}: its bytes are not the ones the manifest lists (fingerprint {expected})")));
    }
    Ok(())
}

/// A format-1 bundle's config.
fn bundle_header(bytes: &[u8]) -> Result<ModelConfig, StylizeError> {
    bundle_config(bytes).map(|(config, _)| config).map_err(|e| match e {
        ModelError::Weights(m) => bad(m),
        other => bad(other.to_string()),
    })
}

/// The shared networks were built for the stylizer's autoencoder and regressor sizes.
fn check_shared_fits(shared: &ModelConfig, stylizer: &ModelConfig) -> Result<(), StylizeError> {
    let fits = shared.ae_hidden == stylizer.ae_hidden
        && shared.ae_mid == stylizer.ae_mid
        && shared.latent_dim == stylizer.latent_dim
        && shared.vae == stylizer.vae
        && shared.regressor_hidden == stylizer.regressor_hidden;
    if fits { Ok(()) } else { Err(bad("its autoencoder or regressor sizes differ from the shared networks'")) }
}

/// Checks a model's config before any network is built from it: the setting and the label count
/// match, and no width is absurd (which would make the loader try to allocate it).
fn check_config(config: &ModelConfig, setting: Setting, labels: usize) -> Result<(), StylizeError> {
    if config.supervised != (setting == Setting::Supervised) {
        let other = if config.supervised { Setting::Supervised } else { Setting::Unsupervised };
        return Err(bad(format!("it holds the {other} model")));
    }
    let widths = [
        config.ae_hidden,
        config.ae_mid,
        config.latent_dim,
        config.content_hidden,
        config.content_dim,
        config.style_dim,
        config.num_styles,
    ]
    .into_iter()
    .chain(config.style_hidden)
    .chain(config.generator_hidden)
    .chain(config.regressor_hidden)
    .chain(config.classifier_hidden);
    if widths.into_iter().any(|w| w == 0 || w > MAX_WIDTH) {
        return Err(bad("its config has a width of 0 or above 8192"));
    }
    if config.supervised && config.num_styles != labels {
        return Err(bad(format!("it knows {} style labels, the manifest lists {labels}", config.num_styles)));
    }
    Ok(())
}
