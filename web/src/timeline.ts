// The timeline: current frame (slider and field), the playback range (two
// fields: saved with the scene through POST /api/playback-range), key
// ticks of the selection's keying set (click one to go there, drag it to
// retime its keys, Alt-drag to copy them: one POST /api/channel-keys with
// moveTo and from, one undo step), previous/next key, set/delete key,
// auto-key, play/stop. It renders from the store (scene, time and keys
// signals).
//
// Playing steps the scene's time one frame at a time through POST /api/time
// and refetches the pose after each step, at most at the scene's frame rate
// and never with two steps in flight.

import type { App } from './app';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';
import type { Store } from './store';

export class Timeline {
  playing = false;
  private readonly slider: HTMLInputElement;
  private readonly field: HTMLInputElement;
  private readonly ticks: HTMLElement;
  private readonly playBtn: HTMLButtonElement;
  private readonly autoKey: HTMLInputElement;
  private pendingAutoKey: boolean | null = null;
  private readonly scopeEl: HTMLElement;
  private readonly keysEl: HTMLElement;
  private readonly rangeEl: HTMLElement;
  private readonly firstField: HTMLInputElement;
  private readonly lastField: HTMLInputElement;
  /** A tick being dragged: its frame and where it is now. */
  private tickDrag: { from: number; to: number } | null = null;
  private retiming: Promise<void> | null = null;
  private scrubTarget: number | null = null;
  private scrubbing: Promise<void> | null = null;
  /** Frames shown while playing, for tests: every frame the pose was fetched at. */
  readonly playedFrames: number[] = [];
  private readonly store: Store;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.store = app.store;
    this.playBtn = h('button.icon', { title: 'Play / stop (Space)', testid: 'play', onclick: () => this.toggle() }, '▶');
    const prevKey = h('button.icon', { title: 'Previous key', testid: 'prev-key', onclick: () => this.jumpKey(-1) }, '|◀');
    const nextKey = h('button.icon', { title: 'Next key', testid: 'next-key', onclick: () => this.jumpKey(1) }, '▶|');
    this.field = h('input.frame', { type: 'number', step: '1', title: 'Current frame', testid: 'frame' });
    this.field.addEventListener('change', () => this.scrub(Number(this.field.value)));
    this.slider = h('input.slider', { type: 'range', step: '1', min: '0', max: '100', testid: 'frame-slider' });
    this.slider.addEventListener('input', () => this.scrub(Number(this.slider.value)));
    this.ticks = h('div.ticks', { testid: 'key-ticks' });
    this.rangeEl = h('span.range', { testid: 'fps' });
    this.firstField = h('input.frame.range-field', { type: 'number', step: '1', title: 'First frame of the playback range', testid: 'range-first' });
    this.lastField = h('input.frame.range-field', { type: 'number', step: '1', title: 'Last frame of the playback range', testid: 'range-last' });
    for (const f of [this.firstField, this.lastField]) f.addEventListener('change', () => this.setRange());
    const track = h('div.track', {}, this.slider, this.ticks);
    const setKey = h('button', { title: 'Key the selection at this frame (S)', testid: 'set-key', onclick: () => run(this.app.key(false)) }, 'Set key', h('kbd', {}, 'S'));
    const delKey = h(
      'button',
      { title: 'Delete the selection’s key at this frame (Shift+S)', testid: 'delete-key', onclick: () => run(this.app.key(true)) },
      'Delete key',
      h('kbd', {}, '⇧S'),
    );
    this.autoKey = h('input', { type: 'checkbox', testid: 'auto-key' });
    // The box shows what was clicked until the server has it: a render from
    // an answer already on its way would otherwise undo the click.
    this.autoKey.addEventListener('change', () => {
      const on = this.autoKey.checked;
      this.pendingAutoKey = on;
      run(
        this.app.setAutoKey(on).finally(() => {
          if (this.pendingAutoKey === on) this.pendingAutoKey = null;
          this.render();
        }),
      );
    });
    const autoLabel = h('label.toggle', { title: 'Auto-key: drags between keys key the character first (K)' }, this.autoKey, 'Auto-key');
    this.scopeEl = h('span.scope', { testid: 'key-scope', title: 'Keying scope of the selection’s character' });
    this.keysEl = h('span.keys', { testid: 'key-frames' });
    fill(
      el,
      h('div.transport', {}, prevKey, this.playBtn, nextKey, this.field),
      h('div.track-wrap', {}, this.firstField, track, this.lastField, this.rangeEl),
      h('div.key-tools', {}, setKey, delKey, autoLabel, this.scopeEl, this.keysEl),
    );
    const signals = this.store.signals;
    signals.sceneChanged.add(() => this.render());
    signals.timeChanged.add(() => this.render());
    signals.keysChanged.add(() => this.render());
  }

  /** True while a move to a frame or of keys is in flight, or playing. */
  busy(): boolean {
    return this.scrubbing !== null || this.retiming !== null || this.playing;
  }

  /** The playback range: the one set on the scene, else the keys', else 0–100. */
  range(): [number, number] {
    const p = this.store.scene?.playbackRange;
    if (p && p[1] >= p[0]) return [Math.round(p[0]), Math.round(p[1])];
    const r = this.store.scene?.range;
    if (r && r.length === 2 && r[1] > r[0]) return [Math.round(r[0]), Math.round(r[1])];
    return [0, 100];
  }

  private setRange(): void {
    const [first, last] = [Number(this.firstField.value), Number(this.lastField.value)];
    if (!Number.isFinite(first) || !Number.isFinite(last) || this.firstField.value === '' || this.lastField.value === '') {
      this.app.status.error('Playback range: two frame numbers');
      this.render();
      return;
    }
    if (last < first) {
      this.app.status.error(`Playback range: the last frame (${last}) is before the first (${first})`);
      this.render();
      return;
    }
    run(this.app.execute(commands.setPlaybackRange(first, last)).finally(() => this.render()));
  }

  /** The frame under client x on the track (the slider thumb's centre runs 7 px in from each end). */
  private frameAt(clientX: number): number {
    const r = this.ticks.getBoundingClientRect();
    const [first, last] = this.range();
    const u = (clientX - r.left - 7) / Math.max(1, r.width - 14);
    return Math.round(first + Math.min(1, Math.max(0, u)) * (last - first));
  }

  /** A tick pressed: a click goes to its frame, a drag retimes its keys (Alt: copies them). */
  private tickDown(e: PointerEvent, tick: HTMLElement, frame: number): void {
    e.preventDefault();
    e.stopPropagation();
    tick.setPointerCapture(e.pointerId);
    this.tickDrag = { from: frame, to: frame };
    const move = (m: PointerEvent) => {
      if (!this.tickDrag) return;
      this.tickDrag.to = this.frameAt(m.clientX);
      this.placeTick(tick, this.tickDrag.to);
      tick.classList.toggle('copying', m.altKey);
    };
    const up = (u: PointerEvent) => {
      tick.removeEventListener('pointermove', move);
      tick.removeEventListener('pointerup', up);
      tick.removeEventListener('pointercancel', up);
      const d = this.tickDrag;
      this.tickDrag = null;
      if (!d || u.type === 'pointercancel') return this.render();
      if (d.to === d.from) return this.scrub(d.from);
      this.retime(d.from, d.to, u.altKey);
    };
    tick.addEventListener('pointermove', move);
    tick.addEventListener('pointerup', up);
    tick.addEventListener('pointercancel', up);
  }

  private retime(from: number, to: number, copy: boolean): void {
    const controls = [...this.store.selection];
    this.retiming = this.app
      .execute(commands.moveKeys(controls, from, to, copy))
      .then(() => undefined)
      .catch((e: unknown) => this.app.status.caught(e))
      .finally(() => {
        this.retiming = null;
        this.render();
      });
  }

  private placeTick(t: HTMLElement, f: number): void {
    const [first, last] = this.range();
    // The slider thumb's centre runs from half a thumb in to half a thumb from the end.
    t.style.left = `calc(7px + (100% - 14px) * ${(f - first) / Math.max(last - first, 1)})`;
  }

  render(): void {
    const s = this.store.scene;
    const [first, last] = this.range();
    this.slider.min = String(first);
    this.slider.max = String(last);
    this.rangeEl.textContent = s ? `${s.fps} fps` : '';
    this.rangeEl.title = s?.playbackRange ? 'Playback range saved with the scene' : 'Playback range: the keys’ (set one in the fields)';
    if (document.activeElement !== this.firstField) this.firstField.value = String(first);
    if (document.activeElement !== this.lastField) this.lastField.value = String(last);
    if (this.tickDrag) return; // a tick being dragged keeps its place
    if (s && this.scrubTarget === null) {
      this.slider.value = String(Math.round(s.frame));
      if (document.activeElement !== this.field) this.field.value = String(Math.round(s.frame * 100) / 100);
    }
    this.autoKey.checked = this.pendingAutoKey ?? !!s?.autoKey;
    const scope = this.store.shownScope();
    this.scopeEl.textContent = `Keying: ${scope || '—'}`;
    const frames = this.store.keys?.frames ?? [];
    this.keysEl.textContent = this.store.keys ? `Keys: ${frames.length ? frames.join(', ') : 'none'}` : 'Keys: (no selection)';
    this.ticks.replaceChildren(
      ...frames
        .filter((f) => f >= first && f <= last)
        .map((f) => {
          const t = h('div.tick', { title: `key at ${f}: click to go there, drag to retime, Alt-drag to copy`, testid: `tick-${f}`, dataset: { frame: String(f) } });
          this.placeTick(t, f);
          if (s && Math.abs(f - s.frame) < 1e-6) t.classList.add('current');
          t.addEventListener('pointerdown', (e) => this.tickDown(e, t, f));
          return t;
        }),
    );
    this.playBtn.textContent = this.playing ? '■' : '▶';
    this.playBtn.classList.toggle('active', this.playing);
  }

  /** Moves to a frame; while a move is in flight only the latest target is kept. */
  scrub(frame: number): void {
    if (!Number.isFinite(frame)) return;
    this.scrubTarget = Math.round(frame);
    if (!this.scrubbing) {
      this.scrubbing = (async () => {
        try {
          // A target set while the keys are re-read is gone to as well
          // (this loop is the only one that moves the frame).
          do {
            while (this.scrubTarget !== null) {
              const f = this.scrubTarget;
              try {
                await this.app.setFrame(f);
              } finally {
                if (this.scrubTarget === f) this.scrubTarget = null;
              }
            }
            await this.app.refreshKeys();
          } while (this.scrubTarget !== null);
        } catch (e) {
          this.scrubTarget = null;
          this.app.status.caught(e);
        } finally {
          this.scrubbing = null;
          this.render();
        }
      })();
    }
  }

  private jumpKey(dir: 1 | -1): void {
    // From the frame last asked for (a move still in flight goes there).
    const frames = this.store.keys?.frames ?? [];
    const cur = this.scrubTarget ?? this.store.scene?.frame ?? 0;
    const target = dir > 0 ? frames.find((f) => f > cur + 1e-6) : [...frames].reverse().find((f) => f < cur - 1e-6);
    if (target === undefined) {
      this.app.status.info(dir > 0 ? 'No key after this frame' : 'No key before this frame');
      return;
    }
    this.scrub(target);
  }

  stepFrame(dir: 1 | -1): void {
    this.scrub((this.store.scene?.frame ?? 0) + dir);
  }

  toggle(): void {
    if (this.playing) this.stop();
    else this.play();
  }

  stop(): void {
    this.playing = false;
    this.render();
  }

  play(): void {
    if (this.playing) return;
    this.playing = true;
    this.render();
    const fps = this.store.scene?.fps && this.store.scene.fps > 0 ? this.store.scene.fps : 24;
    const period = 1000 / fps;
    const loop = async (): Promise<void> => {
      while (this.playing) {
        const t0 = performance.now();
        const [first, last] = this.range();
        const cur = Math.round(this.store.scene?.frame ?? first);
        const next = cur + 1 > last || cur < first ? first : cur + 1;
        try {
          await this.app.setFrame(next);
          this.playedFrames.push(next);
          if (this.playedFrames.length > 1000) this.playedFrames.shift();
        } catch (e) {
          this.app.status.caught(e);
          this.playing = false;
          break;
        }
        const wait = period - (performance.now() - t0);
        if (wait > 0) await new Promise((r) => setTimeout(r, wait));
      }
      this.render();
      run(this.app.refreshKeys());
    };
    run(loop());
  }
}
