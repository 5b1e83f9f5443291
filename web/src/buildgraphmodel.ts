// The build graph the build-graph editor edits (docs/BUILD_GRAPH.md): its
// nodes (start, components, constants, variables' get and set, branches,
// functions), the links between their sockets, the graph's variables and
// the rig's settings, with the palette's node kinds and data types (GET
// /api/graph/palette), and its serialisation to and from the `.build.json`
// object the graph routes take. No DOM and no server here (buildgraph.ts is
// the view, the routes are api.ts's).
//
// Links follow the file's rules: an exec output feeds an exec input, a
// value one of the same type (an int may feed a number; `$variable` is the
// type of the node's variable); an input takes one link and so does an exec
// output, a new link replacing the old. What only compiling can tell (a
// node the chain never reaches, an input read before its node runs) is the
// server's to report. Keys of a node the editor does not know are kept as
// they came; geometry files are absolute here and written relative to the
// saved file's folder, as the definition editor's model does.

import type { BuildGraphJson, BuildGraphNodeJson, ComponentJson, ComponentSchema, GraphKind, GraphPaletteAnswer, GraphRigJson, GraphSocket, GraphType } from './api';
import type { GeoRef } from './defmodel';
import { uuid4 } from './defmodel';
import { isAbsolute, join, relative } from './paths';

/** The node boxes' layout (the view draws them so; free spots are found with it). */
export const kNodeW = 190;
export const kTitleH = 38;
export const kRowH = 20;
const kNodePad = 8;
const kGap = 30;

export const kStart = 'start';

export interface SocketRef {
  node: string;
  socket: string;
}

export interface GraphLink {
  from: SocketRef;
  to: SocketRef;
}

export interface GraphVariable {
  name: string;
  type: string;
  value: unknown;
  /** Keys the editor does not know, kept as they came. */
  extra: Record<string, unknown>;
}

export interface GraphNode {
  id: string;
  kind: string;
  x: number;
  y: number;
  /** component:TYPE: the component, in the `.rig.json` syntax (no children, no guiLocation). */
  component: ComponentJson | null;
  /** constant:TYPE: its value. */
  value: unknown;
  /** variable:get / :set: the variable's name ('' none). */
  variable: string;
  /** function:ID: the rigId of its call ('' made by the server from the rig's name and the node's id). */
  rigId: string;
  /** The values of inputs that are not linked (other kinds than components). */
  values: Record<string, unknown>;
  /** Keys the editor does not know, kept as they came. */
  extra: Record<string, unknown>;
}

export interface RigSettings {
  name: string;
  version: string;
  /** Absolute here (or as written when no folder was known), relative in the file. */
  geometry: GeoRef[];
  /** features, data and whatever else the rig's settings hold, kept as they came. */
  extra: Record<string, unknown>;
}

/** "NODE.SOCKET" (a node id may hold dots, a socket name none). */
export function refText(r: SocketRef): string {
  return `${r.node}.${r.socket}`;
}

/** The reference of "NODE.SOCKET", or null when it has no dot. */
export function parseRef(text: string): SocketRef | null {
  const dot = text.lastIndexOf('.');
  if (dot <= 0 || dot === text.length - 1) return null;
  return { node: text.slice(0, dot), socket: text.slice(dot + 1) };
}

/** One key per link: "FROM->TO". */
export function linkKey(l: GraphLink): string {
  return `${refText(l.from)}->${refText(l.to)}`;
}

/** Whether a value of type `from` may flow into an input of type `to`: the same type, or an int into a number. */
export function canLink(from: string, to: string): boolean {
  return from === to || (from === 'int' && to === 'number');
}

/** The zero of a value type: false, 0, '', [0, 0, 0]. */
export function zeroOf(type: string): unknown {
  if (type.startsWith('list:')) return [];
  if (type === 'component') return null;
  switch (type) {
    case 'bool':
      return false;
    case 'int':
    case 'number':
      return 0;
    case 'vector':
      return [0, 0, 0];
    default:
      return '';
  }
}

