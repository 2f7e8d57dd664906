//! `motion-stylizer inspect FILE.bvh [--json]`.

use anyhow::Context;
use motion_stylizer::bvh::Bvh;
use motion_stylizer::skeleton::{ImportError, UserRig};
use serde_json::json;
use std::path::Path;

pub fn run(file: &Path, as_json: bool) -> anyhow::Result<()> {
    let text = super::read_text(file)?;
    let bvh = Bvh::parse(&text).with_context(|| format!("cannot read {}", file.display()))?;
    // A rig that cannot be retargeted is still worth describing: report what is missing.
    let (rig, matched, missing, scale) = match UserRig::from_bvh(&bvh) {
        Ok(rig) => {
            let r = rig.report();
            (r.rig.clone(), r.matched.clone(), r.missing.clone(), Some(r.scale))
        }
        Err(ImportError::MissingJoints { rig, missing }) => (rig, Vec::new(), missing, None),
        Err(e) => return Err(e).with_context(|| format!("cannot match the rig of {}", file.display())),
    };
    let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
    if as_json {
        let matched_obj: serde_json::Map<String, serde_json::Value> =
            matched.iter().map(|(c, u)| (c.clone(), json!(u))).collect();
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
            "retargetable": missing.is_empty(),
            "scale_to_canonical": scale,
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
        if missing.is_empty() {
            println!("missing:   none");
        } else {
            println!("missing:   {} (cannot be retargeted)", missing.join(", "));
        }
    }
    Ok(())
}
