// The application state: what the server last said (scene, nodes, pose,
// rigs, keys), the refreshes that keep it current, the drag gesture and the
// revision poller that follows changes made by other tabs and scripts.

import { Api, ApiError } from './api';
import type { KeysAnswer, NodesAnswer, PoseAnswer, Quat, RigInfo, SceneInfo, Vec3 } from './api';
import { StatusBar, run } from './status';
import { Viewport } from './viewport';

export const kModeKeys: [string, string, string][] = [
  // [mode, key, label]
  ['forward', '1', 'Forward'],
  ['pseudo-inverse', '2', 'Pseudo-inverse'],
  ['inverse', '3', 'Inverse'],
  ['suspended', '4', 'Suspended'],
  ['magnet', '5', 'Magnet'],
  ['body', '6', 'Body'],
  ['pseudo-inverse-length', '7', 'Pseudo-inv. length'],
  ['magnet-radius', '8', 'Magnet radius'],
];

type Listener = () => void;

export interface DragStats {
  requests: number;
  answers: number;
  failures: number;
  /** Mean round trip of the drag requests of the last gesture, ms. */
  meanRoundTripMs: number;
  gestures: number;
}

export class App {
  scene: SceneInfo | null = null;
  nodes: NodesAnswer | null = null;
  rigs: RigInfo[] = [];
  keys: KeysAnswer | null = null;
  /** The keying scope shown when nothing is selected (from the first control). */
  scope = '';
  readonly names = new Map<string, string>();
  readonly byName = new Map<string, string>();
  /** The newest revision this tab knows it has seen (its own or fetched). */
  knownRevision = -1;
  readonly ready: Promise<void>;
  isReady = false;
  readonly drag = new DragGesture(this);

  private nodesSignature = '';
  private poseRevision = -1;
  private readonly listeners = new Map<string, Listener[]>();
  private resolveReady!: () => void;

  constructor(
    readonly api: Api,
    readonly viewport: Viewport,
    readonly status: StatusBar,
  ) {
    this.ready = new Promise((r) => (this.resolveReady = r));
  }

  on(topic: 'scene' | 'rigs' | 'keys' | 'nodes', f: Listener): void {
    const l = this.listeners.get(topic) ?? [];
    l.push(f);
    this.listeners.set(topic, l);
  }

  private emit(topic: string): void {
    for (const f of this.listeners.get(topic) ?? []) {
      try {
        f();
      } catch (e) {
        this.status.caught(e);
      }
    }
  }

  noteRevision(revision: number): void {
    if (revision > this.knownRevision) this.knownRevision = revision;
  }

  async start(): Promise<void> {
    await this.refreshScene();
    await this.reloadCharacter(true);
    this.viewport.frameAll();
    await Promise.all([this.refreshRigs(), this.refreshKeys()]);
    this.isReady = true;
    this.resolveReady();
    this.status.info(`Loaded ${this.scene?.path ?? 'scene'}: ${this.nodes?.controls.length ?? 0} controls`);
    this.startPolling();
  }

  // -------------------------------------------------------------- refreshes

  async refreshScene(): Promise<void> {
    const s = await this.api.get<SceneInfo>('/api/scene');
    this.scene = s;
    this.noteRevision(s.revision);
    this.viewport.setSelection(s.selection);
    this.emit('scene');
  }

  /** Nodes, and the glTF when the node set or a shape changed (or `force`). */
  async reloadCharacter(force = false): Promise<void> {
    const nodes = await this.api.get<NodesAnswer>('/api/nodes');
    const signature = JSON.stringify({ n: nodes.nodes, c: nodes.controls });
    if (force || signature !== this.nodesSignature) {
      const glb = await this.api.glb();
      await this.viewport.load(glb, nodes);
      this.nodes = nodes;
      this.nodesSignature = signature;
      this.names.clear();
      this.byName.clear();
      for (const n of nodes.nodes) {
        this.names.set(n.uuid, n.name);
        this.byName.set(n.name, n.uuid);
      }
      this.poseRevision = -1;
      if (this.scene) this.viewport.setSelection(this.scene.selection);
      this.emit('nodes');
    }
    await this.refreshPose();
  }

