// What the build-graph editor draws of the model (buildgraph.ts): the
// palette's entries by category and its search filter, and a node's box
// with its title and its exec and data sockets in their type's colour.

import type { GraphKind, GraphSocket } from './api';
import { valueText } from './buildgraphdetails';
import type { Dir } from './buildgraphgestures';
import { kNodeW, kRowH, kTitleH, refText } from './buildgraphmodel';
import type { BuildGraphModel, GraphNode, SocketRef } from './buildgraphmodel';
import { h, fill } from './dom';

/** The palette: one group per category, an entry per kind (a click or a drag onto the graph adds it). */
export function renderPalette(el: HTMLElement, kinds: Iterable<GraphKind>, add: (kind: string) => void): void {
  const byCategory = new Map<string, GraphKind[]>();
  for (const k of kinds) {
    const list = byCategory.get(k.category) ?? [];
    list.push(k);
    byCategory.set(k.category, list);
  }
  fill(
    el,
    [...byCategory].map(([category, list]) =>
      h('div.bg-category', { dataset: { category } }, h('h4', {}, category), list.map((k) => paletteEntry(k, add))),
    ),
  );
}

function paletteEntry(k: GraphKind, add: (kind: string) => void): HTMLElement {
  const entry = h(
    'div.bg-kind',
    {
      title: `${k.id}${k.help ? `: ${k.help}` : ''}`,
      draggable: true,
      testid: `bg-palette-${k.id}`,
      dataset: { kind: k.id, search: `${k.niceName} ${k.id}`.toLowerCase(), category: k.category },
      onclick: () => add(k.id),
    },
    k.niceName,
  );
  entry.addEventListener('dragstart', (e) => e.dataTransfer?.setData('text/x-rigel-kind', k.id));
  return entry;
}

/** Shows the entries whose nice name or id holds every word of `search`, and their categories. */
export function filterPalette(el: HTMLElement, search: string): void {
  const words = search.toLowerCase().split(/\s+/).filter(Boolean);
  for (const cat of el.querySelectorAll<HTMLElement>('.bg-category')) {
    let any = false;
    for (const e of cat.querySelectorAll<HTMLElement>('.bg-kind')) {
      e.hidden = !words.every((w) => (e.dataset.search ?? '').includes(w));
      any ||= !e.hidden;
    }
    cat.hidden = !any;
  }
}

/** What a node's box does with the pointer: its title grabbed, the box pressed, a socket dragged. */
export interface NodeGestures {
  grab(el: HTMLElement, e: PointerEvent): void;
  press(): void;
  link(ref: SocketRef, dir: Dir): void;
}

/** A node's box: its title (name, type or value) and its sockets, inputs left and outputs right. */
export function nodeElement(model: BuildGraphModel, n: GraphNode, selected: boolean, on: NodeGestures): HTMLElement {
  const kind = model.kindOf(n);
  const sub = n.component ? (n.component.type ?? '') : n.kind.startsWith('constant:') ? valueText(n.value) : n.kind;
  const title = h(
    'div.bgnode-title',
    { testid: `bg-title-${n.id}` },
    h('span.bgnode-name', {}, model.title(n)),
    h('span.bgnode-sub', {}, sub),
  );
  const el = h(
    'div.bgnode',
    { dataset: { node: n.id, kind: n.kind, category: kind?.category ?? 'unknown' }, testid: `bg-node-${n.id}` },
    title,
    model.inputsOf(n).map((s, i) => portElement(model, n, s, i, 'in', on)),
    model.outputsOf(n).map((s, i) => portElement(model, n, s, i, 'out', on)),
  );
  el.style.left = `${n.x}px`;
  el.style.top = `${n.y}px`;
  el.style.width = `${kNodeW}px`;
  el.style.height = `${model.nodeHeight(n)}px`;
  el.classList.toggle('selected', selected);
  el.classList.toggle('unknown', !kind);
  title.addEventListener('pointerdown', (e) => {
    if (e.button !== 0) return;
    e.preventDefault();
    on.grab(el, e);
  });
  el.addEventListener('pointerdown', (e) => {
    if (e.button !== 0 || e.defaultPrevented) return;
    on.press();
  });
  return el;
}

function portElement(model: BuildGraphModel, n: GraphNode, s: GraphSocket, i: number, dir: Dir, on: NodeGestures): HTMLElement {
  const ref = { node: n.id, socket: s.name };
  const type = model.socketType(ref, dir);
  const linked = dir === 'in' ? !!model.linkInto(ref) : model.linksFrom(ref).length > 0;
  const dot = h('span.bg-sock', {
    testid: `bg-${dir}-${refText(ref)}`,
    title: `${s.name}: ${type ?? (s.type === '$variable' ? 'the variable’s type (pick a variable)' : s.type)}${s.help ? ` (${s.help})` : ''}`,
    dataset: { node: n.id, socket: s.name, dir },
  });
  dot.classList.toggle('exec', type === 'exec');
  dot.classList.toggle('linked', linked);
  dot.style.setProperty('--sock', model.colorOf(type));
  dot.addEventListener('animationend', () => dot.classList.remove('refused'));
  dot.addEventListener('pointerdown', (e) => {
    if (e.button !== 0) return;
    e.preventDefault();
    e.stopPropagation();
    on.link(ref, dir);
  });
  const label = h('span.bg-sock-label', {}, type === 'exec' && (s.name === 'exec' || s.name === 'then') ? '' : s.name);
  const row = h(`div.bg-port.${dir}`, { dataset: { node: n.id, socket: s.name, dir } }, dir === 'in' ? [dot, label] : [label, dot]);
  row.style.top = `${kTitleH + i * kRowH}px`;
  return row;
}
