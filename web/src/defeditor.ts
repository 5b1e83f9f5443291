// The definition editor (seed 002 §4.3.2, the Node Editor): a palette of the
// component types from GET /api/components, components as nodes of a graph
// hanging from one Rig node, parent -> child links drawn by dragging from a
// node's output port to another node's input, and a details panel generated
// from the selected component's schema.
//
// Only what hangs from the Rig node is part of the definition (as in the
// seed: a node does nothing until it is attached). Every change is validated
// (POST /api/definition/validate) and, with "Live build" on, built into the
// scene (POST /api/definition/build); the panel shows the build's outcome,
// not only the validation's. "Save" writes the file (POST
// /api/definition/save). "Open" loads the definition a rig of the scene was
// built from (GET /api/definition), geometry (<geo>) and all; the geometry
// of a new definition is the scene's character. Geometry files are kept
// absolute here and written relative to the saved file's folder.

import type { App } from './app';
import { ApiError } from './api';
import type { ComponentSchema, ParamSchema } from './api';
import { h, fill, typingTarget } from './dom';
import { dirname, isAbsolute, join, relative } from './paths';
import { run } from './status';

const kShapes = [
  'circle', 'square', 'cube', 'sphere', 'diamond', 'cross', 'arrow', 'doubleArrow',
  'fourArrow', 'fourArrowCircle', 'locator', 'pin', 'triangle',
];
const kNodeW = 150;
const kNodeH = 56;

type Side = 'C' | 'L' | 'R';

interface Guide {
  name: string;
  joint: string;
  translate: [number, number, number];
  /** What the editor does not edit (rotate, scale), kept as it came. */
  extra: Record<string, unknown>;
}

/** A <geo> line: a character file (absolute here, or relative to the saved file's folder). */
interface GeoRef {
  file: string;
  name: string;
}

/** The `.rig.json` form of a component, as GET /api/definition gives it. */
interface ComponentJson {
  type?: string;
  name?: string;
  side?: string;
  version?: string;
  rigId?: string;
  attach?: string;
  guiLocation?: [number, number];
  guides?: { name?: string; joint?: string; translate?: [number, number, number]; [k: string]: unknown }[];
  controls?: { role: string; shape?: string; color?: string; size?: number }[];
  params?: Record<string, unknown>;
  children?: ComponentJson[];
  [k: string]: unknown;
}

interface RigJson {
  rig: {
    name?: string;
    version?: string;
    guiLocation?: [number, number];
    geometry?: { file: string; name?: string }[];
    components?: ComponentJson[];
    [k: string]: unknown;
  };
}

/** The outcome shown under the graph: validation, then (live) the build's. */
type BuildState = 'none' | 'pending' | 'built' | 'failed';

interface ControlLook {
  shape: string;
  color: string;
  size: number | null;
}

interface GNode {
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

export interface Problem {
  where: string;
  message: string;
}

/** A version 4 UUID (crypto.randomUUID needs a secure context; this does not). */
export function uuid4(): string {
  const b = new Uint8Array(16);
  crypto.getRandomValues(b);
  b[6] = (b[6]! & 0x0f) | 0x40;
  b[8] = (b[8]! & 0x3f) | 0x80;
  const x = Array.from(b, (v) => v.toString(16).padStart(2, '0')).join('');
  return `${x.slice(0, 8)}-${x.slice(8, 12)}-${x.slice(12, 16)}-${x.slice(16, 20)}-${x.slice(20)}`;
}

export class DefinitionEditor {
  schemas = new Map<string, ComponentSchema>();
  readonly nodes = new Map<string, GNode>();
  private order: string[] = [];
  private selected: string | null = 'rig';
  private selectedLink: string | null = null; // the child's id
  private nextId = 1;
  private buildTimer: number | null = null;
  private building: Promise<void> | null = null;
  private rebuildAgain = false;
  problems: Problem[] = [];
  /** Builds sent (live or by the button) and their outcome, for tests. */
  readonly builds: { ok: boolean; rig?: string; error?: string }[] = [];
  private valid: boolean | null = null;
  private buildState: BuildState = 'none';
  private buildError = '';
  /** True once the Rig node's geometry was set (by hand or by opening a definition). */
  private geometrySet = false;

