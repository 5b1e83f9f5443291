// The viewport's context menu (seed 004 §4.5's dynamic marking menu):
// right-click a control for the actions on the selection it joins, in one
// of two modes chosen at the menu's top (and kept in the browser):
//   animator: key and delete key, bind pose of the control, its component
//     or its whole character, select the component, FK/IK match of a built
//     limb, its spaces (switch at this frame, the world matrix kept),
//     mirror pose;
//   rigger: copy the control's shape and colour, paste the shape or the
//     colour onto the selection, mirror and flip shapes, mirror a shape to
//     the opposite control; match position / rotation of the selection to
//     the first control selected; a locator at each selected control;
//     mirror the selection's joints to the other side (or update it);
//     bind pose;
// both: frame and isolate. Every action is the JSON API's call that the
// CLI and Python make too, one undo step. Right-drag off a control still
// pans the camera.

import type { ShapeInfo } from './api';
import type { App } from './app';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';
import type { Viewport } from './viewport';

interface Item {
  label: string;
  id: string;
  action: () => Promise<void> | void;
}

export type MenuMode = 'animator' | 'rigger';
const kModeKey = 'rigel.menuMode';
const sep: Item = { label: '', id: '-', action: () => undefined };

export class ContextMenu {
  private readonly el: HTMLElement;
  private modeNow: MenuMode = localStorage.getItem(kModeKey) === 'rigger' ? 'rigger' : 'animator';
  /** What Copy shape kept (pasted as the shape, the colour or both). */
  private copied: ShapeInfo | null = null;
  private at: { uuid: string; x: number; y: number } | null = null;

  constructor(
    container: HTMLElement,
    private readonly viewport: Viewport,
    private readonly app: App,
    private readonly isolate: () => void,
  ) {
    this.el = h('div.context-menu', { testid: 'context-menu', hidden: true, role: 'menu' });
    container.append(this.el);
    container.addEventListener('contextmenu', (e) => {
      const uuid = viewport.pickAt(e.clientX, e.clientY);
      if (!uuid) return; // off a control: the camera pans
      e.preventDefault();
      e.stopPropagation();
      run(this.open(uuid, e.clientX, e.clientY));
    });
    document.addEventListener('pointerdown', (e) => {
      if (!this.el.hidden && !this.el.contains(e.target as Node)) this.close();
    });
    document.addEventListener('keydown', (e) => {
      if (e.key === 'Escape' && !this.el.hidden) {
        e.stopPropagation();
        this.close();
      }
    });
  }

  get isOpen(): boolean {
    return !this.el.hidden;
  }

  get mode(): MenuMode {
    return this.modeNow;
  }

  /** The copied look (for the tests): the control it came from, or null. */
  get clipboard(): string | null {
    return this.copied?.name ?? null;
  }

  close(): void {
    this.el.hidden = true;
    this.at = null;
  }

  private async open(uuid: string, x: number, y: number): Promise<void> {
    if (!this.app.store.selection.includes(uuid)) await this.app.select([uuid], false);
    this.at = { uuid, x, y };
    const items = this.modeNow === 'rigger' ? this.riggerItems(uuid) : await this.items(uuid);
    const rect = this.el.parentElement!.getBoundingClientRect();
    const modes = h(
      'div.menu-modes',
      {},
      ...(['animator', 'rigger'] as const).map((m) =>
        h(`button.menu-mode${m === this.modeNow ? '.active' : ''}`, { testid: `menu-mode-${m}`, onclick: () => this.setMode(m) }, m === 'animator' ? 'Animator' : 'Rigger'),
      ),
    );
    fill(
      this.el,
      modes,
      ...items.map((it) =>
        it.id === '-'
          ? h('div.menu-sep', {})
          : h('button.menu-item', { testid: `menu-${it.id}`, onclick: () => this.pick(it) }, it.label),
      ),
    );
    Object.assign(this.el.style, { left: `${x - rect.left}px`, top: `${y - rect.top}px` });
    this.el.hidden = false;
  }

  private setMode(mode: MenuMode): void {
    this.modeNow = mode;
    localStorage.setItem(kModeKey, mode);
    const at = this.at;
    if (at) run(this.open(at.uuid, at.x, at.y));
  }

  private pick(it: Item): void {
    this.close();
    const r = it.action();
    if (r) run(r);
  }

