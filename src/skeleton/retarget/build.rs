//! Building a [`UserRig`] from a BVH (the module docs' matching, plausibility, world basis, base
//! pose and T-pose): [`UserRig::from_bvh`] and [`UserRig::from_bvh_with`]. Retargeting with it, to
//! and from the canonical rig, is the parent module's.

use crate::bvh::{Bvh, Channel};
use crate::skeleton::canonical::{JOINT_NAMES, NUM_JOINTS, joint::*};
use crate::skeleton::resample;
use crate::skeleton::rigs;
use crate::skeleton::tpose::{Core, build, canonical_tpose, check_human, degenerate};
use crate::skeleton::{ImportError, ManualMap};
use glam::{DQuat, DVec3};

use super::{FLOOR_PERCENTILE, MANUAL, RigReport, STRUCTURAL, UserRig, percentile, well_formed};

/// Largest swing (degrees) a rest pose may need before it is replaced by a clip frame.
const MAX_REST_SWING_DEG: f64 = 120.0;

/// Most frames examined when looking for a base pose in the clip.
const MAX_BASE_CANDIDATES: usize = 240;

fn axis_name(v: DVec3) -> String {
    let (s, a) = if v.x.abs() > 0.5 {
        (v.x, "X")
    } else if v.y.abs() > 0.5 {
        (v.y, "Y")
    } else {
        (v.z, "Z")
    };
    format!("{}{a}", if s > 0.0 { "+" } else { "-" })
}

const FEET: [usize; 4] = [FOOT_L, TOES_L, FOOT_R, TOES_R];

/// The canonical joints of `bvh` from its structure: the rest pose for the geometry (or the first
/// frame when the rest pose has no extent), the rest pose and up to 8 frames for the facing.
fn structural(bvh: &Bvh) -> Option<rigs::Detection> {
    let n = bvh.joints.len();
    let rest_t: Vec<DVec3> = (0..n).map(|u| bvh.local_transform(0, u).0).collect();
    let rest =
        crate::skeleton::fk::forward_kinematics_vec(n, |u| bvh.joints[u].parent, |u| (rest_t[u], DQuat::IDENTITY)).0;
    let step = bvh.frames.div_ceil(8).max(1);
    let frames: Vec<Vec<DVec3>> = (0..bvh.frames).step_by(step).map(|f| bvh.global_pose(f).0).collect();
    let mut poses = vec![rest];
    poses.extend(frames.iter().cloned());
    let map = crate::skeleton::structure::match_structure(&bvh.joints, &poses).or_else(|| {
        frames.first().and_then(|f| {
            let mut p = vec![f.clone()];
            p.extend(frames.iter().cloned());
            crate::skeleton::structure::match_structure(&bvh.joints, &p)
        })
    })?;
    let map = rigs::validate(&bvh.joints, rigs::spine_from_structure(&bvh.joints, rigs::validate(&bvh.joints, map)));
    rigs::missing_required(&map).is_empty().then_some(rigs::Detection { rig: STRUCTURAL, map, base_pose: None })
}

impl UserRig {
    /// Detects the rig of `bvh` (its hierarchy; the frames only serve as base pose when the rest pose
    /// is no use, and to measure the floor) and derives the retargeting.
    pub fn from_bvh(bvh: &Bvh) -> Result<UserRig, ImportError> {
        Self::from_bvh_with(bvh, None)
    }