  private readonly palette: HTMLElement;
  private readonly graph: HTMLElement;
  private readonly svg: SVGSVGElement;
  private readonly tempPath: SVGPathElement;
  private readonly details: HTMLElement;
  private readonly problemsEl: HTMLElement;
  private readonly live: HTMLInputElement;
  private readonly savePath: HTMLInputElement;
  private readonly jointList: HTMLDataListElement;
  private readonly openSelect: HTMLSelectElement;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.nodes.set('rig', this.newRigNode());
    this.order.push('rig');
    this.palette = h('div.palette', { testid: 'palette' });
    this.graph = h('div.graph', { tabIndex: 0, testid: 'graph' });
    this.svg = document.createElementNS('http://www.w3.org/2000/svg', 'svg');
    this.svg.classList.add('links');
    this.tempPath = document.createElementNS('http://www.w3.org/2000/svg', 'path');
    this.tempPath.classList.add('temp-link');
    this.details = h('div.def-details', { testid: 'def-details' });
    this.problemsEl = h('div.problems', { testid: 'def-problems' });
    this.live = h('input', { type: 'checkbox', checked: true, testid: 'def-live' });
    this.savePath = h('input', { type: 'text', placeholder: 'rigs/my_rig.rig.xml', testid: 'def-save-path' });
    this.jointList = h('datalist', { id: 'joint-names' });
    this.openSelect = h('select', { testid: 'def-open-rig', title: 'A rig of the scene' });

    this.graph.addEventListener('dragover', (e) => e.preventDefault());
    this.graph.addEventListener('drop', (e) => {
      e.preventDefault();
      const type = e.dataTransfer?.getData('text/x-rigel-component');
      if (!type) return;
      const r = this.graph.getBoundingClientRect();
      this.addComponent(type, e.clientX - r.left + this.graph.scrollLeft - kNodeW / 2, e.clientY - r.top + this.graph.scrollTop - 12);
    });
    this.graph.addEventListener('pointerdown', (e) => {
      if (e.target === this.graph || e.target === this.svg) {
        this.selectedLink = null;
        this.renderGraph();
      }
    });
    this.graph.addEventListener('keydown', (e) => {
      if (typingTarget(e.target)) return;
      if (e.key === 'Delete' || e.key === 'Backspace') {
        e.preventDefault();
        if (this.selectedLink) this.detach(this.selectedLink);
        else if (this.selected && this.selected !== 'rig') this.removeNode(this.selected);
      }
    });

    fill(
      el,
      h(
        'div.panel-head',
        {},
        h('h2', {}, 'Definition Editor'),
        h('button.small', { title: 'Start a new definition', testid: 'def-new', onclick: () => this.reset() }, 'New'),
        this.openSelect,
        h(
          'button.small',
          {
            title: 'Open the definition the selected rig was built from',
            testid: 'def-open',
            onclick: () => {
              if (this.openSelect.value) run(this.open(this.openSelect.value));
              else this.app.status.info('Open: the scene has no rig');
            },
          },
          'Open',
        ),
      ),
      h('div.hint', {}, 'Click or drag a component type into the graph; drag from a node’s right port to another node to parent it. Delete removes the selected node or link.'),
      this.palette,
      this.graph,
      h(
        'div.button-row',
        {},
        h('label.toggle', { title: 'Build the rig in the scene at every change' }, this.live, 'Live build'),
        h('button', { testid: 'def-validate', onclick: () => run(this.validate()) }, 'Validate'),
        h('button.primary', { testid: 'def-build', onclick: () => run(this.build()) }, 'Build'),
      ),
      h('div.form-row', {}, this.savePath, h('button', { testid: 'def-save', onclick: () => run(this.save()) }, 'Save')),
      this.problemsEl,
      this.details,
      this.jointList,
    );
    this.graph.append(this.svg);
    this.svg.append(this.tempPath);
    app.on('nodes', () => this.fillJoints());
    app.on('rigs', () => this.fillRigs());
    app.on('scene', () => this.defaultGeometry());
    this.renderAll();
  }

  async loadSchemas(): Promise<void> {
    const a = await this.app.api.get<{ components: ComponentSchema[] }>('/api/components');
    this.schemas = new Map(a.components.map((c) => [c.type, c]));
    fill(
      this.palette,
      a.components.map((c) => {
        const chip = h(
          'div.chip',
          {
            title: c.help + (c.rootOnly ? ' (root only)' : '') + (c.needsParent ? ' (needs a parent)' : ''),
            draggable: true,
            testid: `palette-${c.type}`,
            onclick: () => this.addComponent(c.type),
          },
          c.type,
        );
        chip.addEventListener('dragstart', (e) => e.dataTransfer?.setData('text/x-rigel-component', c.type));
        return chip;
      }),
    );
  }

  private fillRigs(): void {
    const names = this.app.rigs.map((r) => r.name);
    const current = this.openSelect.value;
    if (JSON.stringify(names) === JSON.stringify([...this.openSelect.options].map((o) => o.value))) return;
    fill(
      this.openSelect,
      names.length ? names.map((n) => h('option', { value: n, selected: n === current }, n)) : h('option', { value: '' }, '(no rig)'),
    );
  }

  /** A new definition's geometry: the character the scene was opened from. */
  private defaultGeometry(): void {
    const character = this.app.scene?.character;
    const rig = this.nodes.get('rig')!;
    if (this.geometrySet || !character || rig.geometry.length) return;
    rig.geometry = [{ file: character, name: '' }];
    if (this.selected === 'rig') this.renderDetails();
  }

