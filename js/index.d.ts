// Type declarations of the motion-stylizer npm package (the API of index.js).

/** Stable `code` of every error the package throws (an `Error` with `code` and `message`). */
export type ErrorCode =
  | 'BVH_PARSE' // the text is not BVH the reader accepts (also has `line` and `kind`)
  | 'RIG_UNMATCHED' // the skeleton lacks joints the canonical rig needs
  | 'BAD_MAP' // a manual joint mapping that cannot be used (a joint the file lacks, one given twice, ...)
  | 'RIG_DEGENERATE' // the skeleton has no usable geometry
  | 'NOT_HUMAN' // the skeleton is no human body (a quadruped, a single chain, limbs the wrong way)
  | 'RIG_MISMATCH'
  | 'TOO_LONG' // a clip beyond the limits (stylization: 9,000 frames at 30 fps)
  | 'BAD_MOTION' // the motion has non-finite values
  | 'UNKNOWN_LABEL' // a style label the weights do not know
  | 'SETTING_UNAVAILABLE' // the supervised/unsupervised model was not loaded
  | 'BAD_REQUEST' // options the API or the model cannot serve
  | 'BAD_WEIGHTS' // weight files that cannot be used
  | 'BACKEND_UNAVAILABLE' // a backend this build does not have
  | 'BUSY' // WebGPU: a model added while a stylization runs on the engine
  | 'FETCH' // a package or weights file could not be fetched
  | 'MODEL_OUTPUT'
  | 'INTERNAL'; // a bug: the engine trapped (a panic, with its message); the next call runs on a fresh engine

export interface StylizerError extends Error {
  code: ErrorCode;
  /** BVH_PARSE only: 1-based line and the reader's error kind (e.g. 'TooFewFrames'). */
  line?: number;
  kind?: string;
}

export type Bytes = Uint8Array | ArrayBuffer | ArrayBufferView;

export interface WeightFiles {
  manifest: Bytes | string;
  norm: Bytes | string;
  /** The networks both stylizers share (shared.bin; manifest formats 2 and 3). */
  shared?: Bytes;
  supervised?: Bytes;
  unsupervised?: Bytes;
  /**
   * Format 3: a setting's style encoder (supervised-style.bin, unsupervised-style.bin), needed
   * only for reference motions; without it such a request fails with STYLE_ENCODER_UNAVAILABLE.
   */
  supervisedStyle?: Bytes;
  unsupervisedStyle?: Bytes;
}

/** Bytes of the weights fetched (or read) so far, of `total`. */
export interface LoadProgress {
  loaded: number;
  /**
   * The sum of the files' sizes as the manifest lists them (or as announced: Content-Length, the
   * file sizes in Node); 0 while unknown. Only the last call of a download, once every byte has
   * arrived, has `loaded === total`.
   */
  total: number;
  /** The model this download is for: the first one at load, another when it is first used. */
  setting?: 'supervised' | 'unsupervised';
  /** Set on the download of a model's style encoder (format 3: fetched when a reference motion is first used). */
  styleEncoder?: boolean;
}

export interface LoadOptions {
  /**
   * Default: the weights shipped in the package. A folder URL (relative ones: to the page in
   * browsers, to the package in Node; absolute paths work in Node), the files' bytes, or a loaded
   * Stylizer, whose weights (kept in memory) are used again without fetching.
   */
  weights?: string | URL | WeightFiles | Stylizer;
  /**
   * Called as the weights are fetched (or read, or taken from the browser's cache): at load the
   * statistics, the shared networks and the first model (manifest.json, a few kB, is read first
   * and not counted); later, the file of a model fetched when it is first used. Not called for
   * weights given as bytes.
   */
  onProgress?: (progress: LoadProgress) => void;
  /**
   * 'cpu' (default, Burn flex with wasm SIMD); 'webgpu': Burn's wgpu runtime on navigator.gpu (a
   * second wasm file, engine-webgpu_bg.wasm, fetched only then), falling back to 'cpu' where there
   * is no WebGPU or its device fails (see backend and fallbackReason).
   */
  backend?: 'cpu' | 'webgpu' | 'ndarray';
  /**
   * Which models may be used (default both, in this order): the first one the weights have is
   * loaded now, the others when first used (fetched then, from a folder).
   */
  settings?: Array<'supervised' | 'unsupervised'>;
}

