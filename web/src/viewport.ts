// The 3D viewport: the store's character (the glTF of GET
// /api/character.glb), its joints drawn as lines and points, control shapes
// as lines in each control's local space, orbit/pan/zoom, picking of
// controls and the transform gizmo. All control shapes are one draw call
// (ControlLines). It renders from the store, following
// its signals (character, pose, selection, rigs in edit mode); what the
// user does with the mouse goes out through ViewportEvents.
//
// Picking is done in screen space (the distance in pixels from the pointer
// to each projected shape segment) rather than with Raycaster's world-space
// line threshold: a threshold in pixels behaves the same at every zoom and
// for the tiny finger controls as for the global control.

import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { TransformControls } from 'three/examples/jsm/controls/TransformControls.js';
import type { ControlInfo, Quat, RigInfo, Trs, Vec3 } from './api';
import { ControlLines } from './controllines';
import type { ControlShape } from './controllines';
import type { Character, Store } from './store';
import { boxFacesOnScreen, disposeTree, distanceToShape, meshesBox, webglRendererName } from './viewgeom';
import type { ScreenShape } from './viewgeom';

/** How near (CSS pixels) the pointer must be to a control's shape to pick it. */
const kPickRadiusPx = 8;

export interface ViewportEvents {
  /** A click on a control (null: on nothing); `additive` with Shift. */
  pick(uuid: string | null, additive: boolean): void;
  /** The gizmo was grabbed (one gesture starts). */
  gestureStart(): void;
  /** The gizmo moved: where the grabbed control should go, in world space. */
  gestureMove(control: string, t: Vec3, q: Quat): void;
  /** The gizmo was let go. */
  gestureEnd(): void;
}

interface ControlView extends ControlShape {
  info: ControlInfo;
  base: THREE.Color;
}


export interface FrameStats {
  /** Frames rendered in the last second. */
  fps: number;
  /** Poses applied in the last second. */
  posesPerSecond: number;
  frames: number;
  poses: number;
  /** The WebGL renderer the browser reports (e.g. a GPU's name, or SwiftShader). */
  renderer: string;
  /** Whether frames are multisampled (off on software renderers). */
  antialias: boolean;
  /** Draw calls of the last frame, and the control segments drawn in it. */
  drawCalls: number;
  controlSegments: number;
}

/** How the character's meshes are drawn: as loaded, see-through, or not at all. */
export type MeshDisplay = 'shaded' | 'xray' | 'hidden';
export const kMeshDisplays: MeshDisplay[] = ['shaded', 'xray', 'hidden'];

const kSelected = new THREE.Color(0.35, 1.0, 0.75);
const kPrimary = new THREE.Color(1.0, 1.0, 1.0);
const kHover = new THREE.Color(0.6, 0.85, 1.0);

export class Viewport {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly camera: THREE.PerspectiveCamera;
  readonly orbit: OrbitControls;
  readonly gizmo: TransformControls;
  /** The gizmo moves this object (world space); the drags send its matrix. */
  readonly proxy = new THREE.Object3D();

  private root: THREE.Object3D | null = null;
  /** The character's meshes, and each material's own look (what 'shaded' puts back). */
  private meshes: THREE.Mesh[] = [];
  private readonly meshLooks = new Map<THREE.Material, { transparent: boolean; opacity: number; depthWrite: boolean }>();
  private meshMode: MeshDisplay = 'shaded';
  private readonly hiddenGroups = new Set<string>();
  /** Isolate selection: only these controls are drawn and picked (null: all). */
  private isolatedSet: Set<string> | null = null;
  private readonly byUuid = new Map<string, THREE.Object3D>();
  private readonly controls = new Map<string, ControlView>();
  private readonly controlLines = new ControlLines();
  private jointPairs: [THREE.Object3D, THREE.Object3D][] = [];
  private joints: THREE.Object3D[] = [];
  private jointLines: THREE.LineSegments | null = null;
  private jointPoints: THREE.Points | null = null;
  private selection: string[] = [];
  private hover: string | null = null;
  private dirty = true;
  private screenCache: { version: number; shapes: Map<string, ScreenShape> } | null = null;
  private viewVersion = 0;
  private dragging = false;
  private gestureControl: string | null = null;
  private pointerDown: { x: number; y: number; onGizmo: boolean } | null = null;
  private readonly frameTimes: number[] = [];
  private readonly poseTimes: number[] = [];
  private frames = 0;
  private poses = 0;
  private readonly label: HTMLElement;
  private readonly rendererName: string;