/** A component's name with its side, as the build names it ("arm_L"). */
export function fullName(c: ComponentJson): string {
  const name = c.name ?? c.type ?? '';
  return c.side && c.side !== 'C' ? `${name}_${c.side}` : name;
}

/** The part of a kind id after its prefix: "component:limb" → "limb". */
function kindArg(kind: string): string {
  const colon = kind.indexOf(':');
  return colon < 0 ? kind : kind.slice(colon + 1);
}

/** A name for ids: letters, digits and underscores, not starting with a digit. */
function idBase(text: string): string {
  const last = text.split(/[.:]/).filter(Boolean).pop() ?? 'node';
  const clean = last.replace(/[^A-Za-z0-9_]/g, '_');
  return /^[A-Za-z_]/.test(clean) ? clean : `n_${clean}`;
}

function clone<T>(v: T): T {
  return v === undefined ? v : (JSON.parse(JSON.stringify(v)) as T);
}

export class BuildGraphModel {
  /** The palette's data types and node kinds, by name and id. */
  types = new Map<string, GraphType>();
  kinds = new Map<string, GraphKind>();
  /** The component types (GET /api/components): a new component node's guides. */
  schemas = new Map<string, ComponentSchema>();

  rig: RigSettings = { name: 'rig', version: '1.0', geometry: [], extra: {} };
  variables: GraphVariable[] = [];
  /** In the file's order. */
  readonly nodes = new Map<string, GraphNode>();
  links: GraphLink[] = [];
  /** True once the rig's geometry was set (by hand or by loading a graph). */
  geometrySet = false;
  /** Keys of the file's `buildGraph` object the editor does not know, kept. */
  private extra: Record<string, unknown> = {};

  constructor() {
    this.reset();
  }

  setPalette(p: GraphPaletteAnswer): void {
    this.types = new Map(p.types.map((t) => [t.name, t]));
    this.kinds = new Map(p.kinds.map((k) => [k.id, k]));
  }

  /** The types a constant or a variable can hold. */
  valueTypes(): GraphType[] {
    return [...this.types.values()].filter((t) => t.value);
  }

  /** The types a variable can hold: the value types, their lists, component. */
  variableTypes(): GraphType[] {
    return [...this.types.values()].filter((t) => t.variable ?? t.value);
  }

  /** A new graph: a `start` node, no variables. */
  reset(): void {
    this.rig = { name: 'rig', version: '1.0', geometry: [], extra: {} };
    this.variables = [];
    this.nodes.clear();
    this.links = [];
    this.extra = {};
    this.geometrySet = false;
    this.nodes.set(kStart, this.blank(kStart, kStart, 20, 20));
  }

  /** A new graph's geometry: `character` unless the geometry was set; returns whether it changed. */
  defaultGeometry(character: string | null | undefined): boolean {
    if (this.geometrySet || !character || this.rig.geometry.length) return false;
    this.rig.geometry = [{ file: character, name: '' }];
    return true;
  }

  private blank(id: string, kind: string, x: number, y: number): GraphNode {
    return { id, kind, x, y, component: null, value: undefined, variable: '', rigId: '', values: {}, extra: {} };
  }

  // ------------------------------------------------------------------ sockets

  kindOf(n: GraphNode): GraphKind | undefined {
    return this.kinds.get(n.kind);
  }

  /** The node's inputs: its kind's, or (a kind the palette lacks) the sockets its links name. */
  inputsOf(n: GraphNode): GraphSocket[] {
    return this.kindOf(n)?.inputs ?? this.linkedSockets(n, 'to');
  }

  outputsOf(n: GraphNode): GraphSocket[] {
    return this.kindOf(n)?.outputs ?? this.linkedSockets(n, 'from');
  }

  private linkedSockets(n: GraphNode, end: 'from' | 'to'): GraphSocket[] {
    const names = [...new Set(this.links.filter((l) => l[end].node === n.id).map((l) => l[end].socket))];
    return names.map((name) => ({ name, type: '?', help: '' }));
  }

