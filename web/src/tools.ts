// The animator tools in the page (docs/RIG.md, the tools of the animator
// tools issue through their JSON API): FK/IK match of the selected built
// control's limb at the current frame or baked over the timeline's
// playback range (keyed, the switch stepped), mirror
// of the selection to the other side, flip of its whole rig, bind pose of
// the selection, and tween of the selection's keying group between its
// neighbouring keys; a space switch of the selected control at this frame
// (its world matrix kept), transfer of keys between components or
// characters, and glTF export (deform-only for game engines); the pose
// library below them (posepanel.ts). Each change is one request and so one
// undo step (an export writes a file and changes nothing).

import type { App } from './app';
import * as commands from './commands';
import { h, fill } from './dom';
import { PosePanel } from './posepanel';
import { run } from './status';

export class AnimatorTools {
  private readonly tween: HTMLInputElement;
  private readonly target: HTMLElement;
  private readonly space: HTMLSelectElement;
  private readonly transferFrom: HTMLInputElement;
  private readonly transferTo: HTMLInputElement;
  private readonly offset: HTMLInputElement;
  private readonly exportPath: HTMLInputElement;
  private readonly deformOnly: HTMLInputElement;
  readonly poses: PosePanel;
  private readonly overRange: HTMLInputElement;

  constructor(
    el: HTMLElement,
    private readonly app: App,
    /** The timeline's playback range: what "over the range" bakes. */
    private readonly range: () => [number, number] = () => [0, 100],
  ) {
    this.overRange = h('input', { type: 'checkbox', testid: 'tool-over-range' });
    this.tween = h('input', { type: 'range', min: '0', max: '100', value: '50', testid: 'tool-tween-fraction' });
    this.target = h('div.dim', { testid: 'tool-target' });
    const button = (id: string, label: string, title: string, action: () => Promise<void>) =>
      h('button.small', { testid: `tool-${id}`, title, onclick: () => run(action()) }, label);
    this.space = h('select', { testid: 'tool-space', title: 'The selected control’s spaces' });
    this.transferFrom = h('input', { type: 'text', placeholder: 'hero:arm_L', testid: 'tool-transfer-from', title: 'From a component (RIG:COMPONENT) or a character (RIG:)' });
    this.transferTo = h('input', { type: 'text', placeholder: 'hero:arm_R', testid: 'tool-transfer-to', title: 'Onto one of the same type' });
    this.offset = h('input.num', { type: 'number', value: '0', testid: 'tool-transfer-offset', title: 'Offset in frames' });
    this.exportPath = h('input', { type: 'text', value: 'export/shot.glb', testid: 'tool-export-path', title: 'A .glb or .gltf inside the served root' });
    this.deformOnly = h('input', { type: 'checkbox', checked: true, testid: 'tool-export-deform' });
    const poseEl = h('div.pose-panel');
    this.poses = new PosePanel(poseEl, app);
    fill(
      el,
      h('div.panel-head', {}, h('h2', {}, 'Animator Tools')),
      this.target,
      h('label.toggle', { title: 'Match and space switch bake every frame of the timeline’s playback range, not only this frame' }, this.overRange, 'Over the playback range'),
      h('div.form-row', {},
        button('match-fk', 'FK ← IK', 'Key the limb\'s FK controls to its IK pose at this frame (fkIk keyed 0, stepped)', () => this.match('fk')),
        button('match-ik', 'IK ← FK', 'Key the limb\'s IK controls to its FK pose at this frame (fkIk keyed 1, stepped)', () => this.match('ik'))),
      h('div.form-row', {},
        button('mirror', 'Mirror', 'The selection\'s pose onto the other side', () => this.mirror(false)),
        button('flip', 'Flip rig', 'Swap the sides of the selection\'s whole rig', () => this.mirror(true)),
        button('bind-pose', 'Bind pose', 'The selection back to its bind pose', () => this.bindPose())),
      h('div.form-row', {}, h('span', {}, 'Tween'), this.tween,
        button('tween', 'Apply', 'Between the previous (0) and next (100) keys, keyed at this frame', () => this.tweenNow())),
      h('div.form-row', {}, h('span', {}, 'Space'), this.space,
        button('space-switch', 'Switch here', 'Switch the control to this space at this frame, keeping where it is', () => this.switchSpace())),
      h('div.form-row', {}, h('span', {}, 'Transfer'), this.transferFrom, '→', this.transferTo, this.offset,
        button('transfer', 'Go', 'Copy the keys onto the other component or character (matched by role)', () => this.transfer())),
      h('div.form-row', {}, h('span', {}, 'Export'), this.exportPath, h('label.toggle', {}, this.deformOnly, 'deform only'),
        button('export', 'Write', 'Write the scene as glTF (deform only: the skeleton and meshes, baked, for game engines)', () => this.exportNow())),
      poseEl,
    );
    app.store.signals.selectionChanged.add(() => {
      this.render();
      run(this.readSpaces());
    });
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
        (api) => api.match(this.overRange.checked ? { ...c, to, frames: this.range() } : { ...c, to }),
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

  /** The spaces of the selection's first control (none: the box is empty). */
  private async readSpaces(): Promise<void> {
    const first = this.app.store.selection[0];
    const c = first ? this.app.store.nodes?.controls.find((x) => x.uuid === first) : undefined;
    if (!c || c.ephemeral) {
      fill(this.space);
      return;
    }
    const a = await this.app.api.spaces(c.uuid);
    fill(this.space, ...a.spaces.map((s) => h('option', { value: s.name, selected: s.name === a.current }, s.name)));
  }

  private async switchSpace(): Promise<void> {
    const control = this.app.store.selection[0];
    const to = this.space.value;
    if (!control || !to) {
      this.app.status.error('Space switch: select a control with spaces');
      return;
    }
    const frame = this.app.store.scene?.frame ?? 0;
    const frames = this.overRange.checked ? this.range() : null;
    await this.app.execute(
      commands.tool(
        (api) => api.switchSpace(frames ? { control, switch: to, frames } : { control, switch: to, frame }),
        (a) => `Space ${a.from} → ${a.to} ${frames ? `baked over ${frames[0]}–${frames[1]}` : `at frame ${frame}`}`,
      ),
    );
    await this.readSpaces();
  }

  private async transfer(): Promise<void> {
    const from = this.transferFrom.value.trim();
    const to = this.transferTo.value.trim();
    if (!from || !to) {
      this.app.status.error('Transfer: give a source and a target (RIG:COMPONENT or RIG:)');
      return;
    }
    const offset = Number(this.offset.value) || 0;
    await this.app.execute(commands.tool((api) => api.transfer({ from, to, offset }), (a) => `Transferred ${a.channels} channels ${from} → ${to}`));
  }

  private async exportNow(): Promise<void> {
    const path = this.exportPath.value.trim();
    const a = await this.app.api.exportGltf({ path, deformOnly: this.deformOnly.checked });
    this.app.status.info(`Wrote ${a.path}: ${a.nodes} nodes, ${a.meshes} meshes, ${a.animations} animations`);
  }
}
