// The definition the editor edits: a Rig node and component nodes, each
// hanging from one parent (or loose), with their guides, parameters and
// control looks, and its serialisation to and from the `.rig.json` form the
// definition routes take. No DOM and no server here (defeditor.ts is the
// view, the routes are api.ts's).
//
// Only what hangs from the Rig node is part of the definition (as in the
// seed: a node does nothing until it is attached). Geometry (<geo>) files
// are kept absolute here and written relative to the saved file's folder.

import type { ComponentJson, ComponentSchema, ParamSchema, RigJson } from './api';
import { isAbsolute, join, relative } from './paths';

export type Side = 'C' | 'L' | 'R';

export interface Guide {
  name: string;
  joint: string;
  translate: [number, number, number];
  /** What the editor does not edit (rotate, scale), kept as it came. */
  extra: Record<string, unknown>;
}

/** A <geo> line: a character file (absolute here, or relative to the saved file's folder). */
export interface GeoRef {
  file: string;
  name: string;
}

export interface ControlLook {
  shape: string;
  color: string;
  size: number | null;
}

export interface GNode {
  id: string;
  kind: 'rig' | 'component';
  x: number;
  y: number;
  /** The node this one hangs from (the Rig node or a component), or null. */
  parent: string | null;
  name: string;
  version: string;
  type: string;
  side: Side;
  rigId: string;
  attach: string;
  guides: Guide[];
  /** Only the parameters set; the others take the schema's default. */
  params: Record<string, unknown>;
  controls: Record<string, ControlLook>;
  /** Keys of the definition the editor does not edit (features), kept as they came. */
  extra: Record<string, unknown>;
  /** The Rig node's <geo> lines. */
  geometry: GeoRef[];
}

/** The id of the Rig node. */
export const kRig = 'rig';

/** A version 4 UUID (crypto.randomUUID needs a secure context; this does not). */
export function uuid4(): string {
  const b = new Uint8Array(16);
  crypto.getRandomValues(b);
  b[6] = (b[6]! & 0x0f) | 0x40;
  b[8] = (b[8]! & 0x3f) | 0x80;
  const x = Array.from(b, (v) => v.toString(16).padStart(2, '0')).join('');
  return `${x.slice(0, 8)}-${x.slice(8, 12)}-${x.slice(12, 16)}-${x.slice(16, 20)}-${x.slice(20)}`;
}

function newRigNode(): GNode {
  return {
    id: kRig, kind: 'rig', x: 16, y: 110, parent: null, name: 'rig', version: '1.0', type: '', side: 'C',
    rigId: '', attach: '', guides: [], params: {}, controls: {}, extra: {}, geometry: [],
  };
}

export class DefinitionModel {
  /** The component types (GET /api/components), by type. */
  schemas = new Map<string, ComponentSchema>();
  readonly nodes = new Map<string, GNode>();
  /** Node ids in the order they were added (the order children are written in). */
  order: string[] = [];
  /** True once the Rig node's geometry was set (by hand or by loading a definition). */
  geometrySet = false;
  private nextId = 1;

  constructor() {
    this.reset();
  }

  get rig(): GNode {
    return this.nodes.get(kRig)!;
  }

  /** A new, empty definition. */
  reset(): void {
    this.nodes.clear();
    this.nodes.set(kRig, newRigNode());
    this.order = [kRig];
    this.geometrySet = false;
  }

  /**
   * A new definition's geometry: `character` (the file the scene was opened
   * from), unless the geometry was set; returns whether it changed.
   */
  defaultGeometry(character: string | null | undefined): boolean {
    if (this.geometrySet || !character || this.rig.geometry.length) return false;
    this.rig.geometry = [{ file: character, name: '' }];
    return true;
  }

  /** Replaces the definition with a `.rig.json` one whose relative files are relative to `folder`. */
  load(def: RigJson, folder: string): void {
    const r = def.rig ?? {};
    this.nodes.clear();
    this.order = [];
    const rig = newRigNode();
    const { name, version, guiLocation, geometry, components, ...rest } = r;
    rig.name = name ?? 'rig';
    rig.version = version ?? '1.0';
    if (guiLocation) [rig.x, rig.y] = guiLocation;
    rig.extra = rest;
    rig.geometry = (geometry ?? []).map((g) => ({ file: folder && !isAbsolute(g.file) ? join(folder, g.file) : g.file, name: g.name ?? '' }));
    this.geometrySet = true;
    this.nodes.set(kRig, rig);
    this.order.push(kRig);
    // Components without a guiLocation are laid out as a tree, depth to the right.
    let row = 0;
    const add = (c: ComponentJson, parent: string, depth: number): void => {
      const node = this.componentFromJson(c, parent, depth, row++);
      this.nodes.set(node.id, node);
      this.order.push(node.id);
      for (const k of c.children ?? []) add(k, node.id, depth + 1);
    };
    for (const c of components ?? []) add(c, kRig, 1);
  }