  async refreshPose(): Promise<void> {
    const pose = await this.api.get<PoseAnswer>('/api/pose');
    this.applyPose(pose);
  }

  /** Shows a pose unless a newer one is already shown. */
  applyPose(pose: PoseAnswer): void {
    if (typeof pose.revision === 'number') {
      if (pose.revision < this.poseRevision) return;
      this.poseRevision = pose.revision;
      this.noteRevision(pose.revision);
    }
    this.viewport.applyPose(pose.nodes);
  }

  async refreshRigs(): Promise<void> {
    const r = await this.api.get<{ rigs: RigInfo[] }>('/api/rigs');
    this.rigs = r.rigs ?? [];
    const edit = this.rigs.filter((x) => x.editMode).map((x) => x.name);
    this.viewport.setLabel(edit.length ? `Rig Edit Mode: ${edit.join(', ')}` : '');
    this.emit('rigs');
  }

  async refreshKeys(): Promise<void> {
    const sel = this.scene?.selection ?? [];
    if (sel.length) {
      this.keys = await this.api.get<KeysAnswer>(`/api/keys?controls=${sel.map(encodeURIComponent).join(',')}`);
      this.scope = this.keys.scope ?? '';
    } else {
      // Nothing selected: the scopes of the characters (one line per rig).
      this.keys = null;
      const scopes = this.scene?.keyScopes ?? {};
      const names = Object.keys(scopes);
      this.scope = names.length === 1 ? scopes[names[0]!]! : names.map((n) => `${n}: ${scopes[n]}`).join(', ');
    }
    this.emit('keys');
  }

  /** Everything: after undo/redo, rig edits and changes made elsewhere. */
  async refreshAll(): Promise<void> {
    await this.refreshScene();
    await this.reloadCharacter();
    await Promise.all([this.refreshRigs(), this.refreshKeys()]);
  }

  // ---------------------------------------------------------------- actions

  async select(uuids: string[], add: boolean): Promise<void> {
    const a = await this.api.post<{ revision: number; selection: string[] }>('/api/select', { controls: uuids, add });
    if (this.scene) this.scene.selection = a.selection;
    this.viewport.setSelection(a.selection);
    this.emit('scene');
    await this.refreshKeys();
  }

  /** A click in the viewport: replace, add (Shift) or toggle off (Shift on a selected one). */
  async pick(uuid: string | null, additive: boolean): Promise<void> {
    const sel = this.scene?.selection ?? [];
    if (uuid === null) {
      if (!additive && sel.length) await this.select([], false);
      return;
    }
    if (additive && sel.includes(uuid)) {
      await this.select(
        sel.filter((u) => u !== uuid),
        false,
      );
    } else {
      await this.select([uuid], additive);
    }
    const name = this.names.get(uuid) ?? uuid;
    this.status.info(`Selected ${name}${additive ? ' (added)' : ''}`);
  }

  async setMode(mode: string): Promise<void> {
    const a = await this.api.post<{ revision: number; mode: string }>('/api/mode', { mode });
    if (this.scene) this.scene.mode = a.mode ?? mode;
    this.emit('scene');
  }

  async setAutoKey(on: boolean): Promise<void> {
    const a = await this.api.post<{ autoKey?: boolean }>('/api/options', { autoKey: on });
    if (this.scene) this.scene.autoKey = typeof a.autoKey === 'boolean' ? a.autoKey : on;
    this.emit('scene');
  }

  async setFrame(frame: number): Promise<void> {
    const a = await this.api.post<{ revision: number; frame: number; time: number }>('/api/time', { frame });
    if (this.scene) {
      this.scene.frame = a.frame;
      this.scene.time = a.time;
    }
    this.emit('scene');
    await this.refreshPose();
  }

