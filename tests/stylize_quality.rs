//! Quality of the stylization with the TRAINED weights committed under `assets/weights`.
//!
//! Ignored until those weights exist (the other stylization tests use untrained networks and
//! check the plumbing only). Run with
//! `cargo test --release --test stylize_quality -- --ignored`.
#![cfg(feature = "model")]

mod stylize_support;

use motion_stylizer::Motion;
use motion_stylizer::stylize::{self, Request, Setting, StyleSource, Weights, style_code_of};
use stylize_support::import;

fn distance(a: &[f32], b: &[f32]) -> f64 {
    a.iter().zip(b).map(|(x, y)| f64::from(x - y).powi(2)).sum::<f64>().sqrt()
}

/// Mean distance of `motion`'s style code to the codes of `references`, in the unsupervised
/// model's style space (which holds the whole style, labels included, paper §3.4).
fn distance_to(w: &Weights, motion: &Motion, references: &[Vec<f32>]) -> f64 {
    let code = style_code_of(w, Setting::Unsupervised, motion, None).unwrap();
    references.iter().map(|r| distance(&code, r)).sum::<f64>() / references.len() as f64
}

/// Stylizing a normal walk with a reference of style X (motion-based, unsupervised) or with the
/// label X (label-based, supervised) moves the output toward X in the style encoder's space: the
/// output's style code is nearer the X references' codes than the content's is.
#[test]
#[ignore = "needs the trained weights in assets/weights (not committed yet)"]
fn stylized_output_moves_toward_the_reference_style() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/weights");
    let w = Weights::load_dir(&dir).expect("trained weights in assets/weights");
    let content = import("bandai", "dataset-2_walk_normal_001_f120").motion;
    for (label, reference) in [("old", "dataset-2_walk_elderly_001_f120"), ("tired", "dataset-1_walk_tired_001_f90")] {
        let reference = import("bandai", reference).motion;
        let refs = vec![style_code_of(&w, Setting::Unsupervised, &reference, None).unwrap()];
        let before = distance_to(&w, &content, &refs);

        let request = Request::new(StyleSource::motion(&reference)).with_setting(Setting::Unsupervised);
        let out = stylize::stylize(&w, &content, &request).unwrap().remove(0);
        let after = distance_to(&w, &out, &refs);
        assert!(after < before, "{label}, motion-based: {after} is not below {before}");

        if w.has(Setting::Supervised) {
            let request = Request::new(StyleSource::Label(w.style(label).unwrap())).with_seed(1);
            let out = stylize::stylize(&w, &content, &request).unwrap().remove(0);
            let after = distance_to(&w, &out, &refs);
            assert!(after < before, "{label}, label-based: {after} is not below {before}");
        }
    }
}