  private componentFromJson(c: ComponentJson, parent: string, depth: number, row: number): GNode {
    const { type, name, side, version, rigId, attach, guiLocation: at, guides, controls, params, children: _children, ...more } = c;
    const id = `n${this.nextId++}`;
    const schema = this.schemas.get(type ?? '');
    return {
      id,
      kind: 'component',
      x: at ? at[0] : 190 + (depth - 1) * 172,
      y: at ? at[1] : 20 + row * 70,
      parent,
      name: name ?? type ?? id,
      version: version ?? '1.0',
      type: type ?? '',
      side: side === 'L' || side === 'R' ? side : 'C',
      rigId: rigId ?? uuid4(),
      attach: attach ?? '',
      guides: (guides ?? []).map((g, i) => {
        const { name: gname, joint, translate, ...gmore } = g;
        return { name: gname ?? schema?.guides.names[i] ?? '', joint: joint ?? '', translate: translate ?? [0, 0, 0], extra: gmore };
      }),
      params: { ...(params ?? {}) },
      controls: Object.fromEntries((controls ?? []).map((x) => [x.role, { shape: x.shape ?? '', color: x.color ?? '', size: x.size ?? null }])),
      extra: more,
      geometry: [],
    };
  }

  /**
   * A loose node (no parent, so not part of the definition) of component
   * `c`: what the build graph editor's details panel edits of a component
   * node, written back with `componentJson`.
   */
  looseComponent(c: ComponentJson): GNode {
    const node = this.componentFromJson(c, kRig, 1, 0);
    node.parent = null;
    this.nodes.set(node.id, node);
    this.order.push(node.id);
    return node;
  }

  /** A component node in the `.rig.json` form, without its children. */
  componentJson(n: GNode): ComponentJson {
    return this.componentToJson(n, false);
  }

  /** Adds a loose component node of a known type at (x, y) (by default the next free place); null for an unknown type. */
  addComponent(type: string, x?: number, y?: number): GNode | null {
    const schema = this.schemas.get(type);
    if (!schema) return null;
    const id = `n${this.nextId++}`;
    const count = this.order.length - 1;
    const sameType = [...this.nodes.values()].filter((n) => n.type === type).length;
    const guides: Guide[] = [];
    const n = Math.max(schema.guides.min, schema.guides.names.length);
    for (let i = 0; i < n; i++) guides.push({ name: schema.guides.names[i] ?? '', joint: '', translate: [0, 0, 0], extra: {} });
    const node: GNode = {
      id,
      kind: 'component',
      x: x ?? 190 + (count % 2) * 172,
      y: y ?? 20 + Math.floor(count / 2) * 78 + (count % 2) * 24,
      parent: null,
      name: sameType ? `${type}${sameType + 1}` : type,
      version: '1.0',
      type,
      side: 'C',
      rigId: uuid4(),
      attach: '',
      guides,
      params: {},
      controls: {},
      extra: {},
      geometry: [],
    };
    this.nodes.set(id, node);
    this.order.push(id);
    return node;
  }

  /** Removes a component node (its children come loose); returns whether it was part of the definition. */
  removeNode(id: string): boolean {
    if (id === kRig || !this.nodes.has(id)) return false;
    const wasAttached = this.attached(id);
    for (const n of this.nodes.values()) if (n.parent === id) n.parent = null;
    this.nodes.delete(id);
    this.order = this.order.filter((x) => x !== id);
    return wasAttached;
  }

  /** Why `child` cannot hang from `parent`, or null when it can. */
  linkProblem(parentId: string, childId: string): string | null {
    const parent = this.nodes.get(parentId);
    const child = this.nodes.get(childId);
    if (!parent || !child) return 'unknown node';
    if (child.kind === 'rig') return 'the Rig node cannot have a parent';
    if (parentId === childId) return `${child.name} cannot be its own parent`;
    const schema = this.schemas.get(child.type);
    if (schema?.rootOnly && parent.kind !== 'rig') {
      return `${child.name} (${child.type}) is root-only: it can only hang from the Rig node`;
    }
    if (schema?.needsParent && parent.kind === 'rig') {
      return `${child.name} (${child.type}) needs a parent component`;
    }
    const chain: string[] = [child.name];
    for (let p: GNode | undefined = parent; p; p = p.parent ? this.nodes.get(p.parent) : undefined) {
      chain.push(p.name);
      if (p.id === childId) return `cycle: ${chain.reverse().join(' → ')}`;
    }
    return null;
  }

