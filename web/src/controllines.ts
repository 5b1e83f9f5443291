// Every control shape of the character in one draw call: a single
// LineSegments whose vertices are the shapes' points in world space, with a
// colour per vertex. A software renderer (SwiftShader, llvmpipe) pays per
// draw call, so 160 controls as 160 Line objects cost far more than their
// few thousand segments; merged, the shapes cost one call.
//
// The layout (which shapes are drawn, in which order, in which colour) is
// rebuilt when the selection, hover or visibility changes; the positions
// are rewritten before each render from the controls' world matrices.
// Selected shapes come last, so with depth testing off they are drawn over
// the others, as their higher render order did when they were separate.

import * as THREE from 'three';

/** What ControlLines needs of one control's view. */
export interface ControlShape {
  /** The node whose world matrix places the shape. */
  object: THREE.Object3D;
  /** The shape's points in the control's local space. */
  points: THREE.Vector3[];
  closed: boolean;
  /** The colour it is drawn in now. */
  color: THREE.Color;
  visible: boolean;
  /** Drawn over the rest (the selection). */
  top: boolean;
}

function segmentCount(s: ControlShape): number {
  const n = s.points.length;
  if (n < 2) return 0;
  return s.closed && n > 2 ? n : n - 1;
}

export class ControlLines {
  readonly object: THREE.LineSegments;
  private readonly geometry = new THREE.BufferGeometry();
  private readonly material = new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false, transparent: true });
  private order: ControlShape[] = [];
  private capacity = 0;
  private readonly v = new THREE.Vector3();

  constructor() {
    this.object = new THREE.LineSegments(this.geometry, this.material);
    this.object.frustumCulled = false;
    this.object.renderOrder = 10;
    this.object.matrixAutoUpdate = false;
    this.allocate(0);
  }

  /** Segments drawn now (for the tests). */
  get segments(): number {
    return this.geometry.drawRange.count / 2;
  }

  /** Lays out the visible shapes (the top ones last) and writes their colours. */
  layout(shapes: Iterable<ControlShape>): void {
    const below: ControlShape[] = [];
    const above: ControlShape[] = [];
    let segments = 0;
    for (const s of shapes) {
      if (!s.visible || !segmentCount(s)) continue;
      (s.top ? above : below).push(s);
      segments += segmentCount(s);
    }
    this.order = below.concat(above);
    if (segments > this.capacity) this.allocate(Math.max(segments, this.capacity * 2));
    const colors = this.geometry.getAttribute('color') as THREE.BufferAttribute;
    const c = colors.array as Float32Array;
    let k = 0;
    for (const s of this.order) {
      const { r, g, b } = s.color;
      for (let i = 0, n = segmentCount(s) * 2; i < n; i++, k += 3) {
        c[k] = r;
        c[k + 1] = g;
        c[k + 2] = b;
      }
    }
    colors.needsUpdate = true;
    this.geometry.setDrawRange(0, segments * 2);
  }

  /** Rewrites the positions from the controls' world matrices (call after updateMatrixWorld). */
  update(): void {
    const positions = this.geometry.getAttribute('position') as THREE.BufferAttribute;
    const a = positions.array as Float32Array;
    const v = this.v;
    let k = 0;
    const put = (p: THREE.Vector3, m: THREE.Matrix4): void => {
      v.copy(p).applyMatrix4(m);
      a[k++] = v.x;
      a[k++] = v.y;
      a[k++] = v.z;
    };
    for (const s of this.order) {
      const m = s.object.matrixWorld;
      const pts = s.points;
      const n = segmentCount(s);
      for (let i = 0; i < n; i++) {
        put(pts[i]!, m);
        put(pts[(i + 1) % pts.length]!, m);
      }
    }
    positions.needsUpdate = true;
  }

  dispose(): void {
    this.geometry.dispose();
    this.material.dispose();
  }

  private allocate(segments: number): void {
    this.capacity = segments;
    const n = Math.max(segments, 1) * 2 * 3;
    this.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(n), 3));
    this.geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(n), 3));
  }
}
