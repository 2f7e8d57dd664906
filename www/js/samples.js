// The built-in sample clips (copied into samples/ by scripts/build-www.sh), with their style label
// where the data gives one, and their origin and licence (shown in the page's footer too).

const BANDAI = 'Bandai-Namco Research Motion dataset (Kobayashi et al. 2023), CC BY-NC 4.0';

export const SAMPLES = [
  { id: 'walk-normal', file: 'dataset-2_walk_normal_001_f120.bvh', title: 'walk · normal (Bandai, 4 s)', label: 'normal', source: BANDAI },
  { id: 'walk-elderly', file: 'dataset-2_walk_elderly_001_f120.bvh', title: 'walk · old (Bandai, 4 s)', label: 'old', source: BANDAI },
  { id: 'walk-tired', file: 'dataset-1_walk_tired_001_f90.bvh', title: 'walk · tired (Bandai, 3 s)', label: 'tired', source: BANDAI },
  { id: 'hands-active', file: 'dataset-2_raise-up-both-hands_active_001.bvh', title: 'raise both hands · active (Bandai)', label: 'active', source: BANDAI },
  { id: 'm21-walk', file: 'm21_walk.bvh', title: 'walk (21-joint rig, 60 fps)', label: null, source: 'zzzark/Semi-Motion-Style-Transfer, MIT' },
  { id: 'cmu31-xia', file: 'cmu31_xia_neutral_16_000.bvh', title: 'neutral (CMU 31-joint rig, 120 fps)', label: 'normal', source: 'Xia et al. 2015, retargeted by Aberman et al. (deep-motion-editing)' },
  { id: 'ccbase-jump', file: 'iclone100_cmu_002_04.bvh', title: 'jump, balance (CC_Base 100-joint rig)', label: null, source: 'CMU Graphics Lab Motion Capture Database, subject 2 trial 4 (IClone-CMU-Mocap)' },
];

export const sampleById = (id) => SAMPLES.find((s) => s.id === id) ?? null;

/** The sample's BVH text. */
export async function fetchSample(sample) {
  const response = await fetch(new URL(`../samples/${sample.file}`, import.meta.url));
  if (!response.ok) throw Object.assign(new Error(`cannot fetch sample ${sample.file}: HTTP ${response.status}`), { code: 'FETCH' });
  return response.text();
}
