//! Per-body-part styles: a style for the lower body, another for the upper body, another for the
//! head (as Motion Puzzle offers), on one content.
//!
//! How, in a temporal-convolution model whose style code is global to the clip: each part's
//! request is stylized on its own (the whole body, [`stylize`](super::stylize)), then the outputs are combined
//! joint by joint after decoding — local rotations of each part's joints from that part's output,
//! the root (trajectory and hips rotation) and both legs from the lower body's. Local rotations of
//! the upper body and the head ride on the lower body's hips, so the combination is a valid pose
//! on every frame; the lower body's output already has its feet planted (root correction and leg
//! IK in [`stylize`](super::stylize)), and nothing above the hips moves a foot. A part without a request keeps the
//! content's own motion.

use super::{Request, StylizeError, Weights, stylize_async};
use crate::motion::Motion;
use crate::skeleton::canonical::joint::*;

/// A part of the body a style can be given to separately.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BodyPart {
    /// The root (trajectory, hips) and both legs.
    Lower,
    /// Spine, chest, shoulders and arms.
    Upper,
    /// Neck and head.
    Head,
}

impl BodyPart {
    pub const ALL: [BodyPart; 3] = [BodyPart::Lower, BodyPart::Upper, BodyPart::Head];

    /// `"lower"`, `"upper"`, `"head"`.
    pub fn as_str(self) -> &'static str {
        match self {
            BodyPart::Lower => "lower",
            BodyPart::Upper => "upper",
            BodyPart::Head => "head",
        }
    }

    pub fn from_name(name: &str) -> Option<BodyPart> {
        BodyPart::ALL.into_iter().find(|p| p.as_str() == name)
    }

    /// The canonical joints whose local rotations the part owns (every joint is in one part).
    pub fn joints(self) -> &'static [usize] {
        match self {
            BodyPart::Lower => {
                &[HIPS, UPPER_LEG_L, LOWER_LEG_L, FOOT_L, TOES_L, UPPER_LEG_R, LOWER_LEG_R, FOOT_R, TOES_R]
            }
            BodyPart::Upper => &[
                SPINE,
                CHEST,
                SHOULDER_L,
                UPPER_ARM_L,
                LOWER_ARM_L,
                HAND_L,
                SHOULDER_R,
                UPPER_ARM_R,
                LOWER_ARM_R,
                HAND_R,
            ],
            BodyPart::Head => &[NECK, HEAD],
        }
    }
}

/// One request per part; `None` keeps the content's motion for that part. The requests' sample
/// counts must agree.
#[derive(Clone, Debug, Default)]
pub struct PartRequests<'a> {
    pub lower: Option<Request<'a>>,
    pub upper: Option<Request<'a>>,
    pub head: Option<Request<'a>>,
}

impl<'a> PartRequests<'a> {
    pub fn get(&self, part: BodyPart) -> Option<&Request<'a>> {
        match part {
            BodyPart::Lower => self.lower.as_ref(),
            BodyPart::Upper => self.upper.as_ref(),
            BodyPart::Head => self.head.as_ref(),
        }
    }

    pub fn set(&mut self, part: BodyPart, request: Request<'a>) {
        match part {
            BodyPart::Lower => self.lower = Some(request),
            BodyPart::Upper => self.upper = Some(request),
            BodyPart::Head => self.head = Some(request),
        }
    }
}

/// `samples` motions with each part styled as `parts` asks (see the module doc). Errors: those of
/// [`stylize`](super::stylize) for any part's request; [`StylizeError::Parts`] when no part has a request or their
/// sample counts differ.
pub fn stylize_parts(
    weights: &Weights,
    content: &Motion,
    parts: &PartRequests<'_>,
) -> Result<Vec<Motion>, StylizeError> {
    super::pipeline::complete(stylize_parts_async(weights, content, parts))
}

/// [`stylize_parts`] for a device whose results are read asynchronously (WebGPU in a browser).
pub async fn stylize_parts_async(
    weights: &Weights,
    content: &Motion,
    parts: &PartRequests<'_>,
) -> Result<Vec<Motion>, StylizeError> {
    let counts: Vec<usize> = BodyPart::ALL.iter().filter_map(|&p| parts.get(p).map(|r| r.samples)).collect();
    let Some(&samples) = counts.first() else {
        return Err(StylizeError::Parts("give a style to at least one body part".into()));
    };
    if counts.iter().any(|&n| n != samples) {
        return Err(StylizeError::Parts(format!("every part needs the same number of samples, got {counts:?}")));
    }
    // Stylize each part's request once (a part whose request equals an earlier part's reuses its
    // outputs); in BodyPart::ALL's order: lower, upper, head.
    let mut outputs: Vec<Vec<Motion>> = Vec::with_capacity(3);
    for (i, part) in BodyPart::ALL.into_iter().enumerate() {
        let motions = match parts.get(part) {
            None => vec![content.clone(); samples],
            Some(request) => match (0..i).find(|&k| parts.get(BodyPart::ALL[k]) == Some(request)) {
                Some(k) => outputs[k].clone(),
                None => stylize_async(weights, content, request).await?,
            },
        };
        outputs.push(motions);
    }
    (0..samples).map(|i| combine([&outputs[0][i], &outputs[1][i], &outputs[2][i]])).collect()
}

/// The lower body's root and legs, the upper body's spine and arms, the head's neck and head, as
/// one motion (all three as long as each other, on the canonical rig).
pub fn combine([lower, upper, head]: [&Motion; 3]) -> Result<Motion, StylizeError> {
    // Rotations copied as they are (no renormalisation): the lower body's joints and root keep
    // the exact bits of its own output.
    let differ = || StylizeError::Parts("the parts' motions differ in length".into());
    let with_upper = lower.with_joints_from(upper, BodyPart::Upper.joints()).ok_or_else(differ)?;
    with_upper.with_joints_from(head, BodyPart::Head.joints()).ok_or_else(differ)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::canonical::NUM_JOINTS;

    #[test]
    fn every_joint_is_in_exactly_one_part() {
        let mut owner = [0usize; NUM_JOINTS];
        for part in BodyPart::ALL {
            for &j in part.joints() {
                owner[j] += 1;
            }
            assert_eq!(BodyPart::from_name(part.as_str()), Some(part));
        }
        assert_eq!(owner, [1; NUM_JOINTS]);
        assert_eq!(BodyPart::from_name("arms"), None);
    }
}
