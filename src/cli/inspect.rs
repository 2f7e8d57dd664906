//! `motion-stylizer inspect FILE.bvh [--json] [--map FILE.json]`.
//!
//! `retargetable` is exactly whether the import (matching, retargeting, resampling) succeeds; when
//! it does not, `error` says why (with the import's code) and `map` holds the best guesses, so that
//! the JSON's `map` can be edited and passed back with `--map`.

use anyhow::Context;
use motion_stylizer::bvh::Bvh;
use motion_stylizer::skeleton::{self, JOINT_NAMES};
use std::path::Path;

pub fn run(file: &Path, as_json: bool, map_file: Option<&Path>) -> anyhow::Result<()> {
    let text = super::read_text(file)?;
    let manual = super::read_map(map_file)?;
    let bvh = Bvh::parse(&text).with_context(|| format!("cannot read {}", file.display()))?;
    // A rig that cannot be retargeted is still worth describing: what was found, what is missing.
    let (found, _) = skeleton::inspect(&bvh, manual.as_ref());
    if as_json {
        let mut out = serde_json::Map::new();
        out.insert("file".into(), file.display().to_string().into());
        if let serde_json::Value::Object(rest) = found.to_json(&bvh) {
            out.extend(rest);
        }
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    let matched = found.matched(&bvh);
    println!("file:      {}", file.display());
    println!("joints:    {}", bvh.joints.len());
    println!("frames:    {}", bvh.frames);
    println!("fps:       {:.3}", bvh.fps());
    println!("duration:  {:.3} s", bvh.duration());
    println!("rig:       {}", found.rig);
    if let Some(s) = found.scale {
        println!("scale:     {s:.4} (to the canonical rig's centimetres)");
    }
    println!("matched:   {} of {} canonical joints", matched.len(), JOINT_NAMES.len());
    for (c, u) in &matched {
        println!("  {c:<11} <- {u}");
    }
    for (c, how) in &found.synthesised {
        println!("  {c:<11} synthesised ({how})");
    }
    for n in &found.notes {
        println!("note:      {n}");
    }
    match &found.error {
        None => println!("retargetable: yes"),
        Some(e) => {
            if !found.missing.is_empty() {
                println!("missing:   {}", found.missing.join(", "));
            }
            println!("retargetable: no: {e} ({}); `inspect --json` prints a `map` to edit for --map", e.code());
        }
    }
    Ok(())
}
