//! [`Weights`]: the shipped-weights folder (see [`super::manifest`]) loaded from bytes, so that the
//! browser can fetch the files and hand them over; [`Weights::load_dir`] reads the folder natively.

use burn::prelude::*;

use super::StylizeError;
use super::manifest::{self, Manifest};
use crate::dataset::Style;
use crate::features::NormStats;
use crate::model::weights::{bundle_config, load_bundle};
use crate::model::{Model, ModelError};

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

/// The trained models and what goes with them: the manifest, the normalisation statistics and
/// one [`Model`] per available setting.
#[derive(Debug)]
pub struct Weights {
    manifest: Manifest,
    norm: NormStats,
    supervised: Option<Model>,
    unsupervised: Option<Model>,
    /// The supervised model's label centres ([`manifest::LabelCodes`]), `num_styles × style_dim`
    /// row-major, checked against the model.
    label_codes: Option<Vec<f32>>,
}

fn bad(message: impl Into<String>) -> StylizeError {
    StylizeError::BadWeights(message.into())
}

impl Weights {
    /// The weights from the bytes of the folder's files (`manifest.json`, `norm.json`,
    /// `supervised.bin`, `unsupervised.bin`), on the CPU (`flex`) device. At least one bundle is
    /// needed. Errors ([`StylizeError::BadWeights`]): malformed JSON, a manifest of another format
    /// or without labels, statistics of the wrong size, bundles that are not ours, of the other
    /// setting, or whose label count disagrees with the manifest.
    pub fn from_bytes(
        manifest_json: &[u8],
        norm_json: &[u8],
        supervised: Option<&[u8]>,
        unsupervised: Option<&[u8]>,
    ) -> Result<Weights, StylizeError> {
        Self::from_bytes_on(&Device::flex(), manifest_json, norm_json, supervised, unsupervised)
    }

    /// [`Weights::from_bytes`] on a given device.
    pub fn from_bytes_on(
        device: &Device,
        manifest_json: &[u8],
        norm_json: &[u8],
        supervised: Option<&[u8]>,
        unsupervised: Option<&[u8]>,
    ) -> Result<Weights, StylizeError> {
        let manifest: Manifest =
            serde_json::from_slice(manifest_json).map_err(|e| bad(format!("manifest.json: {e}")))?;
        if manifest.format != manifest::FORMAT {
            return Err(bad(format!(
                "manifest format {} (this build reads format {})",
                manifest.format,
                manifest::FORMAT
            )));
        }
        if manifest.styles.is_empty() || manifest.styles.len() > usize::from(u8::MAX) + 1 {
            return Err(bad(format!("the manifest lists {} style labels", manifest.styles.len())));
        }
        let norm: NormStats = serde_json::from_slice(norm_json).map_err(|e| bad(format!("norm.json: {e}")))?;
        if supervised.is_none() && unsupervised.is_none() {
            return Err(bad("no model: neither a supervised nor an unsupervised bundle"));
        }
        let load = |bytes: Option<&[u8]>, setting: Setting| -> Result<Option<Model>, StylizeError> {
            let Some(bytes) = bytes else { return Ok(None) };
            let context = |e: StylizeError| match e {
                StylizeError::BadWeights(m) => bad(format!("{setting} bundle: {m}")),
                other => other,
            };
            check_bundle_header(bytes, setting, manifest.styles.len()).map_err(context)?;
            // The bundle's f16 tensors are read on flex (which casts them to f32) and the f32
            // networks then moved to `device`: burn-ndarray has no f16 tensors and panics on them.
            let (config, model) = load_bundle(bytes, &Device::flex()).map_err(|e| context(e.into()))?;
            Ok(Some(Model::new(config, model.to_device(device))))
        };
        let supervised = load(supervised, Setting::Supervised)?;
        let label_codes = match (&supervised, label_codes_of(&manifest)) {
            (Some(model), Some(codes)) => Some(check_label_codes(codes, model)?),
            _ => None,
        };
        Ok(Weights {
            supervised,
            unsupervised: load(unsupervised, Setting::Unsupervised)?,
            manifest,
            norm,
            label_codes,
        })
    }

    /// Reads the weights folder `dir` (native builds only): `manifest.json`, the statistics file
    /// it names, and the bundle of each setting it lists.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load_dir(dir: impl AsRef<std::path::Path>) -> Result<Weights, StylizeError> {
        let dir = dir.as_ref();
        let read = |name: &str| {
            let path = dir.join(name);
            std::fs::read(&path)
                .map_err(|e| StylizeError::Read { path: path.display().to_string(), message: e.to_string() })
        };
        let manifest_json = read("manifest.json")?;
        let manifest: Manifest =
            serde_json::from_slice(&manifest_json).map_err(|e| bad(format!("manifest.json: {e}")))?;
        let norm_json = read(&manifest.norm)?;
        let (mut supervised, mut unsupervised) = (None, None);
        for entry in &manifest.models {
            let slot = match Setting::from_name(&entry.setting) {
                Some(Setting::Supervised) => &mut supervised,
                Some(Setting::Unsupervised) => &mut unsupervised,
                None => return Err(bad(format!("the manifest lists an unknown setting {:?}", entry.setting))),
            };
            *slot = Some(read(&entry.file)?);
        }
        Self::from_bytes(&manifest_json, &norm_json, supervised.as_deref(), unsupervised.as_deref())
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
    manifest
        .models
        .iter()
        .find(|m| Setting::from_name(&m.setting) == Some(Setting::Supervised))
        .and_then(|m| m.label_codes.as_ref())
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

/// Checks a bundle's config before any network is built from it: the setting and the label count
/// match, and no width is absurd (which would make the loader try to allocate it).
fn check_bundle_header(bytes: &[u8], setting: Setting, labels: usize) -> Result<(), StylizeError> {
    let (config, _) = bundle_config(bytes).map_err(|e| match e {
        ModelError::Weights(m) => bad(m),
        other => bad(other.to_string()),
    })?;
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