  /** The socket `ref` names (an input when `dir` is 'in'), or undefined. */
  socket(ref: SocketRef, dir: 'in' | 'out'): GraphSocket | undefined {
    const n = this.nodes.get(ref.node);
    if (!n) return undefined;
    return (dir === 'in' ? this.inputsOf(n) : this.outputsOf(n)).find((s) => s.name === ref.socket);
  }

  /** The data type of a socket, `$variable` resolved (null: the node has no variable the graph holds). */
  socketType(ref: SocketRef, dir: 'in' | 'out'): string | null {
    const s = this.socket(ref, dir);
    if (!s) return null;
    if (s.type !== '$variable') return s.type;
    const n = this.nodes.get(ref.node);
    return this.variables.find((v) => v.name === n?.variable)?.type ?? null;
  }

  /** The colour of a type ('#888888' for one the palette lacks). */
  colorOf(type: string | null): string {
    return (type && this.types.get(type)?.color) || '#888888';
  }

  /** The link into input `ref`, if any. */
  linkInto(ref: SocketRef): GraphLink | undefined {
    return this.links.find((l) => l.to.node === ref.node && l.to.socket === ref.socket);
  }

  linksFrom(ref: SocketRef): GraphLink[] {
    return this.links.filter((l) => l.from.node === ref.node && l.from.socket === ref.socket);
  }

  // -------------------------------------------------------------------- nodes

  /** The node's title: a component's full name, "Get side", the kind's nice name. */
  title(n: GraphNode): string {
    if (n.component) return fullName(n.component);
    const nice = this.kindOf(n)?.niceName ?? n.kind;
    if (n.kind === 'variable:get' || n.kind === 'variable:set') return `${nice} ${n.variable || '?'}`;
    return nice;
  }

  /** The id of the node with id or title `text`, or null. */
  idOf(text: string): string | null {
    if (this.nodes.has(text)) return text;
    for (const n of this.nodes.values()) if (this.title(n) === text) return n.id;
    return null;
  }

  /** The node box's height (its title, then one row per input or output, side by side). */
  nodeHeight(n: GraphNode): number {
    return kTitleH + Math.max(this.inputsOf(n).length, this.outputsOf(n).length, 1) * kRowH + kNodePad;
  }

  /**
   * A place for a new node of height `height` that overlaps none: the first
   * free one row by row, `columns` columns wide (the graph's visible width).
   */
  freeSpot(height: number, columns = 3): [number, number] {
    const boxes = [...this.nodes.values()].map((n) => [n.x, n.y, n.x + kNodeW, n.y + this.nodeHeight(n)] as const);
    const free = (x: number, y: number): boolean =>
      boxes.every(([x0, y0, x1, y1]) => x + kNodeW + kGap <= x0 || x >= x1 + kGap || y + height + kGap <= y0 || y >= y1 + kGap);
    for (let y = 20; y < 20000; y += kRowH) {
      for (let c = 0; c < Math.max(1, columns); c++) {
        const x = 20 + c * (kNodeW + 2 * kGap);
        if (free(x, y)) return [x, y];
      }
    }
    return [20, 20];
  }

  /** An id for a new node: `base`, else base_2, base_3... */
  private newId(base: string): string {
    if (!this.nodes.has(base)) return base;
    for (let k = 2; ; k++) if (!this.nodes.has(`${base}_${k}`)) return `${base}_${k}`;
  }

  /** A new component of `type`: a free name, a rigId, its schema's guides. */
  private newComponent(type: string): ComponentJson {
    const schema = this.schemas.get(type);
    const taken = new Set([...this.nodes.values()].filter((n) => n.component).map((n) => n.component!.name));
    let name = type;
    for (let k = 2; taken.has(name); k++) name = `${type}${k}`;
    const c: ComponentJson = { type, name, side: 'C', version: '1.0', rigId: uuid4() };
    const count = schema ? Math.max(schema.guides.min, schema.guides.names.length) : 0;
    if (count) c.guides = Array.from({ length: count }, (_, i) => (schema!.guides.names[i] ? { name: schema!.guides.names[i]! } : {}));
    return c;
  }

