// The graph editor (Maya's curve editor): the animation curves of the
// selection's channels (GET /api/curves: a built rig's control and its
// component's switches, an ephemeral control's channels, glTF tracks as
// components or unwrapped Euler angles) drawn over time, keys as points and,
// for the selected keys of curves, their tangent handles.
//
// Click a key to select it (Shift adds or removes), drag in the empty plot
// to box-select; drag selected keys to move them (time snaps to whole
// frames; Shift keeps to the axis moved most); drag a handle to set the
// tangent (both sides; Ctrl breaks it); double-click a curve to insert a
// key there. Alt-drag or the middle button pans, the wheel zooms (Shift:
// time only, Ctrl: values only). Keys: A frame all, F frame selected,
// I insert a key at the current frame, Delete removes the selected keys.
// Every edit is one POST /api/curve-keys, so one undo step (Ctrl+Z).

import type { App } from './app';
import { Coalesced } from './app';
import type { CurveInfo, CurveKeyEdit, CurvesAnswer } from './api';
import * as commands from './commands';
import { bounds, curveColour, gridLines, niceStep, padded, Plot, sampleAt } from './curveplot';
import type { KeyHit, View } from './curveplot';
import { h, fill } from './dom';
import { run } from './status';

const kTangentTypes = ['auto', 'spline', 'linear', 'flat', 'step', 'clamped', 'plateau'] as const;
const kKeyPx = 4;
const kHitPx = 7;
const kHandlePx = 42;
/** Two frames within this are the same key's. */
const kFrameEps = 1e-4;

type Gesture =
  | { kind: 'move'; x0: number; y0: number; frames: number; value: number; moved: boolean }
  | { kind: 'tangent'; curve: CurveInfo; index: number; slope: number; broken: boolean; side: 'in' | 'out'; moved: boolean }
  | { kind: 'box'; x0: number; y0: number; x1: number; y1: number; add: boolean }
  | { kind: 'pan'; x0: number; y0: number; view: View };

export class GraphEditor {
  private answer: CurvesAnswer | null = null;
  /** The frames the samples were fetched over. */
  private fetched: [number, number] | null = null;
  private readonly hiddenCurves = new Set<string>();
  /** Selected keys: frames per curve plug. */
  private selected = new Map<string, number[]>();
  private view: View = { x0: -2, x1: 50, y0: -1, y1: 1 };
  private framedFor = '';
  private gesture: Gesture | null = null;
  private visibleNow = false;
  private euler = true;
  private readonly canvas: HTMLCanvasElement;
  private readonly list: HTMLElement;
  private readonly stats: HTMLElement;
  private readonly valueField: HTMLInputElement;
  private readonly frameField: HTMLInputElement;
  private readonly tangentMenu: HTMLSelectElement;
  private readonly refresher = new Coalesced(() => this.fetch());

