//! Manual joint mappings (issue 15, point 5): for the rigs neither names nor structure settle, a
//! JSON object naming, for canonical joints, the file's joint that plays it:
//!
//! ```json
//! { "Hips": "pelvis", "Spine": "spine_02", "Head": null, "Hand_L": "wrist.L" }
//! ```
//!
//! `null` leaves a canonical joint unmatched (synthesised, or an error for an essential one).
//! Canonical joints the object does not name keep what the automatic matching found, if it found
//! the rig at all. `motion-stylizer inspect --json` prints the mapping it used as `map`, every
//! canonical joint present, ready to edit; the whole `inspect --json` object is accepted too (its
//! `map` is read).

use super::ImportError;
use super::canonical::{JOINT_NAMES, NUM_JOINTS, joint_index};
use super::rigs::JointMap;
use crate::bvh::BvhJoint;

/// A parsed manual mapping: for canonical joints, the file's joint name (or none).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ManualMap {
    entries: Vec<(usize, Option<String>)>,
}

fn bad(reason: impl Into<String>) -> ImportError {
    ImportError::BadMap { reason: reason.into() }
}

/// Longest joint name quoted back in an error.
const MAX_QUOTED: usize = 60;

fn quoted(s: &str) -> String {
    let cut: String = s.chars().take(MAX_QUOTED).collect();
    if cut.len() < s.len() { format!("{cut:?}…") } else { format!("{cut:?}") }
}

impl ManualMap {
    /// Parses the JSON text of a mapping (or of an `inspect --json` object with a `map`).
    pub fn from_json(text: &str) -> Result<ManualMap, ImportError> {
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| bad(format!("not JSON: {e}")))?;
        let obj = match value.get("map") {
            Some(m) => m,
            None => &value,
        };
        let obj = obj.as_object().ok_or_else(|| bad("expected a JSON object: canonical joint -> your joint"))?;
        let mut entries = Vec::with_capacity(obj.len());
        for (k, v) in obj {
            let j = joint_index(k).ok_or_else(|| {
                bad(format!("{} is no canonical joint (they are {})", quoted(k), JOINT_NAMES.join(", ")))
            })?;
            let name = match v {
                serde_json::Value::Null => None,
                serde_json::Value::String(s) => Some(s.clone()),
                other => return Err(bad(format!("{k}: expected a joint name or null, found {other}"))),
            };
            entries.push((j, name));
        }
        Ok(ManualMap { entries })
    }

    /// A mapping from (canonical joint, file joint) pairs.
    pub fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, Option<&'a str>)>,
    ) -> Result<ManualMap, ImportError> {
        let mut entries = Vec::new();
        for (k, v) in pairs {
            let j = joint_index(k).ok_or_else(|| bad(format!("{} is no canonical joint", quoted(k))))?;
            entries.push((j, v.map(str::to_string)));
        }
        Ok(ManualMap { entries })
    }

    /// Whether the mapping names no joint at all.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// `base` (the automatic match, if any) with this mapping's entries applied, checked against
    /// `joints`: every named joint exists, no joint plays two canonical joints.
    pub(super) fn apply(&self, joints: &[BvhJoint], base: Option<JointMap>) -> Result<JointMap, ImportError> {
        let mut map = base.unwrap_or([None; NUM_JOINTS]);
        for (j, name) in &self.entries {
            map[*j] = match name {
                None => None,
                Some(n) => Some(
                    joints
                        .iter()
                        .position(|x| x.name == *n)
                        .ok_or_else(|| bad(format!("{}: the file has no joint {}", JOINT_NAMES[*j], quoted(n))))?,
                ),
            };
        }
        // A joint named explicitly wins over the automatic match of another canonical joint.
        let explicit: Vec<usize> = self.entries.iter().map(|(j, _)| *j).collect();
        for j in 0..NUM_JOINTS {
            let Some(u) = map[j] else { continue };
            for k in 0..NUM_JOINTS {
                if k != j && map[k] == Some(u) {
                    if explicit.contains(&j) && explicit.contains(&k) {
                        return Err(bad(format!(
                            "{} plays both {} and {}",
                            quoted(&joints[u].name),
                            JOINT_NAMES[j],
                            JOINT_NAMES[k]
                        )));
                    }
                    if explicit.contains(&j) {
                        map[k] = None;
                    }
                }
            }
        }
        Ok(map)
    }
}

/// The mapping as JSON: every canonical joint, the file's joint name or `null`.
pub fn map_json(joints: &[BvhJoint], map: &JointMap) -> serde_json::Value {
    let obj: serde_json::Map<String, serde_json::Value> = (0..NUM_JOINTS)
        .map(|j| {
            let v = map[j].and_then(|u| joints.get(u)).map(|x| serde_json::Value::String(x.name.clone()));
            (JOINT_NAMES[j].to_string(), v.unwrap_or(serde_json::Value::Null))
        })
        .collect();
    serde_json::Value::Object(obj)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::canonical::joint::*;
    use glam::DVec3;

    fn joints(names: &[&str]) -> Vec<BvhJoint> {
        names
            .iter()
            .enumerate()
            .map(|(k, n)| BvhJoint {
                name: n.to_string(),
                parent: k.checked_sub(1),
                offset: DVec3::ZERO,
                channels: vec![],
                end_site: None,
                channel_offset: 0,
            })
            .collect()
    }

    #[test]
    fn parses_and_applies() {
        let m = ManualMap::from_json(r#"{"Hips": "a", "Head": null, "Spine": "b"}"#).unwrap();
        let j = joints(&["a", "b", "c"]);
        let mut base = [None; NUM_JOINTS];
        base[HEAD] = Some(2);
        base[CHEST] = Some(1); // taken by the explicit Spine: dropped
        let map = m.apply(&j, Some(base)).unwrap();
        assert_eq!((map[HIPS], map[SPINE], map[CHEST], map[HEAD]), (Some(0), Some(1), None, None));
        // inspect's whole object: its `map`.
        let whole = ManualMap::from_json(r#"{"rig": "x", "map": {"Hips": "a"}}"#).unwrap();
        assert_eq!(whole, ManualMap::from_pairs([("Hips", Some("a"))]).unwrap());
        assert_eq!(map_json(&j, &map)["Spine"], "b");
        assert_eq!(map_json(&j, &map).as_object().unwrap().len(), NUM_JOINTS);
    }

    #[test]
    fn refuses_what_cannot_be_used() {
        let j = joints(&["a", "b"]);
        let code = |text: &str| match ManualMap::from_json(text).and_then(|m| m.apply(&j, None)) {
            Err(e) => (e.code(), e.to_string()),
            Ok(_) => ("ok", String::new()),
        };
        assert_eq!(code("{").0, "BAD_MAP");
        assert!(code(r#"{"Root": "a"}"#).1.contains("no canonical joint"));
        assert!(code(r#"{"Hips": 3}"#).1.contains("expected a joint name"));
        assert!(code(r#"{"Hips": "zz"}"#).1.contains("has no joint"));
        assert!(code(r#"{"Hips": "a", "Spine": "a"}"#).1.contains("plays both"));
        let long = format!(r#"{{"Hips": "{}"}}"#, "x".repeat(10_000));
        assert!(code(&long).1.len() < 200, "quoted names are cut");
    }
}