  constructor(
    private readonly container: HTMLElement,
    private readonly store: Store,
    private readonly events: ViewportEvents,
  ) {
    // A software rasteriser (SwiftShader, llvmpipe: a browser without a GPU,
    // a VM, CI) draws multisampled frames several times slower, so there the
    // view drops antialiasing and high-DPI pixels; ?antialias=1 or 0 decides.
    this.rendererName = webglRendererName();
    const software = /swiftshader|llvmpipe|softpipe|software/i.test(this.rendererName);
    const asked = new URLSearchParams(window.location.search).get('antialias');
    const antialias = asked === null ? !software : asked !== '0';
    this.renderer = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: false });
    this.renderer.setPixelRatio(software ? 1 : Math.min(window.devicePixelRatio, 2));
    this.renderer.setClearColor(0x1d2026);
    this.renderer.domElement.dataset.testid = 'viewport-canvas';
    container.appendChild(this.renderer.domElement);

    this.label = document.createElement('div');
    this.label.className = 'viewport-label';
    container.appendChild(this.label);

    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 200);
    this.camera.position.set(0, 1.3, 4);

    this.scene.add(new THREE.HemisphereLight(0xdfe6f0, 0x30343a, 1.6));
    const key = new THREE.DirectionalLight(0xffffff, 1.6);
    key.position.set(2, 4, 3);
    this.scene.add(key);
    const grid = new THREE.GridHelper(10, 20, 0x4a505a, 0x2e333b);
    this.scene.add(grid);

    this.orbit = new OrbitControls(this.camera, this.renderer.domElement);
    this.orbit.target.set(0, 1, 0);
    this.orbit.enableDamping = false;
    this.orbit.addEventListener('change', () => this.viewChanged());

    this.scene.add(this.proxy, this.controlLines.object);
    this.gizmo = new TransformControls(this.camera, this.renderer.domElement);
    this.gizmo.setSpace('world');
    this.gizmo.setSize(0.9);
    this.gizmo.attach(this.proxy);
    this.gizmo.enabled = false;
    const helper = this.gizmo.getHelper();
    helper.visible = false;
    this.scene.add(helper);
    this.gizmo.addEventListener('dragging-changed', (e) => {
      this.orbit.enabled = !e.value;
    });
    this.gizmo.addEventListener('mouseDown', () => {
      const primary = this.primary();
      if (!primary) return;
      this.dragging = true;
      this.gestureControl = primary;
      this.events.gestureStart();
    });
    this.gizmo.addEventListener('objectChange', () => {
      this.dirty = true;
      if (!this.dragging || !this.gestureControl) return;
      this.proxy.updateMatrixWorld();
      const p = this.proxy.position;
      const q = this.proxy.quaternion;
      this.events.gestureMove(this.gestureControl, [p.x, p.y, p.z], [q.x, q.y, q.z, q.w]);
    });
    this.gizmo.addEventListener('mouseUp', () => {
      if (!this.dragging) return;
      this.dragging = false;
      this.gestureControl = null;
      this.events.gestureEnd();
    });
    this.gizmo.addEventListener('change', () => {
      this.dirty = true;
    });

    const canvas = this.renderer.domElement;
    canvas.addEventListener('pointerdown', (e) => {
      // TransformControls sets `axis` while the pointer is over a handle.
      this.pointerDown = { x: e.clientX, y: e.clientY, onGizmo: this.gizmo.axis !== null && this.gizmo.enabled };
    });
    canvas.addEventListener('pointerup', (e) => {
      const down = this.pointerDown;
      this.pointerDown = null;
      if (!down || down.onGizmo || e.button !== 0) return;
      if (Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4) return; // an orbit, not a click
      const hit = this.pickAt(e.clientX, e.clientY);
      this.events.pick(hit, e.shiftKey);
    });
    canvas.addEventListener('pointermove', (e) => {
      if (this.dragging || (e.buttons & 1) !== 0) return;
      const hit = this.pickAt(e.clientX, e.clientY);
      if (hit !== this.hover) {
        this.hover = hit;
        this.refreshColors();
        canvas.style.cursor = hit ? 'pointer' : '';
      }
    });
    canvas.addEventListener('pointerleave', () => {
      if (this.hover) {
        this.hover = null;
        this.refreshColors();
      }
    });

    const signals = store.signals;
    signals.characterChanged.add((c) => this.load(c));
    signals.poseChanged.add((nodes) => this.applyPose(nodes));
    signals.selectionChanged.add((uuids) => this.setSelection(uuids));
    signals.rigsChanged.add((rigs) => this.showEditMode(rigs));

    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    const loop = (): void => {
      requestAnimationFrame(loop);
      this.renderIfDirty();
    };
    requestAnimationFrame(loop);
  }

  /** Replaces the character with the store's and draws its controls. */
  private load(character: Character): void {
    const nodes = character.nodes;
    if (this.root) {
      this.scene.remove(this.root);
      disposeTree(this.root);
    }
    if (this.jointLines) {
      this.scene.remove(this.jointLines);
      this.jointLines.geometry.dispose();
    }
    if (this.jointPoints) {
      this.scene.remove(this.jointPoints);
      this.jointPoints.geometry.dispose();
    }
    this.byUuid.clear();
    this.controls.clear();
    this.meshes = [];
    this.meshLooks.clear();
    this.root = character.root;
    this.scene.add(this.root);

    this.root.traverse((o) => {
      const uuid = (o.userData as { uuid?: unknown }).uuid;
      if (typeof uuid === 'string' && !this.byUuid.has(uuid)) this.byUuid.set(uuid, o);
      if ((o as THREE.SkinnedMesh).isSkinnedMesh || (o as THREE.Mesh).isMesh) {
        o.frustumCulled = false; // skinned bounds do not follow the pose
        const mesh = o as THREE.Mesh;
        const mats = Array.isArray(mesh.material) ? mesh.material : [mesh.material];
        for (const m of mats) {
          // A material from the file (its colours, textures, alpha) is drawn as
          // the file says; only GLTFLoader's default grey gets the see-through
          // look that keeps the joints and controls inside visible.
          if (character.fileMaterials.has(m)) continue;
          const std = m as THREE.MeshStandardMaterial;
          if (std.isMeshStandardMaterial) {
            std.transparent = true;
            std.opacity = 0.85;
            std.depthWrite = true;
          }
        }
        this.meshes.push(mesh);
        for (const m of mats) this.meshLooks.set(m, { transparent: m.transparent, opacity: m.opacity, depthWrite: m.depthWrite });
      }
    });
    this.applyMeshDisplay();

    // Nodes the glTF did not carry (none, normally) hang under their parent,
    // so local poses still place them.
    let pending = nodes.nodes.filter((n) => !this.byUuid.has(n.uuid));
    for (let pass = 0; pending.length && pass < 64; pass++) {
      const next: typeof pending = [];
      for (const n of pending) {
        const parent = n.parent === null ? this.root : this.byUuid.get(n.parent);
        if (!parent) {
          next.push(n);
          continue;
        }
        const o = new THREE.Object3D();
        o.name = n.name;
        o.userData.uuid = n.uuid;
        parent.add(o);
        this.byUuid.set(n.uuid, o);
      }
      if (next.length === pending.length) break;
      pending = next;
    }

    const jointSet = new Set(nodes.nodes.filter((n) => n.type === 'joint').map((n) => n.uuid));
    this.joints = [];
    this.jointPairs = [];
    for (const n of nodes.nodes) {
      if (!jointSet.has(n.uuid)) continue;
      const o = this.byUuid.get(n.uuid);
      if (!o) continue;
      this.joints.push(o);
      if (n.parent && jointSet.has(n.parent)) {
        const p = this.byUuid.get(n.parent);
        if (p) this.jointPairs.push([p, o]);
      }
    }
    const lineGeo = new THREE.BufferGeometry();
    lineGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(this.jointPairs.length * 6), 3));
    this.jointLines = new THREE.LineSegments(
      lineGeo,
      new THREE.LineBasicMaterial({ color: 0x8fa3bf, transparent: true, opacity: 0.55, depthTest: false }),
    );
    this.jointLines.frustumCulled = false;
    this.jointLines.renderOrder = 5;
    const pointGeo = new THREE.BufferGeometry();
    pointGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(this.joints.length * 3), 3));
    this.jointPoints = new THREE.Points(
      pointGeo,
      new THREE.PointsMaterial({ color: 0xb8c6da, size: 3, sizeAttenuation: false, depthTest: false, transparent: true, opacity: 0.7 }),
    );
    this.jointPoints.frustumCulled = false;
    this.jointPoints.renderOrder = 5;
    this.scene.add(this.jointLines, this.jointPoints);

    this.setControls(nodes.controls);
    this.setSelection(this.store.selection);
    this.dirty = true;
  }

  private setControls(controls: ControlInfo[]): void {
    for (const c of controls) {
      const object = this.byUuid.get(c.uuid);
      if (!object) continue;
      const points = c.shape.points.map((p) => new THREE.Vector3(p[0], p[1], p[2]));
      const base = new THREE.Color(c.shape.color[0], c.shape.color[1], c.shape.color[2]);
      const view = { info: c, object, base, points, closed: c.shape.closed, color: base.clone(), visible: this.shows(c), top: false };
      this.controls.set(c.uuid, view);
    }
    this.refreshColors();
  }

  // ---------------------------------------------------------------- display

  get meshDisplay(): MeshDisplay {
    return this.meshMode;
  }

  /** Draws the meshes shaded (as loaded), see-through (x-ray), or hides them. */
  setMeshDisplay(mode: MeshDisplay): void {
    this.meshMode = mode;
    this.applyMeshDisplay();
  }

  private applyMeshDisplay(): void {
    for (const mesh of this.meshes) {
      mesh.visible = this.meshMode !== 'hidden';
      const mats = Array.isArray(mesh.material) ? mesh.material : [mesh.material];
      for (const m of mats) {
        const look = this.meshLooks.get(m);
        if (!look) continue;
        const xray = this.meshMode === 'xray';
        m.transparent = xray || look.transparent;
        m.opacity = xray ? Math.min(look.opacity, 0.3) : look.opacity;
        m.depthWrite = xray ? false : look.depthWrite;
        m.needsUpdate = true;
      }
    }
    this.dirty = true;
  }

  /** What the meshes show now (for the tests): how many, how many drawn, their opacities. */
  meshState(): { meshes: number; visible: number; opacity: number[] } {
    const opacity: number[] = [];
    for (const mesh of this.meshes) for (const m of Array.isArray(mesh.material) ? mesh.material : [mesh.material]) opacity.push(m.opacity);
    return { meshes: this.meshes.length, visible: this.meshes.filter((m) => m.visible).length, opacity };
  }

  /** The control groups (a built rig's components, an ephemeral rig's regions) with their counts, in first-seen order. */
  groups(): { group: string; controls: number; visible: boolean }[] {
    const out = new Map<string, number>();
    for (const c of this.controls.values()) out.set(c.info.group, (out.get(c.info.group) ?? 0) + 1);
    return [...out].map(([group, controls]) => ({ group, controls, visible: !this.hiddenGroups.has(group) }));
  }

  /** Shows or hides a group's controls: hidden ones are neither drawn nor picked. */
  setGroupVisible(group: string, visible: boolean): void {
    if (visible) this.hiddenGroups.delete(group);
    else this.hiddenGroups.add(group);
    this.applyVisibility();
  }

  /** Isolates these controls (only they are drawn and picked), or shows all again with null. */
  setIsolated(uuids: readonly string[] | null): void {
    this.isolatedSet = uuids ? new Set(uuids) : null;
    this.applyVisibility();
  }

  get isolated(): readonly string[] | null {
    return this.isolatedSet ? [...this.isolatedSet] : null;
  }

  private shows(c: ControlInfo): boolean {
    return !this.hiddenGroups.has(c.group) && (!this.isolatedSet || this.isolatedSet.has(c.uuid));
  }

  private applyVisibility(): void {
    for (const c of this.controls.values()) c.visible = this.shows(c.info);
    this.controlLines.layout(this.controls.values());
    this.viewVersion++;
    this.dirty = true;
  }

  /** The controls drawn whose shape's centre on screen lies in the client rectangle (box select). */
  controlsIn(x0: number, y0: number, x1: number, y1: number): string[] {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const [ax, bx] = [Math.min(x0, x1) - rect.left, Math.max(x0, x1) - rect.left];
    const [ay, by] = [Math.min(y0, y1) - rect.top, Math.max(y0, y1) - rect.top];
    const out: string[] = [];
    for (const [uuid, s] of this.screenShapes()) {
      let [x, y, n] = s.origin ? [s.origin[0], s.origin[1], 1] : [0, 0, 0];
      for (let i = 0; !s.origin && i < s.xy.length; i += 2)
        if (!Number.isNaN(s.xy[i]!)) [x, y, n] = [x + s.xy[i]!, y + s.xy[i + 1]!, n + 1];
      if (n && x / n >= ax && x / n <= bx && y / n >= ay && y / n <= by) out.push(uuid);
    }
    return out;
  }

  /** Frames the camera on the selected controls (at least half a unit across), or everything without a selection. */
  frameSelected(): void {
    const selected = this.store.selection.map((u) => this.controls.get(u)).filter((c) => c !== undefined);
    if (!selected.length) return this.frameAll();
    this.root?.updateMatrixWorld(true);
    const box = new THREE.Box3();
    const v = new THREE.Vector3();
    for (const c of selected) box.expandByPoint(c.object.getWorldPosition(v));
    box.expandByVector(new THREE.Vector3(0.25, 0.25, 0.25));
    this.fit(box);
  }

  /** Frames the camera on the character's joints (or its meshes). */
  frameAll(): void {
    if (!this.root) return;
    this.root.updateMatrixWorld(true);
    const box = new THREE.Box3();
    const v = new THREE.Vector3();
    for (const j of this.joints) box.expandByPoint(j.getWorldPosition(v));
    for (const c of this.controls.values()) box.expandByPoint(c.object.getWorldPosition(v));
    if (this.meshMode !== 'hidden') box.union(this.meshBox());
    if (box.isEmpty()) box.setFromObject(this.root);
    if (!box.isEmpty()) this.fit(box);
  }

  /** The meshes' posed world box (viewgeom.meshesBox). */
  meshBox(): THREE.Box3 {
    this.root?.updateMatrixWorld(true);
    return meshesBox(this.meshes);
  }

  /** Where the meshes' box faces' centres fall on screen (client pixels), for the tests. */
  meshScreenBox(): { left: number; top: number; right: number; bottom: number } | null {
    return boxFacesOnScreen(this.meshBox(), (p) => this.toScreen(p));
  }

  private fit(box: THREE.Box3): void {
    const center = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    // Fit height and width (the view looks along -Z, slightly from the side).
    const tanHalf = Math.tan((this.camera.fov * Math.PI) / 360);
    const fitH = size.y / 2 / tanHalf;
    const fitW = size.x / 2 / (tanHalf * this.camera.aspect);
    const dist = Math.max(fitH, fitW, 0.2) * 1.12 + size.z / 2;
    this.orbit.target.copy(center);
    this.camera.position.copy(center).add(new THREE.Vector3(0.3, 0.12, 1).normalize().multiplyScalar(dist));
    this.camera.near = Math.max(dist / 500, 0.001);
    this.camera.far = dist * 50;
    this.camera.updateProjectionMatrix();
    this.orbit.update();
    this.viewChanged();
  }

  /** Applies local TRS (what glTF nodes hold) per uuid; unknown uuids are skipped. */
  private applyPose(nodes: ReadonlyMap<string, Trs>): void {
    for (const [uuid, v] of nodes) {
      const o = this.byUuid.get(uuid);
      if (!o) continue;
      o.position.set(v[0], v[1], v[2]);
      o.quaternion.set(v[3], v[4], v[5], v[6]);
      o.scale.set(v[7], v[8], v[9]);
    }
    this.poses++;
    this.poseTimes.push(performance.now());
    this.viewChanged();
    if (!this.dragging) this.syncProxy();
  }

  private setSelection(uuids: readonly string[]): void {
    this.selection = uuids.filter((u) => this.controls.has(u));
    this.refreshColors();
    const primary = this.primary();
    this.gizmo.enabled = primary !== null;
    this.gizmo.getHelper().visible = primary !== null;
    if (!this.dragging) this.syncProxy();
    this.dirty = true;
  }

  /** The control the gizmo sits on: the last one selected. */
  primary(): string | null {
    return this.selection.length ? this.selection[this.selection.length - 1]! : null;
  }

  setGizmoMode(mode: 'translate' | 'rotate'): void {
    this.gizmo.setMode(mode);
    this.dirty = true;
  }

  gizmoMode(): 'translate' | 'rotate' | 'scale' {
    return this.gizmo.getMode();
  }

  isDragging(): boolean {
    return this.dragging;
  }

  /** The label over the view names the rigs in rig edit mode. */
  private showEditMode(rigs: readonly RigInfo[]): void {
    const edit = rigs.filter((x) => x.editMode).map((x) => x.name);
    const text = edit.length ? `Rig Edit Mode: ${edit.join(', ')}` : '';
    this.label.textContent = text;
    this.label.style.display = text ? '' : 'none';
  }

  hasControl(uuid: string): boolean {
    return this.controls.has(uuid);
  }

  controlNames(): Map<string, string> {
    const m = new Map<string, string>();
    for (const [u, c] of this.controls) m.set(u, c.info.name);
    return m;
  }

  /** World position of a node (metres) in the pose shown. */
  worldPosition(uuid: string): Vec3 | null {
    const o = this.byUuid.get(uuid);
    if (!o) return null;
    o.updateWorldMatrix(true, false);
    const v = new THREE.Vector3().setFromMatrixPosition(o.matrixWorld);
    return [v.x, v.y, v.z];
  }

  /** Puts the gizmo's proxy on the primary control's world position and rotation. */
  syncProxy(): void {
    const primary = this.primary();
    const c = primary ? this.controls.get(primary) : undefined;
    if (!c) return;
    c.object.updateWorldMatrix(true, false);
    const s = new THREE.Vector3();
    c.object.matrixWorld.decompose(this.proxy.position, this.proxy.quaternion, s);
    this.proxy.updateMatrixWorld();
    this.dirty = true;
  }

  // ---------------------------------------------------------------- picking

  /** The control whose shape is nearest the client point, within kPickRadiusPx. */
  pickAt(clientX: number, clientY: number): string | null {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const best = this.nearest(clientX - rect.left, clientY - rect.top, null);
    return best && best.dist <= kPickRadiusPx ? best.uuid : null;
  }

  /**
   * Where to click to pick `uuid` (client CSS pixels): the point of its
   * shape that the picker resolves to it with the widest margin to every
   * other control, or null when no point of it can be picked (off screen or
   * hidden under others). A right click (`rightClick`) is not caught by
   * the gizmo, so points under it count then.
   */
  project(uuid: string, rightClick = false): { x: number; y: number } | null {
    const shapes = this.screenShapes();
    const own = shapes.get(uuid);
    if (!own) return null;
    const rect = this.renderer.domElement.getBoundingClientRect();
    const w = rect.width;
    const h = rect.height;
    const candidates: [number, number][] = [];
    const n = own.xy.length / 2;
    for (let i = 0; i < n; i++) {
      const x = own.xy[2 * i]!;
      const y = own.xy[2 * i + 1]!;
      if (Number.isNaN(x)) continue;
      candidates.push([x, y]);
      const j = i + 1 < n ? i + 1 : own.closed ? 0 : -1;
      if (j >= 0 && !Number.isNaN(own.xy[2 * j]!)) candidates.push([(x + own.xy[2 * j]!) / 2, (y + own.xy[2 * j + 1]!) / 2]);
    }
    if (own.origin) candidates.push(own.origin);
    let best: { x: number; y: number; margin: number } | null = null;
    for (const [x, y] of candidates) {
      if (x < 2 || y < 2 || x > w - 2 || y > h - 2) continue;
      if (!rightClick && this.gizmoCatches(rect.left + x, rect.top + y)) continue; // a click there grabs the gizmo
      const hit = this.nearest(x, y, null);
      if (!hit || hit.uuid !== uuid || hit.dist > kPickRadiusPx) continue;
      const other = this.nearest(x, y, uuid);
      const margin = other ? other.dist - hit.dist : Infinity;
      if (!best || margin > best.margin) best = { x, y, margin };
    }
    return best ? { x: rect.left + best.x, y: rect.top + best.y } : null;
  }

  /**
   * True when a press at the client point would grab the gizmo rather than
   * pick: the same test TransformControls makes (a ray against the pickers
   * of its mode; they are TransformControls internals, read defensively).
   */
  gizmoCatches(clientX: number, clientY: number): boolean {
    const helper = this.gizmo.getHelper();
    if (!this.gizmo.enabled || !helper.visible) return false;
    const inner = (this.gizmo as unknown as { _gizmo?: { picker?: Record<string, THREE.Object3D> } })._gizmo;
    const picker = inner?.picker?.[this.gizmo.getMode()];
    if (!picker) return false;
    helper.updateMatrixWorld(true);
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    return ray.intersectObject(picker, true).some((i) => i.object.visible);
  }

  /** Client point of a world point (for tests and overlays). */
  toScreen(p: Vec3): { x: number; y: number; visible: boolean } {
    this.camera.updateMatrixWorld();
    const rect = this.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3(p[0], p[1], p[2]).project(this.camera);
    return {
      x: rect.left + ((v.x + 1) / 2) * rect.width,
      y: rect.top + ((1 - v.y) / 2) * rect.height,
      visible: v.z > -1 && v.z < 1,
    };
  }

  /**
   * A point on the gizmo's translate arrow for a world axis (client pixels),
   * and the arrow's direction on screen: the same scale TransformControls
   * gives its handles (distance * tan(fov/2) * size / 4).
   */
  gizmoHandle(axis: 'x' | 'y' | 'z'): { x: number; y: number; dx: number; dy: number } | null {
    if (!this.gizmo.enabled) return null;
    this.proxy.updateMatrixWorld();
    const pos = new THREE.Vector3().setFromMatrixPosition(this.proxy.matrixWorld);
    const factor =
      pos.distanceTo(this.camera.position) *
      Math.min((1.9 * Math.tan((Math.PI * this.camera.fov) / 360)) / this.camera.zoom, 7);
    const unit = (factor * this.gizmo.size) / 4;
    const dir = new THREE.Vector3(axis === 'x' ? 1 : 0, axis === 'y' ? 1 : 0, axis === 'z' ? 1 : 0);
    const at = pos.clone().addScaledVector(dir, 0.42 * unit);
    const far = pos.clone().addScaledVector(dir, 0.6 * unit);
    const a = this.toScreen([at.x, at.y, at.z]);
    const b = this.toScreen([far.x, far.y, far.z]);
    const len = Math.hypot(b.x - a.x, b.y - a.y) || 1;
    return { x: a.x, y: a.y, dx: (b.x - a.x) / len, dy: (b.y - a.y) / len };
  }

  private nearest(x: number, y: number, exclude: string | null): { uuid: string; dist: number } | null {
    let best: { uuid: string; dist: number } | null = null;
    for (const [uuid, s] of this.screenShapes()) {
      if (uuid === exclude) continue;
      const d = distanceToShape(s, x, y);
      if (!best || d < best.dist) best = { uuid, dist: d };
    }
    return best;
  }

  private screenShapes(): Map<string, ScreenShape> {
    if (this.screenCache && this.screenCache.version === this.viewVersion) return this.screenCache.shapes;
    const shapes = new Map<string, ScreenShape>();
    const rect = this.renderer.domElement.getBoundingClientRect();
    const w = rect.width;
    const h = rect.height;
    this.camera.updateMatrixWorld();
    this.root?.updateMatrixWorld(true);
    const v = new THREE.Vector3();
    const toPx = (out: Float32Array, i: number): void => {
      v.project(this.camera);
      if (v.z < -1 || v.z > 1) {
        out[2 * i] = NaN;
        out[2 * i + 1] = NaN;
      } else {
        out[2 * i] = ((v.x + 1) / 2) * w;
        out[2 * i + 1] = ((1 - v.y) / 2) * h;
      }
    };
    for (const [uuid, c] of this.controls) {
      if (!c.object.visible || !c.visible) continue;
      const m = c.object.matrixWorld;
      const xy = new Float32Array(c.points.length * 2);
      c.points.forEach((p, i) => {
        v.copy(p).applyMatrix4(m);
        toPx(xy, i);
      });
      const o = new Float32Array(2);
      v.setFromMatrixPosition(m);
      toPx(o, 0);
      // A shape without points picks at the control's origin.
      const origin: [number, number] | null = !c.points.length && !Number.isNaN(o[0]!) ? [o[0]!, o[1]!] : null;
      shapes.set(uuid, { xy, closed: c.closed, origin });
    }
    this.screenCache = { version: this.viewVersion, shapes };
    return shapes;
  }

  // -------------------------------------------------------------- rendering

  private refreshColors(): void {
    const primary = this.primary();
    const selected = new Set(this.selection);
    for (const [uuid, c] of this.controls) {
      if (uuid === primary) c.color.copy(kPrimary);
      else if (selected.has(uuid)) c.color.copy(kSelected);
      else if (uuid === this.hover) c.color.copy(c.base).lerp(kHover, 0.6);
      else c.color.copy(c.base);
      c.top = selected.has(uuid);
    }
    this.controlLines.layout(this.controls.values());
    this.dirty = true;
  }

  private viewChanged(): void {
    this.viewVersion++;
    this.dirty = true;
  }

  private resize(): void {
    const w = Math.max(this.container.clientWidth, 1);
    const h = Math.max(this.container.clientHeight, 1);
    // The canvas's CSS size stays 100% of the container (no inline pixel
    // size that would keep the layout from shrinking).
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.viewChanged();
  }

  private updateJoints(): void {
    if (!this.jointLines || !this.jointPoints) return;
    const lp = this.jointLines.geometry.getAttribute('position') as THREE.BufferAttribute;
    const a = lp.array as Float32Array;
    this.jointPairs.forEach(([p, c], i) => {
      const pe = p.matrixWorld.elements;
      const ce = c.matrixWorld.elements;
      a.set([pe[12]!, pe[13]!, pe[14]!, ce[12]!, ce[13]!, ce[14]!], i * 6);
    });
    lp.needsUpdate = true;
    const pp = this.jointPoints.geometry.getAttribute('position') as THREE.BufferAttribute;
    const b = pp.array as Float32Array;
    this.joints.forEach((j, i) => {
      const e = j.matrixWorld.elements;
      b.set([e[12]!, e[13]!, e[14]!], i * 3);
    });
    pp.needsUpdate = true;
  }

  private renderIfDirty(): void {
    if (!this.dirty) return;
    this.dirty = false;
    this.scene.updateMatrixWorld();
    this.updateJoints();
    this.controlLines.update();
    this.renderer.render(this.scene, this.camera);
    this.frames++;
    this.frameTimes.push(performance.now());
  }

  /** Frames rendered and poses applied, over the last second. */
  stats(): FrameStats {
    const now = performance.now();
    while (this.frameTimes.length && now - this.frameTimes[0]! > 1000) this.frameTimes.shift();
    while (this.poseTimes.length && now - this.poseTimes[0]! > 1000) this.poseTimes.shift();
    return {
      fps: this.frameTimes.length,
      posesPerSecond: this.poseTimes.length,
      frames: this.frames,
      poses: this.poses,
      renderer: this.rendererName,
      antialias: this.renderer.getContext().getContextAttributes()?.antialias ?? false,
      drawCalls: this.renderer.info.render.calls,
      controlSegments: this.controlLines.segments,
    };
  }

  /** Forces a render on the next animation frame. */
  invalidate(): void {
    this.dirty = true;
  }
}
