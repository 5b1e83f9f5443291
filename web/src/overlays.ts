// Motion trails and ghosts (onion skin) in the viewport, computed on the
// server from the evaluated curves (GET /api/trails, GET /api/ghosts) and
// drawn as a few line objects: one line and one set of key points per
// selected control's trail over the playback range, one set of bone
// segments per ghost frame (before the current frame tinted red, after it
// green, fainter further away), around the current frame or at the
// selection's keys. Trails follow the selection, the keys and
// every edit (a drag), ghosts the time too; one request of each in flight
// at a time, so they stay on while dragging and playing.

import * as THREE from 'three';
import type { App } from './app';
import { Coalesced } from './app';
import type { GhostsAnswer, TrailsAnswer } from './api';
import { run } from './status';
import type { Viewport } from './viewport';

/** Ghosts each side of the current frame, and the frames between them. */
export const kGhostCount = 3;
export const kGhostStep = 2;

export class Overlays {
  private trailsOn = false;
  private ghostsOn = false;
  private ghostsAtKeys = false;
  private trailsStale = true;
  private trails: TrailsAnswer | null = null;
  private ghosts: GhostsAnswer | null = null;
  private readonly trailGroup = new THREE.Group();
  private readonly ghostGroup = new THREE.Group();
  private readonly refresher = new Coalesced(() => this.fetch());

  constructor(
    private readonly viewport: Viewport,
    private readonly app: App,
    private readonly range: () => [number, number],
  ) {
    this.trailGroup.name = 'motion trails';
    this.ghostGroup.name = 'ghosts';
    viewport.scene.add(this.trailGroup, this.ghostGroup);
    // A trail changes with the selection, the keys and edits (a drag), not
    // with the time: playing re-reads only the ghosts.
    const refresh = (trails: boolean) => {
      if (trails) this.trailsStale = true;
      if (this.trailsOn || this.ghostsOn) run(this.refresh());
    };
    const s = app.store.signals;
    s.selectionChanged.add(() => refresh(true));
    s.keysChanged.add(() => refresh(true));
    s.poseChanged.add(() => refresh(this.app.drag.active));
    s.timeChanged.add(() => refresh(false));
    s.sceneChanged.add(() => refresh(true));
  }

  get showTrails(): boolean {
    return this.trailsOn;
  }

  get showGhosts(): boolean {
    return this.ghostsOn;
  }

  /** 'off', 'around' (the current frame) or 'keys' (the selection's keys). */
  get ghostMode(): 'off' | 'around' | 'keys' {
    return !this.ghostsOn ? 'off' : this.ghostsAtKeys ? 'keys' : 'around';
  }

  setTrails(on: boolean): void {
    this.trailsOn = on;
    this.trailsStale = true;
    if (!on) this.clear(this.trailGroup);
    run(this.refresh());
  }

  setGhosts(on: boolean, atKeys = false): void {
    this.ghostsOn = on;
    this.ghostsAtKeys = atKeys;
    if (!on) this.clear(this.ghostGroup);
    run(this.refresh());
  }

  /** True while a fetch is running or queued (the tests wait for it). */
  get busy(): boolean {
    return this.refresher.busy;
  }

  /** What is drawn (for the tests): each trail's control, points and keys; the ghost frames. */
  state(): { trails: { control: string; points: Vec3List; keys: number[] }[]; ghosts: number[]; bones: number } {
    return {
      trails: this.trailsOn ? (this.trails?.trails ?? []).map((t) => ({ control: t.name, points: t.points, keys: t.keys })) : [],
      ghosts: this.ghostsOn ? (this.ghosts?.frames ?? []).map((f) => f.frame) : [],
      bones: this.ghostGroup.children.length ? (this.ghosts?.parents.filter((p) => p >= 0).length ?? 0) : 0,
    };
  }

  refresh(): Promise<void> {
    return this.refresher.run();
  }

  private async fetch(): Promise<void> {
    const selection = [...this.app.store.selection];
    const [first, last] = this.range();
    const readTrails = this.trailsStale;
    this.trailsStale = false;
    const [trails, ghosts] = await Promise.all([
      readTrails && this.trailsOn && selection.length ? this.app.api.trails(selection, first, last) : Promise.resolve(null),
      this.ghostsOn ? this.app.api.ghosts(kGhostCount, kGhostCount, kGhostStep, this.ghostsAtKeys) : Promise.resolve(null),
    ]);
    if (readTrails) {
      this.trails = trails;
      this.drawTrails();
    }
    this.ghosts = ghosts;
    this.drawGhosts();
    this.viewport.invalidate();
  }

  private clear(group: THREE.Group): void {
    for (const o of [...group.children]) {
      group.remove(o);
      const m = o as THREE.Line;
      m.geometry?.dispose();
      (m.material as THREE.Material | undefined)?.dispose();
    }
    this.viewport.invalidate();
  }

  private drawTrails(): void {
    this.clear(this.trailGroup);
    if (!this.trailsOn || !this.trails) return;
    for (const t of this.trails.trails) {
      const line = new THREE.Line(
        new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute(t.points.flat(), 3)),
        new THREE.LineBasicMaterial({ color: 0xffa040, depthTest: false, transparent: true, opacity: 0.9 }),
      );
      line.renderOrder = 10;
      const keyed = t.frames.flatMap((f, i) => (t.keys.some((k) => Math.abs(k - f) < 1e-6) ? [t.points[i]!] : []));
      const keys = new THREE.Points(
        new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute(keyed.flat(), 3)),
        new THREE.PointsMaterial({ color: 0xffe060, size: 7, sizeAttenuation: false, depthTest: false }),
      );
      keys.renderOrder = 11;
      this.trailGroup.add(line, keys);
    }
  }

  private drawGhosts(): void {
    this.clear(this.ghostGroup);
    if (!this.ghostsOn || !this.ghosts) return;
    const now = this.app.store.scene?.frame ?? 0;
    const { parents } = this.ghosts;
    for (const f of this.ghosts.frames) {
      const segments: number[] = [];
      f.points.forEach((p, j) => {
        const parent = parents[j]!;
        if (parent >= 0) segments.push(...f.points[parent]!, ...p);
      });
      const distance = this.ghostsAtKeys ? 0.5 : Math.abs(f.frame - now) / (kGhostCount * kGhostStep);
      const bones = new THREE.LineSegments(
        new THREE.BufferGeometry().setAttribute('position', new THREE.Float32BufferAttribute(segments, 3)),
        new THREE.LineBasicMaterial({
          color: f.frame < now ? 0xff6a6a : 0x6aff9a,
          transparent: true,
          opacity: Math.max(0.15, 0.7 * (1 - distance) + 0.15),
          depthTest: false,
        }),
      );
      bones.renderOrder = 9;
      this.ghostGroup.add(bones);
    }
  }
}

type Vec3List = [number, number, number][];