  /**
   * Adds a node of a palette kind at (x, y) (by default a free spot);
   * null for a kind the palette lacks or a second `start`.
   */
  addNode(kind: string, x?: number, y?: number, columns = 3): GraphNode | null {
    const k = this.kinds.get(kind);
    if (!k || (kind === kStart && this.nodes.has(kStart))) return null;
    const component = kind.startsWith('component:') ? this.newComponent(kindArg(kind)) : null;
    const id = this.newId(kind === kStart ? kStart : idBase(component?.name ?? kindArg(kind)));
    const n = this.blank(id, kind, 0, 0);
    n.component = component;
    if (kind.startsWith('constant:')) n.value = zeroOf(kindArg(kind));
    if (kind.startsWith('variable:')) n.variable = this.variables[0]?.name ?? '';
    if (x === undefined || y === undefined) [x, y] = this.freeSpot(this.heightOf(k), columns);
    n.x = Math.max(0, Math.round(x));
    n.y = Math.max(0, Math.round(y));
    this.nodes.set(id, n);
    return n;
  }

  private heightOf(k: GraphKind): number {
    return kTitleH + Math.max(k.inputs.length, k.outputs.length, 1) * kRowH + kNodePad;
  }

  /** Removes a node and its links (never `start`); returns whether it was there. */
  removeNode(id: string): boolean {
    if (id === kStart || !this.nodes.has(id)) return false;
    this.nodes.delete(id);
    this.links = this.links.filter((l) => l.from.node !== id && l.to.node !== id);
    return true;
  }

  moveNode(id: string, x: number, y: number): void {
    const n = this.nodes.get(id);
    if (!n) return;
    n.x = Math.max(0, Math.round(x));
    n.y = Math.max(0, Math.round(y));
  }

  // -------------------------------------------------------------------- links

  /** Why output `from` cannot feed input `to`, or null when it can. */
  linkProblem(from: SocketRef, to: SocketRef): string | null {
    const why = this.whyNot(from, to);
    return why ? `link '${refText(from)}' -> '${refText(to)}': ${why}` : null;
  }

  private whyNot(from: SocketRef, to: SocketRef): string | null {
    const a = this.nodes.get(from.node);
    const b = this.nodes.get(to.node);
    if (!a) return `no node '${from.node}'`;
    if (!b) return `no node '${to.node}'`;
    if (!this.socket(from, 'out')) return `'${from.node}' has no output '${from.socket}'`;
    if (!this.socket(to, 'in')) return `'${to.node}' has no input '${to.socket}'`;
    if (a.id === b.id) return 'a node cannot feed itself';
    const ft = this.socketType(from, 'out');
    const tt = this.socketType(to, 'in');
    if (ft === null) return `'${from.node}' reads no variable of the graph: pick one first`;
    if (tt === null) return `'${to.node}' writes no variable of the graph: pick one first`;
    if ((ft === 'exec') !== (tt === 'exec')) {
      return ft === 'exec' ? `an exec output runs a node: it cannot feed a ${tt} input` : `a ${ft} output cannot feed an exec input`;
    }
    if (!canLink(ft, tt)) return `a ${ft} output cannot feed a ${tt} input`;
    if (ft !== 'exec' && this.runsInBuild(a) && !this.runsInBuild(b) && b.kind !== 'variable:set') {
      return `a function's output is made while building: only a function node that runs in the build (or a Set) takes it, not ${b.kind}`;
    }
    const cycle = this.cycle(from, to, ft === 'exec');
    return cycle ? `cycle: ${cycle.join(' → ')}` : null;
  }

  /** Whether `n` is a function node that runs as a build step (not a pure one, which runs while compiling). */
  private runsInBuild(n: GraphNode): boolean {
    return n.kind.startsWith('function:') && (this.kindOf(n)?.inputs.some((s) => s.type === 'exec') ?? true);
  }

