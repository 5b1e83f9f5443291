// The picker (the Picker tab): every control of the scene as a button in
// its group (GET /api/picker: a built rig's components, an ephemeral rig's
// face and hands, its other controls by part), laid out as the character
// faces the viewer: rows head to toe, its right side on the left. Click a
// control to select it (Shift adds or removes), a group's title to select
// the whole group. Above it, named selection sets (GET/POST
// /api/selection-sets, saved with the scene): select one (Shift adds),
// save the selection under a name, remove one; saving and removing are one
// undo step each.

import type { App } from './app';
import { Coalesced } from './app';
import type { PickerAnswer, PickerGroup, SelectionSetsAnswer } from './api';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';

const kParts = ['head', 'arm', 'hand', 'torso', 'leg', 'tail', 'root', 'other'] as const;
const kSides = ['R', 'C', 'L'] as const;

export class Picker {
  private picker: PickerAnswer | null = null;
  private sets: SelectionSetsAnswer | null = null;
  private visibleNow = false;
  private readonly setsEl: HTMLElement;
  private readonly grid: HTMLElement;
  private readonly nameField: HTMLInputElement;
  private readonly buttons = new Map<string, HTMLButtonElement>();
  private readonly refresher = new Coalesced(() => this.fetch());

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.setsEl = h('div.set-list', { testid: 'selection-sets' });
    this.grid = h('div.picker-grid', { testid: 'picker' });
    this.nameField = h('input', { type: 'text', placeholder: 'set name', testid: 'set-name' });
    this.nameField.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') run(this.saveSet());
    });
    fill(
      el,
      h('div.panel-head', {}, h('h2', {}, 'Picker')),
      h('h3', {}, 'Selection sets'),
      this.setsEl,
      h('div.form-row', {}, this.nameField, h('button.small', { testid: 'set-save', title: 'Save the selection as a set of this name', onclick: () => run(this.saveSet()) }, 'Save selection')),
      this.grid,
    );
    const s = app.store.signals;
    s.nodesChanged.add(() => run(this.refresh()));
    s.sceneChanged.add(() => run(this.refresh()));
    s.selectionChanged.add(() => this.markSelection());
  }

  set visible(on: boolean) {
    this.visibleNow = on;
    if (on) run(this.refresh());
  }

  /** True while a fetch is running or queued (the tests wait for it). */
  get busy(): boolean {
    return this.refresher.busy;
  }

  refresh(): Promise<void> {
    return this.refresher.run();
  }

  private async fetch(): Promise<void> {
    if (!this.visibleNow) return;
    const [picker, sets] = await Promise.all([this.app.api.picker(), this.app.api.selectionSets()]);
    const changed = JSON.stringify(picker.groups) !== JSON.stringify(this.picker?.groups);
    this.picker = picker;
    this.sets = sets;
    if (changed) this.renderGrid();
    this.renderSets();
  }

  private async select(uuids: string[], add: boolean): Promise<void> {
    const sel = this.app.store.selection;
    if (add && uuids.length === 1 && sel.includes(uuids[0]!)) {
      await this.app.select(sel.filter((u) => u !== uuids[0]), false);
    } else {
      await this.app.select(uuids, add);
    }
  }

  private async saveSet(): Promise<void> {
    const name = this.nameField.value.trim();
    if (!name) {
      this.app.status.error('Selection set: give it a name');
      return;
    }
    if (!this.app.store.selection.length) {
      this.app.status.error('Selection set: select the controls to save first');
      return;
    }
    this.sets = await this.app.execute(commands.selectionSet({ op: 'save', name, controls: [...this.app.store.selection] }));
    this.nameField.value = '';
    this.renderSets();
  }

  private async setOp(op: 'remove' | 'select', name: string, add = false): Promise<void> {
    this.sets = await this.app.execute(commands.selectionSet(op === 'select' ? { op, name, add } : { op, name }));
    this.renderSets();
  }

  private renderSets(): void {
    const sets = this.sets?.sets ?? [];
    fill(
      this.setsEl,
      sets.length ? null : h('p.dim', {}, 'No selection sets yet: select controls, name the set, save.'),
      ...sets.map((s) =>
        h(
          'div.set-row',
          { testid: `set-${s.name}` },
          h('button.small.set-select', { title: `Select ${s.members.map((m) => m.name).join(', ')} (Shift adds)`, onclick: (e: MouseEvent) => run(this.setOp('select', s.name, e.shiftKey)) }, s.name),
          h('span.dim', {}, `${s.members.length}${s.missing.length ? ` (+${s.missing.length} missing)` : ''}`),
          h('button.small', { title: `Remove the set ${s.name}`, testid: `set-remove-${s.name}`, onclick: () => run(this.setOp('remove', s.name)) }, '✕'),
        ),
      ),
    );
  }

  private renderGrid(): void {
    this.buttons.clear();
    const groups = this.picker?.groups ?? [];
    const rigs = [...new Set(groups.map((g) => g.rig))];
    fill(
      this.grid,
      groups.length ? null : h('p.dim', {}, 'No controls in the scene.'),
      ...rigs.map((rig) => {
        const mine = groups.filter((g) => g.rig === rig);
        const rows = kParts
          .filter((part) => mine.some((g) => g.part === part))
          .map((part) =>
            h(
              'div.picker-row',
              { dataset: { part } },
              ...kSides.map((side) => h('div.picker-cell', { dataset: { side } }, ...mine.filter((g) => g.part === part && g.side === side).map((g) => this.group(g)))),
            ),
          );
        return h('section.picker-rig', {}, h('h3', {}, rig || '(no rig)', h('span.dim', {}, '  right · centre · left')), ...rows);
      }),
    );
    this.markSelection();
  }

  private group(g: PickerGroup): HTMLElement {
    const title = h('button.picker-title', { title: `Select all of ${g.name} (Shift adds)`, testid: `picker-group-${g.name}` }, g.name);
    title.addEventListener('click', (e) => run(this.select(g.controls.map((c) => c.uuid), e.shiftKey)));
    const buttons = g.controls.map((c) => {
      const b = h('button.picker-control', { title: c.name, testid: `pick-${c.name}` }, c.label);
      b.addEventListener('click', (e) => run(this.select([c.uuid], e.shiftKey)));
      this.buttons.set(c.uuid, b);
      return b;
    });
    return h('div.picker-group', { dataset: { part: g.part, side: g.side } }, title, h('div.picker-controls', {}, ...buttons));
  }

  private markSelection(): void {
    const sel = new Set(this.app.store.selection);
    for (const [uuid, b] of this.buttons) b.classList.toggle('active', sel.has(uuid));
  }
}
