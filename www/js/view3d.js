// The perspective view: the content and the result as bodies of capsules on the canonical rig's
// bones (three.js, orbit controls), on a ground with a soft shadow under each body, following the
// bodies as they walk. It draws the same display-space motions as the orthographic views
// (views.js: Y up, facing +Z, centimetres) at the player's time, in the same layout.
//
// A motion's joints are the user's; `canonicalIndices` (canonical.js) maps the canonical joints onto
// them with the importer's matches, so every rig gets the same body.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { CANONICAL, PARENTS } from './canonical.js';
import { COLORS, frameAt, layoutItems } from './views.js';

/** Capsule radius (cm) of the bone that ends at each canonical joint (by name without the side). */
const RADIUS = {
  Spine: 10, Chest: 11, Neck: 5, Head: 5, Shoulder: 5, UpperArm: 5, LowerArm: 4.2, Hand: 3.6,
  UpperLeg: 7.5, LowerLeg: 6.5, Foot: 5.2, Toes: 4,
};
const HEAD_RADIUS = 10;
const CM = 0.01; // display centimetres → scene metres

/** The capsules of one motion: [from, to, radius] joint indices of its own skeleton. */
function bonesOf(indices) {
  const bones = [];
  for (let j = 1; j < CANONICAL.length; j++) {
    if (indices[j] < 0) continue;
    let a = PARENTS[j];
    while (a > 0 && indices[a] < 0) a = PARENTS[a];
    if (indices[a] < 0) continue;
    bones.push([indices[a], indices[j], RADIUS[CANONICAL[j].replace(/_[LR]$/, '')]]);
  }
  return bones;
}

/** A radial gradient: the soft contact shadow under a body. */
function shadowTexture() {
  const c = document.createElement('canvas');
  c.width = c.height = 128;
  const g = c.getContext('2d');
  const r = g.createRadialGradient(64, 64, 0, 64, 64, 64);
  r.addColorStop(0, 'rgba(0,0,0,0.75)');
  r.addColorStop(0.5, 'rgba(0,0,0,0.35)');
  r.addColorStop(1, 'rgba(0,0,0,0)');
  g.fillStyle = r;
  g.fillRect(0, 0, 128, 128);
  const t = new THREE.CanvasTexture(c);
  t.colorSpace = THREE.SRGBColorSpace;
  return t;
}

/** One body: capsules, a head, a contact shadow, posed from a display motion each frame. */
class Body {
  constructor(scene, item, floor, shadowMap, translucent) {
    const { m, shift, color } = item;
    this.m = m;
    this.shift = shift;
    this.floor = floor;
    this.group = new THREE.Group();
    this.material = new THREE.MeshStandardMaterial({
      color, roughness: 0.55, metalness: 0.05, transparent: translucent, opacity: translucent ? 0.5 : 1,
    });
    this.indices = m.canonical ?? canonicalIndices([], []);
    this.bones = bonesOf(this.indices).map(([a, b, radius]) => {
      const length = Math.max(1e-3, this.point(0, a).distanceTo(this.point(0, b)));
      const mesh = new THREE.Mesh(new THREE.CapsuleGeometry(radius * CM, length, 4, 10), this.material);
      mesh.castShadow = true;
      this.group.add(mesh);
      return { a, b, mesh, length };
    });
    const head = this.indices[4];
    this.head = head >= 0 ? new THREE.Mesh(new THREE.SphereGeometry(HEAD_RADIUS * CM, 20, 14), this.material) : null;
    if (this.head) {
      this.head.castShadow = true;
      this.group.add(this.head);
    }
    this.shadow = new THREE.Mesh(
      new THREE.PlaneGeometry(1, 1),
      new THREE.MeshBasicMaterial({ map: shadowMap, transparent: true, depthWrite: false, opacity: translucent ? 0.6 : 1 }),
    );
    this.shadow.rotation.x = -Math.PI / 2;
    this.shadow.renderOrder = -1;
    scene.add(this.group, this.shadow);
  }

  /** Joint `j` of frame `f` in scene metres (the floor at y = 0, the layout's shift applied). */
  point(f, j, out = new THREE.Vector3()) {
    const p = this.m.positions;
    const i = (f * this.m.joints + j) * 3;
    return out.set((p[i] + this.shift) * CM, (p[i + 1] - this.floor) * CM, p[i + 2] * CM);
  }

  /** Poses the body at `time` seconds; returns its hips position. */
  pose(time) {
    const f = frameAt(this.m, time);
    const a = new THREE.Vector3();
    const b = new THREE.Vector3();
    const up = new THREE.Vector3(0, 1, 0);
    for (const bone of this.bones) {
      this.point(f, bone.a, a);
      this.point(f, bone.b, b);
      const d = b.clone().sub(a);
      const length = d.length();
      bone.mesh.position.copy(a).addScaledVector(d, 0.5);
      if (length > 1e-6) bone.mesh.quaternion.setFromUnitVectors(up, d.divideScalar(length));
      bone.mesh.scale.set(1, length / bone.length, 1);
    }
    if (this.head) {
      const neck = this.point(f, this.indices[3] >= 0 ? this.indices[3] : this.indices[0]);
      const head = this.point(f, this.indices[4]);
      const dir = head.clone().sub(neck).normalize();
      this.head.position.copy(head).addScaledVector(dir, HEAD_RADIUS * CM * 0.8);
    }
    const hips = this.point(f, this.indices[0] >= 0 ? this.indices[0] : this.m.trail);
    // The contact shadow: under the hips, smaller and fainter as the body rises off the ground.
    let low = Infinity;
    for (let j = 0; j < this.m.joints; j++) low = Math.min(low, this.point(f, j, a).y);
    const lift = Math.max(0, low);
    this.shadow.position.set(hips.x, 0.002, hips.z);
    this.shadow.scale.setScalar(0.9 / (1 + lift * 2));
    this.shadow.material.opacity = (this.material.transparent ? 0.6 : 1) / (1 + lift * 4);
    return hips;
  }