  async key(remove: boolean): Promise<void> {
    if (!(this.scene?.selection.length ?? 0)) {
      this.status.error(remove ? 'Delete key: select a control first' : 'Set key: select a control first');
      return;
    }
    const a = await this.api.post<{ revision: number; frames: number[] }>('/api/key', remove ? { delete: true } : {});
    this.status.info(`${remove ? 'Deleted key' : 'Keyed'} at frame ${this.scene?.frame ?? ''}; keys: ${(a.frames ?? []).join(', ') || 'none'}`);
    await Promise.all([this.refreshKeys(), this.refreshScene()]);
  }

  async undo(redo: boolean): Promise<void> {
    if (this.drag.active) return;
    const a = await this.api.post<{ revision: number; label: string }>(redo ? '/api/redo' : '/api/undo', {});
    this.status.info(`${redo ? 'Redo' : 'Undo'}: ${a.label ?? ''}`);
    await this.refreshAll();
  }

  // ------------------------------------------------------------- revisions

  private startPolling(): void {
    let busy = false;
    const tick = async (): Promise<void> => {
      if (busy || this.api.pendingWrites > 0 || this.drag.active) return;
      busy = true;
      try {
        const r = await this.api.get<{ revision: number }>('/api/revision');
        // A POST may have started while the GET was out: its revision is ours.
        if (r.revision > this.knownRevision && this.api.pendingWrites === 0 && !this.drag.active) {
          this.knownRevision = r.revision;
          await this.refreshAll();
        }
      } catch {
        // reported by the client
      } finally {
        busy = false;
      }
    };
    window.setInterval(() => run(tick()), 250);
  }
}

/**
 * One gizmo gesture: drags are sent with at most one request in flight (the
 * newest target wins), each answer's pose is shown, and the release waits
 * for the last drag. After a refused drag the gesture sends nothing more, so
 * a 409 is reported once, not at every mouse move.
 */
export class DragGesture {
  active = false;
  readonly stats: DragStats = { requests: 0, answers: 0, failures: 0, meanRoundTripMs: 0, gestures: 0 };
  private pending: { control: string; t: Vec3; q: Quat } | null = null;
  private pump: Promise<void> | null = null;
  private failed = false;
  private roundTrips: number[] = [];

  constructor(private readonly app: App) {}

  start(): void {
    this.active = true;
    this.failed = false;
    this.roundTrips = [];
    this.stats.gestures++;
  }

  move(control: string, t: Vec3, q: Quat): void {
    if (!this.active || this.failed) return;
    this.pending = { control, t, q };
    if (!this.pump) this.pump = this.drain();
  }

  private async drain(): Promise<void> {
    try {
      while (this.pending && !this.failed) {
        const p = this.pending;
        this.pending = null;
        const t0 = performance.now();
        this.stats.requests++;
        try {
          const a = await this.app.api.post<PoseAnswer>('/api/drag', { control: p.control, to: { t: p.t, q: p.q } });
          this.stats.answers++;
          this.roundTrips.push(performance.now() - t0);
          this.stats.meanRoundTripMs = this.roundTrips.reduce((s, x) => s + x, 0) / this.roundTrips.length;
          this.app.applyPose(a);
        } catch (e) {
          this.stats.failures++;
          this.failed = true;
          if (!(e instanceof ApiError)) this.app.status.caught(e);
        }
      }
    } finally {
      this.pump = null;
    }
  }

  async end(): Promise<void> {
    if (!this.active) return;
    while (this.pump) await this.pump;
    try {
      await this.app.api.post('/api/release', {});
    } finally {
      this.active = false;
      this.pending = null;
    }
    await Promise.all([this.app.refreshPose(), this.app.refreshKeys(), this.app.refreshScene()]);
  }
}