  constructor(
    private readonly el: HTMLElement,
    private readonly app: App,
  ) {
    this.canvas = h('canvas.curve-canvas', { tabIndex: 0, testid: 'curve-canvas' });
    this.list = h('div.curve-list', { testid: 'curve-list' });
    this.stats = h('span.dim', { testid: 'curve-stats' });
    this.frameField = h('input.num', { type: 'text', title: 'Frame of the selected key', testid: 'curve-frame' });
    this.valueField = h('input.num', { type: 'text', title: 'Value of the selected keys', testid: 'curve-value' });
    this.tangentMenu = h(
      'select',
      { title: 'Tangent type of the selected keys', testid: 'curve-tangent' },
      h('option', { value: '' }, 'Tangents…'),
      ...kTangentTypes.map((t) => h('option', { value: t }, t)),
    );
    this.tangentMenu.addEventListener('change', () => {
      const t = this.tangentMenu.value;
      this.tangentMenu.value = '';
      if (t) run(this.setTangents(t));
    });
    const euler = h('input', { type: 'checkbox', checked: true, testid: 'curve-euler' });
    euler.addEventListener('change', () => {
      this.euler = euler.checked;
      run(this.refresh());
    });
    for (const [field, apply] of [
      [this.frameField, (v: number) => this.typeFrame(v)],
      [this.valueField, (v: number) => this.typeValue(v)],
    ] as const) {
      field.addEventListener('keydown', (e) => {
        if (e.key === 'Enter') field.blur();
      });
      field.addEventListener('change', () => {
        const v = Number(field.value.trim());
        if (field.value.trim() === '' || !Number.isFinite(v)) {
          this.app.status.error(`'${field.value}' is not a number`);
          this.renderStats();
          return;
        }
        run(apply(v));
      });
    }
    const bar = h(
      'div.curve-bar',
      {},
      h('h2', {}, 'Graph Editor'),
      h('button.small', { title: 'Frame all (A)', testid: 'curve-frame-all', onclick: () => this.frameAll() }, 'Frame all'),
      h('button.small', { title: 'Frame selected keys (F)', testid: 'curve-frame-selected', onclick: () => this.frameSelected() }, 'Frame selected'),
      h('button.small', { title: 'Insert a key at the current frame on the shown curves (I)', testid: 'curve-insert', onclick: () => run(this.insertAtCurrent()) }, 'Insert key'),
      h('button.small', { title: 'Delete the selected keys (Delete)', testid: 'curve-delete', onclick: () => run(this.deleteSelected()) }, 'Delete keys'),
      this.tangentMenu,
      h('label.toggle', { title: 'Rotation tracks as Euler angles (degrees) or quaternion components' }, euler, 'Euler'),
      h('label.toggle', {}, 'Frame', this.frameField),
      h('label.toggle', {}, 'Value', this.valueField),
      this.stats,
    );
    fill(el, bar, h('div.curve-body', {}, this.list, h('div.curve-plot', {}, this.canvas)));
    this.wire();
    const refresh = () => run(this.refresh());
    const s = app.store.signals;
    s.selectionChanged.add(refresh);
    s.keysChanged.add(refresh);
    s.nodesChanged.add(refresh);
    s.timeChanged.add(() => this.draw());
    new ResizeObserver(() => this.draw()).observe(this.canvas);
  }

  set visible(on: boolean) {
    this.visibleNow = on;
    this.el.hidden = !on;
    if (on) run(this.refresh());
  }

  get visible(): boolean {
    return this.visibleNow;
  }

  /** True while a fetch is running or queued (the tests wait for it). */
  get busy(): boolean {
    return this.refresher.busy;
  }

  /** The curves shown (for the tests). */
  get curves(): CurveInfo[] {
    return this.answer?.curves ?? [];
  }

  /** The selected keys as [plug, frame] (for the tests). */
  get selection(): [string, number][] {
    return [...this.selected].flatMap(([plug, frames]) => frames.map((f): [string, number] => [plug, f]));
  }

  /** Client pixels of a key (by curve plug and key frame), or of its tangent handle's end; null when not shown. */
  point(plug: string, frame: number, handle?: 'in' | 'out'): { x: number; y: number } | null {
    const c = this.shown().find((k) => k.plug === plug);
    const i = c ? c.frames.findIndex((f) => Math.abs(f - frame) < kFrameEps) : -1;
    if (!c || i < 0) return null;
    const r = this.canvas.getBoundingClientRect();
    const plot = this.plot();
    if (handle) {
      const hs = plot.handles(c, i, kHandlePx);
      return hs ? { x: r.left + hs[handle][0], y: r.top + hs[handle][1] } : null;
    }
    return { x: r.left + plot.px(c.frames[i]!), y: r.top + plot.py(c.values[i]!) };
  }

  /** Client pixels of a point of the plot. */
  at(frame: number, value: number): { x: number; y: number } {
    const r = this.canvas.getBoundingClientRect();
    const plot = this.plot();
    return { x: r.left + plot.px(frame), y: r.top + plot.py(value) };
  }

  refresh(): Promise<void> {
    return this.refresher.run();
  }

  // ------------------------------------------------------------------ data

  private async fetch(): Promise<void> {
    if (!this.visibleNow) return;
    const selection = this.app.store.selection;
    if (!selection.length) {
      this.answer = null;
      this.render();
      return;
    }
    const r = this.app.store.scene?.range ?? [0, 100];
    const span = this.view.x1 - this.view.x0;
    const first = Math.floor(Math.min(r[0], this.view.x0 - span / 2));
    const last = Math.ceil(Math.max(r[1], this.view.x1 + span / 2));
    const step = Math.max(0.125, (last - first) / 1500);
    this.answer = await this.app.api.curves({ controls: [...selection], first, last, step, euler: this.euler });
    this.fetched = [first, last];
    this.render();
  }

