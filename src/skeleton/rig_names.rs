//! The name tables of the rigs [`super::rigs`] detects: per naming scheme, each canonical joint's
//! candidate user joint names (in priority order); the generic matcher's synonyms; and the base
//! poses of the rigs whose zero-rotation rest pose is no use. Data only: adding a rig's names
//! happens here.

use super::canonical::joint::*;
use super::rigs::BasePose;

pub(super) const BANDAI_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["Hips"]),
    (SPINE, &["Spine"]),
    (CHEST, &["Chest"]),
    (NECK, &["Neck"]),
    (HEAD, &["Head"]),
    (SHOULDER_L, &["Shoulder_L"]),
    (UPPER_ARM_L, &["UpperArm_L"]),
    (LOWER_ARM_L, &["LowerArm_L"]),
    (HAND_L, &["Hand_L"]),
    (SHOULDER_R, &["Shoulder_R"]),
    (UPPER_ARM_R, &["UpperArm_R"]),
    (LOWER_ARM_R, &["LowerArm_R"]),
    (HAND_R, &["Hand_R"]),
    (UPPER_LEG_L, &["UpperLeg_L"]),
    (LOWER_LEG_L, &["LowerLeg_L"]),
    (FOOT_L, &["Foot_L"]),
    (TOES_L, &["Toes_L"]),
    (UPPER_LEG_R, &["UpperLeg_R"]),
    (LOWER_LEG_R, &["LowerLeg_R"]),
    (FOOT_R, &["Foot_R"]),
    (TOES_R, &["Toes_R"]),
];

/// CMU-31 (`LHipJoint`, `LowerBack`, `Neck`, `Neck1`, …). `Neck1` plays the neck: CMU's `Neck` starts
/// at the top of `Spine1` (zero-length bone), while `Neck1` sits where the canonical Neck does, just
/// above the shoulders. `LowerBack` and `Neck` stay unmatched. The 21-joint rig of
/// Semi-Motion-Style-Transfer (`m21`: `Spine`, `Spine1`, `Neck1`, …) uses the same names, so it shares
/// this table (`Neck` as a fallback for rigs without `Neck1`).
pub(super) const CMU31_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["Hips"]),
    (SPINE, &["Spine"]),
    (CHEST, &["Spine1"]),
    (NECK, &["Neck1", "Neck"]),
    (HEAD, &["Head"]),
    (SHOULDER_L, &["LeftShoulder"]),
    (UPPER_ARM_L, &["LeftArm"]),
    (LOWER_ARM_L, &["LeftForeArm"]),
    (HAND_L, &["LeftHand"]),
    (SHOULDER_R, &["RightShoulder"]),
    (UPPER_ARM_R, &["RightArm"]),
    (LOWER_ARM_R, &["RightForeArm"]),
    (HAND_R, &["RightHand"]),
    (UPPER_LEG_L, &["LeftUpLeg"]),
    (LOWER_LEG_L, &["LeftLeg"]),
    (FOOT_L, &["LeftFoot"]),
    (TOES_L, &["LeftToeBase"]),
    (UPPER_LEG_R, &["RightUpLeg"]),
    (LOWER_LEG_R, &["RightLeg"]),
    (FOOT_R, &["RightFoot"]),
    (TOES_R, &["RightToeBase"]),
];

/// Reallusion Character Creator (`CC_Base_*`, iClone). The Hip (root) is the Hips: it carries both the
/// Pelvis (legs) and the Waist (spine). Spine01 and Spine02 sit where the canonical Spine and Chest do;
/// the neck is NeckTwist02 (NeckTwist01 barely moves in practice, NeckTwist02 does). Pelvis, Waist,
/// NeckTwist01, twist/share bones, fingers, toes and face stay unmatched.
pub(super) const CC_BASE_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["CC_Base_Hip"]),
    (SPINE, &["CC_Base_Spine01", "CC_Base_Waist"]),
    (CHEST, &["CC_Base_Spine02"]),
    (NECK, &["CC_Base_NeckTwist02", "CC_Base_NeckTwist01"]),
    (HEAD, &["CC_Base_Head"]),
    (SHOULDER_L, &["CC_Base_L_Clavicle"]),
    (UPPER_ARM_L, &["CC_Base_L_Upperarm"]),
    (LOWER_ARM_L, &["CC_Base_L_Forearm"]),
    (HAND_L, &["CC_Base_L_Hand"]),
    (SHOULDER_R, &["CC_Base_R_Clavicle"]),
    (UPPER_ARM_R, &["CC_Base_R_Upperarm"]),
    (LOWER_ARM_R, &["CC_Base_R_Forearm"]),
    (HAND_R, &["CC_Base_R_Hand"]),
    (UPPER_LEG_L, &["CC_Base_L_Thigh"]),
    (LOWER_LEG_L, &["CC_Base_L_Calf"]),
    (FOOT_L, &["CC_Base_L_Foot"]),
    (TOES_L, &["CC_Base_L_ToeBase"]),
    (UPPER_LEG_R, &["CC_Base_R_Thigh"]),
    (LOWER_LEG_R, &["CC_Base_R_Calf"]),
    (FOOT_R, &["CC_Base_R_Foot"]),
    (TOES_R, &["CC_Base_R_ToeBase"]),
];