    /// [`UserRig::from_bvh`] with a manual joint mapping: its entries replace the automatic match
    /// (rig `"manual"`); canonical joints it does not name keep the automatic match, if any.
    pub fn from_bvh_with(bvh: &Bvh, manual: Option<&ManualMap>) -> Result<UserRig, ImportError> {
        well_formed(bvh)?;
        resample::check_budget(bvh.frames, bvh.num_channels(), bvh.frame_time)?;
        let joints = bvh.joints.clone();
        let auto = rigs::detect(&joints).or_else(|e| structural(bvh).ok_or(e));
        let auto = match manual {
            None => auto,
            Some(m) => {
                let base = auto.as_ref().ok().map(|d| d.map);
                let map = m.apply(&joints, base)?;
                let checked = rigs::validate(&joints, map);
                if let Some(j) = (0..NUM_JOINTS).find(|&j| checked[j] != map[j]) {
                    return Err(ImportError::BadMap {
                        reason: format!(
                            "{} ({:?}) is not below the joint of its canonical parent",
                            JOINT_NAMES[j],
                            map[j].map(|u| joints[u].name.as_str()).unwrap_or("")
                        ),
                    });
                }
                let missing = rigs::missing_required(&map);
                if !missing.is_empty() {
                    return Err(ImportError::MissingJoints { missing, rig: MANUAL.to_string() });
                }
                Ok(rigs::Detection { rig: MANUAL, map, base_pose: auto.ok().and_then(|d| d.base_pose) })
            }
        };
        let det = auto.map_err(|e| {
            // One or two chains (of four joints or more: a smaller file is no skeleton to judge, its
            // error names the missing joints) cannot be two arms and two legs, whatever the names.
            let ends = (0..joints.len()).filter(|&u| !joints.iter().any(|j| j.parent == Some(u))).count();
            if ends <= 2 && joints.len() >= 4 {
                ImportError::NotHuman {
                    reason: format!("{} joints with {ends} end(s): a human has two arms and two legs", joints.len()),
                }
            } else {
                ImportError::MissingJoints { missing: e.missing, rig: e.rig.to_string() }
            }
        })?;
        let map = det.map;
        let mut inverse = vec![None; joints.len()];
        for (j, u) in map.iter().enumerate() {
            if let Some(u) = u {
                inverse[*u] = Some(j);
            }
        }

        let rest_t: Vec<DVec3> = (0..joints.len()).map(|u| bvh.local_transform(0, u).0).collect();
        // Base pose: the rest pose if usable, else the scheme's table, else the best clip frame.
        let rest = vec![DQuat::IDENTITY; joints.len()];
        let rest_core = build(&joints, &rest_t, &map, &inverse, &rest);
        let mut notes = Vec::new();
        let (base_local, core, base_name) = match (rest_core, det.base_pose) {
            (Ok(core), _) if core.max_swing <= MAX_REST_SWING_DEG.to_radians() => (rest, core, "rest".to_string()),
            (_, Some(table)) => {
                let base: Vec<DQuat> = joints
                    .iter()
                    .map(|j| {
                        let n = rigs::normalise(&j.name);
                        table
                            .iter()
                            .find(|(t, _)| rigs::normalise(t) == n)
                            .map(|(_, q)| DQuat::from_array(*q).normalize())
                            .unwrap_or(DQuat::IDENTITY)
                    })
                    .collect();
                let core = build(&joints, &rest_t, &map, &inverse, &base)?;
                (base, core, "table".to_string())
            }
            (rest_core, None) => {
                // Take the clip frame needing the smallest swings.
                let step = bvh.frames.div_ceil(MAX_BASE_CANDIDATES).max(1);
                let mut best: Option<(Vec<DQuat>, Core, usize)> = None;
                for f in (0..bvh.frames).step_by(step) {
                    let base: Vec<DQuat> = (0..joints.len()).map(|u| bvh.local_transform(f, u).1).collect();
                    if let Ok(core) = build(&joints, &rest_t, &map, &inverse, &base)
                        && best.as_ref().is_none_or(|b| core.max_swing < b.1.max_swing)
                    {
                        best = Some((base, core, f));
                    }
                }
                match (best, rest_core) {
                    (Some((base, core, f)), Err(e)) => {
                        notes.push(format!("the rest pose is degenerate ({e}): the reference pose is frame {f}"));
                        (base, core, format!("frame {f}"))
                    }
                    (Some((base, core, f)), Ok(rc)) if core.max_swing < rc.max_swing => {
                        notes.push(format!(
                            "the rest pose is far from a T- or A-pose (a bone {:.0}° off): the reference pose is frame {f}",
                            rc.max_swing.to_degrees()
                        ));
                        (base, core, format!("frame {f}"))
                    }
                    (_, Ok(rc)) => (rest, rc, "rest".into()),
                    (None, Err(e)) => return Err(e),
                }
            }
        };

        check_human(&joints, &rest_t, &map, &base_local, core.world)?;
        let synthesised: Vec<(String, String)> = (0..NUM_JOINTS)
            .filter(|&j| map[j].is_none())
            .map(|j| {
                let how = match j {
                    HEAD => "turns with the neck",
                    TOES_L | TOES_R => "along the foot",
                    SHOULDER_L | SHOULDER_R => "turns with the chest",
                    _ => "along the spine (turns with the joint below)",
                };
                (JOINT_NAMES[j].to_string(), how.to_string())
            })
            .collect();
        if !synthesised.is_empty() {
            let names: Vec<&str> = synthesised.iter().map(|(j, _)| j.as_str()).collect();
            notes.push(format!("synthesised on the canonical rig: {}", names.join(", ")));
        }

        // The chain root … Hips and the joint carrying the translation.
        let hips = map[HIPS].expect("required");
        let mut hips_chain = vec![hips];
        while let Some(p) = joints[*hips_chain.last().expect("non-empty")].parent {
            hips_chain.push(p);
        }
        hips_chain.reverse();
        let has_pos = |u: usize| joints[u].channels.iter().any(|c| matches!(c, Channel::Position(_)));
        let carrier = hips_chain.iter().rev().copied().find(|&u| has_pos(u));

        let feet_can: Vec<usize> = FEET.iter().copied().filter(|&j| map[j].is_some()).collect();
        let feet_user: Vec<usize> = feet_can.iter().map(|&j| map[j].expect("matched")).collect();
        let can = canonical_tpose();
        let lowest = |js: &[usize]| js.iter().map(|&j| can[j].y).fold(f64::INFINITY, f64::min);
        let foot_rest = lowest(&feet_can) - lowest(&FEET);
        let up = core.world.inverse() * DVec3::Y;
        let fwd = core.world.inverse() * DVec3::Z;
        let mut rig = UserRig {
            report: RigReport {
                rig: det.rig.to_string(),
                matched: (0..NUM_JOINTS)
                    .filter_map(|j| map[j].map(|u| (JOINT_NAMES[j].to_string(), joints[u].name.clone())))
                    .collect(),
                missing: (0..NUM_JOINTS).filter(|&j| map[j].is_none()).map(|j| JOINT_NAMES[j].to_string()).collect(),
                scale: core.scale,
                up_axis: axis_name(up),
                forward_axis: axis_name(fwd),
                floor: 0.0,
                base_pose: base_name,
            },
            synthesised,
            notes,
            joints,
            rest_t,
            map,
            inverse,
            base_local,
            t_global: core.t_global,
            world: core.world,
            scale: core.scale,
            floor: 0.0,
            hips_chain,
            carrier,
            feet_can,
            feet_user,
            foot_rest,
        };
        let plan = resample::plan(bvh.frames, resample::source_fps(bvh.frame_time))?;
        let floor = percentile(&mut rig.user_lows(bvh, &plan), FLOOR_PERCENTILE);
        if !floor.is_finite() {
            return Err(degenerate("the feet's heights are not finite"));
        }
        rig.floor = floor;
        rig.report.floor = floor;
        Ok(rig)
    }
}
