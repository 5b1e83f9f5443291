// The node editors' pointer gestures and link geometry (buildgraph.ts;
// defeditor.ts drags its nodes with dragNode): dragging a node, dragging a
// link from a socket to a socket, where a socket sits, and the curve a
// link draws.

import type { BuildGraphModel, SocketRef } from './buildgraphmodel';
import { kNodeW, kRowH, kTitleH, refText } from './buildgraphmodel';

export type Dir = 'in' | 'out';

/** Where a socket's centre is, in graph coordinates (null: no such node or socket). */
export function socketPosition(model: BuildGraphModel, ref: SocketRef, dir: Dir): [number, number] | null {
  const n = model.nodes.get(ref.node);
  if (!n) return null;
  const list = dir === 'in' ? model.inputsOf(n) : model.outputsOf(n);
  const i = list.findIndex((s) => s.name === ref.socket);
  if (i < 0) return null;
  return [dir === 'in' ? n.x : n.x + kNodeW, n.y + kTitleH + i * kRowH + kRowH / 2];
}

/** The graph coordinates of a pointer event over `graph` (its scroll included). */
export function graphPoint(graph: HTMLElement, ev: { clientX: number; clientY: number }): [number, number] {
  const r = graph.getBoundingClientRect();
  return [ev.clientX - r.left - graph.clientLeft + graph.scrollLeft, ev.clientY - r.top - graph.clientTop + graph.scrollTop];
}

/** A link's path from an output at (x1, y1) to an input at (x2, y2). */
export function curve(x1: number, y1: number, x2: number, y2: number): string {
  const dx = Math.max(40, Math.abs(x2 - x1) / 2);
  return `M${x1},${y1} C${x1 + dx},${y1} ${x2 - dx},${y2} ${x2},${y2}`;
}

/**
 * Drags a node at (`n.x`, `n.y`) from pointer event `e`: `move(x, y)` with its new corner
 * once the pointer has moved 3 pixels, then `done(moved)` on release (a
 * click without motion is not a move).
 */
export function dragNode(n: { x: number; y: number }, e: PointerEvent, on: { move(x: number, y: number): void; done(moved: boolean): void }): void {
  const sx = e.clientX;
  const sy = e.clientY;
  const ox = n.x;
  const oy = n.y;
  let moved = false;
  const move = (ev: PointerEvent): void => {
    const dx = ev.clientX - sx;
    const dy = ev.clientY - sy;
    if (!moved && Math.hypot(dx, dy) < 3) return;
    moved = true;
    on.move(ox + dx, oy + dy);
  };
  const up = (): void => {
    window.removeEventListener('pointermove', move);
    window.removeEventListener('pointerup', up);
    on.done(moved);
  };
  window.addEventListener('pointermove', move);
  window.addEventListener('pointerup', up);
}

/**
 * Drags a link from socket `start` (at `p`) with `temp` following the
 * pointer; on release over a socket of the other direction, `connect(from,
 * to)` (an output to an input); over another socket of the same direction,
 * `refuse` says why.
 */
export function dragLink(
  graph: HTMLElement,
  temp: SVGPathElement,
  start: SocketRef,
  dir: Dir,
  p: [number, number],
  on: { connect(from: SocketRef, to: SocketRef): void; refuse(from: SocketRef, to: SocketRef, message: string): void },
): void {
  const move = (ev: PointerEvent): void => {
    const [x, y] = graphPoint(graph, ev);
    temp.setAttribute('d', dir === 'out' ? curve(p[0], p[1], x, y) : curve(x, y, p[0], p[1]));
    temp.style.display = 'block';
  };
  const up = (ev: PointerEvent): void => {
    window.removeEventListener('pointermove', move);
    window.removeEventListener('pointerup', up);
    temp.style.display = 'none';
    const port = document.elementFromPoint(ev.clientX, ev.clientY)?.closest<HTMLElement>('.bg-port');
    const node = port?.dataset.node;
    const socket = port?.dataset.socket;
    if (!port || node === undefined || socket === undefined) return;
    if (port.dataset.dir === dir) {
      if (node !== start.node || socket !== start.socket) {
        on.refuse(start, { node, socket }, `'${refText(start)}' and '${node}.${socket}' are both ${dir === 'in' ? 'inputs' : 'outputs'}`);
      }
      return;
    }
    const other = { node, socket };
    if (dir === 'out') on.connect(start, other);
    else on.connect(other, start);
  };
  window.addEventListener('pointermove', move);
  window.addEventListener('pointerup', up);
}
