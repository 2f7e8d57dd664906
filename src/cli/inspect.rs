//! `motion-stylizer inspect FILE.bvh [--json] [--map FILE.json]`.
//!
//! `retargetable` is exactly whether the import (matching, retargeting, resampling) succeeds; when
//! it does not, `error` says why (with the import's code) and `map` holds the best guesses, so that
//! the JSON's `map` can be edited and passed back with `--map`.

use anyhow::Context;
use motion_stylizer::bvh::Bvh;
use motion_stylizer::skeleton::{self, ImportError, JOINT_NAMES, rigs};
use serde_json::json;
use std::path::Path;

pub fn run(file: &Path, as_json: bool, map_file: Option<&Path>) -> anyhow::Result<()> {
    let text = super::read_text(file)?;
    let manual = super::read_map(map_file)?;
    let bvh = Bvh::parse(&text).with_context(|| format!("cannot read {}", file.display()))?;
    // A rig that cannot be retargeted is still worth describing: what was found, what is missing.
    let result = skeleton::import_with(&bvh, manual.as_ref());
    let (rig, map, missing, scale, synthesised, notes, base_pose, error) = match &result {
        Ok(imp) => {
            let r = imp.rig.report();
            let synth: Vec<(String, String)> = imp.rig.synthesised().to_vec();
            (
                r.rig.clone(),
                *imp.rig.joint_map(),
                r.missing.clone(),
                Some(r.scale),
                synth,
                imp.rig.notes().to_vec(),
                Some(r.base_pose.clone()),
                None,
            )
        }
        Err(e) => {
            let (rig, guess) = match rigs::detect(&bvh.joints) {
                Ok(d) => (d.rig.to_string(), d.map),
                Err(u) => (u.rig.to_string(), *u.map),
            };
            let (rig, missing) = match e {
                ImportError::MissingJoints { missing, rig } => (rig.clone(), missing.clone()),
                _ => (rig, Vec::new()),
            };
            (rig, guess, missing, None, Vec::new(), Vec::new(), None, Some(e))
        }
    };
    let matched: Vec<(&str, &str)> =
        (0..JOINT_NAMES.len()).filter_map(|j| map[j].map(|u| (JOINT_NAMES[j], bvh.joints[u].name.as_str()))).collect();
    let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
    if as_json {
        let matched_obj: serde_json::Map<String, serde_json::Value> =
            matched.iter().map(|(c, u)| (c.to_string(), json!(u))).collect();
        let synth_obj: serde_json::Map<String, serde_json::Value> =
            synthesised.iter().map(|(c, how)| (c.clone(), json!(how))).collect();
        let out = json!({
            "file": file.display().to_string(),
            "joints": bvh.joints.len(),
            "joint_names": names,
            "frames": bvh.frames,
            "fps": bvh.fps(),
            "duration_s": bvh.duration(),
            "channels": bvh.num_channels(),
            "rig": rig,
            "matched": matched_obj,
            "missing": missing,
            "synthesised": synth_obj,
            "retargetable": error.is_none(),
            "error": error.map(|e| json!({ "code": e.code(), "message": e.to_string() })),
            "scale_to_canonical": scale,
            "base_pose": base_pose,
            "notes": notes,
            "map": skeleton::map_json(&bvh.joints, &map),
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!("file:      {}", file.display());
        println!("joints:    {}", bvh.joints.len());
        println!("frames:    {}", bvh.frames);
        println!("fps:       {:.3}", bvh.fps());
        println!("duration:  {:.3} s", bvh.duration());
        println!("rig:       {rig}");
        if let Some(s) = scale {
            println!("scale:     {s:.4} (to the canonical rig's centimetres)");
        }
        println!("matched:   {} of 21 canonical joints", matched.len());
        for (c, u) in &matched {
            println!("  {c:<11} <- {u}");
        }
        for (c, how) in &synthesised {
            println!("  {c:<11} synthesised ({how})");
        }
        for n in &notes {
            println!("note:      {n}");
        }
        match &error {
            None => println!("retargetable: yes"),
            Some(e) => {
                if !missing.is_empty() {
                    println!("missing:   {}", missing.join(", "));
                }
                println!("retargetable: no: {e} ({}); `inspect --json` prints a `map` to edit for --map", e.code());
            }
        }
    }
    Ok(())
}