  /** True when no build or validation is waiting or running (for tests). */
  idle(): boolean {
    return this.buildTimer === null && this.building === null;
  }

  private fillJoints(): void {
    const joints = (this.app.nodes?.nodes ?? []).filter((n) => n.type === 'joint').map((n) => n.name);
    fill(
      this.jointList,
      joints.map((j) => h('option', { value: j })),
    );
  }

  // ------------------------------------------------------------------ model

  private newRigNode(): GNode {
    return {
      id: 'rig', kind: 'rig', x: 16, y: 110, parent: null, name: 'rig', version: '1.0', type: '', side: 'C',
      rigId: '', attach: '', guides: [], params: {}, controls: {}, extra: {}, geometry: [],
    };
  }

  reset(): void {
    this.nodes.clear();
    this.nodes.set('rig', this.newRigNode());
    this.order = ['rig'];
    this.selected = 'rig';
    this.selectedLink = null;
    this.problems = [];
    this.valid = null;
    this.buildState = 'none';
    this.geometrySet = false;
    this.defaultGeometry();
    this.renderAll();
    this.renderProblems();
  }

  /** Opens the definition rig `name` of the scene was built from. */
  async open(name: string): Promise<void> {
    const a = await this.app.api.get<{ rig: string; path: string; definition: RigJson }>(`/api/definition?rig=${encodeURIComponent(name)}`);
    // The definition's relative files are relative to its folder.
    const root = this.app.scene?.root ?? '';
    const file = a.path ? (isAbsolute(a.path) || !root ? a.path : join(root, a.path)) : '';
    this.load(a.definition, file ? dirname(file) : root);
    if (file && root && file.startsWith(`${root.replace(/\/$/, '')}/`)) this.savePath.value = relative(root, file);
    this.app.status.info(`Opened the definition of ${a.rig}${a.path ? ` (${a.path})` : ''}`);
  }

  /** Replaces the graph with a `.rig.json` definition whose relative files are relative to `folder`. */
  load(def: RigJson, folder: string): void {
    const r = def.rig ?? {};
    this.nodes.clear();
    this.order = [];
    const rig = this.newRigNode();
    const { name, version, guiLocation, geometry, components, ...rest } = r;
    rig.name = name ?? 'rig';
    rig.version = version ?? '1.0';
    if (guiLocation) [rig.x, rig.y] = guiLocation;
    rig.extra = rest;
    rig.geometry = (geometry ?? []).map((g) => ({ file: folder && !isAbsolute(g.file) ? join(folder, g.file) : g.file, name: g.name ?? '' }));
    this.geometrySet = true;
    this.nodes.set('rig', rig);
    this.order.push('rig');
    // Components without a guiLocation are laid out as a tree, depth to the right.
    let row = 0;
    const add = (c: ComponentJson, parent: string, depth: number): void => {
      const { type, name: cname, side, version: cversion, rigId, attach, guiLocation: at, guides, controls, params, children, ...more } = c;
      const id = `n${this.nextId++}`;
      const schema = this.schemas.get(type ?? '');
      const node: GNode = {
        id,
        kind: 'component',
        x: at ? at[0] : 190 + (depth - 1) * 172,
        y: at ? at[1] : 20 + row * 70,
        parent,
        name: cname ?? type ?? id,
        version: cversion ?? '1.0',
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
      row++;
      this.nodes.set(id, node);
      this.order.push(id);
      for (const k of children ?? []) add(k, id, depth + 1);
    };
    for (const c of components ?? []) add(c, 'rig', 1);
    this.selected = 'rig';
    this.selectedLink = null;
    this.problems = [];
    this.valid = null;
    this.buildState = 'none';
    this.renderAll();
    this.renderProblems();
  }

  /** Adds a component node (unattached); returns its id. */
  addComponent(type: string, x?: number, y?: number): string | null {
    const schema = this.schemas.get(type);
    if (!schema) {
      this.app.status.error(`Unknown component type ${type}`);
      return null;
    }
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
    this.selected = id;
    this.selectedLink = null;
    this.renderAll();
    this.app.status.info(`Added a ${type} node; connect it to build it`);
    return id;
  }

  removeNode(id: string): void {
    if (id === 'rig') return;
    for (const n of this.nodes.values()) if (n.parent === id) n.parent = null;
    const wasAttached = this.attached(id);
    this.nodes.delete(id);
    this.order = this.order.filter((x) => x !== id);
    if (this.selected === id) this.selected = 'rig';
    this.renderAll();
    if (wasAttached) this.changed();
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

  connect(parentId: string, childId: string): boolean {
    const problem = this.linkProblem(parentId, childId);
    const parent = this.nodes.get(parentId);
    const child = this.nodes.get(childId);
    if (problem || !parent || !child) {
      this.app.status.error(`Link refused: ${problem ?? 'unknown node'}`);
      return false;
    }
    if (child.parent === parentId) return true;
    child.parent = parentId;
    child.attach = '';
    this.selected = childId;
    this.selectedLink = null;
    this.renderAll();
    this.app.status.info(`${child.name} now hangs from ${parent.kind === 'rig' ? 'the Rig node' : parent.name}`);
    this.changed();
    return true;
  }

  detach(childId: string): void {
    const child = this.nodes.get(childId);
    if (!child || !child.parent) return;
    const was = this.attached(childId);
    child.parent = null;
    this.selectedLink = null;
    this.renderAll();
    if (was) this.changed();
  }

  /** True when the node hangs (through its parents) from the Rig node. */
  attached(id: string): boolean {
    for (let n = this.nodes.get(id); n; n = n.parent ? this.nodes.get(n.parent) : undefined) {
      if (n.kind === 'rig') return true;
    }
    return false;
  }

  private children(id: string): GNode[] {
    return this.order.map((x) => this.nodes.get(x)!).filter((n) => n && n.parent === id);
  }

  /** The definition in its `.rig.json` form (only what hangs from the Rig node). */
  definition(): unknown {
    const rig = this.nodes.get('rig')!;
    const round = (v: number): number => Math.round(v);
    const comp = (n: GNode): Record<string, unknown> => {
      const schema = this.schemas.get(n.type);
      const c: Record<string, unknown> = {
        type: n.type,
        name: n.name,
        side: n.side,
        version: n.version,
        rigId: n.rigId,
      };
      if (n.attach.trim()) c.attach = n.attach.trim();
      c.guiLocation = [round(n.x), round(n.y)];
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
          const o: Record<string, unknown> = { role, size: l.size ?? def?.size ?? 1 };
          if (l.shape) o.shape = l.shape;
          if (l.color) o.color = l.color;
          return o;
        });
      if (controls.length) c.controls = controls;
      if (Object.keys(n.params).length) c.params = { ...n.params };
      Object.assign(c, n.extra);
      const kids = this.children(n.id);
      if (kids.length) c.children = kids.map(comp);
      return c;
    };
    const out: Record<string, unknown> = {
      name: rig.name,
      version: rig.version,
      guiLocation: [round(rig.x), round(rig.y)],
    };
    const geometry = rig.geometry
      .filter((g) => g.file.trim())
      .map((g) => {
        const o: Record<string, unknown> = { file: this.geometryFile(g.file.trim()) };
        if (g.name.trim()) o.name = g.name.trim();
        return o;
      });
    if (geometry.length) out.geometry = geometry;
    Object.assign(out, rig.extra);
    out.components = this.children('rig').map(comp);
    return { rig: out };
  }

