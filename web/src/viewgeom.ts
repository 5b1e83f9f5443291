// The viewport's helpers that hold no state: the browser's WebGL renderer
// name, distances from a click to a control's shape on screen, and freeing
// a loaded character's GPU resources.

import type * as THREE from 'three';

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