  private shown(): CurveInfo[] {
    return this.curves.filter((c) => !this.hiddenCurves.has(c.plug));
  }

  private isSelected(c: CurveInfo, i: number): boolean {
    const f = c.frames[i]!;
    return (this.selected.get(c.plug) ?? []).some((s) => Math.abs(s - f) < kFrameEps);
  }

  /** The selected keys that exist on the curves shown, with their curves. */
  private selectedKeys(): KeyHit[] {
    const out: KeyHit[] = [];
    for (const c of this.shown()) for (let i = 0; i < c.frames.length; ++i) if (this.isSelected(c, i)) out.push({ curve: c, index: i });
    return out;
  }

  private select(keys: KeyHit[], add: boolean): void {
    if (!add) this.selected = new Map();
    for (const k of keys) {
      const list = this.selected.get(k.curve.plug) ?? [];
      if (!list.some((f) => Math.abs(f - k.curve.frames[k.index]!) < kFrameEps)) list.push(k.curve.frames[k.index]!);
      this.selected.set(k.curve.plug, list);
    }
    this.renderStats();
    this.draw();
  }

  private deselect(k: KeyHit): void {
    const f = k.curve.frames[k.index]!;
    const list = (this.selected.get(k.curve.plug) ?? []).filter((s) => Math.abs(s - f) >= kFrameEps);
    this.selected.set(k.curve.plug, list);
    this.renderStats();
    this.draw();
  }

  // ------------------------------------------------------------------ edits

  private async send(op: 'edit' | 'insert' | 'delete', keys: CurveKeyEdit[], label: string): Promise<void> {
    if (!keys.length) {
      this.app.status.info(op === 'insert' ? 'No curve shown to key' : 'Select keys first');
      return;
    }
    await this.app.execute(commands.curveKeys({ op, keys }, label));
    await this.refresh();
  }

  private async moveSelected(frames: number, value: number): Promise<void> {
    const keys = this.selectedKeys();
    const edits: CurveKeyEdit[] = keys.map(({ curve, index }) => {
      const e: CurveKeyEdit = { curve: curve.plug, frame: curve.frames[index]! };
      if (frames !== 0) e.toFrame = curve.frames[index]! + frames;
      if (value !== 0 && curve.editable) e.value = curve.values[index]! + value;
      if (curve.kind === 'vectorTrack') e.component = curve.component;
      return e;
    });
    const moved = edits.filter((e) => e.toFrame !== undefined || e.value !== undefined);
    await this.send('edit', moved, 'Moved keys');
    // The selection follows its keys.
    if (frames !== 0) {
      for (const [plug, list] of this.selected) this.selected.set(plug, list.map((f) => f + frames));
      this.renderStats();
      this.draw();
    }
  }

  private async setTangents(type: string): Promise<void> {
    const keys = this.selectedKeys().filter((k) => k.curve.kind === 'curve');
    await this.send('edit', keys.map(({ curve, index }) => ({ curve: curve.plug, frame: curve.frames[index]!, tangent: type })), `Tangents ${type}`);
  }

  private async deleteSelected(): Promise<void> {
    const keys = this.selectedKeys();
    await this.send('delete', keys.map(({ curve, index }) => ({ curve: curve.plug, frame: curve.frames[index]! })), 'Deleted keys');
    this.selected = new Map();
    this.renderStats();
  }

  private async insertAt(curves: CurveInfo[], frame: number): Promise<void> {
    const editable = curves.filter((c) => c.editable);
    await this.send('insert', editable.map((c) => ({ curve: c.plug, frame })), `Inserted keys at frame ${frame}`);
  }

  private async insertAtCurrent(): Promise<void> {
    const frame = Math.round(this.app.store.scene?.frame ?? 0);
    const withSelection = this.shown().filter((c) => (this.selected.get(c.plug) ?? []).length);
    await this.insertAt(withSelection.length ? withSelection : this.shown(), frame);
  }

