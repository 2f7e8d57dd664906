//! Weights folder formats 2 and 3 (issue 17): one shared file (autoencoder + regressor) and per
//! setting a stylizer file (format 3: content encoder + generator) and, format 3, its style
//! encoder's file apart; each tensor in f16 or integers with scales; the manifest lists every
//! file's size and fingerprint. Format 1 folders (a whole bundle per setting) are still read.

mod stylize_support;

use burn::prelude::*;
use motion_stylizer::model::weights::{
    PartEncoding, PartError, PartKind, SharedNets, TensorEncoding, float_params, load_part, load_shared, save_bundle,
    save_part,
};
use motion_stylizer::model::{MotionModel, Stylizer};
use motion_stylizer::stylize::{self, Request, Setting, StyleSource, StylizeError, WeightFiles, Weights};
use motion_stylizer::train::export::{EncodingChoice, Encodings, repack};
use std::path::{Path, PathBuf};
use stylize_support::{WALK, config, import, norm, out_dir};

/// A format-1 folder whose two bundles carry the same autoencoder and regressor (as trained
/// weights do), with different stylizers.
/// A format-1 folder (two bundles, each with its own autoencoder and regressor), written once per
/// test process: the tests run in parallel threads, and two writing the same files at once would
/// read each other's half-written bundles.
fn format1_dir() -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(write_format1_dir).clone()
}

fn write_format1_dir() -> PathBuf {
    let dir = out_dir("parts-format1");
    let sup = MotionModel::seeded(&config(true), &Device::flex(), 11);
    let other = MotionModel::seeded(&config(false), &Device::flex(), 12);
    let unsup = MotionModel {
        autoencoder: sup.autoencoder.clone(),
        stylizer: other.stylizer,
        regressor: sup.regressor.clone(),
    };
    std::fs::write(dir.join("supervised.bin"), save_bundle(&config(true), sup).unwrap()).unwrap();
    std::fs::write(dir.join("unsupervised.bin"), save_bundle(&config(false), unsup).unwrap()).unwrap();
    std::fs::write(dir.join("manifest.json"), serde_json::to_vec_pretty(&stylize_support::manifest()).unwrap())
        .unwrap();
    std::fs::write(dir.join("norm.json"), serde_json::to_vec(&norm()).unwrap()).unwrap();
    dir
}

fn encodings(shared: &str, stylizer: &str) -> Encodings {
    Encodings::new(PartEncoding::parse(shared).unwrap(), PartEncoding::parse(stylizer).unwrap())
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap()
}

/// The label-based result of the walk, as BVH text.
fn label_output(w: &Weights) -> String {
    let content = import("bandai", WALK).motion;
    let request = Request::new(StyleSource::Label(w.style("old").unwrap())).with_seed(7);
    stylize::stylize(w, &content, &request).unwrap()[0].to_bvh().to_bvh_string()
}

/// One label-based and one prior-based (unsupervised) result of the walk, as BVH text.
fn outputs(w: &Weights) -> Vec<String> {
    let content = import("bandai", WALK).motion;
    let old = w.style("old").unwrap();
    [(StyleSource::Label(old), Setting::Supervised), (StyleSource::Prior, Setting::Unsupervised)]
        .into_iter()
        .map(|(source, setting)| {
            let request = Request::new(source).with_setting(setting).with_seed(7);
            stylize::stylize(w, &content, &request).unwrap()[0].to_bvh().to_bvh_string()
        })
        .collect()
}

fn bad_weights(e: StylizeError) -> String {
    match e {
        StylizeError::BadWeights(m) => m,
        other => panic!("expected BadWeights, got {other:?}"),
    }
}