  dispose(scene) {
    scene.remove(this.group, this.shadow);
    for (const bone of this.bones) bone.mesh.geometry.dispose();
    this.head?.geometry.dispose();
    this.shadow.geometry.dispose();
    this.shadow.material.dispose();
    this.material.dispose();
  }
}

/** The page's perspective view, on `canvas`; a no-op with a note where WebGL is unavailable. */
export class View3D {
  constructor(canvas, note) {
    this.canvas = canvas;
    this.bodies = [];
    this.options = {};
    this.time = 0;
    this.frames = 0; // frames rendered (for the tests)
    const gl = canvas.getContext('webgl2', { antialias: true }) ?? null;
    if (!gl) {
      if (note) note.hidden = false;
      canvas.dataset.webgl = 'false';
      return;
    }
    canvas.dataset.webgl = 'true';
    this.renderer = new THREE.WebGLRenderer({ canvas, context: gl, antialias: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    this.renderer.shadowMap.enabled = true;
    this.renderer.shadowMap.type = THREE.PCFShadowMap;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color('#161b22');
    this.scene.fog = new THREE.Fog('#161b22', 9, 22);
    this.camera = new THREE.PerspectiveCamera(38, 1, 0.05, 60);
    this.camera.position.set(1.9, 1.45, 2.9);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.target.set(0, 0.9, 0);
    this.controls.enableDamping = false;
    this.controls.maxPolarAngle = Math.PI * 0.495;
    this.controls.minDistance = 0.8;
    this.controls.maxDistance = 14;
    this.controls.addEventListener('change', () => this.render());

    this.scene.add(new THREE.HemisphereLight('#dfe8f5', '#3a3226', 1.6));
    this.sun = new THREE.DirectionalLight('#ffffff', 1.8);
    this.sun.castShadow = true;
    this.sun.shadow.mapSize.set(1024, 1024);
    Object.assign(this.sun.shadow.camera, { left: -2.5, right: 2.5, top: 2.5, bottom: -2.5, near: 0.5, far: 12 });
    this.sun.shadow.radius = 3;
    this.sun.shadow.bias = -0.0005;
    this.scene.add(this.sun, this.sun.target);
    const ground = new THREE.Mesh(new THREE.PlaneGeometry(80, 80), new THREE.MeshStandardMaterial({ color: '#2a313b', roughness: 0.95 }));
    ground.rotation.x = -Math.PI / 2;
    ground.receiveShadow = true;
    this.scene.add(ground);
    const grid = new THREE.GridHelper(80, 160, '#48525f', '#353d48');
    grid.position.y = 0.001;
    grid.material.transparent = true;
    grid.material.opacity = 0.6;
    this.scene.add(grid);
    this.shadowMap = shadowTexture();
    this.follow = null;

    this.observer = new ResizeObserver(() => this.resize());
    this.observer.observe(canvas);
    this.resize();
  }

  get ready() {
    return Boolean(this.renderer);
  }

  /** Same arguments as Views.set: {content, result, layout, showContent, showResult}. */
  set({ content = this.content, result = this.result, ...options }) {
    this.content = content;
    this.result = result;
    this.options = { ...this.options, ...options };
    if (!this.ready) return;
    for (const b of this.bodies) b.dispose(this.scene);
    const items = layoutItems(content, result, this.options);
    const floor = content?.floor ?? result?.floor ?? 0;
    const overlay = this.options.layout !== 'side' && items.length > 1;
    // In the overlay, the content is see-through so that the result inside it shows.
    this.bodies = items.map((item) => new Body(this.scene, item, floor, this.shadowMap, overlay && item.color === COLORS.content));
    this.follow = null;
    this.draw(this.time);
  }

  resize() {
    if (!this.ready) return;
    const w = Math.max(1, this.canvas.clientWidth);
    const h = Math.max(1, this.canvas.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /** Poses the bodies at `time` and moves the camera and the light with them. */
  draw(time) {
    this.time = time;
    if (!this.ready) return;
    const centre = new THREE.Vector3();
    for (const b of this.bodies) centre.add(b.pose(time));
    if (this.bodies.length) {
      centre.divideScalar(this.bodies.length);
      centre.y = 0.9;
      // The camera keeps its place relative to the bodies (and the user's orbit around them).
      if (this.follow) {
        const delta = centre.clone().sub(this.follow);
        this.camera.position.add(delta);
        this.controls.target.add(delta);
      } else {
        this.camera.position.add(centre.clone().sub(this.controls.target));
        this.controls.target.copy(centre);
      }
      this.follow = centre;
      this.sun.position.set(centre.x + 1.2, 5, centre.z + 1.8);
      this.sun.target.position.set(centre.x, 0, centre.z);
    }
    // update() renders through the 'change' listener when the camera moved.
    if (!this.controls.update()) this.render();
  }

  render() {
    if (!this.ready) return;
    this.renderer.render(this.scene, this.camera);
    this.frames++;
  }
}
