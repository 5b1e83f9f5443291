// Box select in the viewport: Ctrl+drag draws a rectangle and selects the
// controls whose shapes' centres lie in it (Ctrl+Shift adds them to the
// selection), one POST /api/select. The press is taken before the camera's
// orbit sees it, and a plain drag still orbits.

import type { App } from './app';
import { h } from './dom';
import { run } from './status';
import type { Viewport } from './viewport';

export function installBoxSelect(container: HTMLElement, viewport: Viewport, app: App): void {
  const box = h('div.select-box', { testid: 'select-box', hidden: true });
  container.append(box);
  let start: { x: number; y: number; id: number } | null = null;
  const place = (x: number, y: number): void => {
    const r = container.getBoundingClientRect();
    Object.assign(box.style, {
      left: `${Math.min(start!.x, x) - r.left}px`,
      top: `${Math.min(start!.y, y) - r.top}px`,
      width: `${Math.abs(x - start!.x)}px`,
      height: `${Math.abs(y - start!.y)}px`,
    });
  };
  container.addEventListener(
    'pointerdown',
    (e) => {
      if (!(e.ctrlKey || e.metaKey) || e.button !== 0 || viewport.gizmoCatches(e.clientX, e.clientY)) return;
      e.stopPropagation();
      e.preventDefault();
      start = { x: e.clientX, y: e.clientY, id: e.pointerId };
      container.setPointerCapture(e.pointerId);
      place(e.clientX, e.clientY);
      box.hidden = false;
    },
    { capture: true },
  );
  container.addEventListener(
    'pointermove',
    (e) => {
      if (!start || e.pointerId !== start.id) return;
      e.stopPropagation();
      place(e.clientX, e.clientY);
    },
    { capture: true },
  );
  const end = (e: PointerEvent): void => {
    if (!start || e.pointerId !== start.id) return;
    e.stopPropagation();
    const from = start;
    start = null;
    box.hidden = true;
    if (container.hasPointerCapture(e.pointerId)) container.releasePointerCapture(e.pointerId);
    if (e.type === 'pointercancel') return;
    const uuids = viewport.controlsIn(from.x, from.y, e.clientX, e.clientY);
    if (!uuids.length && !e.shiftKey) {
      run(app.select([], false));
      return;
    }
    run(app.select(uuids, e.shiftKey).then(() => app.status.info(`Box selected ${uuids.length} control${uuids.length === 1 ? '' : 's'}`)));
  };
  container.addEventListener('pointerup', end, { capture: true });
  container.addEventListener('pointercancel', end, { capture: true });
}