/// Mixamo (`mixamorig:Hips`, `Spine`, `Spine1`, `Spine2`, …; any `mixamorigN:` prefix or none). Spine1
/// and Spine2 sit where the canonical Spine and Chest do; Mixamo's first `Spine` stays unmatched.
pub(super) const MIXAMO_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["Hips"]),
    (CHEST, &["Spine2", "Spine1"]),
    (SPINE, &["Spine1", "Spine"]),
    (NECK, &["Neck"]),
    (HEAD, &["Head"]),
    (SHOULDER_L, &["LeftShoulder"]),
    (UPPER_ARM_L, &["LeftArm"]),
    (LOWER_ARM_L, &["LeftForeArm"]),
    (HAND_L, &["LeftHand"]),
    (SHOULDER_R, &["RightShoulder"]),
    (UPPER_ARM_R, &["RightArm"]),
    (LOWER_ARM_R, &["RightForeArm"]),
    (HAND_R, &["RightHand"]),
    (UPPER_LEG_L, &["LeftUpLeg"]),
    (LOWER_LEG_L, &["LeftLeg"]),
    (FOOT_L, &["LeftFoot"]),
    (TOES_L, &["LeftToeBase", "LeftToe_End"]),
    (UPPER_LEG_R, &["RightUpLeg"]),
    (LOWER_LEG_R, &["RightLeg"]),
    (FOOT_R, &["RightFoot"]),
    (TOES_R, &["RightToeBase", "RightToe_End"]),
];

// The tables below are compared after [`super::rigs::normalise`] (case, separators, namespaces and
// `Bip01`-style prefixes dropped), so `L_Hip`, `l_hip` and `LHip` are one name. Spine and chest of
// the schemes marked so in [`super::rigs::SCHEMES`] are then set from the structure (the chest is the
// spine joint the arms hang from); the table's spine names are the fallback.

/// Daz Studio / Poser, and old Second Life BVH (CMU's "Daz-friendly" conversion: `hip`, `abdomen`,
/// `chest`, `neck`, `head`, `lCollar`, `lShldr`, `lForeArm`, `lHand`, `lButtock`, `lThigh`, `lShin`,
/// `lFoot`); Daz Genesis (`abdomenLower`/`Upper`, `chestLower`/`Upper`, `neckLower`/`Upper`,
/// `lShldrBend`, `lForearmBend`, `lThighBend`, `lMetatarsals`, `lToe`).
pub(super) const DAZ_POSER_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["hip", "hips"]),
    (SPINE, &["abdomen", "abdomenUpper", "abdomenLower", "abdomen2"]),
    (CHEST, &["chest", "chestUpper", "chestLower", "chest2"]),
    (NECK, &["neck", "neckLower", "neckUpper", "neck1"]),
    (HEAD, &["head"]),
    (SHOULDER_L, &["lCollar"]),
    (UPPER_ARM_L, &["lShldr", "lShldrBend", "lUpArm"]),
    (LOWER_ARM_L, &["lForeArm", "lForearmBend", "lLoArm"]),
    (HAND_L, &["lHand"]),
    (SHOULDER_R, &["rCollar"]),
    (UPPER_ARM_R, &["rShldr", "rShldrBend", "rUpArm"]),
    (LOWER_ARM_R, &["rForeArm", "rForearmBend", "rLoArm"]),
    (HAND_R, &["rHand"]),
    (UPPER_LEG_L, &["lThigh", "lThighBend"]),
    (LOWER_LEG_L, &["lShin"]),
    (FOOT_L, &["lFoot"]),
    (TOES_L, &["lToe", "lMetatarsals", "lToes"]),
    (UPPER_LEG_R, &["rThigh", "rThighBend"]),
    (LOWER_LEG_R, &["rShin"]),
    (FOOT_R, &["rFoot"]),
    (TOES_R, &["rToe", "rMetatarsals", "rToes"]),
];

