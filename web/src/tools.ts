// The animator tools in the page (docs/RIG.md, the tools of the animator
// tools issue through their JSON API): FK/IK match of the selected built
// control's limb at the current frame (keyed, the switch stepped), mirror
// of the selection to the other side, flip of its whole rig, bind pose of
// the selection, and tween of the selection's keying group between its
// neighbouring keys. Each is one request and so one undo step.

import type { App } from './app';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';

export class AnimatorTools {
  private readonly tween: HTMLInputElement;
  private readonly target: HTMLElement;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.tween = h('input', { type: 'range', min: '0', max: '100', value: '50', testid: 'tool-tween-fraction' });
    this.target = h('div.dim', { testid: 'tool-target' });
    const button = (id: string, label: string, title: string, action: () => Promise<void>) =>
      h('button.small', { testid: `tool-${id}`, title, onclick: () => run(action()) }, label);
    fill(
      el,
      h('div.panel-head', {}, h('h2', {}, 'Animator Tools')),
      this.target,
      h('div.form-row', {},
        button('match-fk', 'FK ← IK', 'Key the limb\'s FK controls to its IK pose at this frame (fkIk keyed 0, stepped)', () => this.match('fk')),
        button('match-ik', 'IK ← FK', 'Key the limb\'s IK controls to its FK pose at this frame (fkIk keyed 1, stepped)', () => this.match('ik'))),
      h('div.form-row', {},
        button('mirror', 'Mirror', 'The selection\'s pose onto the other side', () => this.mirror(false)),
        button('flip', 'Flip rig', 'Swap the sides of the selection\'s whole rig', () => this.mirror(true)),
        button('bind-pose', 'Bind pose', 'The selection back to its bind pose', () => this.bindPose())),
      h('div.form-row', {}, h('span', {}, 'Tween'), this.tween,
        button('tween', 'Apply', 'Between the previous (0) and next (100) keys, keyed at this frame', () => this.tweenNow())),
    );
    app.store.signals.selectionChanged.add(() => this.render());
    app.store.signals.nodesChanged.add(() => this.render());
    this.render();
  }

  /** The selection's first built control: its rig and component (its group). */
  private component(): { rig: string; component: string } | null {
    for (const uuid of this.app.store.selection) {
      const c = this.app.store.nodes?.controls.find((x) => x.uuid === uuid);
      if (c && !c.ephemeral && c.rig && c.group && c.group !== c.rig) return { rig: c.rig, component: c.group };
    }
    return null;
  }

  private render(): void {
    const c = this.component();
    fill(this.target, c ? `${c.rig}:${c.component}` : this.app.store.selection.length ? 'no built rig component selected' : 'nothing selected');
  }

  private need(): string[] | null {
    const sel = [...this.app.store.selection];
    if (!sel.length) this.app.status.error('Select a control first');
    return sel.length ? sel : null;
  }

  private async match(to: 'fk' | 'ik'): Promise<void> {
    const c = this.component();
    if (!c) {
      this.app.status.error('FK/IK match: select a control of a built rig\'s limb');
      return;
    }
    await this.app.execute(
      commands.tool(
        (api) => api.match({ ...c, to }),
        (a) => `Matched ${c.component} ${to === 'fk' ? 'FK to IK' : 'IK to FK'}: ${a.keys} keys, error ${a.maxError.toExponential(1)}`,
      ),
    );
  }

  private async mirror(flip: boolean): Promise<void> {
    const controls = this.need();
    if (!controls) return;
    await this.app.execute(
      commands.tool(
        (api) => api.mirror(flip ? { controls, all: true, flip: true } : { controls }),
        (a) => `${flip ? 'Flipped' : 'Mirrored'}: ${(a.set ?? []).length} controls set`,
      ),
    );
  }

  private async bindPose(): Promise<void> {
    const controls = this.need();
    if (!controls) return;
    await this.app.execute(commands.tool((api) => api.bindPose(controls), (a) => `Bind pose: ${(a.set ?? []).length} nodes`));
  }

  private async tweenNow(): Promise<void> {
    const controls = this.need();
    if (!controls) return;
    const fraction = Number(this.tween.value) / 100;
    await this.app.execute(commands.tool((api) => api.tween({ controls, fraction }), () => `Tween ${Math.round(fraction * 100)}%`));
  }
}