#[test]
fn f16_repack_shares_one_autoencoder_and_stylizes_exactly_as_format_1() {
    let old = format1_dir();
    let new = out_dir("parts-f16");
    let manifest = repack(&old, &new, Encodings::default()).unwrap();
    assert_eq!(manifest.format, 3);
    let shared = manifest.shared.as_ref().unwrap();
    assert_eq!(shared.file.file, "shared.bin");
    assert_eq!(shared.holds, ["autoencoder", "regressor"]);
    const FILES: [&str; 7] = [
        "shared.bin",
        "supervised.bin",
        "supervised-style.bin",
        "unsupervised.bin",
        "unsupervised-style.bin",
        "norm.json",
        "manifest.json",
    ];
    for name in FILES {
        assert!(new.join(name).is_file(), "{name}");
    }
    // The shared networks are in one file only: the stylizers' files together are smaller than
    // the two format-1 bundles by about one autoencoder + regressor each.
    let size = |d: &Path, n: &str| std::fs::metadata(d.join(n)).unwrap().len();
    let old_total = size(&old, "supervised.bin") + size(&old, "unsupervised.bin");
    let new_total: u64 = FILES[..5].iter().map(|n| size(&new, n)).sum();
    assert!(new_total + size(&new, "shared.bin") * 9 / 10 < old_total, "{new_total} vs {old_total}");
    for m in &manifest.models {
        assert_eq!(m.bytes, Some(size(&new, &m.file)));
        assert_eq!(m.encoding.as_deref(), Some("f16"));
        let style = m.style_encoder.as_ref().unwrap();
        assert_eq!(
            (style.file.as_str(), style.bytes),
            (format!("{}-style.bin", m.setting).as_str(), size(&new, &style.file))
        );
    }

    let a = Weights::load_dir(&old).unwrap();
    let b = Weights::load_dir(&new).unwrap();
    assert_eq!(b.settings(), [Setting::Supervised, Setting::Unsupervised]);
    assert!(b.has_style_encoder(Setting::Supervised) && b.has_style_encoder(Setting::Unsupervised));
    assert_eq!(outputs(&a), outputs(&b), "the same bytes out of format 1 and format 3 f16");

    // Repacking a format-3 folder again gives the same files.
    let again = out_dir("parts-f16-again");
    repack(&new, &again, Encodings::default()).unwrap();
    for name in &FILES[..5] {
        assert_eq!(read(&new, name), read(&again, name), "{name}");
    }
    assert_eq!(read(&new, "manifest.json"), read(&again, "manifest.json"));
}

/// Format 3's point: label- and prior-based stylization need no style encoder; a reference
/// motion asks for it with a stable code, and once added the results are the folder's.
#[test]
fn the_style_encoder_is_loaded_only_when_a_reference_motion_needs_it() {
    let dir = out_dir("parts-style-later");
    repack(&format1_dir(), &dir, Encodings::default()).unwrap();
    let [manifest, norm, shared, sup, sup_style, unsup_style] = [
        "manifest.json",
        "norm.json",
        "shared.bin",
        "supervised.bin",
        "supervised-style.bin",
        "unsupervised-style.bin",
    ]
    .map(|n| read(&dir, n));
    let files = WeightFiles {
        manifest: &manifest,
        norm: &norm,
        shared: Some(&shared),
        supervised: Some(&sup),
        ..Default::default()
    };
    let mut w = Weights::from_files(files).unwrap();
    assert!(!w.has_style_encoder(Setting::Supervised));
    let full = Weights::load_dir(&dir).unwrap();
    assert_eq!(label_output(&w), label_output(&full), "label-based without it");

    let content = import("bandai", WALK).motion;
    let old = w.style("old").unwrap();
    let by_motion = Request::new(StyleSource::Motion { motion: &content, label: Some(old) }).with_seed(7);
    let e = stylize::stylize(&w, &content, &by_motion).unwrap_err();
    assert!(matches!(e, StylizeError::StyleEncoderUnavailable { .. }), "{e:?}");
    assert_eq!(e.code(), "STYLE_ENCODER_UNAVAILABLE");

    // The other setting's style encoder, the stylizer's file, or a damaged one: refused, and
    // nothing changes.
    for wrong in [&unsup_style, &sup] {
        let m = bad_weights(w.add_style_encoder(Setting::Supervised, wrong).unwrap_err());
        assert!(m.contains("supervised style encoder file"), "{m}");
    }
    let mut damaged = sup_style.clone();
    let middle = damaged.len() / 2;
    damaged[middle] ^= 1;
    assert!(bad_weights(w.add_style_encoder(Setting::Supervised, &damaged).unwrap_err()).contains("fingerprint"));
    assert!(!w.has_style_encoder(Setting::Supervised));
    // No unsupervised model loaded: that setting's style encoder has nowhere to go.
    assert!(matches!(
        w.add_style_encoder(Setting::Unsupervised, &unsup_style),
        Err(StylizeError::SettingUnavailable { setting: Setting::Unsupervised })
    ));

    w.add_style_encoder(Setting::Supervised, &sup_style).unwrap();
    assert!(w.has_style_encoder(Setting::Supervised));
    let bvh = |w: &Weights| stylize::stylize(w, &content, &by_motion).unwrap()[0].to_bvh().to_bvh_string();
    assert_eq!(bvh(&w), bvh(&full));
}