/// Second Life's avatar skeleton (`mPelvis`, `mTorso`, `mChest`, `mNeck`, `mHead`, `mCollarLeft`,
/// `mShoulderLeft`, `mElbowLeft`, `mWristLeft`, `mHipLeft`, `mKneeLeft`, `mAnkleLeft`, `mFootLeft`).
pub(super) const SECOND_LIFE_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["mPelvis"]),
    (SPINE, &["mTorso", "mSpine2", "mSpine1"]),
    (CHEST, &["mChest", "mSpine4", "mSpine3"]),
    (NECK, &["mNeck"]),
    (HEAD, &["mHead"]),
    (SHOULDER_L, &["mCollarLeft"]),
    (UPPER_ARM_L, &["mShoulderLeft"]),
    (LOWER_ARM_L, &["mElbowLeft"]),
    (HAND_L, &["mWristLeft"]),
    (SHOULDER_R, &["mCollarRight"]),
    (UPPER_ARM_R, &["mShoulderRight"]),
    (LOWER_ARM_R, &["mElbowRight"]),
    (HAND_R, &["mWristRight"]),
    (UPPER_LEG_L, &["mHipLeft"]),
    (LOWER_LEG_L, &["mKneeLeft"]),
    (FOOT_L, &["mAnkleLeft"]),
    (TOES_L, &["mFootLeft", "mToeLeft"]),
    (UPPER_LEG_R, &["mHipRight"]),
    (LOWER_LEG_R, &["mKneeRight"]),
    (FOOT_R, &["mAnkleRight"]),
    (TOES_R, &["mFootRight", "mToeRight"]),
];

/// Acclaim ASF bone names as BVH joints (each joint sits where its bone starts: `lfemur` at the hip,
/// `lwrist` at the wrist): `root` or `pelvis`, `lhipjoint`, `lfemur`, `ltibia`, `lfoot`, `ltoes`,
/// `lowerback`, `upperback`, `thorax`, `lowerneck`, `upperneck`, `head`, `lclavicle`, `lhumerus`,
/// `lradius`, `lwrist`, `lhand`. As in CMU-31 (the same skeleton), `upperback` plays the spine and
/// `upperneck` the neck; `lhand` is the hand where there is no `lwrist`.
pub(super) const ACCLAIM_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["pelvis", "root", "hip", "hips"]),
    (SPINE, &["upperback", "lowerback"]),
    (CHEST, &["thorax"]),
    (NECK, &["upperneck", "lowerneck", "neck"]),
    (HEAD, &["head"]),
    (SHOULDER_L, &["lclavicle"]),
    (UPPER_ARM_L, &["lhumerus"]),
    (LOWER_ARM_L, &["lradius"]),
    (HAND_L, &["lwrist", "lhand"]),
    (SHOULDER_R, &["rclavicle"]),
    (UPPER_ARM_R, &["rhumerus"]),
    (LOWER_ARM_R, &["rradius"]),
    (HAND_R, &["rwrist", "rhand"]),
    (UPPER_LEG_L, &["lfemur"]),
    (LOWER_LEG_L, &["ltibia"]),
    (FOOT_L, &["lfoot"]),
    (TOES_L, &["ltoes"]),
    (UPPER_LEG_R, &["rfemur"]),
    (LOWER_LEG_R, &["rtibia"]),
    (FOOT_R, &["rfoot"]),
    (TOES_R, &["rtoes"]),
];

