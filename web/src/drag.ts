// One gizmo gesture: drags are sent with at most one request in flight (the
// newest target wins), each answer's pose goes into the store (the viewport
// shows it), and the release waits for the last drag. After a refused drag
// the gesture sends nothing more, so a 409 is reported once, not at every
// mouse move.

import { ApiError } from './api';
import type { Quat, Vec3 } from './api';
import type { App } from './app';

export interface DragStats {
  requests: number;
  answers: number;
  failures: number;
  /** Mean round trip of the drag requests of the last gesture, ms. */
  meanRoundTripMs: number;
  gestures: number;
}

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
          const a = await this.app.api.drag({ control: p.control, to: { t: p.t, q: p.q } });
          this.stats.answers++;
          this.roundTrips.push(performance.now() - t0);
          this.stats.meanRoundTripMs = this.roundTrips.reduce((s, x) => s + x, 0) / this.roundTrips.length;
          this.app.store.applyPose(a);
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

  /** The release: one undo step; the pose, keys (auto-key) and scene (undo) are read again. */
  async end(): Promise<void> {
    if (!this.active) return;
    const answersAtStart = this.answersAtStart;
    while (this.pump) await this.pump;
    try {
      await this.app.api.release();
    } finally {
      this.active = false;
      this.pending = null;
    }
    if (!this.failed && this.stats.answers > answersAtStart) this.app.succeeded();
    await this.app.reread(['pose', 'keys', 'scene']);
  }
}