  /**
   * A geometry file as the saved definition names it: relative to the
   * folder of the file it is saved to (an absolute path is moved there; a
   * relative one is already relative to it).
   */
  private geometryFile(file: string): string {
    const root = this.app.scene?.root;
    if (!isAbsolute(file) || !root) return file;
    return relative(dirname(join(root, this.saveTarget())), file);
  }

  /** The path Save writes to (relative to the server root). */
  private saveTarget(): string {
    return this.savePath.value.trim() || `${this.nodes.get('rig')!.name}.rig.xml`;
  }

  // ----------------------------------------------------------- server work

  /** A change to what hangs from the Rig node: validate, and build when live. */
  private changed(): void {
    if (!this.live.checked) {
      run(this.validate());
      return;
    }
    if (this.buildTimer !== null) window.clearTimeout(this.buildTimer);
    this.buildTimer = window.setTimeout(() => {
      this.buildTimer = null;
      run(this.build());
    }, 300);
  }

  async validate(): Promise<boolean> {
    const a = await this.app.api.post<{ ok: boolean; problems: Problem[] }>('/api/definition/validate', { definition: this.definition() });
    this.problems = a.problems ?? [];
    this.valid = a.ok;
    this.renderProblems();
    return a.ok;
  }

  /** Validates, then rebuilds the rig in the scene; builds never overlap. */
  async build(): Promise<void> {
    if (this.building) {
      this.rebuildAgain = true;
      return this.building;
    }
    this.building = (async () => {
      do {
        this.rebuildAgain = false;
        if (!this.children('rig').length) {
          this.app.status.info('Attach a component to the Rig node to build');
          return;
        }
        this.buildState = 'pending';
        const ok = await this.validate();
        if (!ok) {
          this.buildState = 'none';
          this.renderProblems();
          this.builds.push({ ok: false, error: 'invalid' });
          this.app.status.error(`Definition not built: ${this.problems.length} problem${this.problems.length === 1 ? '' : 's'} (${this.problems[0]?.message ?? ''})`);
          return;
        }
        try {
          // docs/SERVER.md says `components`; the server answers `rebuilt` (rigIds).
          const a = await this.app.api.post<{ revision: number; rig: string; components?: unknown[]; rebuilt?: string[] }>(
            '/api/definition/build',
            { definition: this.definition() },
          );
          this.builds.push({ ok: true, rig: a.rig });
          this.buildState = 'built';
          this.renderProblems();
          this.app.succeeded();
          const count = a.components ? `${a.components.length} components` : `${a.rebuilt?.length ?? 0} rebuilt`;
          this.app.status.info(`Built ${a.rig} (${count})`);
        } catch (e) {
          const message = e instanceof Error ? e.message : String(e);
          this.builds.push({ ok: false, error: message });
          // Valid is not enough: the panel says the build failed, and why.
          this.buildState = 'failed';
          this.buildError = this.app.status.rename(e instanceof ApiError ? e.message : message);
          this.renderProblems();
          throw e;
        }
        await this.app.refreshAll();
      } while (this.rebuildAgain);
    })().finally(() => {
      this.building = null;
    });
    return this.building;
  }