  /** Hangs `child` from `parent` (its attach hook reset); returns why not, or null. */
  connect(parentId: string, childId: string): string | null {
    const problem = this.linkProblem(parentId, childId);
    if (problem) return problem;
    const child = this.nodes.get(childId)!;
    if (child.parent !== parentId) {
      child.parent = parentId;
      child.attach = '';
    }
    return null;
  }

  /** Takes a node off its parent; returns whether it was part of the definition. */
  detach(childId: string): boolean {
    const child = this.nodes.get(childId);
    if (!child || !child.parent) return false;
    const was = this.attached(childId);
    child.parent = null;
    return was;
  }

  /** True when the node hangs (through its parents) from the Rig node. */
  attached(id: string): boolean {
    for (let n = this.nodes.get(id); n; n = n.parent ? this.nodes.get(n.parent) : undefined) {
      if (n.kind === 'rig') return true;
    }
    return false;
  }

  children(id: string): GNode[] {
    return this.order.map((x) => this.nodes.get(x)!).filter((n) => n && n.parent === id);
  }

  /** The hook names of a component: `guide[i]` stands for each guide's name or joint. */
  hooksOf(n: GNode): string[] {
    const schema = this.schemas.get(n.type);
    if (!schema) return [];
    const out: string[] = [];
    for (const hook of schema.hooks) {
      if (hook === 'guide[i]') {
        n.guides.forEach((g, i) => out.push(g.name || g.joint || String(i)));
      } else {
        out.push(hook);
      }
    }
    return [...out, 'START', 'MIDDLE', 'END'];
  }

  /** Sets a parameter; its default is not written (the parameter is then unset). */
  static setParam(n: GNode, p: ParamSchema, v: unknown): void {
    if (JSON.stringify(v) === JSON.stringify(p.default)) delete n.params[p.name];
    else n.params[p.name] = v;
  }

  /** The id of the node named `name`, or null. */
  idOf(name: string): string | null {
    for (const n of this.nodes.values()) if (n.name === name) return n.id;
    return null;
  }

  /**
   * The definition in its `.rig.json` form (only what hangs from the Rig
   * node), its absolute geometry files made relative to `folder` (the
   * absolute folder of the file it is saved to; null: as they are).
   */
  toJson(folder: string | null): RigJson {
    const rig = this.rig;
    const round = (v: number): number => Math.round(v);
    const out: RigJson['rig'] = {
      name: rig.name,
      version: rig.version,
      guiLocation: [round(rig.x), round(rig.y)],
    };
    const geometry = rig.geometry
      .filter((g) => g.file.trim())
      .map((g) => {
        const file = g.file.trim();
        const o: { file: string; name?: string } = { file: folder && isAbsolute(file) ? relative(folder, file) : file };
        if (g.name.trim()) o.name = g.name.trim();
        return o;
      });
    if (geometry.length) out.geometry = geometry;
    Object.assign(out, rig.extra);
    out.components = this.children(kRig).map((n) => this.componentToJson(n));
    return { rig: out };
  }

  private componentToJson(n: GNode, children = true): ComponentJson {
    const schema = this.schemas.get(n.type);
    const c: ComponentJson = {
      type: n.type,
      name: n.name,
      side: n.side,
      version: n.version,
      rigId: n.rigId,
    };
    if (n.attach.trim()) c.attach = n.attach.trim();
    c.guiLocation = [Math.round(n.x), Math.round(n.y)];
    if (n.guides.length) {
      c.guides = n.guides.map((g) => {
        const o: Record<string, unknown> = {};
        if (g.name) o.name = g.name;
        if (g.joint.trim()) o.joint = g.joint.trim();
        if (g.translate.some((v) => v !== 0)) o.translate = g.translate;
        return { ...o, ...g.extra };
      });
    }
    const controls = Object.entries(n.controls)
      .filter(([, l]) => l.shape || l.color || l.size !== null)
      .map(([role, l]) => {
        const def = schema?.controls.find((x) => x.role === role);
        const o: { role: string; shape?: string; color?: string; size?: number } = { role, size: l.size ?? def?.size ?? 1 };
        if (l.shape) o.shape = l.shape;
        if (l.color) o.color = l.color;
        return o;
      });
    if (controls.length) c.controls = controls;
    if (Object.keys(n.params).length) c.params = { ...n.params };
    Object.assign(c, n.extra);
    const kids = children ? this.children(n.id) : [];
    if (kids.length) c.children = kids.map((k) => this.componentToJson(k));
    return c;
  }
}
