//! Reads BVH files, writes each back with our writer and dumps world joint positions for a few frames,
//! for the three.js compatibility check (`tests/js/bvh_threejs.test.mjs`).
//!
//! ```text
//! cargo run --release --example bvh_dump -- OUT_DIR IN.bvh...
//! ```
//!
//! For every `IN.bvh`: `OUT_DIR/<stem>.bvh` (our writer's output) and `OUT_DIR/<stem>.json` with the
//! frame time, the sampled frame indices and, per sampled frame, the world position of every joint and
//! every End Site computed by [`Bvh::global_pose`] on the *input* file. `OUT_DIR/manifest.json` lists
//! the stems.
use motion_stylizer::bvh::Bvh;
use serde_json::json;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (out_dir, inputs) = match args.split_first() {
        Some((out, inputs)) if !inputs.is_empty() => (Path::new(out), inputs),
        _ => return Err("usage: bvh_dump OUT_DIR IN.bvh...".into()),
    };
    std::fs::create_dir_all(out_dir)?;
    let mut stems = Vec::new();
    for input in inputs {
        let text = std::fs::read_to_string(input)?;
        let bvh = Bvh::parse(&text).map_err(|e| format!("{input}: {e}"))?;
        let stem = Path::new(input).file_stem().ok_or("no file name")?.to_string_lossy().into_owned();
        std::fs::write(out_dir.join(format!("{stem}.bvh")), bvh.to_bvh_string())?;

        let last = bvh.frames - 1;
        let mut frames = vec![0, 1, last / 3, last / 2, 2 * last / 3, last.saturating_sub(1), last];
        frames.retain(|&f| f <= last);
        frames.sort_unstable();
        frames.dedup();
        let mut joints = Vec::new();
        let mut end_sites = Vec::new();
        for &f in &frames {
            let (pos, rot) = bvh.global_pose(f);
            joints.push(pos.iter().map(|p| p.to_array()).collect::<Vec<_>>());
            let sites: serde_json::Map<String, serde_json::Value> = bvh
                .joints
                .iter()
                .enumerate()
                .filter_map(|(j, joint)| {
                    let site = joint.end_site?;
                    Some((joint.name.clone(), json!((pos[j] + rot[j] * site).to_array())))
                })
                .collect();
            end_sites.push(sites);
        }
        let dump = json!({
            "source": input,
            "frame_time": bvh.frame_time,
            "num_frames": bvh.frames,
            "frames": frames,
            "names": bvh.joints.iter().map(|j| j.name.as_str()).collect::<Vec<_>>(),
            "joints": joints,
            "end_sites": end_sites,
        });
        std::fs::write(out_dir.join(format!("{stem}.json")), serde_json::to_string(&dump)?)?;
        stems.push(stem);
    }
    std::fs::write(out_dir.join("manifest.json"), serde_json::to_string(&json!({ "cases": stems }))?)?;
    Ok(())
}