  /**
   * The nodes of the cycle a link from `from` to `to` would close among the
   * links of its class (exec or data), the links it replaces left out; null
   * when none.
   */
  private cycle(from: SocketRef, to: SocketRef, exec: boolean): string[] | null {
    const isExec = (l: GraphLink): boolean => this.socketType(l.from, 'out') === 'exec';
    const kept = this.links.filter(
      (l) => isExec(l) === exec && !(l.to.node === to.node && l.to.socket === to.socket) && !(exec && l.from.node === from.node && l.from.socket === from.socket),
    );
    // Depth first from `to`'s node along the links: reaching `from`'s node closes a cycle.
    const path: string[] = [];
    const seen = new Set<string>();
    const walk = (id: string): boolean => {
      path.push(id);
      if (id === from.node) return true;
      if (!seen.has(id)) {
        seen.add(id);
        for (const l of kept) if (l.from.node === id && walk(l.to.node)) return true;
      }
      path.pop();
      return false;
    };
    return walk(to.node) ? [from.node, ...path] : null;
  }

  /**
   * Links output `from` to input `to`: the input's old link goes, and an
   * exec output's old link; returns why not, or the links it replaced.
   */
  connect(from: SocketRef, to: SocketRef): { problem: string } | { replaced: GraphLink[] } {
    const problem = this.linkProblem(from, to);
    if (problem) return { problem };
    const exec = this.socketType(from, 'out') === 'exec';
    const replaced = this.links.filter(
      (l) => (l.to.node === to.node && l.to.socket === to.socket) || (exec && l.from.node === from.node && l.from.socket === from.socket),
    );
    this.links = this.links.filter((l) => !replaced.includes(l));
    this.links.push({ from: { ...from }, to: { ...to } });
    return { replaced };
  }

  /** Removes the link with key `key` (linkKey); returns whether it was there. */
  disconnect(key: string): boolean {
    const before = this.links.length;
    this.links = this.links.filter((l) => linkKey(l) !== key);
    return this.links.length !== before;
  }

  // ------------------------------------------------------------------- values

  /** The value an unlinked input of a node other than a component takes: its own, the kind's default, or its type's zero. */
  inputValue(n: GraphNode, socket: string): unknown {
    if (socket in n.values) return n.values[socket];
    const s = this.inputsOf(n).find((x) => x.name === socket);
    if (s?.default !== undefined) return s.default;
    return zeroOf(this.socketType({ node: n.id, socket }, 'in') ?? '');
  }

  setInputValue(n: GraphNode, socket: string, value: unknown): void {
    n.values[socket] = value;
  }

  // ---------------------------------------------------------------- variables