/** An imported motion: resampled to 30 fps and retargeted onto the canonical rig inside. */
/**
 * A manual joint mapping: canonical joint (Hips, Spine, Chest, Neck, Head, Shoulder_L,
 * UpperArm_L, LowerArm_L, Hand_L, UpperLeg_L, LowerLeg_L, Foot_L, Toes_L and the _R ones) → the
 * file's joint name, or null to leave it unmatched (synthesised, or an error for an essential
 * joint). Joints not named keep the automatic match.
 */
export type JointMap = Record<string, string | null>;

/** `inspectBvh`'s result (the JSON of `motion-stylizer inspect --json`, without `file`). */
export interface Inspection {
  joints: number;
  joint_names: string[];
  frames: number;
  fps: number;
  duration_s: number;
  channels: number;
  rig: string;
  matched: Record<string, string>;
  missing: string[];
  synthesised: Record<string, string>;
  /** Whether importBvh succeeds (with the same map). */
  retargetable: boolean;
  error: { code: string; message: string } | null;
  scale_to_canonical: number | null;
  base_pose: string | null;
  notes: string[];
  /** The mapping used, or the best guesses: every canonical joint, ready to edit. */
  map: JointMap;
}

export class Motion {
  readonly frames: number;
  readonly fps: number;
  /** Detected rig: 'bandai' | 'cmu31' | 'm21' | 'cc_base' | 'mixamo' | 'generic'. */
  readonly rig: string;
  rigReport(): {
    rig: string;
    matched: Array<[string, string]>;
    missing: string[];
    scale: number;
    up_axis: string;
    forward_axis: string;
    floor: number;
    base_pose: string;
  };
  /**
   * The file as it was given, for drawing it: its joints and their world positions by the
   * package's forward kinematics, in the file's units and axes. Every step-th frame only, where
   * the file is faster than 60 fps (step = floor(1 / (60 · frame time))) or has more than
   * 6,000,000 position values; `fps` and `frames` are after that step, `file` the file's own.
   */
  source(): SourceMotion;
  /** Releases its memory in the engine now rather than when garbage-collected (a later use imports it again). */
  free(): void;
}

export interface SourceMotion {
  /** Joint names, in file order (a parent before its children). */
  names: string[];
  /** Each joint's parent index, -1 for the root. */
  parents: number[];
  fps: number;
  frames: number;
  /** World joint positions: frames × joints × 3. */
  positions: Float32Array;
  /** The file's own frame count and rate. */
  file: { frames: number; fps: number };
}

/** One style source. With the supervised model, `styleMotion` takes the reference's `label`, or infers it (`inferredLabel` on the results). */
export type StyleSource =
  | { label: string }
  | { styleMotion: Motion | string; label?: string }
  | { prior: true }
  | { mix: { a: StyleSource; b: StyleSource; t: number } };

/**
 * A style per body part: `lower` (the root and both legs), `upper` (spine, chest, arms), `head`
 * (neck, head); `'content'` keeps the content's own motion there. Each part is stylized on its own
 * (the whole body) and the outputs are combined joint by joint: the root and the foot contacts are
 * the lower body's source's.
 */
export type BodyParts = {
  lower?: StyleSource | 'content';
  upper?: StyleSource | 'content';
  head?: StyleSource | 'content';
};

export type StylizeOptions = (StyleSource | {}) & {
  /** A style per body part; the parts not named take the options' own style (or keep the content without one). */
  parts?: BodyParts;
  /** Use the model trained without labels (motion- and prior-based only). Default false. */
  unsupervised?: boolean;
  /** Number of outputs, 1-64. Default 1. */
  samples?: number;
  /** Seed of the random draws; same seed and input, same output bits. Default 0. */
  seed?: number | bigint;
  /**
   * Scale of the style codes drawn from the prior (label- and prior-based), 0-4. Default 0.3
   * (measured: closer to the label's style than the paper's 1.0); 0 is the label's mean style.
   */
  temperature?: number;
  /**
   * How far the output goes towards the style, 0-2: 0 gives back the content's motion, 1 (default)
   * the stylizer's output, 2 twice its change (exaggerated). The style shift grows with it.
   */
  strength?: number;
  /**
   * Style guidance, 0-3 (default the library's): how much further the output goes along the
   * difference between the style's output and the neutral style's (`normal`) for the same
   * content; 0 is the networks' output as trained.
   */
  guidance?: number;
  /** Output skeleton: the content's own rig (default) or the canonical 21-joint rig. */
  rig?: 'content' | 'canonical';
};