/// HumanIK / MotionBuilder (`Hips`, `Spine` … `Spine9`, `Neck`, `Neck1`, `Head`, `LeftUpLeg`,
/// `LeftUpLegRoll`, `LeftLeg`, `LeftFoot`, `LeftToeBase`, `LeftShoulder`, `LeftArm`, `LeftArmRoll`,
/// `LeftForeArm`, `LeftHand`, any `Character1:` namespace), and Rokoko / Perception Neuron (the same
/// names, Rokoko's `LeftThigh`, `LeftShin`, `LeftToe`). Roll bones stay unmatched.
pub(super) const HUMANIK_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["Hips"]),
    (SPINE, &["Spine1", "Spine"]),
    (CHEST, &["Spine2", "Spine1"]),
    (NECK, &["Neck", "Neck1"]),
    (HEAD, &["Head"]),
    (SHOULDER_L, &["LeftShoulder"]),
    (UPPER_ARM_L, &["LeftArm", "LeftUpperArm"]),
    (LOWER_ARM_L, &["LeftForeArm", "LeftLowerArm"]),
    (HAND_L, &["LeftHand"]),
    (SHOULDER_R, &["RightShoulder"]),
    (UPPER_ARM_R, &["RightArm", "RightUpperArm"]),
    (LOWER_ARM_R, &["RightForeArm", "RightLowerArm"]),
    (HAND_R, &["RightHand"]),
    (UPPER_LEG_L, &["LeftUpLeg", "LeftThigh", "LeftUpperLeg"]),
    (LOWER_LEG_L, &["LeftLeg", "LeftShin", "LeftLowerLeg"]),
    (FOOT_L, &["LeftFoot"]),
    (TOES_L, &["LeftToeBase", "LeftToe", "LeftToes"]),
    (UPPER_LEG_R, &["RightUpLeg", "RightThigh", "RightUpperLeg"]),
    (LOWER_LEG_R, &["RightLeg", "RightShin", "RightLowerLeg"]),
    (FOOT_R, &["RightFoot"]),
    (TOES_R, &["RightToeBase", "RightToe", "RightToes"]),
];

/// 3ds Max Biped (`Bip01 Pelvis`, `Bip01 Spine` … `Spine3`, `Bip01 Neck`, `Bip01 Head`,
/// `Bip01 L Clavicle`, `L UpperArm`, `L Forearm`, `L Hand`, `L Thigh`, `L Calf`, `L Foot`, `L Toe0`;
/// any `BipNN`/`BipNNN` prefix, spaces written as `_`). The `Bip01` root stays unmatched; the
/// clavicles hang from the neck, so the chest is the spine joint below it.
pub(super) const BIPED_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["Pelvis"]),
    (SPINE, &["Spine1", "Spine"]),
    (CHEST, &["Spine2", "Spine1"]),
    (NECK, &["Neck"]),
    (HEAD, &["Head"]),
    (SHOULDER_L, &["L_Clavicle"]),
    (UPPER_ARM_L, &["L_UpperArm"]),
    (LOWER_ARM_L, &["L_Forearm"]),
    (HAND_L, &["L_Hand"]),
    (SHOULDER_R, &["R_Clavicle"]),
    (UPPER_ARM_R, &["R_UpperArm"]),
    (LOWER_ARM_R, &["R_Forearm"]),
    (HAND_R, &["R_Hand"]),
    (UPPER_LEG_L, &["L_Thigh"]),
    (LOWER_LEG_L, &["L_Calf"]),
    (FOOT_L, &["L_Foot"]),
    (TOES_L, &["L_Toe0", "L_Toe"]),
    (UPPER_LEG_R, &["R_Thigh"]),
    (LOWER_LEG_R, &["R_Calf"]),
    (FOOT_R, &["R_Foot"]),
    (TOES_R, &["R_Toe0", "R_Toe"]),
];

/// SMPL / SMPL-X (`Pelvis`, `L_Hip`, `L_Knee`, `L_Ankle`, `L_Foot`, `Spine1` … `Spine3`, `Neck`,
/// `Head`, `L_Collar`, `L_Shoulder`, `L_Elbow`, `L_Wrist`, `L_Hand`; also `left_hip` …). The ankle is
/// the foot joint, SMPL's foot the ball of the foot, its shoulder the upper arm and its wrist the hand.
pub(super) const SMPL_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["Pelvis"]),
    (SPINE, &["Spine2", "Spine1", "Spine"]),
    (CHEST, &["Spine3", "Chest", "Spine2"]),
    (NECK, &["Neck"]),
    (HEAD, &["Head"]),
    (SHOULDER_L, &["L_Collar", "Left_Collar"]),
    (UPPER_ARM_L, &["L_Shoulder", "Left_Shoulder"]),
    (LOWER_ARM_L, &["L_Elbow", "Left_Elbow"]),
    (HAND_L, &["L_Wrist", "Left_Wrist"]),
    (SHOULDER_R, &["R_Collar", "Right_Collar"]),
    (UPPER_ARM_R, &["R_Shoulder", "Right_Shoulder"]),
    (LOWER_ARM_R, &["R_Elbow", "Right_Elbow"]),
    (HAND_R, &["R_Wrist", "Right_Wrist"]),
    (UPPER_LEG_L, &["L_Hip", "Left_Hip"]),
    (LOWER_LEG_L, &["L_Knee", "Left_Knee"]),
    (FOOT_L, &["L_Ankle", "Left_Ankle"]),
    (TOES_L, &["L_Foot", "Left_Foot"]),
    (UPPER_LEG_R, &["R_Hip", "Right_Hip"]),
    (LOWER_LEG_R, &["R_Knee", "Right_Knee"]),
    (FOOT_R, &["R_Ankle", "Right_Ankle"]),
    (TOES_R, &["R_Foot", "Right_Foot"]),
];

