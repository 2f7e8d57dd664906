//! `motion-stylizer retarget FILE.bvh -o OUT.bvh|OUT.glb [--onto RIG.bvh [--onto-map RIG.json]] [--map FILE.json]`.

use super::output::Rig;
use anyhow::Context;
use motion_stylizer::bvh::Bvh;
use motion_stylizer::skeleton::{self, UserRig};
use std::path::Path;

pub fn run(
    file: &Path,
    output: &Path,
    onto: Option<&Path>,
    map: Option<&Path>,
    onto_map: Option<&Path>,
) -> anyhow::Result<()> {
    let text = super::read_text(file)?;
    let map = super::read_map(map)?;
    let imported =
        skeleton::import_bvh_with(&text, map.as_ref()).with_context(|| format!("cannot import {}", file.display()))?;
    let rig = match onto {
        None => None,
        Some(rig_path) => {
            let rig_text = super::read_text(rig_path)?;
            let rig_bvh = Bvh::parse(&rig_text).with_context(|| format!("cannot read {}", rig_path.display()))?;
            let rig_map = super::read_map(onto_map)?;
            let rig = UserRig::from_bvh_with(&rig_bvh, rig_map.as_ref())
                .with_context(|| format!("cannot use {} as a rig", rig_path.display()))?;
            Some(rig)
        }
    };
    let out = match &rig {
        None => imported.motion.to_bvh(),
        Some(rig) => rig.from_canonical(&imported.motion),
    };
    let space = rig.as_ref().map_or(Rig::Canonical, |r| Rig::User(r.report()));
    super::output::write_motion(output, &out, space)?;
    eprintln!(
        "{} ({}, {} frames) -> {} ({} frames at 30 fps)",
        file.display(),
        imported.rig.report().rig,
        imported.motion.frames(),
        output.display(),
        out.frames
    );
    Ok(())
}