  async save(): Promise<void> {
    const rig = this.nodes.get('rig')!;
    const path = this.saveTarget();
    const a = await this.app.api.post<{ path: string; version: string }>('/api/definition/save', { definition: this.definition(), path });
    this.app.succeeded();
    if (a.version) rig.version = a.version;
    // The answer's path is absolute; the field keeps the root-relative one a request takes.
    this.savePath.value = path;
    this.app.status.info(`Saved ${a.path ?? path} (version ${a.version ?? rig.version})`);
    if (this.selected === 'rig') this.renderDetails();
  }

  // -------------------------------------------------------------- rendering

  private renderAll(): void {
    this.renderGraph();
    this.renderDetails();
  }

  private renderProblems(): void {
    this.problemsEl.dataset.state = this.valid === false ? 'invalid' : this.buildState === 'failed' ? 'build-failed' : this.valid ? 'valid' : 'none';
    if (this.valid === false && this.problems.length) {
      fill(
        this.problemsEl,
        this.problems.map((p) => h('div.problem', {}, h('b', {}, p.where || 'definition'), ': ', this.app.status.rename(p.message))),
      );
      return;
    }
    if (!this.valid) {
      fill(this.problemsEl);
      return;
    }
    switch (this.buildState) {
      case 'failed':
        fill(this.problemsEl, h('div.problem', { testid: 'def-build-error' }, h('b', {}, 'build failed'), ': ', this.buildError));
        break;
      case 'pending':
        fill(this.problemsEl, h('div.ok', {}, 'valid; building…'));
        break;
      case 'built':
        fill(this.problemsEl, h('div.ok', {}, '✔ valid and built'));
        break;
      default:
        fill(this.problemsEl, h('div.ok', {}, '✔ valid'));
    }
  }

  private portPos(n: GNode, port: 'in' | 'out'): [number, number] {
    return [port === 'out' ? n.x + kNodeW : n.x, n.y + kNodeH / 2];
  }

  private renderGraph(): void {
    for (const el of [...this.graph.querySelectorAll('.gnode')]) el.remove();
    for (const el of [...this.svg.querySelectorAll('.link')]) el.remove();
    let maxX = 600;
    let maxY = 300;
    for (const id of this.order) {
      const n = this.nodes.get(id)!;
      maxX = Math.max(maxX, n.x + kNodeW + 40);
      maxY = Math.max(maxY, n.y + kNodeH + 40);
      if (n.parent) {
        const p = this.nodes.get(n.parent);
        if (p) {
          const [x1, y1] = this.portPos(p, 'out');
          const [x2, y2] = this.portPos(n, 'in');
          const path = document.createElementNS('http://www.w3.org/2000/svg', 'path');
          path.setAttribute('d', curve(x1, y1, x2, y2));
          path.classList.add('link');
          if (this.attached(id)) path.classList.add('live');
          if (this.selectedLink === id) path.classList.add('selected');
          path.dataset.child = id;
          path.addEventListener('pointerdown', (e) => {
            e.stopPropagation();
            this.selectedLink = id;
            this.graph.focus();
            this.renderGraph();
          });
          this.svg.append(path);
        }
      }
      this.graph.append(this.nodeElement(n));
    }
    this.svg.setAttribute('width', String(maxX));
    this.svg.setAttribute('height', String(maxY));
  }