  private async typeValue(v: number): Promise<void> {
    const keys = this.selectedKeys().filter((k) => k.curve.editable);
    await this.send(
      'edit',
      keys.map(({ curve, index }) => {
        const e: CurveKeyEdit = { curve: curve.plug, frame: curve.frames[index]!, value: v };
        if (curve.kind === 'vectorTrack') e.component = curve.component;
        return e;
      }),
      `Key value ${v}`,
    );
  }

  private async typeFrame(frame: number): Promise<void> {
    const keys = this.selectedKeys();
    if (keys.length !== 1) {
      this.app.status.error('Frame: select one key to retime it (drag several)');
      this.renderStats();
      return;
    }
    const { curve, index } = keys[0]!;
    await this.moveSelected(frame - curve.frames[index]!, 0);
  }

  // ------------------------------------------------------------------ view

  frameAll(): void {
    const b = bounds(this.shown(), () => null);
    if (b) this.setView(padded(b));
  }

  frameSelected(): void {
    const keys = this.selectedKeys();
    if (!keys.length) return this.frameAll();
    const b = bounds(this.shown(), (c) => keys.filter((k) => k.curve === c).map((k) => k.index));
    if (b) this.setView(padded(b));
  }

  private setView(v: View): void {
    this.view = v;
    this.draw();
    // Samples fetched over a range the view has left are fetched again.
    const f = this.fetched;
    if (f && (v.x0 < f[0] || v.x1 > f[1])) run(this.refresh());
  }

  private plot(): Plot {
    return new Plot(this.view, this.canvas.clientWidth || 1, this.canvas.clientHeight || 1);
  }

  // ------------------------------------------------------------------ render

  private render(): void {
    const curves = this.curves;
    const signature = curves.map((c) => c.plug).join('\n');
    if (signature !== this.framedFor) {
      this.framedFor = signature;
      for (const plug of [...this.selected.keys()]) if (!curves.some((c) => c.plug === plug)) this.selected.delete(plug);
      this.frameAll();
    }
    fill(
      this.list,
      curves.length ? null : h('p.dim', {}, this.app.store.selection.length ? 'The selection has no keyed channels.' : 'Select a control to see its curves.'),
      ...curves.map((c, i) => {
        const box = h('input', { type: 'checkbox', checked: !this.hiddenCurves.has(c.plug) });
        box.addEventListener('change', () => {
          if (box.checked) this.hiddenCurves.delete(c.plug);
          else this.hiddenCurves.add(c.plug);
          this.draw();
        });
        const name = h('span.curve-name', { title: `${c.plug} (${c.curve}): click to select its keys`, style: { color: curveColour(c, i) } }, this.label(c));
        name.addEventListener('click', (e) => this.select(c.frames.map((_, k) => ({ curve: c, index: k })), e.shiftKey));
        return h('label.curve-row', { testid: `curve-${c.plug}` }, box, name);
      }),
    );
    this.renderStats();
    this.draw();
  }

  private label(c: CurveInfo): string {
    const node = c.plug.slice(0, c.plug.lastIndexOf('.'));
    const short = node.slice(node.lastIndexOf('_') + 1);
    return `${short}.${c.label}`;
  }

  private renderStats(): void {
    const keys = this.selectedKeys();
    this.stats.textContent = keys.length ? `${keys.length} key${keys.length === 1 ? '' : 's'} selected` : '';
    const first = keys[0];
    if (document.activeElement !== this.frameField) this.frameField.value = first ? String(Math.round(first.curve.frames[first.index]! * 1000) / 1000) : '';
    if (document.activeElement !== this.valueField) {
      const values = new Set(keys.map((k) => k.curve.values[k.index]!));
      this.valueField.value = values.size === 1 ? commands.formatValue([...values][0]!) : '';
    }
    this.frameField.disabled = keys.length !== 1;
    this.valueField.disabled = !keys.some((k) => k.curve.editable);
  }

