//! BVH writer.
use super::{Axis, Bvh, Channel};
use glam::DVec3;

impl Bvh {
    /// This motion as BVH text in the usual layout (`HIERARCHY`, `ROOT`/`JOINT`/`End Site` blocks
    /// indented with tabs, `MOTION`, `Frames:`, `Frame Time:`, one line per frame), which
    /// [`Bvh::parse`], three.js's `BVHLoader` and other viewers load back with the same pose.
    ///
    /// * Numbers are written in shortest round-trip form (ryū: `0.0333333`, `-12.5`, `1e-7`;
    ///   `90` for `90.0`), so re-parsing gives back bit-identical values.
    /// * An OFFSET component that a position channel of the same joint replaces is written as `0`.
    ///   It never affects the pose here (the channel replaces it), but some readers, three.js among
    ///   them, *add* position channels to the OFFSET; a zero makes both readings agree. The re-parsed
    ///   [`BvhJoint::offset`](super::BvhJoint::offset) of such a joint therefore has zeros there.
    /// * Joints are written depth-first, children in index order, with their channels gathered
    ///   accordingly; for a `Bvh` from [`Bvh::parse`] that is the original order.
    ///
    /// `self` must be well formed, as every parsed `Bvh` is: joint 0 the root, every parent index
    /// smaller than its child's, `values.len() == frames × num_channels()`, finite values, and each
    /// joint's `channel_offset` the sum of the channel counts before it. Otherwise this panics
    /// (a programming error) or writes a file that the reader rejects (non-finite values).
    pub fn to_bvh_string(&self) -> String {
        let n = self.joints.len();
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (i, j) in self.joints.iter().enumerate() {
            if let Some(p) = j.parent {
                assert!(p < i, "joint {i}: parent {p} does not precede it");
                children[p].push(i);
            }
        }
        let nch = self.num_channels();
        assert_eq!(self.values.len(), self.frames * nch, "values.len() != frames × num_channels");

        let mut out = String::with_capacity(256 + 100 * n + self.values.len() * 11);
        let mut num = ryu::Buffer::new();
        // Depth-first order of the joints as written: each joint's channels go to the row in this order.
        let mut order = Vec::with_capacity(n);
        out.push_str("HIERARCHY\n");
        // (joint, next child to visit); the depth is the stack height.
        let mut stack: Vec<(usize, usize)> = Vec::new();
        for root in (0..n).filter(|&i| self.joints[i].parent.is_none()) {
            self.open_joint(&mut out, &mut num, root, 0);
            order.push(root);
            stack.push((root, 0));
            while let Some(&(joint, next)) = stack.last() {
                let depth = stack.len();
                if let Some(&child) = children[joint].get(next) {
                    stack[depth - 1].1 += 1;
                    self.open_joint(&mut out, &mut num, child, depth);
                    order.push(child);
                    stack.push((child, 0));
                } else {
                    if let Some(site) = self.joints[joint].end_site {
                        indent(&mut out, depth);
                        out.push_str("End Site\n");
                        indent(&mut out, depth);
                        out.push_str("{\n");
                        indent(&mut out, depth + 1);
                        out.push_str("OFFSET");
                        push_vec(&mut out, &mut num, site);
                        indent(&mut out, depth);
                        out.push_str("}\n");
                    }
                    indent(&mut out, depth - 1);
                    out.push_str("}\n");
                    stack.pop();
                }
            }
        }
        out.push_str("MOTION\nFrames: ");
        out.push_str(&self.frames.to_string());
        out.push_str("\nFrame Time: ");
        push_num(&mut out, &mut num, self.frame_time);
        out.push('\n');

        // Channel ranges in written order.
        let ranges: Vec<(usize, usize)> = order
            .iter()
            .map(|&j| (self.joints[j].channel_offset, self.joints[j].channel_offset + self.joints[j].channels.len()))
            .filter(|r| r.0 < r.1)
            .collect();
        if nch > 0 {
            for row in self.values.chunks_exact(nch) {
                let mut first = true;
                for &(a, b) in &ranges {
                    for &v in &row[a..b] {
                        if !first {
                            out.push(' ');
                        }
                        first = false;
                        push_num(&mut out, &mut num, v);
                    }
                }
                out.push('\n');
            }
        }
        out
    }

    fn open_joint(&self, out: &mut String, num: &mut ryu::Buffer, j: usize, depth: usize) {
        let joint = &self.joints[j];
        indent(out, depth);
        out.push_str(if depth == 0 { "ROOT " } else { "JOINT " });
        out.push_str(&joint.name);
        out.push('\n');
        indent(out, depth);
        out.push_str("{\n");
        let mut offset = joint.offset;
        for ch in &joint.channels {
            if let Channel::Position(a) = *ch {
                offset[a.index()] = 0.0;
            }
        }
        indent(out, depth + 1);
        out.push_str("OFFSET");
        push_vec(out, num, offset);
        indent(out, depth + 1);
        out.push_str("CHANNELS ");
        out.push_str(&joint.channels.len().to_string());
        for ch in &joint.channels {
            out.push_str(match *ch {
                Channel::Position(Axis::X) => " Xposition",
                Channel::Position(Axis::Y) => " Yposition",
                Channel::Position(Axis::Z) => " Zposition",
                Channel::Rotation(Axis::X) => " Xrotation",
                Channel::Rotation(Axis::Y) => " Yrotation",
                Channel::Rotation(Axis::Z) => " Zrotation",
            });
        }
        out.push('\n');
    }
}

fn indent(out: &mut String, depth: usize) {
    for _ in 0..depth {
        out.push('\t');
    }
}

/// ` x y z\n`
fn push_vec(out: &mut String, num: &mut ryu::Buffer, v: DVec3) {
    for c in v.to_array() {
        out.push(' ');
        push_num(out, num, c);
    }
    out.push('\n');
}

/// Shortest round-trip decimal, without ryū's `.0` on integers.
#[inline]
fn push_num(out: &mut String, num: &mut ryu::Buffer, v: f64) {
    let s = num.format(v);
    out.push_str(s.strip_suffix(".0").unwrap_or(s));
}