/// Unreal Engine's mannequin (`root`, `pelvis`, `spine_01` … `spine_05`, `neck_01`, `head`,
/// `clavicle_l`, `upperarm_l`, `lowerarm_l`, `hand_l`, `thigh_l`, `calf_l`, `foot_l`, `ball_l`; twist
/// bones unmatched).
pub(super) const UNREAL_TABLE: &[(usize, &[&str])] = &[
    (HIPS, &["pelvis"]),
    (SPINE, &["spine_02", "spine_01"]),
    (CHEST, &["spine_03", "spine_02"]),
    (NECK, &["neck_01", "neck_02"]),
    (HEAD, &["head"]),
    (SHOULDER_L, &["clavicle_l"]),
    (UPPER_ARM_L, &["upperarm_l"]),
    (LOWER_ARM_L, &["lowerarm_l"]),
    (HAND_L, &["hand_l"]),
    (SHOULDER_R, &["clavicle_r"]),
    (UPPER_ARM_R, &["upperarm_r"]),
    (LOWER_ARM_R, &["lowerarm_r"]),
    (HAND_R, &["hand_r"]),
    (UPPER_LEG_L, &["thigh_l"]),
    (LOWER_LEG_L, &["calf_l"]),
    (FOOT_L, &["foot_l"]),
    (TOES_L, &["ball_l"]),
    (UPPER_LEG_R, &["thigh_r"]),
    (LOWER_LEG_R, &["calf_r"]),
    (FOOT_R, &["foot_r"]),
    (TOES_R, &["ball_r"]),
];

/// Prefixes of common exporters, dropped by the generic matcher (after lower-casing).
pub(super) const GENERIC_PREFIXES: [&str; 10] =
    ["cc_base_", "bip01_", "bip01 ", "bip001 ", "bip001_", "def-", "def_", "jnt_", "j_", "b_"];

/// Generic synonyms, in matching order (a user joint is used once, so earlier entries win).
pub(super) const GENERIC_CENTRE: &[(usize, &[&str])] = &[
    (HIPS, &["hips", "hip", "pelvis"]),
    (HEAD, &["head"]),
    (NECK, &["neck", "neck1", "neck01"]),
    (CHEST, &["chest", "upperchest", "spine2", "spine02", "spine3", "spine03", "thorax"]),
    (SPINE, &["spine", "spine1", "spine01", "abdomen", "lowerback", "waist", "torso"]),
];

pub(super) const GENERIC_SIDED: &[([usize; 2], &[&str])] = &[
    ([UPPER_ARM_L, UPPER_ARM_R], &["upperarm", "arm", "humerus", "shoulder"]),
    ([SHOULDER_L, SHOULDER_R], &["clavicle", "collar", "shoulder"]),
    ([LOWER_ARM_L, LOWER_ARM_R], &["forearm", "lowerarm", "elbow"]),
    ([HAND_L, HAND_R], &["hand", "wrist"]),
    ([UPPER_LEG_L, UPPER_LEG_R], &["upleg", "upperleg", "thigh", "femur", "hip"]),
    ([LOWER_LEG_L, LOWER_LEG_R], &["leg", "lowerleg", "calf", "shin", "knee", "tibia"]),
    ([FOOT_L, FOOT_R], &["ankle", "foot"]),
    ([TOES_L, TOES_R], &["toebase", "toe", "toes", "ball", "toe0", "foot"]),
];

