// The pose library panel (under the animator tools; docs/RIG.md, "Pose
// library"): the poses of a library folder inside the served root (GET
// /api/poses), each applied whole or to the selection, mirrored, or
// blended by the fraction slider (POST /api/poses/apply, keyed when asked),
// removed, each shown by its thumbnail (GET /api/poses/thumbnail: the
// skeleton in the pose, saved with it); the selection's pose (or its whole
// rig's) saved under a name.
// Each change is one request, one undo step (saving and removing change
// files, not the scene).

import type { App } from './app';
import type { PoseInfo } from './api';
import * as commands from './commands';
import { h, fill } from './dom';
import { run } from './status';

export class PosePanel {
  private readonly library: HTMLInputElement;
  private readonly name: HTMLInputElement;
  private readonly fraction: HTMLInputElement;
  private readonly onSelection: HTMLInputElement;
  private readonly keyIt: HTMLInputElement;
  private readonly list: HTMLElement;
  private poses: PoseInfo[] = [];
  private thumbUrls: string[] = [];

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.library = h('input', { type: 'text', value: 'poses', title: 'The library folder, inside the served root', testid: 'pose-library' });
    this.library.addEventListener('change', () => run(this.refresh()));
    this.name = h('input', { type: 'text', placeholder: 'pose name', testid: 'pose-name' });
    this.fraction = h('input', { type: 'range', min: '0', max: '100', value: '100', title: 'Blend: how much of the pose', testid: 'pose-fraction' });
    this.onSelection = h('input', { type: 'checkbox', testid: 'pose-on-selection' });
    this.keyIt = h('input', { type: 'checkbox', testid: 'pose-key' });
    this.list = h('div.pose-list', { testid: 'pose-list' });
    fill(
      el,
      h('h3', {}, 'Pose library'),
      h('div.form-row', {}, this.library, h('button.small', { testid: 'pose-refresh', onclick: () => run(this.refresh()) }, 'List')),
      h('div.form-row', {}, this.name, h('button.small', { testid: 'pose-save', title: 'Save the selection’s pose (its whole rig with nothing selected)', onclick: () => run(this.save()) }, 'Save pose')),
      h('div.form-row', {}, h('span', {}, 'Blend'), this.fraction),
      h('div.form-row', {}, h('label.toggle', {}, this.onSelection, 'Selection only'), h('label.toggle', {}, this.keyIt, 'Key')),
      this.list,
    );
  }

  async refresh(): Promise<void> {
    try {
      this.poses = (await this.app.api.poses(this.library.value.trim(), { expected: [404] })).poses;
    } catch {
      this.poses = []; // no such folder yet: saving makes it
    }
    this.render();
  }

  private render(): void {
    for (const url of this.thumbUrls) URL.revokeObjectURL(url);
    this.thumbUrls = [];
    const library = this.library.value.trim() || 'poses';
    fill(
      this.list,
      this.poses.length ? null : h('p.dim', {}, 'No poses in this library yet.'),
      ...this.poses.map((p) =>
        h(
          'div.pose-row',
          { testid: `pose-${p.name}`, title: p.error ?? `${p.rig}: ${p.entries} controls` },
          p.thumbnail ? this.thumbnail(library, p.name) : h('span.pose-thumb.empty', {}),
          h('span.pose-name', {}, p.name, p.error ? ' (unreadable)' : ''),
          h('button.small', { testid: `pose-apply-${p.name}`, onclick: () => run(this.apply(p, false)) }, 'Apply'),
          h('button.small', { testid: `pose-mirror-${p.name}`, onclick: () => run(this.apply(p, true)) }, 'Mirrored'),
          h('button.small', { testid: `pose-remove-${p.name}`, title: `Delete ${p.name}.pose.json`, onclick: () => run(this.remove(p)) }, '✕'),
        ),
      ),
    );
  }

  /** The pose's thumbnail, loaded in the background (the skeleton in the pose, from the front). */
  private thumbnail(library: string, name: string): HTMLElement {
    const img = h('img.pose-thumb', { testid: `pose-thumb-${name}`, alt: name, width: '36', height: '48' }) as HTMLImageElement;
    this.app.api
      .poseThumbnail(library, name)
      .then((bytes) => {
        const url = URL.createObjectURL(new Blob([bytes], { type: 'image/svg+xml' }));
        this.thumbUrls.push(url);
        img.src = url;
      })
      .catch(() => img.classList.add('missing'));
    return img;
  }

  private async save(): Promise<void> {
    const name = this.name.value.trim();
    if (!name) {
      this.app.status.error('Save pose: give it a name');
      return;
    }
    const controls = [...this.app.store.selection];
    const library = this.library.value.trim();
    const a = await this.app.api.savePose(controls.length ? { library, name, controls } : { library, name });
    this.app.status.info(`Saved pose ${a.name} (${a.entries} controls) in ${library}`);
    this.name.value = '';
    await this.refresh();
  }

  private async apply(p: PoseInfo, mirror: boolean): Promise<void> {
    const fraction = Number(this.fraction.value) / 100;
    const controls = this.onSelection.checked ? [...this.app.store.selection] : undefined;
    const req = { library: this.library.value.trim(), name: p.name, mirror, fraction, key: this.keyIt.checked, ...(controls ? { controls } : {}) };
    await this.app.execute(
      commands.tool(
        (api) => api.applyPose(req),
        (a) => `Applied ${p.name}${mirror ? ' mirrored' : ''}${fraction < 1 ? ` at ${Math.round(fraction * 100)}%` : ''}: ${(a.set ?? []).length} controls`,
      ),
    );
  }

  private async remove(p: PoseInfo): Promise<void> {
    await this.app.api.removePose({ library: this.library.value.trim(), name: p.name });
    this.app.status.info(`Removed pose ${p.name}`);
    await this.refresh();
  }
}