/** The three.js module as toThreeClip uses it (typed loosely, so that three is not a dependency). */
export type ThreeModule = {
  Bone: new () => any;
  Group: new () => any;
  Skeleton: new (bones: any[]) => any;
  AnimationClip: new (name: string, duration: number, tracks: any[]) => any;
  QuaternionKeyframeTrack: new (name: string, times: ArrayLike<number>, values: ArrayLike<number>) => any;
  VectorKeyframeTrack: new (name: string, times: ArrayLike<number>, values: ArrayLike<number>) => any;
  PropertyBinding: { sanitizeNodeName(name: string): string };
};

export interface ThreeClip {
  /** A THREE.Group holding the root bone: add it to a scene, play `clip` on `new AnimationMixer(root)`. */
  root: any;
  /** THREE.Bone per joint, in the order of `skeleton.names` (names made safe for tracks and unique). */
  bones: any[];
  /** THREE.Skeleton of `bones` (bind a SkinnedMesh to it, or draw it with THREE.SkeletonHelper(root)). */
  skeleton: any;
  /** THREE.AnimationClip: a position track per joint with position channels, a quaternion track per joint with rotation channels. */
  clip: any;
  /** Metres per unit of the rig's BVH (0.01 for the canonical rig, in centimetres). */
  metresPerUnit: number;
  /** The turn from the rig's axes to Y up, facing +Z, applied at the root: [x, y, z, w]. */
  orientation: [number, number, number, number];
}

export class StylizedMotion {
  readonly frames: number;
  readonly fps: number;
  /** Joint names and parent indices (-1 for the root), in the order of positions(). */
  readonly skeleton: { names: string[]; parents: number[] };
  /** BVH text. */
  toBvh(): string;
  /** World joint positions: frames × joints × 3. */
  positions(): Float32Array;
  /**
   * Binary glTF (.glb bytes): the skeleton (one node per joint, a skin and a mesh of bone shapes)
   * and one animation over the clip, in metres, Y up, facing +Z. Errors: BAD_MOTION, TOO_LONG.
   */
  toGlb(): Uint8Array;
  /**
   * A three.js Skeleton and AnimationClip of this motion without a BVH or glTF round trip; pass the
   * three.js module (`import * as THREE from 'three'`). Same space as toGlb().
   */
  toThreeClip(THREE: ThreeModule, options?: { name?: string }): ThreeClip;
  /** Set when the style came from a reference given without a label to the supervised model: the label inferred for it. */
  readonly inferredLabel?: string;
  /** With `parts`: the label inferred for each part whose reference was given without one. */
  readonly inferredLabels?: Partial<Record<'lower' | 'upper' | 'head', string>>;
  /** Releases its memory in the engine now rather than when garbage-collected; it cannot be used after. */
  free(): void;
}

export class Stylizer {
  static load(options?: LoadOptions): Promise<Stylizer>;
  /** The backend in use ('cpu', 'webgpu', or 'ndarray'). */
  readonly backend: string;
  /** Why the requested backend is not the one in use; null when it is. */
  readonly fallbackReason: string | null;
  /** Milliseconds Stylizer.load took (wasm start-up, fetching and loading the weights). */
  readonly loadMs: number;
  /**
   * The weights' fingerprint, 8 hex digits (FNV-1a of manifest.json's and the statistics' bytes):
   * the same weights, the same id.
   */
  readonly weightsId: string;
  styles(): string[];
  /** The models it can use: those loaded and those it fetches when first used. */
  settings(): Array<'supervised' | 'unsupervised'>;
  /** The models loaded now. */
  loadedSettings(): Array<'supervised' | 'unsupervised'>;
  /**
   * Imports BVH text of any rig the importer knows (errors BVH_PARSE, BAD_MAP, RIG_UNMATCHED,
   * RIG_DEGENERATE, NOT_HUMAN, TOO_LONG, BAD_MOTION); `map` is applied over the automatic match.
   */
  importBvh(text: string, options?: { map?: JointMap }): Motion;
  /** What the importer makes of BVH text, also when it cannot import it (`motion-stylizer inspect --json`). */
  inspectBvh(text: string, options?: { map?: JointMap }): Inspection;
  stylize(content: Motion | string, options: StylizeOptions): Promise<StylizedMotion[]>;
  /**
   * The supervised model's style label for a reference (the one it reconstructs the motion best
   * under). Async: the style encoder may be fetched first (format-3 weights).
   */
  inferLabel(reference: Motion | string): Promise<string>;
  /** Releases the engine's memory now rather than when garbage-collected (a later call loads the kept weights again). */
  free(): void;
}

export default Stylizer;