/// Base pose of the Bandai rig: the local rotations of the reference standing frame (frame 0 of
/// `dataset-2_walk_normal_001`, Hips without its yaw), printed by `tools/bandai_reference.py`. The
/// rig's zero-rotation rest pose has every bone along its parent's +X, so it defines no pose to align.
/// `joint_Root` rests at zero rotation.
pub(super) const BANDAI_BASE_POSE: BasePose = &[
    ("Hips", [-0.013790, -0.006499, 0.708703, 0.705343]),
    ("Spine", [0.714183, -0.029658, 0.025675, 0.698859]),
    ("Chest", [0.021667, -0.005625, 0.010507, 0.999694]),
    ("Neck", [-0.004132, 0.019700, 0.019606, 0.999605]),
    ("Head", [0.000404, -0.033325, 0.052047, 0.998088]),
    ("Shoulder_L", [-0.405552, -0.396023, -0.575569, 0.589418]),
    ("UpperArm_L", [0.190799, -0.213534, -0.573747, 0.767341]),
    ("LowerArm_L", [0.069735, -0.237676, 0.017110, 0.968687]),
    ("Hand_L", [0.051742, -0.074448, 0.041734, 0.995007]),
    ("Shoulder_R", [0.448775, -0.391472, 0.528079, 0.605378]),
    ("UpperArm_R", [0.244142, -0.267795, -0.501000, 0.785926]),
    ("LowerArm_R", [0.048252, -0.240132, 0.011943, 0.969467]),
    ("Hand_R", [0.050958, -0.051153, 0.056533, 0.995786]),
    ("UpperLeg_L", [0.096216, -0.039758, 0.994561, 0.003195]),
    ("LowerLeg_L", [0.000650, 0.133376, -0.000087, 0.991065]),
    ("Foot_L", [-0.002993, -0.464358, 0.014541, 0.885523]),
    ("Toes_L", [-0.000279, -0.155381, 0.000024, 0.987855]),
    ("UpperLeg_R", [-0.993266, 0.006151, 0.002888, -0.115659]),
    ("LowerLeg_R", [0.000204, 0.123797, 0.000003, 0.992308]),
    ("Foot_R", [-0.007212, -0.523717, 0.041431, 0.850854]),
    ("Toes_R", [-0.000922, -0.181132, 0.000079, 0.983458]),
];