  private nodeElement(n: GNode): HTMLElement {
    const schema = this.schemas.get(n.type);
    const title = n.kind === 'rig' ? `Rig: ${n.name}` : `${n.name}${n.side !== 'C' ? `_${n.side}` : ''}`;
    const sub = n.kind === 'rig' ? `v${n.version}` : `${n.type}${schema?.rootOnly ? ' · root' : ''}`;
    const outPort = h('div.port.out', { title: 'Drag to a node to make it a child', testid: `port-out-${n.id}` });
    const inPort = n.kind === 'rig' ? null : h('div.port.in', { title: 'Parent', testid: `port-in-${n.id}` });
    const el = h(
      'div.gnode',
      { dataset: { node: n.id, kind: n.kind, type: n.type }, testid: `node-${n.id}` },
      inPort,
      h('div.gnode-title', {}, title),
      h('div.gnode-sub', {}, sub),
      outPort,
    );
    el.style.left = `${n.x}px`;
    el.style.top = `${n.y}px`;
    el.classList.toggle('selected', this.selected === n.id);
    el.classList.toggle('detached', n.kind === 'component' && !this.attached(n.id));
    el.classList.toggle('rig-node', n.kind === 'rig');

    // Move by dragging the body; a click without motion selects.
    el.addEventListener('pointerdown', (e) => {
      if (e.target === outPort || e.button !== 0) return;
      e.preventDefault();
      this.graph.focus();
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
        n.x = Math.max(0, ox + dx);
        n.y = Math.max(0, oy + dy);
        el.style.left = `${n.x}px`;
        el.style.top = `${n.y}px`;
        this.redrawLinks();
      };
      const up = (): void => {
        window.removeEventListener('pointermove', move);
        window.removeEventListener('pointerup', up);
        if (!moved) {
          this.selected = n.id;
          this.selectedLink = null;
          this.renderAll();
        } else {
          this.renderGraph();
        }
      };
      window.addEventListener('pointermove', move);
      window.addEventListener('pointerup', up);
    });