  private async items(uuid: string): Promise<Item[]> {
    const app = this.app;
    const c = app.store.nodes?.controls.find((x) => x.uuid === uuid);
    const name = app.store.names.get(uuid) ?? uuid;
    const built = c && !c.ephemeral && c.rig && c.group && c.group !== c.rig ? { rig: c.rig, component: c.group } : null;
    const tool = <A>(send: Parameters<typeof commands.tool<A>>[0], message: (a: A) => string) => () => app.execute(commands.tool(send, message)).then(() => undefined);
    const items: Item[] = [
      { label: 'Key', id: 'key', action: () => app.key(false) },
      { label: 'Delete key', id: 'delete-key', action: () => app.key(true) },
      sep,
      { label: `Bind pose: ${name}`, id: 'bind-control', action: tool((api) => api.bindPose([uuid]), () => `Bind pose: ${name}`) },
    ];
    if (built) {
      const comp = `${built.rig}:${built.component}`;
      items.push(
        { label: `Bind pose: ${comp}`, id: 'bind-component', action: tool((api) => api.bindPose([comp]), () => `Bind pose: ${comp}`) },
        { label: `Bind pose: ${built.rig} (character)`, id: 'bind-character', action: tool((api) => api.bindPose([`${built.rig}:`]), () => `Bind pose: ${built.rig}`) },
        { label: `Select ${built.component}`, id: 'select-component', action: () => this.selectGroup(built.rig, built.component) },
        sep,
        { label: 'Match FK ← IK', id: 'match-fk', action: tool((api) => api.match({ ...built, to: 'fk' }), (a) => `Matched ${comp} FK to IK: ${a.keys} keys`) },
        { label: 'Match IK ← FK', id: 'match-ik', action: tool((api) => api.match({ ...built, to: 'ik' }), (a) => `Matched ${comp} IK to FK: ${a.keys} keys`) },
      );
      const spaces = await app.api.spaces(uuid).catch(() => null);
      for (const s of spaces?.spaces ?? []) {
        if (s.name === spaces?.current) continue;
        const frame = app.store.scene?.frame ?? 0;
        items.push({
          label: `Space → ${s.name}`,
          id: `space-${s.name}`,
          action: tool((api) => api.switchSpace({ control: uuid, switch: s.name, frame }), () => `${name}: space ${s.name} at frame ${frame}`),
        });
      }
      items.push({ label: 'Mirror pose', id: 'mirror', action: tool((api) => api.mirror({ controls: [...app.store.selection] }), (a) => `Mirrored ${(a.set ?? []).length} controls`) });
    }
    items.push(
      sep,
      { label: 'Frame selected', id: 'frame', action: () => this.viewport.frameSelected() },
      { label: 'Isolate selection', id: 'isolate', action: () => this.isolate() },
    );
    return items;
  }

  /** The rigger's actions on the selection (the right-clicked control among it). */
  private riggerItems(uuid: string): Item[] {
    const app = this.app;
    const name = app.store.names.get(uuid) ?? uuid;
    const selection = [...app.store.selection];
    const rigging = <A>(send: (api: App['api']) => Promise<A>, message: (a: A) => string) => () =>
      app.execute({ send, message: (a: A) => message(a), affects: ['everything'] }).then(() => undefined);
    const copied = this.copied;
    const items: Item[] = [
      { label: `Copy shape and colour of ${name}`, id: 'copy-shape', action: async () => { this.copied = await app.api.shape(uuid); } },
    ];
    if (copied) {
      const look = { points: copied.points, closed: copied.closed, color: copied.color };
      items.push(
        { label: `Paste shape of ${copied.name}`, id: 'paste-shape', action: rigging((api) => api.shapeEdit({ op: 'paste', controls: selection, shape: look, parts: ['shape'] }), () => `Pasted the shape of ${copied.name}`) },
        { label: `Paste colour of ${copied.name}`, id: 'paste-color', action: rigging((api) => api.shapeEdit({ op: 'paste', controls: selection, shape: look, parts: ['color'] }), () => `Pasted the colour of ${copied.name}`) },
      );
    }
    items.push(
      { label: 'Mirror shape (YZ)', id: 'mirror-shape', action: rigging((api) => api.shapeEdit({ op: 'mirror', controls: selection }), () => 'Mirrored the shapes') },
      { label: 'Flip shape (YZ)', id: 'flip-shape', action: rigging((api) => api.shapeEdit({ op: 'flip', controls: selection }), () => 'Flipped the shapes') },
      { label: 'Mirror shape to opposite control', id: 'opposite-shape', action: rigging((api) => api.shapeEdit({ op: 'opposite', controls: selection }), (a) => `Mirrored ${(a.pairs ?? []).length} shapes to the other side`) },
      sep,
    );
    if (selection.length >= 2) {
      const [target, ...rest] = selection as [string, ...string[]];
      const to = app.store.names.get(target) ?? target;
      const match = (position: boolean, rotation: boolean) =>
        rigging((api) => api.align({ nodes: rest, target, position, rotation }), (a) => `Matched ${a.moved.length} to ${to}`);
      items.push(
        { label: `Match position to ${to}`, id: 'match-position', action: match(true, false) },
        { label: `Match rotation to ${to}`, id: 'match-rotation', action: match(false, true) },
        { label: `Match transform to ${to}`, id: 'match-transform', action: match(true, true) },
      );
    }
    items.push(
      { label: 'Create locator', id: 'locator', action: rigging((api) => api.locators({ nodes: selection }), (a) => `Created ${a.locators.map((l) => l.name).join(', ')}`) },
      sep,
      { label: 'Mirror joints', id: 'mirror-joints', action: rigging((api) => api.mirrorJoints({ joints: selection }), (a) => `Mirrored joints: ${a.created.length} created`) },
      { label: 'Mirror joints (update the other side)', id: 'mirror-joints-update', action: rigging((api) => api.mirrorJoints({ joints: selection, update: true }), (a) => `Mirrored joints: ${a.created.length} created, ${a.updated.length} updated`) },
      sep,
      { label: `Bind pose: ${name}`, id: 'bind-control', action: rigging((api) => api.bindPose([uuid]), () => `Bind pose: ${name}`) },
      sep,
      { label: 'Frame selected', id: 'frame', action: () => this.viewport.frameSelected() },
      { label: 'Isolate selection', id: 'isolate', action: () => this.isolate() },
    );
    return items;
  }

  private async selectGroup(rig: string, group: string): Promise<void> {
    const uuids = (this.app.store.nodes?.controls ?? []).filter((x) => x.rig === rig && x.group === group).map((x) => x.uuid);
    await this.app.select(uuids, false);
  }
}
