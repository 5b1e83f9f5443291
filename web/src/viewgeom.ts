// The viewport's helpers that hold no state: the browser's WebGL renderer
// name, distances from a click to a control's shape on screen, freeing a
// loaded character's GPU resources, and the posed box of the meshes.

import * as THREE from 'three';

/** A control's shape projected to the canvas (CSS pixels; NaN where behind the camera). */
export interface ScreenShape {
  /** x, y pairs in canvas pixels; NaN where the point is behind the camera. */
  xy: Float32Array;
  closed: boolean;
  origin: [number, number] | null;
}

/** The renderer string of the browser's WebGL ('' when there is none). */
export function webglRendererName(): string {
  const gl = document.createElement('canvas').getContext('webgl2') ?? document.createElement('canvas').getContext('webgl');
  if (!gl) return '';
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER) ?? '');
  gl.getExtension('WEBGL_lose_context')?.loseContext();
  return name;
}

export function distanceToShape(s: ScreenShape, x: number, y: number): number {
  let best = Infinity;
  const n = s.xy.length / 2;
  if (n === 1) {
    const px = s.xy[0]!;
    if (!Number.isNaN(px)) best = Math.hypot(px - x, s.xy[1]! - y);
  }
  const segs = s.closed ? n : n - 1;
  for (let i = 0; i < segs; i++) {
    const j = (i + 1) % n;
    const ax = s.xy[2 * i]!;
    const ay = s.xy[2 * i + 1]!;
    const bx = s.xy[2 * j]!;
    const by = s.xy[2 * j + 1]!;
    if (Number.isNaN(ax) || Number.isNaN(bx)) continue;
    best = Math.min(best, segmentDistance(x, y, ax, ay, bx, by));
  }
  if (s.origin) best = Math.min(best, Math.hypot(s.origin[0] - x, s.origin[1] - y));
  return best;
}

function segmentDistance(px: number, py: number, ax: number, ay: number, bx: number, by: number): number {
  const dx = bx - ax;
  const dy = by - ay;
  const len2 = dx * dx + dy * dy;
  let t = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0;
  t = Math.max(0, Math.min(1, t));
  return Math.hypot(px - (ax + t * dx), py - (ay + t * dy));
}

export function disposeTree(root: THREE.Object3D): void {
  root.traverse((o) => {
    const m = o as THREE.Mesh;
    if (m.geometry) m.geometry.dispose();
    const mats = m.material ? (Array.isArray(m.material) ? m.material : [m.material]) : [];
    for (const mat of mats) mat.dispose();
  });
}

/**
 * The world box of meshes in the pose shown (world matrices up to date):
 * skinned ones through their bones, so a head above its last joint counts;
 * empty without meshes.
 */
export function meshesBox(meshes: readonly THREE.Mesh[]): THREE.Box3 {
  const box = new THREE.Box3();
  for (const mesh of meshes) {
    const skinned = mesh as THREE.SkinnedMesh;
    if (skinned.isSkinnedMesh) {
      skinned.skeleton.update();
      skinned.computeBoundingBox();
    } else if (!mesh.geometry.boundingBox) mesh.geometry.computeBoundingBox();
    const local = skinned.isSkinnedMesh ? skinned.boundingBox : mesh.geometry.boundingBox;
    if (local && !local.isEmpty()) box.union(local.clone().applyMatrix4(mesh.matrixWorld));
  }
  return box;
}

/**
 * Where the centres of a box's six faces fall on screen (the top face's is
 * the top of a character's head), as the extremes; null for an empty box.
 */
export function boxFacesOnScreen(
  box: THREE.Box3,
  toScreen: (p: [number, number, number]) => { x: number; y: number },
): { left: number; top: number; right: number; bottom: number } | null {
  if (box.isEmpty()) return null;
  const out = { left: Infinity, top: Infinity, right: -Infinity, bottom: -Infinity };
  const c = box.getCenter(new THREE.Vector3());
  for (let i = 0; i < 6; i++) {
    const q: [number, number, number] = [c.x, c.y, c.z];
    const axis = i >> 1;
    q[axis] = (i & 1 ? box.max : box.min).getComponent(axis);
    const p = toScreen(q);
    out.left = Math.min(out.left, p.x);
    out.right = Math.max(out.right, p.x);
    out.top = Math.min(out.top, p.y);
    out.bottom = Math.max(out.bottom, p.y);
  }
  return out;
}