#[test]
fn a_setting_can_be_added_later_on_the_shared_networks() {
    let dir = out_dir("parts-lazy");
    repack(&format1_dir(), &dir, Encodings::default()).unwrap();
    let [manifest, norm, shared, sup, sup_style, unsup, unsup_style] = [
        "manifest.json",
        "norm.json",
        "shared.bin",
        "supervised.bin",
        "supervised-style.bin",
        "unsupervised.bin",
        "unsupervised-style.bin",
    ]
    .map(|n| read(&dir, n));
    let files = WeightFiles {
        manifest: &manifest,
        norm: &norm,
        shared: Some(&shared),
        supervised: Some(&sup),
        supervised_style: Some(&sup_style),
        ..Default::default()
    };
    let mut w = Weights::from_files(files).unwrap();
    assert_eq!(w.settings(), [Setting::Supervised]);
    assert_eq!(w.listed(), [Setting::Supervised, Setting::Unsupervised]);
    assert!(matches!(w.model(Setting::Unsupervised), Err(StylizeError::SettingUnavailable { .. })));
    // The other setting's file in the wrong slot, or damaged, is refused and changes nothing.
    let wrong = bad_weights(w.add_setting(Setting::Unsupervised, &sup).unwrap_err());
    assert!(wrong.contains("unsupervised file"), "{wrong}");
    let mut damaged = unsup.clone();
    let last = damaged.len() - 1;
    damaged[last] ^= 1;
    let message = bad_weights(w.add_setting(Setting::Unsupervised, &damaged).unwrap_err());
    assert!(message.contains("fingerprint"), "{message}");
    assert_eq!(w.settings(), [Setting::Supervised]);
    w.add_setting(Setting::Unsupervised, &unsup).unwrap();
    assert_eq!(w.settings(), [Setting::Supervised, Setting::Unsupervised]);
    w.add_style_encoder(Setting::Unsupervised, &unsup_style).unwrap();
    assert_eq!(outputs(&w), outputs(&Weights::load_dir(&dir).unwrap()));
}

#[test]
fn format_3_files_are_checked_against_the_manifest() {
    let dir = out_dir("parts-checks");
    repack(&format1_dir(), &dir, encodings("q8", "q4g64")).unwrap();
    let (manifest, norm, shared, sup) =
        (read(&dir, "manifest.json"), read(&dir, "norm.json"), read(&dir, "shared.bin"), read(&dir, "supervised.bin"));
    let files = |shared: Option<&'static [u8]>, sup: &'static [u8], norm: &'static [u8]| WeightFiles {
        manifest: Box::leak(manifest.clone().into_boxed_slice()),
        norm,
        shared,
        supervised: Some(sup),
        ..Default::default()
    };
    let leak = |v: &Vec<u8>| -> &'static [u8] { Box::leak(v.clone().into_boxed_slice()) };
    assert!(Weights::from_files(files(Some(leak(&shared)), leak(&sup), leak(&norm))).is_ok());
    // No shared file.
    let m = bad_weights(Weights::from_files(files(None, leak(&sup), leak(&norm))).unwrap_err());
    assert!(m.contains("shared.bin"), "{m}");
    // The shared file where the stylizer goes, and the stylizer's where the shared one goes.
    let m = bad_weights(Weights::from_files(files(Some(leak(&sup)), leak(&shared), leak(&norm))).unwrap_err());
    assert!(m.contains("shared"), "{m}");
    // Truncated, or one byte changed, in any file.
    for cut in [0, 7, 12, 100, shared.len() / 2, shared.len() - 1] {
        let e = Weights::from_files(files(Some(leak(&shared[..cut].to_vec())), leak(&sup), leak(&norm))).unwrap_err();
        assert!(matches!(e, StylizeError::BadWeights(_)), "{e:?}");
    }
    let mut changed = sup.clone();
    changed[sup.len() / 2] ^= 0x40;
    let m = bad_weights(Weights::from_files(files(Some(leak(&shared)), leak(&changed), leak(&norm))).unwrap_err());
    assert!(m.contains("fingerprint"), "{m}");
    let mut changed_norm = norm.clone();
    changed_norm.push(b' ');
    let m = bad_weights(Weights::from_files(files(Some(leak(&shared)), leak(&sup), leak(&changed_norm))).unwrap_err());
    assert!(m.contains("norm.json"), "{m}");
    // Format 3 bytes through the format-1 entry point (no shared file): refused, not a panic.
    assert!(Weights::from_bytes(&manifest, &norm, Some(&sup), None).is_err());
}

