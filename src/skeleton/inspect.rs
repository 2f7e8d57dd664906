//! What the importer makes of a file, also when it cannot import it (`motion-stylizer inspect`,
//! the package's `inspectBvh`, the demo's mapping panel): the rig, the joints matched, missing
//! and synthesised, and on failure the error with the best guesses, as a mapping to edit and pass
//! back ([`ManualMap`]).

use serde_json::json;

use super::canonical::JOINT_NAMES;
use super::import::{ImportError, Imported, import_with};
use super::manual::{ManualMap, map_json};
use super::rigs::{self, JointMap};
use crate::bvh::Bvh;

/// The inspection of one parsed file.
#[derive(Debug)]
pub struct Inspection {
    /// The rig family detected (or guessed, on failure).
    pub rig: String,
    /// The mapping used (or, on failure, the best guesses with a manual mapping's entries
    /// applied): canonical joint → file joint index.
    pub map: JointMap,
    /// Canonical joints the file lacks.
    pub missing: Vec<String>,
    /// Canonical joints made up from the others: (joint, how).
    pub synthesised: Vec<(String, String)>,
    /// What the importer decided that a user should know (e.g. the reference pose's source).
    pub notes: Vec<String>,
    /// Factor to the canonical rig's centimetres (imported files only).
    pub scale: Option<f64>,
    /// Where the reference pose came from (imported files only).
    pub base_pose: Option<String>,
    /// Why the file cannot be imported; `None`: it can ("retargetable").
    pub error: Option<ImportError>,
}

impl Inspection {
    /// Whether the import succeeds (matching, retargeting, resampling).
    pub fn retargetable(&self) -> bool {
        self.error.is_none()
    }

    /// (canonical joint, file joint) of every matched joint, in canonical order.
    pub fn matched<'a>(&self, bvh: &'a Bvh) -> Vec<(&'static str, &'a str)> {
        (0..JOINT_NAMES.len())
            .filter_map(|j| self.map[j].and_then(|u| bvh.joints.get(u)).map(|x| (JOINT_NAMES[j], x.name.as_str())))
            .collect()
    }

    /// The JSON object `inspect --json` prints (without its `file`): the file's header facts, the
    /// rig, `matched`, `missing`, `synthesised`, `retargetable`, `error` ({code, message}) and
    /// `map`, every canonical joint present, ready to edit.
    pub fn to_json(&self, bvh: &Bvh) -> serde_json::Value {
        let matched: serde_json::Map<String, serde_json::Value> =
            self.matched(bvh).into_iter().map(|(c, u)| (c.to_string(), json!(u))).collect();
        let synthesised: serde_json::Map<String, serde_json::Value> =
            self.synthesised.iter().map(|(c, how)| (c.clone(), json!(how))).collect();
        let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
        json!({
            "joints": bvh.joints.len(),
            "joint_names": names,
            "frames": bvh.frames,
            "fps": bvh.fps(),
            "duration_s": bvh.duration(),
            "channels": bvh.num_channels(),
            "rig": self.rig,
            "matched": matched,
            "missing": self.missing,
            "synthesised": synthesised,
            "retargetable": self.retargetable(),
            "error": self.error.as_ref().map(|e| json!({ "code": e.code(), "message": e.to_string() })),
            "scale_to_canonical": self.scale,
            "base_pose": self.base_pose,
            "notes": self.notes,
            "map": map_json(&bvh.joints, &self.map),
        })
    }
}

/// Inspects a parsed file: imports it (with `manual` applied, if given) and describes the result,
/// or, when the import fails, what was found and the best guesses for a manual mapping. Also
/// returns the import itself when it succeeded.
pub fn inspect(bvh: &Bvh, manual: Option<&ManualMap>) -> (Inspection, Option<Imported>) {
    match import_with(bvh, manual) {
        Ok(imported) => {
            let r = imported.rig.report();
            let inspection = Inspection {
                rig: r.rig.clone(),
                map: *imported.rig.joint_map(),
                missing: r.missing.clone(),
                synthesised: imported.rig.synthesised().to_vec(),
                notes: imported.rig.notes().to_vec(),
                scale: Some(r.scale),
                base_pose: Some(r.base_pose.clone()),
                error: None,
            };
            (inspection, Some(imported))
        }
        Err(e) => {
            let (rig, guess) = match rigs::detect(&bvh.joints) {
                Ok(d) => (d.rig.to_string(), d.map),
                Err(u) => (u.rig.to_string(), *u.map),
            };
            // A mapping given by hand stays in the guesses (what was chosen is what to edit next).
            let guess = manual.and_then(|m| m.apply(&bvh.joints, Some(guess)).ok()).unwrap_or(guess);
            let (rig, missing) = match &e {
                ImportError::MissingJoints { missing, rig } => (rig.clone(), missing.clone()),
                _ => (rig, Vec::new()),
            };
            let inspection = Inspection {
                rig,
                map: guess,
                missing,
                synthesised: Vec::new(),
                notes: Vec::new(),
                scale: None,
                base_pose: None,
                error: Some(e),
            };
            (inspection, None)
        }
    }
}
