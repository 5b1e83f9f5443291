// The channel box (Maya's attribute editor for animators): the keyable
// channels of the selection at the current frame (GET /api/channels):
// translate, rotate and scale as components, and a built rig's component's
// own (fkIk, a foot's roll, a hand's curl, the space switch) beside them,
// each with its value and whether it is keyed here, elsewhere or not at all.
// A value is typed (Enter) or dragged (drag the channel's name: one change
// when the button comes up); K keys the channel and ✕ deletes its key at
// this frame. With several controls selected an edit goes to each one's
// matching channel. Every edit is one request, so one undo step.

import type { App } from './app';
import type { ChannelRow, ChannelsAnswer } from './api';
import { Coalesced } from './app';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';

/** Value change per pixel of a drag on a channel's name. */
function dragStep(attr: string): number {
  if (/^rotate[XYZ]$/.test(attr)) return 0.5;
  if (/^(translate|scale)[XYZ]$/.test(attr)) return 0.005;
  return 0.01;
}

interface Shown {
  row: ChannelRow;
  input: HTMLInputElement;
  line: HTMLElement;
}

export class ChannelBox {
  private answer: ChannelsAnswer | null = null;
  private shown = new Map<string, Shown>();
  private signature = '';
  private readonly body: HTMLElement;
  private readonly head: HTMLElement;
  private readonly refresher = new Coalesced(() => this.fetch());
  private dragging = false;
  private visibleNow = false;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.head = h('div.channel-head', { testid: 'channel-head' });
    this.body = h('div.channel-list', { testid: 'channel-list' });
    fill(el, h('div.panel-head', {}, h('h2', {}, 'Channel Box')), this.head, this.body);
    const refresh = () => run(this.refresh());
    const s = app.store.signals;
    s.selectionChanged.add(refresh);
    s.timeChanged.add(refresh);
    s.poseChanged.add(refresh);
    s.keysChanged.add(refresh);
    s.nodesChanged.add(refresh);
  }

  set visible(on: boolean) {
    this.visibleNow = on;
    if (on) run(this.refresh());
  }

  get visible(): boolean {
    return this.visibleNow;
  }

  /** True while a fetch is running or queued (the tests wait for it). */
  get busy(): boolean {
    return this.refresher.busy;
  }

  /** The rows shown (for the tests): plug, value and keyed state. */
  get rows(): ChannelRow[] {
    return [...this.shown.values()].map((s) => s.row);
  }

  refresh(): Promise<void> {
    return this.refresher.run();
  }

  private async fetch(): Promise<void> {
    const selection = this.app.store.selection;
    if (!this.visibleNow || this.dragging) return;
    if (!selection.length) {
      this.answer = null;
      this.render();
      return;
    }
    this.answer = await this.app.api.channels([...selection]);
    this.render();
  }

  /** The label of a row: the control's own channels by name, a component node's as NODE.attr. */
  private label(row: ChannelRow, control: string): string {
    if (row.node === control) return row.attr;
    const short = row.node.slice(row.node.lastIndexOf('_') + 1);
    return `${short}.${row.attr}`;
  }

  /** The nodes an edit of `row` goes to: each selected control's matching channel. */
  private targets(row: ChannelRow): string[] {
    const boxes = this.answer?.controls ?? [];
    const first = boxes[0];
    if (!first) return [];
    const own = row.node === first.control;
    const out: string[] = [];
    for (const box of boxes) {
      const match = box.channels.find((r) => r.attr === row.attr && (r.node === box.control) === own);
      if (match && !out.includes(match.node)) out.push(match.node);
    }
    return out;
  }

  private render(): void {
    const boxes = this.answer?.controls ?? [];
    const first = boxes[0];
    if (!first) {
      this.shown.clear();
      this.signature = '';
      fill(this.head, h('p.dim', {}, 'Select a control to see its channels.'));
      fill(this.body);
      return;
    }
    const names = boxes.map((b) => b.control);
    fill(
      this.head,
      h('div.dim', { testid: 'channel-controls' }, names.length > 1 ? `${names[0]} +${names.length - 1} (edits go to each)` : names[0]!),
    );
    const signature = JSON.stringify(first.channels.map((r) => r.plug)) + names.join(',');
    if (signature === this.signature) {
      // The same channels: values and states in place (a focused field keeps what is being typed).
      for (const row of first.channels) {
        const s = this.shown.get(row.plug);
        if (!s) continue;
        s.row = row;
        if (document.activeElement !== s.input) s.input.value = commands.formatValue(row.value);
        s.line.dataset.keyed = row.keyed;
      }
      return;
    }
    this.signature = signature;
    this.shown.clear();
    const lines = first.channels.map((row) => this.line(row, this.label(row, first.control)));
    fill(this.body, ...lines);
  }

  private line(row: ChannelRow, label: string): HTMLElement {
    const input = h('input.channel-value', { type: 'text', value: commands.formatValue(row.value), testid: `channel-value-${label}` });
    const name = h('span.channel-name', { title: `${row.plug}: drag to change, type a value and press Enter` }, label);
    const shown: Shown = { row, input, line: h('div') };
    const line = h(
      'div.channel-row',
      { testid: `channel-${label}`, dataset: { keyed: row.keyed, plug: row.plug } },
      h('span.keyed-mark', { title: 'keyed here / keyed elsewhere / not keyed' }),
      name,
      input,
      h('button.small', { title: `Key ${label} at this frame`, testid: `channel-key-${label}`, onclick: () => run(this.key(shown, label, false)) }, 'K'),
      h('button.small', { title: `Delete the key of ${label} at this frame`, testid: `channel-unkey-${label}`, onclick: () => run(this.key(shown, label, true)) }, '✕'),
    );
    shown.line = line;
    this.shown.set(row.plug, shown);
    input.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') {
        e.preventDefault();
        input.blur();
      } else if (e.key === 'Escape') {
        input.value = commands.formatValue(shown.row.value);
        input.blur();
      }
    });
    input.addEventListener('change', () => {
      const v = Number(input.value.trim());
      if (input.value.trim() === '' || !Number.isFinite(v)) {
        this.app.status.error(`${label}: '${input.value}' is not a number`);
        input.value = commands.formatValue(shown.row.value);
        return;
      }
      run(this.set(shown.row, label, v));
    });
    name.addEventListener('pointerdown', (e) => {
      e.preventDefault();
      name.setPointerCapture(e.pointerId);
      const x0 = e.clientX;
      const v0 = shown.row.value;
      const step = dragStep(shown.row.attr);
      let v = v0;
      this.dragging = true;
      const move = (m: PointerEvent) => {
        v = v0 + (m.clientX - x0) * step;
        input.value = commands.formatValue(v);
      };
      const up = () => {
        name.removeEventListener('pointermove', move);
        name.removeEventListener('pointerup', up);
        name.removeEventListener('pointercancel', up);
        this.dragging = false;
        if (v !== v0) run(this.set(shown.row, label, v));
      };
      name.addEventListener('pointermove', move);
      name.addEventListener('pointerup', up);
      name.addEventListener('pointercancel', up);
    });
    return line;
  }

  private async set(row: ChannelRow, label: string, value: number): Promise<void> {
    await this.app.execute(commands.setChannel(this.targets(row), row.attr, value, label));
    await this.refresh();
  }

  private async key(shown: Shown, label: string, remove: boolean): Promise<void> {
    await this.app.execute(commands.keyChannel(this.targets(shown.row), shown.row.keyAttr, remove, label));
    await this.refresh();
  }
}