    // Link by dragging from the output port onto another node.
    outPort.addEventListener('pointerdown', (e) => {
      e.preventDefault();
      e.stopPropagation();
      const [x1, y1] = this.portPos(n, 'out');
      const r = this.graph.getBoundingClientRect();
      const move = (ev: PointerEvent): void => {
        const x2 = ev.clientX - r.left + this.graph.scrollLeft;
        const y2 = ev.clientY - r.top + this.graph.scrollTop;
        this.tempPath.setAttribute('d', curve(x1, y1, x2, y2));
        this.tempPath.style.display = '';
      };
      const up = (ev: PointerEvent): void => {
        window.removeEventListener('pointermove', move);
        window.removeEventListener('pointerup', up);
        this.tempPath.style.display = 'none';
        const target = document.elementFromPoint(ev.clientX, ev.clientY)?.closest<HTMLElement>('.gnode');
        const childId = target?.dataset.node;
        if (childId && childId !== n.id) this.connect(n.id, childId);
        else if (childId === n.id) this.app.status.error(`Link refused: ${n.name} cannot be its own parent`);
      };
      window.addEventListener('pointermove', move);
      window.addEventListener('pointerup', up);
    });
    return el;
  }

  private redrawLinks(): void {
    for (const path of [...this.svg.querySelectorAll<SVGPathElement>('.link')]) {
      const n = this.nodes.get(path.dataset.child ?? '');
      const p = n?.parent ? this.nodes.get(n.parent) : undefined;
      if (!n || !p) continue;
      const [x1, y1] = this.portPos(p, 'out');
      const [x2, y2] = this.portPos(n, 'in');
      path.setAttribute('d', curve(x1, y1, x2, y2));
    }
  }

  /** Re-renders the node's box after a field edit (name, side) without touching the details. */
  private refreshNode(n: GNode): void {
    const old = this.graph.querySelector(`.gnode[data-node="${n.id}"]`);
    if (old) old.replaceWith(this.nodeElement(n));
  }

  private renderDetails(): void {
    const n = this.selected ? this.nodes.get(this.selected) : undefined;
    if (!n) {
      fill(this.details);
      return;
    }
    const edit = (structural = false): void => {
      this.refreshNode(n);
      if (structural) this.renderDetails();
      if (this.attached(n.id)) this.changed();
    };
    const text = (label: string, value: string, set: (v: string) => void, testid: string, extra: Record<string, unknown> = {}): HTMLElement => {
      const input = h('input', { type: 'text', value, testid, ...extra });
      input.addEventListener('change', () => {
        set(input.value);
        edit();
      });
      return h('label.field', {}, h('span', {}, label), input);
    };
    if (n.kind === 'rig') {
      fill(
        this.details,
        h('h3', {}, 'Rig'),
        text('Name', n.name, (v) => (n.name = v.trim()), 'def-rig-name'),
        text('Version', n.version, (v) => (n.version = v.trim()), 'def-rig-version'),
        h('h4', {}, 'Geometry'),
        h('div.hint', {}, 'The character files the rig is built on (<geo>); saved relative to the definition’s folder.'),
        n.geometry.map((g, i) => {
          const file = h('input', { type: 'text', value: g.file, placeholder: 'character file', testid: `def-geo-file-${i}` });
          file.addEventListener('change', () => {
            g.file = file.value.trim();
            this.geometrySet = true;
            edit();
          });
          const mesh = h('input', { type: 'text', value: g.name, placeholder: 'mesh (optional)', testid: `def-geo-name-${i}` });
          mesh.addEventListener('change', () => {
            g.name = mesh.value.trim();
            this.geometrySet = true;
            edit();
          });
          return h('div.guide-row', {}, file, mesh);
        }),
        h(
          'div.button-row',
          {},
          h('button.small', {
            testid: 'def-geo-add',
            onclick: () => {
              n.geometry.push({ file: '', name: '' });
              this.geometrySet = true;
              edit(true);
            },
          }, '+ geometry'),
          h('button.small', {
            disabled: !n.geometry.length, testid: 'def-geo-remove',
            onclick: () => {
              n.geometry.pop();
              this.geometrySet = true;
              edit(true);
            },
          }, '− geometry'),
        ),
        h('div.hint', {}, `${this.children('rig').length} root component(s). Saving over a file with other content bumps the version.`),
      );
      return;
    }
    const schema = this.schemas.get(n.type);
    const side = h('select', { testid: 'def-side' }, (['C', 'L', 'R'] as Side[]).map((s) => h('option', { value: s, selected: n.side === s }, s)));
    side.addEventListener('change', () => {
      n.side = side.value as Side;
      edit();
    });
    const parent = n.parent ? this.nodes.get(n.parent) : undefined;
    const hooks = parent?.kind === 'component' ? this.hooksOf(parent) : [];
    const attachList = `hooks-${n.id}`;
    const attach = parent?.kind === 'component'
      ? [
          text('Attach', n.attach, (v) => (n.attach = v), 'def-attach', { list: attachList, placeholder: hooks[0] ? `${hooks[0]} (hook 0)` : 'hook 0' }),
          h('datalist', { id: attachList }, hooks.map((x) => h('option', { value: x }))),
        ]
      : null;

    const guideRows = n.guides.map((g, i) => {
      const fixed = schema?.guides.names[i];
      const joint = h('input', { type: 'text', value: g.joint, list: 'joint-names', placeholder: 'joint (empty: use translate)', testid: `def-guide-joint-${i}` });
      joint.addEventListener('change', () => {
        g.joint = joint.value.trim();
        edit();
      });
      const name = fixed
        ? h('span.guide-name', {}, fixed)
        : h('input.guide-name', { type: 'text', value: g.name, placeholder: `guide ${i}`, testid: `def-guide-name-${i}` });
      if (name instanceof HTMLInputElement) {
        name.addEventListener('change', () => {
          g.name = name.value.trim();
          edit();
        });
      }
      const xyz = g.translate.map((v, k) => {
        const input = h('input.num', { type: 'number', step: '0.01', value: String(v), title: `translate ${'xyz'[k]}` });
        input.addEventListener('change', () => {
          g.translate[k] = Number(input.value) || 0;
          edit();
        });
        return input;
      });
      return h('div.guide-row', {}, name, joint, h('span.xyz', {}, xyz));
    });
    const canAdd = !schema || schema.guides.max < 0 || n.guides.length < schema.guides.max;
    const canRemove = !schema || n.guides.length > schema.guides.min;

    fill(
      this.details,
      h('h3', {}, `${n.type} component`),
      schema ? h('div.hint', {}, schema.help) : null,
      text('Name', n.name, (v) => (n.name = v.trim()), 'def-name'),
      h('label.field', {}, h('span', {}, 'Side'), side),
      text('Version', n.version, (v) => (n.version = v.trim()), 'def-version'),
      h('label.field', {}, h('span', {}, 'rigId'), h('code.rigid', {}, n.rigId)),
      attach,
      h('h4', {}, `Guides ${schema ? `(${schema.guides.min}${schema.guides.max < 0 ? '+' : schema.guides.max !== schema.guides.min ? `–${schema.guides.max}` : ''})` : ''}`),
      schema?.guides.help ? h('div.hint', {}, schema.guides.help) : null,
      guideRows,
      h(
        'div.button-row',
        {},
        h('button.small', {
          disabled: !canAdd, testid: 'def-guide-add',
          onclick: () => {
            const i = n.guides.length;
            n.guides.push({ name: schema?.guides.names[i] ?? '', joint: '', translate: [0, 0, 0], extra: {} });
            edit(true);
          },
        }, '+ guide'),
        h('button.small', {
          disabled: !canRemove, testid: 'def-guide-remove',
          onclick: () => {
            n.guides.pop();
            edit(true);
          },
        }, '− guide'),
      ),
      schema?.params.length ? h('h4', {}, 'Parameters') : null,
      (schema?.params ?? []).map((p) => this.paramField(n, p, () => edit())),
      schema?.controls.length ? h('h4', {}, 'Controls') : null,
      (schema?.controls ?? []).map((c) => {
        const look = n.controls[c.role] ?? { shape: '', color: '', size: null };
        const store = (): void => {
          n.controls[c.role] = look;
          edit();
        };
        const shape = h('select', { title: 'shape' }, h('option', { value: '' }, `${c.shape} (default)`), kShapes.map((s) => h('option', { value: s, selected: look.shape === s }, s)));
        shape.addEventListener('change', () => {
          look.shape = shape.value;
          store();
        });
        const color = h('input', { type: 'text', value: look.color, placeholder: c.color, title: 'palette name or #rrggbb' });
        color.addEventListener('change', () => {
          look.color = color.value.trim();
          store();
        });
        const size = h('input.num', { type: 'number', step: '0.01', min: '0.001', value: look.size === null ? '' : String(look.size), placeholder: String(c.size), title: 'size' });
        size.addEventListener('change', () => {
          look.size = size.value === '' ? null : Number(size.value);
          store();
        });
        return h('div.control-row', { title: c.help }, h('span.role', {}, c.role), shape, color, size);
      }),
      h(
        'div.button-row',
        {},
        n.parent ? h('button.small', { testid: 'def-detach', onclick: () => this.detach(n.id) }, 'Detach from parent') : null,
        h('button.small.danger-outline', { testid: 'def-delete', onclick: () => this.removeNode(n.id) }, 'Delete node'),
      ),
    );
  }

  /** The hook names of a component: `guide[i]` stands for each guide's name or joint. */
  private hooksOf(n: GNode): string[] {
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

  private paramField(n: GNode, p: ParamSchema, edited: () => void): HTMLElement {
    const isSet = p.name in n.params;
    const value = isSet ? n.params[p.name] : p.default;
    const set = (v: unknown): void => {
      if (JSON.stringify(v) === JSON.stringify(p.default)) delete n.params[p.name];
      else n.params[p.name] = v;
      edited();
    };
    const range = p.min !== undefined || p.max !== undefined ? ` [${p.min ?? '−∞'}, ${p.max ?? '∞'}]` : '';
    let input: HTMLElement;
    const testid = `def-param-${p.name}`;
    switch (p.type) {
      case 'bool': {
        const c = h('input', { type: 'checkbox', checked: value === true, testid });
        c.addEventListener('change', () => set(c.checked));
        input = c;
        break;
      }
      case 'enum': {
        const s = h('select', { testid }, (p.choices ?? []).map((ch) => h('option', { value: ch, selected: ch === value }, ch)));
        s.addEventListener('change', () => set(s.value));
        input = s;
        break;
      }
      case 'int':
      case 'double': {
        const i = h('input.num', { type: 'number', step: p.type === 'int' ? '1' : 'any', value: String(value ?? ''), testid });
        if (p.min !== undefined) i.min = String(p.min);
        if (p.max !== undefined) i.max = String(p.max);
        i.addEventListener('change', () => {
          const v = Number(i.value);
          if (i.value === '' || !Number.isFinite(v)) {
            this.app.status.error(`${p.name}: not a number`);
            return;
          }
          if ((p.min !== undefined && v < p.min) || (p.max !== undefined && v > p.max)) {
            this.app.status.error(`${p.name}: ${v} is out of range${range}`);
          }
          set(p.type === 'int' ? Math.round(v) : v);
        });
        input = i;
        break;
      }
      case 'vec3': {
        const v = (Array.isArray(value) ? value : [0, 0, 0]) as number[];
        const inputs = [0, 1, 2].map((k) => h('input.num', { type: 'number', step: 'any', value: String(v[k] ?? 0) }));
        for (const i of inputs) i.addEventListener('change', () => set(inputs.map((x) => Number(x.value) || 0)));
        input = h('span.xyz', { testid }, inputs);
        break;
      }
      default: {
        const t = h('input', { type: 'text', value: String(value ?? ''), testid });
        t.addEventListener('change', () => set(t.value));
        input = t;
      }
    }
    const reset = isSet
      ? h('button.link', { title: `Back to the default (${JSON.stringify(p.default)})`, onclick: () => { delete n.params[p.name]; edited(); this.renderDetails(); } }, '↺')
      : null;
    return h('label.field', { title: p.help ?? '' }, h('span', {}, `${p.name}`, h('small', {}, ` ${p.type}${range}`)), input, reset);
  }

  /** Test hooks: node ids by name. */
  idOf(name: string): string | null {
    for (const n of this.nodes.values()) if (n.name === name) return n.id;
    return null;
  }
}

function curve(x1: number, y1: number, x2: number, y2: number): string {
  const dx = Math.max(40, Math.abs(x2 - x1) / 2);
  return `M${x1},${y1} C${x1 + dx},${y1} ${x2 - dx},${y2} ${x2},${y2}`;
}