#[test]
fn part_files_refuse_what_does_not_fit_the_networks() {
    let dev = Device::flex();
    let cfg = config(true);
    let model = MotionModel::seeded(&cfg, &dev, 3);
    let shared = SharedNets { autoencoder: model.autoencoder.clone(), regressor: model.regressor.clone() };
    let bytes = save_part(PartKind::Shared, &cfg, shared, &PartEncoding::F16).unwrap();
    assert!(load_shared(&bytes, &dev).is_ok());
    // A shared file read as a stylizer.
    let e = load_part(PartKind::Stylizer, Stylizer::new(&cfg, &dev), &bytes).unwrap_err();
    assert_eq!(e, PartError::WrongPart { expected: PartKind::Stylizer, found: PartKind::Shared });
    // The stylizer's file of a wider network into this one: a shape error naming the tensor.
    let wide = config(true).with_num_styles(17);
    let other = save_part(PartKind::Stylizer, &wide, Stylizer::new(&wide, &dev), &PartEncoding::F16).unwrap();
    match load_part(PartKind::Stylizer, Stylizer::new(&cfg, &dev), &other).unwrap_err() {
        PartError::Tensor { path, message } => assert!(message.contains("shape"), "{path}: {message}"),
        e => panic!("{e:?}"),
    }
    assert_eq!(load_shared(b"garbage!", &dev).unwrap_err(), PartError::NotOurs);
    assert_eq!(load_shared(&bytes[..20], &dev).unwrap_err(), PartError::Truncated);
}

/// The squared error of the decoded weights relative to their squared sum, over the tensors of
/// at least 4,096 values (the quantised ones).
fn relative_error(original: &[(String, Vec<usize>, Vec<f32>)], decoded: &[(String, Vec<usize>, Vec<f32>)]) -> f64 {
    let (mut err, mut sum) = (0f64, 0f64);
    assert_eq!(original.len(), decoded.len());
    for ((path, shape, a), (path2, shape2, b)) in original.iter().zip(decoded) {
        assert_eq!((path, shape), (path2, shape2));
        if a.len() < 4096 {
            continue;
        }
        for (x, y) in a.iter().zip(b) {
            err += f64::from(x - y).powi(2);
            sum += f64::from(*x).powi(2);
        }
    }
    err / sum
}

