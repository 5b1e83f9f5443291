// The Rig Manager (seed 002 §4.3.1): the scene's rigs with their definition
// file and versions, Add from a definition, Remove, Update (keeping keys in
// local or world space), rig edit mode, and build stepping. It renders the
// store's rigs (rigsChanged) and runs its changes as commands.
//
// A definition edited on disk changes no revision, so while the panel is
// shown it refetches GET /api/rigs every two seconds to notice a rig that
// went out of date.

import type { App } from './app';
import type { RigInfo } from './api';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';

export class RigManager {
  private selected: string | null = null;
  // Form state survives the re-renders of the periodic refetch.
  private keepWorld = false;
  private force = false;
  private definitionOut = '';
  private shown = '';
  private readonly list: HTMLElement;
  private readonly details: HTMLElement;
  private readonly addPath: HTMLInputElement;
  private readonly addEdit: HTMLInputElement;
  visible = true;
  /** Opens a rig's definition in the definition editor (set by main.ts). */
  openDefinition: (rig: string) => void = () => undefined;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.addPath = h('input', { type: 'text', placeholder: 'rigs/hero.rig.xml (relative to the server root)', testid: 'rig-add-path' });
    this.addPath.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') run(this.add());
    });
    this.addEdit = h('input', { type: 'checkbox', testid: 'rig-add-edit' });
    this.list = h('div.rig-list', { testid: 'rig-list' });
    this.details = h('div.rig-details', { testid: 'rig-details' });
    fill(
      el,
      h(
        'div.panel-head',
        {},
        h('h2', {}, 'Rig Manager'),
        h('button.small', { title: 'Refetch the rigs', testid: 'rig-refresh', onclick: () => run(this.app.refreshRigs()) }, 'Refresh'),
      ),
      h(
        'div.form-row',
        {},
        this.addPath,
        h('button.primary', { testid: 'rig-add', onclick: () => run(this.add()) }, 'Add rig'),
      ),
      h('label.toggle', { title: 'Build the rig in rig edit mode (moved controls become guides)' }, this.addEdit, 'Add in rig edit mode'),
      this.list,
      this.details,
    );
    app.store.signals.rigsChanged.add(() => this.render());
    window.setInterval(() => {
      if (this.visible && this.app.isReady && !this.app.offline && !this.app.drag.active && document.visibilityState === 'visible') {
        run(this.app.refreshRigs(true));
      }
    }, 2000);
    this.render();
  }

  private rig(): RigInfo | undefined {
    return this.app.store.rigs.find((r) => r.name === this.selected);
  }

  render(): void {
    const rigs = this.app.store.rigs;
    // The periodic refetch re-renders only when something changed.
    const key = JSON.stringify([rigs, this.selected]);
    if (key === this.shown) return;
    this.shown = key;
    if (this.selected && !rigs.some((r) => r.name === this.selected)) this.selected = null;
    if (!this.selected && rigs.length) this.selected = rigs[0]!.name;
    if (!rigs.length) {
      fill(this.list, h('div.empty', {}, 'No rig in the scene. Add one from a definition file.'));
    } else {
      fill(
        this.list,
        rigs.map((r) => {
          const row = h(
            'div.rig-row',
            {
              testid: `rig-${r.name}`,
              dataset: { rig: r.name, outOfDate: String(r.outOfDate) },
              onclick: () => {
                this.selected = r.name;
                this.render();
              },
            },
            h('div.rig-name', {}, r.outOfDate ? h('span.warn-icon', { title: 'out of date' }, '⚠') : null, r.name, r.editMode ? h('span.badge', {}, 'EDIT') : null),
            h('div.rig-version', {}, `v${r.version}`),
            h('div.rig-def', { title: r.definition }, r.definition || '(no definition)'),
          );
          row.classList.toggle('selected', r.name === this.selected);
          row.classList.toggle('out-of-date', r.outOfDate);
          return row;
        }),
      );
    }
    this.renderDetails();
  }

  private renderDetails(): void {
    const r = this.rig();
    if (!r) {
      fill(this.details);
      return;
    }
    const keepWorld = h('input', { type: 'checkbox', checked: this.keepWorld, testid: 'rig-keep-world' });
    keepWorld.addEventListener('change', () => (this.keepWorld = keepWorld.checked));
    const force = h('input', { type: 'checkbox', checked: this.force, testid: 'rig-force' });
    force.addEventListener('change', () => (this.force = force.checked));
    const defOut = h('input', { type: 'text', value: this.definitionOut, placeholder: 'write the definition to (optional)', testid: 'rig-edit-out' });
    defOut.addEventListener('input', () => (this.definitionOut = defOut.value));
    const stale = r.components.filter((c) => c.outOfDate);
    const added = r.added ?? [];
    const which = [
      stale.length ? `changed: ${stale.map((c) => c.name).join(', ')}` : '',
      added.length ? `new: ${added.map((c) => c.name).join(', ')}` : '',
    ].filter(Boolean).join('; ');
    const warning = r.outOfDate
      ? h(
          'div.warning',
          { testid: 'rig-warning' },
          `⚠ ${r.name} is out of date: the rig is v${r.version}, its definition ${r.definition} is v${r.definitionVersion ?? '?'}${which ? ` (${which})` : ''}. Update to rebuild the changed components.`,
        )
      : r.definitionFound === false
        ? h('div.warning', { testid: 'rig-definition-missing' }, `⚠ ${r.name}: its definition cannot be read: ${r.definitionProblem ?? r.definition}`)
        : null;
    const update = h(
      'button',
      {
        testid: 'rig-update',
        title: 'Rebuild the components whose definition changed',
        onclick: () => run(this.update(r.name, keepWorld.checked ? 'world' : 'local', force.checked)),
      },
      'Update',
    );
    update.classList.toggle('danger', r.outOfDate);
    const step = (body: { to?: number; by?: number }): void => run(this.step(r.name, body));
    fill(
      this.details,
      warning,
      h(
        'table.kv',
        {},
        h('tr', {}, h('th', {}, 'Rig'), h('td', {}, r.name)),
        h('tr', {}, h('th', {}, 'Version'), h('td', { testid: 'rig-version' }, r.version)),
        h('tr', {}, h('th', {}, 'Definition'), h('td', {}, r.definition || '—')),
        h('tr', {}, h('th', {}, 'Definition version'), h('td', { testid: 'rig-def-version' }, r.definitionVersion ?? '—')),
        h('tr', {}, h('th', {}, 'Edit mode'), h('td', {}, r.editMode ? 'yes' : 'no')),
      ),
      h(
        'div.button-row',
        {},
        update,
        h('label.toggle', { title: 'Keys keep their world positions through the update (else their local values)' }, keepWorld, 'Keep world positions of keys'),
        h('label.toggle', { title: 'Rebuild every component, changed or not' }, force, 'Force'),
      ),
      h(
        'div.button-row',
        {},
        h('button.danger-outline', { testid: 'rig-remove', onclick: () => run(this.remove(r.name)) }, 'Remove'),
        h(
          'button',
          { testid: 'rig-open-definition', title: 'Open the definition this rig was built from in the definition editor', onclick: () => this.openDefinition(r.name) },
          'Edit definition',
        ),
        r.editMode
          ? [
              defOut,
              h('button', { testid: 'rig-commit-edit', onclick: () => run(this.commitEdit(r.name, defOut.value.trim())) }, 'Commit edit mode'),
              h('button', { testid: 'rig-leave-edit', title: 'Build the rig again out of edit mode', onclick: () => run(this.setEditMode(r.name, false)) }, 'Leave edit mode'),
            ]
          : h(
              'button',
              { testid: 'rig-enter-edit', title: 'Build the rig again in rig edit mode: moved controls become guides', onclick: () => run(this.setEditMode(r.name, true)) },
              'Enter rig edit mode',
            ),
      ),
      h('h3', {}, 'Build steps'),
      h(
        'div.stepper',
        {},
        h('button.icon', { title: 'Back to the start', testid: 'step-first', onclick: () => step({ to: 0 }) }, '|◀'),
        h('button.icon', { title: 'One step back', testid: 'step-back', onclick: () => step({ by: -1 }) }, '◀'),
        h('span.step-pos', { testid: 'step-position' }, `${r.buildPosition} / ${r.steps}`),
        h('button.icon', { title: 'One step forward', testid: 'step-forward', onclick: () => step({ by: 1 }) }, '▶'),
        h('button.icon', { title: 'To the end', testid: 'step-last', onclick: () => step({ to: r.steps }) }, '▶|'),
      ),
      h('h3', {}, 'Features'),
      (r.features ?? []).length === 0
        ? h('span.hint', {}, 'No build step of this rig names a feature.')
        : h(
            'div.features',
            {},
            (r.features ?? []).map((f) => {
              const label = f.switch ? `${f.feature} / ${f.switch}` : f.feature;
              const box = h('input', { type: 'checkbox', checked: f.enabled, testid: `rig-feature-${label}` });
              box.addEventListener('change', () => run(this.setFeature(r.name, f.feature, f.switch, box.checked)));
              return h('label.toggle', { title: 'Build the steps of this feature (the build is redone from the first step it changes)' }, box, label);
            }),
          ),
      h('h3', {}, `Components (${r.components.length})`),
      h(
        'ul.components',
        {},
        r.components.map((c) => {
          const li = h(
            'li',
            { testid: `rig-component-${c.name}`, dataset: { state: c.state ?? 'current' } },
            c.outOfDate ? h('span.warn-icon', { title: 'out of date' }, '⚠ ') : null,
            h('b', {}, c.name),
            ` ${c.type} v${c.version}`,
            c.state === 'changed' ? ` → v${c.definitionVersion ?? '?'} (changed)` : c.state === 'removed' ? ' (not in the definition: Update removes it)' : '',
            c.parent ? h('span.dim', {}, ` ← ${c.parent}`) : null,
          );
          li.classList.toggle('out-of-date', !!c.outOfDate);
          return li;
        }),
        added.map((c) => {
          const li = h(
            'li',
            { testid: `rig-component-${c.name}`, dataset: { state: 'added' } },
            h('span.warn-icon', { title: 'not built yet' }, '⚠ '),
            h('b', {}, c.name),
            ` ${c.type} v${c.definitionVersion ?? c.version ?? '?'} (new in the definition: Update builds it)`,
          );
          li.classList.add('out-of-date');
          return li;
        }),
      ),
    );
  }

  async add(): Promise<void> {
    const path = this.addPath.value.trim();
    if (!path) {
      this.app.status.error('Add rig: enter the path of a definition (relative to the server root)');
      return;
    }
    await this.app.execute(commands.also(commands.addRig(path, this.addEdit.checked), (a) => (this.selected = a.rig)));
  }

  async update(rig: string, keepKeys: 'local' | 'world', force: boolean): Promise<void> {
    await this.app.execute(commands.updateRig(rig, keepKeys, force));
  }

  async remove(rig: string): Promise<void> {
    await this.app.execute(commands.removeRig(rig));
  }

  async commitEdit(rig: string, out: string): Promise<void> {
    await this.app.execute(commands.commitEdit(rig, out));
  }

  async setFeature(rig: string, feature: string, switchName: string, enabled: boolean): Promise<void> {
    await this.app.execute(commands.setFeature(rig, feature, switchName, enabled));
  }

  async setEditMode(rig: string, on: boolean): Promise<void> {
    await this.app.execute(commands.setEditMode(rig, on));
  }

  async step(rig: string, target: { to?: number; by?: number }): Promise<void> {
    await this.app.execute(commands.step(rig, target));
  }
}