  /** Why a variable named `name` cannot be added (or renamed to), or null. */
  variableProblem(name: string, except = ''): string | null {
    if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(name)) return `'${name}' is not a variable name (letters, digits, _)`;
    if (name !== except && this.variables.some((v) => v.name === name)) return `the graph has a variable '${name}' already`;
    return null;
  }

  addVariable(name: string, type: string, value: unknown = zeroOf(type)): string | null {
    const t = this.types.get(type);
    const problem = this.variableProblem(name) ?? ((t?.variable ?? t?.value) ? null : `a variable cannot hold a ${type}`);
    if (problem) return problem;
    this.variables.push({ name, type, value, extra: {} });
    return null;
  }

  /** Renames a variable and the get and set nodes that name it. */
  renameVariable(from: string, to: string): string | null {
    const v = this.variables.find((x) => x.name === from);
    if (!v) return `no variable '${from}'`;
    const problem = this.variableProblem(to, from);
    if (problem) return problem;
    v.name = to;
    for (const n of this.nodes.values()) if (n.variable === from) n.variable = to;
    return null;
  }

  /** Gives a variable another type (its value becomes the type's zero). */
  setVariableType(name: string, type: string): void {
    const v = this.variables.find((x) => x.name === name);
    if (!v || v.type === type) return;
    v.type = type;
    v.value = zeroOf(type);
  }

  /** Removes a variable; get and set nodes that name it keep the name (validation reports them). */
  removeVariable(name: string): void {
    this.variables = this.variables.filter((v) => v.name !== name);
  }

  // ------------------------------------------------------------------- files

  /** Replaces the graph with a `.build.json` object whose relative files are relative to `folder`. */
  load(file: BuildGraphJson | BuildGraphJson['buildGraph'], folder: string): void {
    const g = ('buildGraph' in file ? file.buildGraph : file) as BuildGraphJson['buildGraph'];
    const { format: _format, rig, variables, nodes, links, ...extra } = g;
    this.extra = extra;
    const { name, version, geometry, ...rigExtra }: GraphRigJson = rig ?? {};
    this.rig = {
      name: name ?? 'rig',
      version: version ?? '1.0',
      geometry: (geometry ?? []).map((x) => ({ file: folder && !isAbsolute(x.file) ? join(folder, x.file) : x.file, name: x.name ?? '' })),
      extra: rigExtra,
    };
    this.geometrySet = true;
    this.variables = (variables ?? []).map(({ name: vn, type, value, ...more }) => ({ name: vn, type, value, extra: more }));
    this.nodes.clear();
    (nodes ?? []).forEach((n, i) => {
      const node = this.nodeFromJson(n, i);
      this.nodes.set(node.id, node);
    });
    this.links = [];
    for (const l of links ?? []) {
      const from = parseRef(l.from);
      const to = parseRef(l.to);
      if (from && to) this.links.push({ from, to });
    }
  }

  private nodeFromJson(j: BuildGraphNodeJson, index: number): GraphNode {
    const { id, kind, position, component, value, values, variable, rigId, ...extra } = j;
    const n = this.blank(id, kind, 0, 0);
    // Nodes without a place: a grid, four to a row.
    [n.x, n.y] = position ?? [20 + (index % 4) * (kNodeW + 2 * kGap), 20 + Math.floor(index / 4) * 220];
    if (component) {
      const { guiLocation: _gui, children: _children, ...c } = clone(component);
      n.component = c;
    }
    n.value = clone(value);
    n.values = clone(values ?? {});
    n.variable = variable ?? '';
    n.rigId = rigId ?? '';
    n.extra = extra;
    return n;
  }

  /**
   * The graph as a `.build.json` object, its absolute geometry files made
   * relative to `folder` (the absolute folder of the file it is saved to;
   * null: as they are).
   */
  toJson(folder: string | null): BuildGraphJson {
    const geometry = this.rig.geometry
      .filter((x) => x.file.trim())
      .map((x) => {
        const file = x.file.trim();
        const o: { file: string; name?: string } = { file: folder && isAbsolute(file) ? relative(folder, file) : file };
        if (x.name.trim()) o.name = x.name.trim();
        return o;
      });
    const rig: GraphRigJson = { name: this.rig.name, version: this.rig.version };
    if (geometry.length) rig.geometry = geometry;
    Object.assign(rig, this.rig.extra);
    const g: BuildGraphJson['buildGraph'] = { format: 1, rig, nodes: [], links: [] };
    if (this.variables.length) g.variables = this.variables.map((v) => ({ name: v.name, type: v.type, value: clone(v.value), ...v.extra }));
    g.nodes = [...this.nodes.values()].map((n) => this.nodeToJson(n));
    g.links = this.links.map((l) => ({ from: refText(l.from), to: refText(l.to) }));
    return { buildGraph: { ...g, ...this.extra } };
  }

  private nodeToJson(n: GraphNode): BuildGraphNodeJson {
    const j: BuildGraphNodeJson = { id: n.id, kind: n.kind, position: [Math.round(n.x), Math.round(n.y)] };
    if (n.variable) j.variable = n.variable;
    if (n.rigId) j.rigId = n.rigId;
    if (n.component) j.component = clone(n.component);
    if (n.value !== undefined) j.value = clone(n.value);
    if (Object.keys(n.values).length) j.values = clone(n.values);
    return { ...j, ...n.extra };
  }
}