  draw(): void {
    const c = this.canvas;
    const w = c.clientWidth;
    const ht = c.clientHeight;
    if (!this.visibleNow || !w || !ht) return;
    const dpr = window.devicePixelRatio || 1;
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(ht * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(ht * dpr);
    }
    const ctx = c.getContext('2d');
    if (!ctx) return;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = '#16181d';
    ctx.fillRect(0, 0, w, ht);
    const plot = this.plot();
    this.drawGrid(ctx, plot);
    const g = this.gesture;
    const offset = g?.kind === 'move' ? { frames: g.frames, value: g.value } : { frames: 0, value: 0 };
    this.shown().forEach((curve) => this.drawCurve(ctx, plot, curve, this.curves.indexOf(curve), offset));
    if (g?.kind === 'box') {
      ctx.strokeStyle = '#ffd34d';
      ctx.setLineDash([4, 3]);
      ctx.strokeRect(Math.min(g.x0, g.x1), Math.min(g.y0, g.y1), Math.abs(g.x1 - g.x0), Math.abs(g.y1 - g.y0));
      ctx.setLineDash([]);
    }
  }

  private drawGrid(ctx: CanvasRenderingContext2D, plot: Plot): void {
    const { x0, x1, y0, y1 } = this.view;
    ctx.font = '10px system-ui, sans-serif';
    ctx.lineWidth = 1;
    const xs = niceStep(x1 - x0, plot.width / 70, true);
    for (const f of gridLines(x0, x1, xs)) {
      const x = Math.round(plot.px(f)) + 0.5;
      ctx.strokeStyle = f === 0 ? '#3a404c' : '#23262e';
      ctx.beginPath();
      ctx.moveTo(x, 0);
      ctx.lineTo(x, plot.height);
      ctx.stroke();
      ctx.fillStyle = '#7d8594';
      ctx.fillText(String(f), x + 2, plot.height - 3);
    }
    const ys = niceStep(y1 - y0, plot.height / 40);
    for (const v of gridLines(y0, y1, ys)) {
      const y = Math.round(plot.py(v)) + 0.5;
      ctx.strokeStyle = v === 0 ? '#3a404c' : '#23262e';
      ctx.beginPath();
      ctx.moveTo(0, y);
      ctx.lineTo(plot.width, y);
      ctx.stroke();
      ctx.fillStyle = '#7d8594';
      ctx.fillText(String(Math.round(v / ys) * ys === v ? +v.toPrecision(6) : v.toFixed(3)), 3, y - 2);
    }
    const now = this.app.store.scene?.frame;
    if (now !== undefined) {
      const x = Math.round(plot.px(now)) + 0.5;
      ctx.strokeStyle = '#d04545';
      ctx.beginPath();
      ctx.moveTo(x, 0);
      ctx.lineTo(x, plot.height);
      ctx.stroke();
    }
  }

  private drawCurve(ctx: CanvasRenderingContext2D, plot: Plot, c: CurveInfo, index: number, offset: { frames: number; value: number }): void {
    const colour = curveColour(c, index);
    const s = c.samples;
    ctx.strokeStyle = colour;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    for (let i = 0; i < s.frames.length; ++i) {
      const x = plot.px(s.frames[i]!);
      const y = plot.py(s.values[i]!);
      if (i === 0) ctx.moveTo(x, y);
      else ctx.lineTo(x, y);
    }
    ctx.stroke();
    for (let i = 0; i < c.frames.length; ++i) {
      const sel = this.isSelected(c, i);
      const df = sel ? offset.frames : 0;
      const dv = sel && c.editable ? offset.value : 0;
      const x = plot.px(c.frames[i]! + df);
      const y = plot.py(c.values[i]! + dv);
      if (sel && df === 0 && dv === 0) {
        const hs = plot.handles(c, i, kHandlePx);
        if (hs) {
          ctx.strokeStyle = '#9aa3b2';
          ctx.lineWidth = 1;
          ctx.beginPath();
          ctx.moveTo(hs.in[0], hs.in[1]);
          ctx.lineTo(x, y);
          ctx.lineTo(hs.out[0], hs.out[1]);
          ctx.stroke();
          ctx.fillStyle = '#c9a6ff';
          for (const p of [hs.in, hs.out]) ctx.fillRect(p[0] - 2.5, p[1] - 2.5, 5, 5);
        }
      }
      ctx.fillStyle = sel ? '#ffd34d' : '#0b0c0f';
      ctx.strokeStyle = sel ? '#ffd34d' : colour;
      ctx.lineWidth = 1;
      ctx.fillRect(x - kKeyPx, y - kKeyPx, kKeyPx * 2, kKeyPx * 2);
      ctx.strokeRect(x - kKeyPx + 0.5, y - kKeyPx + 0.5, kKeyPx * 2 - 1, kKeyPx * 2 - 1);
    }
  }

