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

/**
 * Runs an async job one at a time: a call while it runs is answered by the
 * one run that starts after it (every caller sees a run that began after
 * its call), so overlapping refreshes never apply an older answer last.
 */
class Coalesced {
  private running: Promise<void> | null = null;
  private next: Promise<void> | null = null;

  constructor(private readonly job: () => Promise<void>) {}

  run(): Promise<void> {
    if (!this.running) {
      this.running = this.job().finally(() => {
        this.running = null;
      });
      return this.running;
    }
    if (!this.next) {
      this.next = this.running
        .catch(() => undefined)
        .then(() => {
          this.next = null;
          return this.run();
        });
    }
    return this.next;
  }

  get busy(): boolean {
    return this.running !== null || this.next !== null;
  }
}

/** Poll periods: while connected, and the backoff while the server is gone. */
const kPollMs = 250;
const kRetryFirstMs = 500;
const kRetryMaxMs = 4000;

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
  /** True while the server does not answer (the poller retries with a backoff). */
  offline = false;
  /** Poll attempts that got no answer, and when each was made (for tests). */
  readonly retries: number[] = [];

  private nodesSignature = '';
  private poseRevision = -1;
  private readonly listeners = new Map<string, Listener[]>();
  private resolveReady!: () => void;
  private forceReload = false;
  private readonly refresher = new Coalesced(() => this.refreshEverything());
  // Every fetch takes a number when it starts; an answer older than the one
  // shown (a fetch that started earlier and came back later) is dropped.
  private seq = 0;
  private readonly shown = { scene: 0, nodes: 0, rigs: 0, keys: 0 };

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

  /**
   * True when nothing is in flight: no request but the background ones, no
   * refresh running or queued, no gesture, and the server answering (what
   * the end-to-end tests wait for before reading the screen).
   */
  settled(): boolean {
    return this.isReady && this.api.pending === 0 && !this.refresher.busy && !this.drag.active && !this.offline;
  }

  async start(): Promise<void> {
    await this.refreshAll(true);
    this.viewport.frameAll();
    this.isReady = true;
    this.resolveReady();
    this.status.info(`Loaded ${this.scene?.path || 'scene'}: ${this.nodes?.controls.length ?? 0} controls`);
    this.startPolling();
  }

  /** A user action succeeded: an error still shown is about an earlier one. */
  succeeded(): void {
    this.status.clearError();
  }

  // -------------------------------------------------------------- refreshes

  async refreshScene(): Promise<void> {
    const n = ++this.seq;
    const s = await this.api.get<SceneInfo>('/api/scene');
    if (n < this.shown.scene) return;
    this.shown.scene = n;
    this.scene = s;
    this.noteRevision(s.revision);
    this.viewport.setSelection(s.selection);
    this.emit('scene');
  }

  /** The scene changed here (an answer of a POST): older fetches of it are stale. */
  private sceneChanged(): void {
    this.shown.scene = ++this.seq;
    this.emit('scene');
  }

  /**
   * Nodes, and the glTF when the node set or a shape changed (or `force`):
   * the node list is replaced by the server's, never merged, so the nodes
   * of a removed rig go with it.
   */
  private async reloadCharacter(force = false): Promise<void> {
    const n = ++this.seq;
    const nodes = await this.api.get<NodesAnswer>('/api/nodes');
    if (n < this.shown.nodes) return;
    const signature = JSON.stringify({ n: nodes.nodes, c: nodes.controls });
    if (force || signature !== this.nodesSignature) {
      const glb = await this.api.glb();
      if (n < this.shown.nodes) return;
      await this.viewport.load(glb, nodes);
      this.nodesSignature = signature;
      this.names.clear();
      this.byName.clear();
      for (const x of nodes.nodes) {
        this.names.set(x.uuid, x.name);
        this.byName.set(x.name, x.uuid);
      }
      this.poseRevision = -1;
      if (this.scene) this.viewport.setSelection(this.scene.selection);
    }
    this.shown.nodes = n;
    this.nodes = nodes;
    this.emit('nodes');
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

  async refreshRigs(background = false): Promise<void> {
    const n = ++this.seq;
    const r = await this.api.get<{ rigs: RigInfo[] }>('/api/rigs', { background });
    if (n < this.shown.rigs) return;
    this.shown.rigs = n;
    this.rigs = r.rigs ?? [];
    const edit = this.rigs.filter((x) => x.editMode).map((x) => x.name);
    this.viewport.setLabel(edit.length ? `Rig Edit Mode: ${edit.join(', ')}` : '');
    this.emit('rigs');
  }

  async refreshKeys(): Promise<void> {
    const n = ++this.seq;
    const sel = this.scene?.selection ?? [];
    let keys: KeysAnswer | null = null;
    if (sel.length) keys = await this.api.get<KeysAnswer>(`/api/keys?controls=${sel.map(encodeURIComponent).join(',')}`);
    if (n < this.shown.keys) return;
    this.shown.keys = n;
    this.keys = keys;
    if (keys) {
      this.scope = keys.scope ?? '';
    } else {
      // Nothing selected: the scopes of the characters (one line per rig).
      const scopes = this.scene?.keyScopes ?? {};
      const names = Object.keys(scopes);
      this.scope = names.length === 1 ? scopes[names[0]!]! : names.map((x) => `${x}: ${scopes[x]}`).join(', ');
    }
    this.emit('keys');
  }

  /**
   * Everything: after undo/redo, rig edits and changes made elsewhere. One
   * refresh runs at a time; calls during one share the next.
   */
  refreshAll(force = false): Promise<void> {
    this.forceReload = this.forceReload || force;
    return this.refresher.run();
  }

  private async refreshEverything(): Promise<void> {
    const force = this.forceReload;
    this.forceReload = false;
    await this.refreshScene();
    await this.reloadCharacter(force);
    await Promise.all([this.refreshRigs(), this.refreshKeys()]);
  }

  // ---------------------------------------------------------------- actions

  async select(uuids: string[], add: boolean): Promise<void> {
    const a = await this.api.post<{ revision: number; selection: string[] }>('/api/select', { controls: uuids, add });
    if (this.scene) this.scene.selection = a.selection;
    this.viewport.setSelection(a.selection);
    this.sceneChanged();
    this.succeeded();
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
    this.sceneChanged();
    this.succeeded();
  }

  async setAutoKey(on: boolean): Promise<void> {
    const a = await this.api.post<{ autoKey?: boolean }>('/api/options', { autoKey: on });
    if (this.scene) this.scene.autoKey = typeof a.autoKey === 'boolean' ? a.autoKey : on;
    this.sceneChanged();
    this.succeeded();
  }

  async setFrame(frame: number): Promise<void> {
    const a = await this.api.post<{ revision: number; frame: number; time: number }>('/api/time', { frame });
    if (this.scene) {
      this.scene.frame = a.frame;
      this.scene.time = a.time;
    }
    this.sceneChanged();
    this.succeeded();
    await this.refreshPose();
  }

  async key(remove: boolean): Promise<void> {
    if (!(this.scene?.selection.length ?? 0)) {
      this.status.error(remove ? 'Delete key: select a control first' : 'Set key: select a control first');
      return;
    }
    const a = await this.api.post<{ revision: number; frames: number[] }>('/api/key', remove ? { delete: true } : {});
    this.succeeded();
    this.status.info(`${remove ? 'Deleted key' : 'Keyed'} at frame ${this.scene?.frame ?? ''}; keys: ${(a.frames ?? []).join(', ') || 'none'}`);
    await Promise.all([this.refreshKeys(), this.refreshScene()]);
  }

  /**
   * Undo (or redo). With nothing to undo (the scene says so, or the server
   * answers 409 because another tab took it first) the bar says so quietly:
   * that is a state, not an error.
   */
  async undo(redo: boolean): Promise<void> {
    if (this.drag.active) return;
    const what = redo ? 'redo' : 'undo';
    if (this.scene && !(redo ? this.scene.canRedo : this.scene.canUndo)) {
      this.status.info(`Nothing to ${what}`);
      return;
    }
    let a: { revision: number; label: string };
    try {
      a = await this.api.post<{ revision: number; label: string }>(`/api/${what}`, {}, { expected: [409] });
    } catch (e) {
      if (!(e instanceof ApiError) || e.status !== 409) throw e;
      this.status.info(`Nothing to ${what}`);
      await this.refreshScene();
      return;
    }
    this.succeeded();
    this.status.info(`${redo ? 'Redo' : 'Undo'}: ${a.label ?? ''}`);
    await this.refreshAll();
  }

  // ------------------------------------------------------------- revisions

  /** Any request reached the server (up) or got no answer (down). */
  connection(up: boolean, err?: ApiError): void {
    if (up === !this.offline) return;
    this.offline = !up;
    this.status.offline(!up, err ? err.route : '');
  }

  /**
   * Follows the revision: every 250 ms while the server answers; once it
   * does not, one "connection lost" state and retries backing off from 0.5 s
   * to 4 s, and when it answers again a full refresh (it may be a new server
   * whose revisions start again).
   */
  private startPolling(): void {
    let retryMs = kRetryFirstMs;
    let wasOffline = false;
    const tick = async (): Promise<void> => {
      let next = kPollMs;
      try {
        if (this.offline || wasOffline || (this.api.pendingWrites === 0 && !this.drag.active)) {
          const r = await this.api.get<{ revision: number }>('/api/revision', { background: true });
          retryMs = kRetryFirstMs;
          if (wasOffline) {
            wasOffline = false;
            this.knownRevision = r.revision;
            this.poseRevision = -1;
            await this.refreshAll(true);
          } else if (r.revision > this.knownRevision && this.api.pendingWrites === 0 && !this.drag.active) {
            // A POST may have started while the GET was out: its revision is ours.
            this.knownRevision = r.revision;
            await this.refreshAll();
          }
        }
      } catch (e) {
        if (this.offline) {
          wasOffline = true;
          this.retries.push(Date.now());
          if (this.retries.length > 100) this.retries.shift();
          next = retryMs;
          retryMs = Math.min(retryMs * 2, kRetryMaxMs);
        } else if (!(e instanceof ApiError)) {
          this.status.caught(e);
        }
      } finally {
        window.setTimeout(() => run(tick()), next);
      }
    };
    window.setTimeout(() => run(tick()), kPollMs);
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
  private answersAtStart = 0;

  constructor(private readonly app: App) {}

  start(): void {
    this.active = true;
    this.failed = false;
    this.answersAtStart = this.stats.answers;
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
    const answersAtStart = this.answersAtStart;
    while (this.pump) await this.pump;
    try {
      await this.app.api.post('/api/release', {});
    } finally {
      this.active = false;
      this.pending = null;
    }
    if (!this.failed && this.stats.answers > answersAtStart) this.app.succeeded();
    await Promise.all([this.app.refreshPose(), this.app.refreshKeys(), this.app.refreshScene()]);
  }
}
