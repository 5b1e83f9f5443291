// The viewport's context menu (seed 004 §4.5's marking menu, the
// animator's part of it): right-click a control for the actions on the
// selection it joins: key and delete key, bind pose of the control, its
// component or its whole character, select the component, FK/IK match of
// a built limb, its spaces (switch at this frame, the world matrix kept),
// mirror, frame and isolate. Every action is the JSON API's call that the
// CLI and Python make too, one undo step. Right-drag off a control still
// pans the camera.

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

export class ContextMenu {
  private readonly el: HTMLElement;

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

  close(): void {
    this.el.hidden = true;
  }

  private async open(uuid: string, x: number, y: number): Promise<void> {
    if (!this.app.store.selection.includes(uuid)) await this.app.select([uuid], false);
    const items = await this.items(uuid);
    const rect = this.el.parentElement!.getBoundingClientRect();
    fill(
      this.el,
      ...items.map((it) =>
        it.id === '-'
          ? h('div.menu-sep', {})
          : h('button.menu-item', { testid: `menu-${it.id}`, onclick: () => this.pick(it) }, it.label),
      ),
    );
    Object.assign(this.el.style, { left: `${x - rect.left}px`, top: `${y - rect.top}px` });
    this.el.hidden = false;
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
      { label: '', id: '-', action: () => undefined },
      { label: `Bind pose: ${name}`, id: 'bind-control', action: tool((api) => api.bindPose([uuid]), () => `Bind pose: ${name}`) },
    ];
    if (built) {
      const comp = `${built.rig}:${built.component}`;
      items.push(
        { label: `Bind pose: ${comp}`, id: 'bind-component', action: tool((api) => api.bindPose([comp]), () => `Bind pose: ${comp}`) },
        { label: `Bind pose: ${built.rig} (character)`, id: 'bind-character', action: tool((api) => api.bindPose([`${built.rig}:`]), () => `Bind pose: ${built.rig}`) },
        { label: `Select ${built.component}`, id: 'select-component', action: () => this.selectGroup(built.rig, built.component) },
        { label: '', id: '-', action: () => undefined },
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
      { label: '', id: '-', action: () => undefined },
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