/// Base pose of the CC_Base rig: the local rotations of frame 0 of the fixture
/// `iclone100_cmu_002_04.bvh` (CMU 02_04 on Reallusion's CC_Base rig; standing, arms down), the Hip
/// without its yaw (-66.57°). Its zero-rotation rest pose has the legs and arms pointing up (a 180°
/// swing would leave the twist undefined), and many bones (face, eyes, toes, clavicles) hold constant
/// non-zero rotations, which unmatched joints keep on the way back.
#[allow(clippy::approx_constant)] // measured data, not π/4 rotations
pub(super) const CC_BASE_POSE: BasePose = &[
    ("CC_Base_Hip", [-0.029423, 0.018272, -0.009811, 0.999352]),
    ("CC_Base_Pelvis", [0.102535, -0.000000, 0.000001, 0.994729]),
    ("CC_Base_L_Thigh", [-0.031461, 0.120688, 0.992064, 0.015940]),
    ("CC_Base_L_Calf", [-0.188347, -0.004035, -0.000781, 0.982094]),
    ("CC_Base_L_Foot", [0.706379, -0.160967, 0.094670, 0.682757]),
    ("CC_Base_L_ToeBaseShareBone", [0.161572, 0.024943, -0.019907, 0.986345]),
    ("CC_Base_L_ToeBase", [0.168670, 0.024127, -0.019849, 0.985177]),
    ("CC_Base_L_PinkyToe1", [-0.256359, 0.032873, -0.035425, 0.965373]),
    ("CC_Base_L_RingToe1", [-0.284501, 0.048458, -0.017651, 0.957288]),
    ("CC_Base_L_MidToe1", [-0.217739, 0.037325, -0.001644, 0.975292]),
    ("CC_Base_L_IndexToe1", [-0.229676, 0.043497, 0.007201, 0.972268]),
    ("CC_Base_L_BigToe1", [-0.060003, 0.000870, 0.018561, 0.998025]),
    ("CC_Base_L_CalfTwist01", [0.000001, 0.004191, -0.000000, 0.999991]),
    ("CC_Base_L_CalfTwist02", [-0.000004, -0.028855, 0.000001, 0.999584]),
    ("CC_Base_L_KneeShareBone", [0.087266, 0.020298, -0.000533, 0.995978]),
    ("CC_Base_L_ThighTwist01", [-0.000010, -0.014857, -0.000063, 0.999890]),
    ("CC_Base_L_ThighTwist02", [-0.000007, 0.014854, 0.000055, 0.999890]),
    ("CC_Base_R_Thigh", [-0.068287, -0.133047, -0.988115, 0.035565]),
    ("CC_Base_R_ThighTwist01", [-0.000016, 0.031903, 0.000008, 0.999491]),
    ("CC_Base_R_ThighTwist02", [-0.000000, -0.031900, -0.000000, 0.999491]),
    ("CC_Base_R_Calf", [-0.181079, 0.003678, 0.000025, 0.983462]),
    ("CC_Base_R_Foot", [0.707204, 0.113338, -0.066975, 0.694645]),
    ("CC_Base_R_ToeBase", [0.126061, -0.028012, 0.020120, 0.991423]),
    ("CC_Base_R_PinkyToe1", [-0.256335, -0.032870, 0.035488, 0.965377]),
    ("CC_Base_R_BigToe1", [-0.059867, -0.000870, -0.018578, 0.998033]),
    ("CC_Base_R_IndexToe1", [-0.229527, -0.043494, -0.007190, 0.972303]),
    ("CC_Base_R_MidToe1", [-0.217694, -0.037335, 0.001628, 0.975301]),
    ("CC_Base_R_RingToe1", [-0.284634, -0.048476, 0.017730, 0.957246]),
    ("CC_Base_R_ToeBaseShareBone", [0.161994, -0.024911, 0.019764, 0.986279]),
    ("CC_Base_R_KneeShareBone", [0.083610, -0.019981, 0.000855, 0.996298]),
    ("CC_Base_R_CalfTwist01", [-0.000070, -0.003928, -0.000012, 0.999992]),
    ("CC_Base_R_CalfTwist02", [-0.000168, 0.021540, 0.000080, 0.999768]),
    ("CC_Base_Waist", [0.187027, -0.006722, 0.017586, 0.982174]),
    ("CC_Base_Spine01", [-0.158258, -0.011039, 0.009364, 0.987292]),
    ("CC_Base_Spine02", [-0.045299, -0.006084, 0.000241, 0.998955]),
    ("CC_Base_NeckTwist01", [0.078370, -0.040199, -0.040275, 0.995299]),
    ("CC_Base_NeckTwist02", [0.012320, -0.047605, 0.041151, 0.997942]),
    ("CC_Base_Head", [-0.054230, -0.024863, 0.015637, 0.998096]),
    ("CC_Base_FacialBone", [0.499994, 0.499994, 0.500012, 0.500000]),
    ("CC_Base_JawRoot", [-0.000050, -0.000051, 0.707091, 0.707123]),
    ("CC_Base_Tongue01", [0.000002, -0.000032, 0.079503, 0.996835]),
    ("CC_Base_Tongue02", [0.000007, -0.000010, 0.099209, 0.995067]),
    ("CC_Base_Tongue03", [-0.000001, -0.000001, 0.000072, 1.000000]),
    ("CC_Base_Teeth02", [-1.000000, 0.000002, -0.000097, 0.000080]),
    ("CC_Base_R_Eye", [0.707107, -0.000004, 0.707107, 0.000004]),
    ("CC_Base_L_Eye", [-0.707107, -0.000001, -0.707107, 0.000001]),
    ("CC_Base_UpperJaw", [0.000037, -0.000039, 0.707110, 0.707104]),
    ("CC_Base_Teeth01", [1.000000, -0.000010, -0.000034, 0.000011]),
    ("CC_Base_L_Clavicle", [-0.025688, 0.155985, -0.679792, 0.716164]),
    ("CC_Base_L_Upperarm", [0.252396, 0.288360, -0.682388, 0.622488]),
    ("CC_Base_L_Forearm", [0.290809, 0.011138, 0.177891, 0.940032]),
    ("CC_Base_L_ForearmTwist01", [-0.000001, -0.029625, -0.000000, 0.999561]),
    ("CC_Base_L_ForearmTwist02", [-0.000005, -0.143993, -0.000002, 0.989579]),
    ("CC_Base_L_ElbowShareBone", [-0.190048, -0.029253, -0.080210, 0.978055]),
    ("CC_Base_L_Hand", [-0.233568, -0.270303, 0.158457, 0.920475]),
    ("CC_Base_L_Mid1", [0.030120, -0.000148, -0.047469, 0.998418]),
    ("CC_Base_L_Mid2", [-0.006244, 0.003500, -0.003967, 0.999967]),
    ("CC_Base_L_Mid3", [0.004516, 0.000138, -0.003938, 0.999982]),
    ("CC_Base_L_Index1", [0.025877, -0.001409, 0.011027, 0.999603]),
    ("CC_Base_L_Index2", [0.004920, 0.005639, -0.004531, 0.999962]),
    ("CC_Base_L_Index3", [-0.003468, -0.000128, -0.010781, 0.999936]),
    ("CC_Base_L_Ring1", [0.023548, 0.002015, 0.018566, 0.999548]),
    ("CC_Base_L_Ring2", [-0.009478, -0.000285, -0.001011, 0.999955]),
    ("CC_Base_L_Ring3", [0.002039, -0.000242, -0.010705, 0.999941]),
    ("CC_Base_L_Pinky1", [0.029497, 0.001737, 0.034170, 0.998979]),
    ("CC_Base_L_Pinky2", [-0.017515, -0.001276, -0.001144, 0.999845]),
    ("CC_Base_L_Pinky3", [0.012709, -0.000050, -0.053911, 0.998465]),
    ("CC_Base_L_Thumb1", [0.110290, -0.082557, -0.196120, 0.970854]),
    ("CC_Base_L_Thumb2", [-0.169247, 0.004184, 0.044395, 0.984564]),
    ("CC_Base_L_Thumb3", [0.042212, 0.000290, -0.010853, 0.999050]),
    ("CC_Base_L_UpperarmTwist01", [0.000001, -0.145220, -0.000001, 0.989399]),
    ("CC_Base_L_UpperarmTwist02", [-0.000002, 0.145222, 0.000001, 0.989399]),
    ("CC_Base_R_Clavicle", [-0.025638, -0.155948, 0.679801, 0.716166]),
    ("CC_Base_R_Upperarm", [0.269363, -0.302344, 0.653016, 0.640001]),
    ("CC_Base_R_UpperarmTwist01", [0.000000, 0.153082, 0.000000, 0.988213]),
    ("CC_Base_R_UpperarmTwist02", [-0.000002, -0.153080, -0.000001, 0.988214]),
    ("CC_Base_R_Forearm", [0.302878, -0.012049, -0.186379, 0.934550]),
    ("CC_Base_R_ForearmTwist01", [-0.000000, 0.032590, 0.000000, 0.999469]),
    ("CC_Base_R_ForearmTwist02", [-0.000005, 0.048722, 0.000002, 0.998812]),
    ("CC_Base_R_ElbowShareBone", [-0.199179, 0.032201, 0.082269, 0.975973]),
    ("CC_Base_R_Hand", [0.083747, 0.101571, -0.211881, 0.968388]),
    ("CC_Base_R_Mid1", [0.031776, 0.000088, 0.048112, 0.998336]),
    ("CC_Base_R_Mid2", [-0.006133, -0.003444, 0.001613, 0.999974]),
    ("CC_Base_R_Mid3", [0.004504, -0.000180, 0.005290, 0.999976]),
    ("CC_Base_R_Ring1", [0.025069, -0.002084, -0.018517, 0.999512]),
    ("CC_Base_R_Ring2", [-0.009483, 0.000275, 0.000552, 0.999955]),
    ("CC_Base_R_Ring3", [0.002025, 0.000256, 0.010954, 0.999938]),
    ("CC_Base_R_Thumb1", [0.122623, 0.222601, 0.178972, 0.950464]),
    ("CC_Base_R_Thumb2", [-0.144544, -0.003823, -0.036782, 0.988807]),
    ("CC_Base_R_Thumb3", [0.019342, -0.000647, 0.004296, 0.999803]),
    ("CC_Base_R_Index1", [0.027347, 0.001277, -0.009834, 0.999577]),
    ("CC_Base_R_Index2", [0.004991, -0.005650, 0.001596, 0.999970]),
    ("CC_Base_R_Index3", [-0.003494, 0.000166, 0.012334, 0.999918]),
    ("CC_Base_R_Pinky1", [0.030998, -0.001784, -0.034092, 0.998936]),
    ("CC_Base_R_Pinky2", [-0.017510, 0.001298, 0.000702, 0.999846]),
    ("CC_Base_R_Pinky3", [0.012705, 0.000036, 0.054171, 0.998451]),
    ("CC_Base_R_RibsTwist", [-0.000003, -0.640561, -0.767907, 0.000003]),
    ("CC_Base_R_Breast", [0.000000, 0.000000, -0.000000, 1.000000]),
    ("CC_Base_L_RibsTwist", [0.000013, 0.640562, 0.767907, 0.000008]),
    ("CC_Base_L_Breast", [0.000000, 0.000000, 0.000000, 1.000000]),
];