#[test]
fn integer_encodings_stay_within_their_step_and_f16_is_exact_to_f16() {
    let dev = Device::flex();
    let cfg = config(false);
    let stylizer = MotionModel::seeded(&cfg, &dev, 5).stylizer;
    let original = float_params(&stylizer).unwrap();
    let mut sizes = Vec::new();
    // Uniform steps of max/qmax over roughly Gaussian weights (~3.5 σ at the largest): an error
    // variance of step²/12, less where clipping helps.
    for (spec, bound) in [("f16", 1e-6), ("q8", 2e-4), ("q6", 3e-3), ("q4g64", 4e-2), ("q4", 4e-2)] {
        let encoding = PartEncoding::parse(spec).unwrap();
        let bytes = save_part(PartKind::Stylizer, &cfg, stylizer.clone(), &encoding).unwrap();
        sizes.push((spec, bytes.len()));
        let loaded = load_part(PartKind::Stylizer, Stylizer::new(&cfg, &dev), &bytes).unwrap();
        let decoded = float_params(&loaded).unwrap();
        let error = relative_error(&original, &decoded);
        assert!(error <= bound, "{spec}: squared error {error} of the weights' squared sum");
        assert!(error > 0.0 || spec == "f16");
    }
    let size = |s: &str| sizes.iter().find(|(n, _)| *n == s).unwrap().1 as f64;
    assert!(size("q8") < size("f16") * 0.55, "{sizes:?}");
    assert!(size("q4") < size("f16") * 0.3, "{sizes:?}");
    // Overrides by path prefix.
    let mixed = PartEncoding::parse("q4g64,style_encoder=q8").unwrap();
    assert_eq!(
        mixed.of("stylizer.style_encoder.down1.conv.weight", &[96, 64, 3]),
        TensorEncoding::Int { bits: 8, group: 0 }
    );
    assert_eq!(mixed.of("generator.block1.conv.conv.weight", &[96, 64, 3]), TensorEncoding::Int { bits: 4, group: 64 });
    assert_eq!(mixed.of("generator.block1.conv.conv.bias", &[96]), TensorEncoding::F16);
    assert_eq!(mixed.name(), "q4g64,style_encoder=q8");
    for bad in ["q3", "q9", "int8", "q4g0", "q8,x", "", "q16"] {
        assert!(PartEncoding::parse(bad).is_none(), "{bad}");
    }
}

#[test]
fn each_setting_can_have_its_own_encoding() {
    let dir = out_dir("parts-per-setting");
    let mut enc = encodings("f16", "q8");
    enc.unsupervised = PartEncoding::parse("q4g64").unwrap();
    let manifest = repack(&format1_dir(), &dir, enc).unwrap();
    let of = |setting: &str| manifest.models.iter().find(|m| m.setting == setting).unwrap().encoding.clone();
    assert_eq!(of("supervised").as_deref(), Some("q8"));
    assert_eq!(of("unsupervised").as_deref(), Some("q4g64"));
    let (sup, unsup) = (read(&dir, "supervised.bin").len(), read(&dir, "unsupervised.bin").len());
    assert!(unsup * 10 < sup * 7, "4 bits against 8: {unsup} vs {sup} bytes");
    // Both load and stylize.
    let w = Weights::load_dir(&dir).unwrap();
    assert!(!outputs(&w).is_empty());
}

/// `repack` with nothing chosen keeps every file's encoding, byte for byte (re-encoding the
/// dequantised weights in their own encoding is exact); a file chosen changes alone.
#[test]
fn a_folder_keeps_its_encodings_unless_one_is_chosen() {
    let mixed = out_dir("parts-keep-mixed");
    let mut enc = encodings("q8g16", "q8,style_encoder=f16");
    enc.unsupervised = PartEncoding::parse("q4g64").unwrap();
    repack(&format1_dir(), &mixed, enc).unwrap();
    let kept = out_dir("parts-keep-kept");
    let manifest = repack(&mixed, &kept, EncodingChoice::default()).unwrap();
    for f in ["manifest.json", "shared.bin", "supervised.bin", "supervised-style.bin", "unsupervised.bin"] {
        assert!(read(&kept, f) == read(&mixed, f), "{f} written again unchanged");
    }
    assert_eq!(manifest.shared.as_ref().map(|s| s.encoding.as_str()), Some("q8g16"));
    let one = out_dir("parts-keep-one");
    let choice = EncodingChoice { unsupervised: PartEncoding::parse("q8"), ..EncodingChoice::default() };
    let manifest = repack(&mixed, &one, choice).unwrap();
    let of = |setting: &str| manifest.models.iter().find(|m| m.setting == setting).unwrap().encoding.clone();
    assert_eq!(of("unsupervised").as_deref(), Some("q8"));
    assert_eq!(of("supervised").as_deref(), Some("q8,style_encoder=f16"));
    assert!(read(&one, "shared.bin") == read(&mixed, "shared.bin"));
}