  // ------------------------------------------------------------------ input

  private local(e: MouseEvent): [number, number] {
    const r = this.canvas.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  }

  private keyAt(x: number, y: number): KeyHit | null {
    const plot = this.plot();
    let best: KeyHit | null = null;
    let bestD = kHitPx;
    for (const c of this.shown())
      for (let i = 0; i < c.frames.length; ++i) {
        const d = Math.hypot(plot.px(c.frames[i]!) - x, plot.py(c.values[i]!) - y);
        if (d <= bestD) {
          bestD = d;
          best = { curve: c, index: i };
        }
      }
    return best;
  }

  private handleAt(x: number, y: number): (KeyHit & { side: 'in' | 'out' }) | null {
    const plot = this.plot();
    for (const k of this.selectedKeys()) {
      const hs = k.curve.kind === 'curve' ? plot.handles(k.curve, k.index, kHandlePx) : null;
      if (!hs) continue;
      for (const side of ['in', 'out'] as const) if (Math.hypot(hs[side][0] - x, hs[side][1] - y) <= kHitPx) return { ...k, side };
    }
    return null;
  }

  private wire(): void {
    const c = this.canvas;
    c.addEventListener('pointerdown', (e) => this.down(e));
    c.addEventListener('pointermove', (e) => this.move(e));
    c.addEventListener('pointerup', (e) => this.up(e));
    c.addEventListener('pointercancel', () => {
      this.gesture = null;
      run(this.refresh()); // a tangent previewed goes back to the server's
    });
    c.addEventListener('dblclick', (e) => this.doubleClick(e));
    c.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
    c.addEventListener('keydown', (e) => this.key(e));
  }

  private down(e: PointerEvent): void {
    this.canvas.focus();
    const [x, y] = this.local(e);
    if (e.button === 1 || (e.button === 0 && e.altKey)) {
      this.gesture = { kind: 'pan', x0: x, y0: y, view: { ...this.view } };
    } else if (e.button === 0) {
      const handle = this.handleAt(x, y);
      const key = handle ? null : this.keyAt(x, y);
      if (handle) {
        const side = handle.side;
        const slopes = side === 'in' ? handle.curve.inSlopes : handle.curve.outSlopes;
        this.gesture = { kind: 'tangent', curve: handle.curve, index: handle.index, side, slope: slopes?.[handle.index] ?? 0, broken: e.ctrlKey, moved: false };
      } else if (key) {
        if (e.shiftKey && this.isSelected(key.curve, key.index)) {
          this.deselect(key);
          return;
        }
        if (!this.isSelected(key.curve, key.index)) this.select([key], e.shiftKey);
        this.gesture = { kind: 'move', x0: x, y0: y, frames: 0, value: 0, moved: false };
      } else {
        this.gesture = { kind: 'box', x0: x, y0: y, x1: x, y1: y, add: e.shiftKey };
      }
    } else {
      return;
    }
    e.preventDefault();
    this.canvas.setPointerCapture(e.pointerId);
  }

  private move(e: PointerEvent): void {
    const g = this.gesture;
    if (!g) return;
    const [x, y] = this.local(e);
    const plot = this.plot();
    if (g.kind === 'pan') {
      const df = (x - g.x0) / plot.sx;
      const dv = (y - g.y0) / plot.sy;
      this.view = { x0: g.view.x0 - df, x1: g.view.x1 - df, y0: g.view.y0 + dv, y1: g.view.y1 + dv };
    } else if (g.kind === 'box') {
      g.x1 = x;
      g.y1 = y;
    } else if (g.kind === 'move') {
      let dx = x - g.x0;
      let dy = y - g.y0;
      if (!g.moved && Math.hypot(dx, dy) < 3) return;
      g.moved = true;
      if (e.shiftKey) {
        if (Math.abs(dx) > Math.abs(dy)) dy = 0;
        else dx = 0;
      }
      g.frames = Math.round(dx / plot.sx);
      g.value = -dy / plot.sy;
    } else {
      const k = { f: g.curve.frames[g.index]!, v: g.curve.values[g.index]! };
      let df = plot.frameAt(x) - k.f;
      const min = 1 / plot.sx; // a pixel: a handle never turns vertical
      if (g.side === 'out') df = Math.max(df, min);
      else df = Math.min(df, -min);
      g.slope = (plot.valueAt(y) - k.v) / df;
      g.moved = true;
      // Preview: the answer's slopes, this key's changed.
      const slopes = g.side === 'in' ? g.curve.inSlopes : g.curve.outSlopes;
      if (slopes) slopes[g.index] = g.slope;
      if (!g.broken) {
        const other = g.side === 'in' ? g.curve.outSlopes : g.curve.inSlopes;
        if (other) other[g.index] = g.slope;
      }
    }
    this.draw();
  }

