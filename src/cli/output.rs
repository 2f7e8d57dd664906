//! Writing a motion file, in the format its extension names: `.glb` (binary glTF,
//! [`motion_stylizer::gltf`]) or BVH (`.bvh` and anything else, as before). `.gltf` (JSON glTF with
//! a separate buffer) is refused with a pointer to `.glb`.

use anyhow::{Context, bail};
use motion_stylizer::bvh::Bvh;
use motion_stylizer::gltf::{self, GltfOptions};
use motion_stylizer::skeleton::RigReport;
use std::path::Path;

/// The file formats `-o` can write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Bvh,
    Glb,
}

impl Format {
    /// The format of `path`, by its extension (case-insensitive): `.glb` is glTF, `.gltf` an error,
    /// everything else BVH.
    pub fn of(path: &Path) -> anyhow::Result<Format> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("glb") => Ok(Format::Glb),
            Some("gltf") => {
                bail!("{}: write binary glTF instead (-o NAME.glb); .gltf is not supported", path.display())
            }
            _ => Ok(Format::Bvh),
        }
    }
}

/// Which space the motion's BVH is in, for its glTF (metres, Y up, facing +Z).
pub enum Rig<'a> {
    Canonical,
    User(&'a RigReport),
}

impl Rig<'_> {
    fn gltf_options(&self) -> GltfOptions {
        match self {
            Rig::Canonical => GltfOptions::canonical(),
            Rig::User(report) => GltfOptions::for_rig(report),
        }
    }
}

/// Writes `bvh` to `path` as BVH text or as `.glb` (by the extension), with the path in errors.
pub fn write_motion(path: &Path, bvh: &Bvh, rig: Rig<'_>) -> anyhow::Result<()> {
    match Format::of(path)? {
        Format::Bvh => super::write_text(path, &bvh.to_bvh_string()),
        Format::Glb => {
            let bytes = gltf::to_glb(bvh, &rig.gltf_options())
                .with_context(|| format!("cannot write {} as glTF", path.display()))?;
            std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension() {
        assert_eq!(Format::of(Path::new("a/out.glb")).unwrap(), Format::Glb);
        assert_eq!(Format::of(Path::new("OUT.GLB")).unwrap(), Format::Glb);
        assert_eq!(Format::of(Path::new("out.bvh")).unwrap(), Format::Bvh);
        assert_eq!(Format::of(Path::new("out")).unwrap(), Format::Bvh);
        assert!(Format::of(Path::new("out.gltf")).is_err());
    }
}
