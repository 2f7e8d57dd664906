//! BVH writer. (Being written: see the helper brief.)
use super::Bvh;

impl Bvh {
    pub fn to_bvh_string(&self) -> String {
        unimplemented!("BVH writer")
    }
}