  private up(e: PointerEvent): void {
    const g = this.gesture;
    this.gesture = null;
    if (this.canvas.hasPointerCapture(e.pointerId)) this.canvas.releasePointerCapture(e.pointerId);
    if (!g) return;
    if (g.kind === 'box') {
      this.boxSelect(g);
    } else if (g.kind === 'move') {
      if (g.moved && (g.frames !== 0 || g.value !== 0)) run(this.moveSelected(g.frames, g.value));
    } else if (g.kind === 'tangent') {
      if (g.moved) {
        const edit: CurveKeyEdit = { curve: g.curve.plug, frame: g.curve.frames[g.index]! };
        if (g.side === 'in' || !g.broken) edit.inSlope = g.slope;
        if (g.side === 'out' || !g.broken) edit.outSlope = g.slope;
        run(this.send('edit', [edit], 'Tangent'));
      }
    } else {
      this.setView(this.view);
    }
    this.draw();
  }

  private boxSelect(g: Extract<Gesture, { kind: 'box' }>): void {
    const plot = this.plot();
    const [xa, xb] = [Math.min(g.x0, g.x1), Math.max(g.x0, g.x1)];
    const [ya, yb] = [Math.min(g.y0, g.y1), Math.max(g.y0, g.y1)];
    const inside: KeyHit[] = [];
    for (const c of this.shown())
      for (let i = 0; i < c.frames.length; ++i) {
        const x = plot.px(c.frames[i]!);
        const y = plot.py(c.values[i]!);
        if (x >= xa - kKeyPx && x <= xb + kKeyPx && y >= ya - kKeyPx && y <= yb + kKeyPx) inside.push({ curve: c, index: i });
      }
    this.select(inside, g.add);
  }

  private doubleClick(e: MouseEvent): void {
    const [x, y] = this.local(e);
    const plot = this.plot();
    const frame = Math.round(plot.frameAt(x));
    let best: CurveInfo | null = null;
    let bestD = 8;
    for (const c of this.shown()) {
      const v = sampleAt(c, plot.frameAt(x));
      if (v === null) continue;
      const d = Math.abs(plot.py(v) - y);
      if (d <= bestD) {
        bestD = d;
        best = c;
      }
    }
    if (best) run(this.insertAt([best], frame));
  }

  private wheel(e: WheelEvent): void {
    e.preventDefault();
    const [x, y] = this.local(e);
    const plot = this.plot();
    const k = Math.pow(1.15, Math.sign(e.deltaY));
    const f = plot.frameAt(x);
    const v = plot.valueAt(y);
    const { x0, x1, y0, y1 } = this.view;
    const zx = e.ctrlKey ? 1 : k;
    const zy = e.shiftKey ? 1 : k;
    this.setView({ x0: f - (f - x0) * zx, x1: f + (x1 - f) * zx, y0: v - (v - y0) * zy, y1: v + (y1 - v) * zy });
  }

  private key(e: KeyboardEvent): void {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    switch (e.key.toLowerCase()) {
      case 'a':
        this.frameAll();
        break;
      case 'f':
        this.frameSelected();
        break;
      case 'i':
        run(this.insertAtCurrent());
        break;
      case 'delete':
      case 'backspace':
        run(this.deleteSelected());
        break;
      default:
        return;
    }
    e.preventDefault();
    e.stopPropagation();
  }
}
