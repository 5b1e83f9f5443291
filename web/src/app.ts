// The application: the store's state kept current (the refreshes, the
// revision poller that follows changes made by other tabs and scripts),
// and the changes the user makes, run as commands (commands.ts) whose
// answers go into the store before what they affect is read again.

import { ApiError } from './api';
import type { Api } from './api';
import * as commands from './commands';
import type { Command, Reread } from './commands';
import { parseCharacter } from './character';
import { DragGesture } from './drag';
import { StatusBar, run } from './status';
import { Store } from './store';

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

/**
 * Runs an async job one at a time: a call while it runs is answered by the
 * one run that starts after it (every caller sees a run that began after
 * its call), so overlapping refreshes never apply an older answer last.
 */
export class Coalesced {
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
  readonly ready: Promise<void>;
  isReady = false;
  readonly drag: DragGesture;
  /** True while the server does not answer (the poller retries with a backoff). */
  offline = false;
  /** Poll attempts that got no answer, and when each was made (for tests). */
  readonly retries: number[] = [];

  private nodesSignature = '';
  private resolveReady!: () => void;
  private forceReload = false;
  private readonly refresher = new Coalesced(() => this.refreshEverything());

  constructor(
    readonly api: Api,
    readonly store: Store,
    readonly status: StatusBar,
  ) {
    this.ready = new Promise((r) => (this.resolveReady = r));
    this.drag = new DragGesture(this);
  }

  // What the tests read (window.rigel.app): the store's state.
  get scene() {
    return this.store.scene;
  }
  get nodes() {
    return this.store.nodes;
  }
  get rigs() {
    return this.store.rigs;
  }
  get keys() {
    return this.store.keys;
  }
  get knownRevision(): number {
    return this.store.knownRevision;
  }

  /**
   * True when nothing is in flight: no request but the background ones, no
   * refresh running or queued, no gesture, and the server answering (what
   * the end-to-end tests wait for before reading the screen).
   */
  settled(): boolean {
    return this.isReady && this.api.pending === 0 && !this.refresher.busy && !this.drag.active && !this.offline;
  }

  /** Reads everything; `loaded` runs once it is shown, before the app says it is ready. */
  async start(loaded: () => void = () => undefined): Promise<void> {
    await this.refreshAll(true);
    loaded();
    this.isReady = true;
    this.resolveReady();
    this.status.info(`Loaded ${this.store.scene?.path || 'scene'}: ${this.store.nodes?.controls.length ?? 0} controls`);
    this.startPolling();
  }

  /** A user action succeeded: an error still shown is about an earlier one. */
  succeeded(): void {
    this.status.clearError();
  }

  // -------------------------------------------------------------- refreshes

  async refreshScene(): Promise<void> {
    const ticket = this.store.ticket();
    this.store.setScene(await this.api.scene(), ticket);
  }

  /**
   * Nodes, and the glTF when the node set or a shape changed (or `force`):
   * the node list is replaced by the server's, never merged, so the nodes
   * of a removed rig go with it.
   */
  private async reloadCharacter(force = false): Promise<void> {
    const ticket = this.store.ticket();
    const nodes = await this.api.nodes();
    if (this.store.stale('nodes', ticket)) return;
    const signature = JSON.stringify({ n: nodes.nodes, c: nodes.controls });
    if (force || signature !== this.nodesSignature) {
      const glb = await this.api.characterGlb();
      if (this.store.stale('nodes', ticket)) return;
      this.store.setCharacter(await parseCharacter(glb, nodes));
      this.nodesSignature = signature;
    }
    this.store.setNodes(nodes, ticket);
    await this.refreshPose();
  }

  async refreshPose(): Promise<void> {
    this.store.applyPose(await this.api.pose());
  }

  async refreshRigs(background = false): Promise<void> {
    const ticket = this.store.ticket();
    const r = await this.api.rigs({ background });
    this.store.setRigs(r.rigs ?? [], ticket);
  }

  async refreshKeys(): Promise<void> {
    const ticket = this.store.ticket();
    const sel = this.store.selection;
    const keys = sel.length ? await this.api.keys([...sel]) : null;
    this.store.setKeys(keys, ticket);
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

  /** Reads again what a change can affect (`everything`: one full refresh, in turn). */
  async reread(parts: readonly Reread[]): Promise<void> {
    if (parts.includes('everything')) return this.refreshAll();
    const readers: Record<Exclude<Reread, 'everything'>, () => Promise<void>> = {
      scene: () => this.refreshScene(),
      pose: () => this.refreshPose(),
      keys: () => this.refreshKeys(),
      rigs: () => this.refreshRigs(),
    };
    await Promise.all(parts.map((p) => readers[p as Exclude<Reread, 'everything'>]()));
  }

  // ---------------------------------------------------------------- commands

  /**
   * Runs a change: its request, its answer into the store, the error shown
   * cleared (the action succeeded), its message, then what it affects read
   * again. A refused request rejects (the client has reported it).
   */
  async execute<A>(command: Command<A>): Promise<A> {
    const answer = await command.send(this.api);
    command.apply?.(answer, this.store);
    this.succeeded();
    const message = command.message?.(answer, this.store);
    if (message) this.status.info(message);
    await this.reread(command.affects);
    return answer;
  }

  async select(uuids: string[], add: boolean): Promise<void> {
    await this.execute(commands.select(uuids, add));
  }

  /** A click in the viewport: replace, add (Shift) or toggle off (Shift on a selected one). */
  async pick(uuid: string | null, additive: boolean): Promise<void> {
    const sel = this.store.selection;
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
    const name = this.store.names.get(uuid) ?? uuid;
    this.status.info(`Selected ${name}${additive ? ' (added)' : ''}`);
  }

  async setMode(mode: string): Promise<void> {
    await this.execute(commands.setMode(mode));
  }

  async setAutoKey(on: boolean): Promise<void> {
    await this.execute(commands.setAutoKey(on));
  }

  async setFrame(frame: number): Promise<void> {
    await this.execute(commands.setFrame(frame));
  }

  async key(remove: boolean): Promise<void> {
    if (!this.store.selection.length) {
      this.status.error(remove ? 'Delete key: select a control first' : 'Set key: select a control first');
      return;
    }
    await this.execute(commands.key(remove));
  }

  /**
   * Undo (or redo). With nothing to undo (the scene says so, or the server
   * answers 409 because another tab took it first) the bar says so quietly:
   * that is a state, not an error.
   */
  async undo(redo: boolean): Promise<void> {
    if (this.drag.active) return;
    const what = redo ? 'redo' : 'undo';
    const scene = this.store.scene;
    if (scene && !(redo ? scene.canRedo : scene.canUndo)) {
      this.status.info(`Nothing to ${what}`);
      return;
    }
    let sent = false;
    try {
      await this.execute(commands.also(commands.undo(redo), () => (sent = true)));
    } catch (e) {
      if (sent || !(e instanceof ApiError) || e.status !== 409) throw e;
      this.status.info(`Nothing to ${what}`);
      await this.refreshScene();
    }
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
          const r = await this.api.revision();
          retryMs = kRetryFirstMs;
          if (wasOffline) {
            wasOffline = false;
            this.store.resetRevisions(r.revision);
            await this.refreshAll(true);
          } else if (r.revision > this.store.knownRevision && this.api.pendingWrites === 0 && !this.drag.active) {
            // A POST may have started while the GET was out: its revision is ours.
            this.store.knownRevision = r.revision;
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
