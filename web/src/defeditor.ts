// The definition editor (seed 002 §4.3.2, the Node Editor), its view: a
// palette of the component types from GET /api/components, the model's
// nodes (defmodel.ts) as boxes of a graph hanging from one Rig node, parent
// -> child links drawn by dragging from a node's output port to another
// node's input, and a details panel (defdetails.ts) generated from the
// selected component's schema.
//
// Every change to what hangs from the Rig node is validated and, with "Live
// build" on, built into the scene (a command: the scene is read again); the
// panel shows the build's outcome, not only the validation's. "Save" writes
// the file. "Open" loads the definition a rig of the scene was built from,
// geometry (<geo>) and all; the geometry of a new definition is the scene's
// character.

import type { App } from './app';
import type { Problem, RigJson } from './api';
import * as commands from './commands';
import { dragNode } from './buildgraphgestures';
import { renderDetails } from './defdetails';
import type { DetailsContext } from './defdetails';
import { DefinitionModel, kRig } from './defmodel';
import type { GNode } from './defmodel';
import { h, fill, typingTarget } from './dom';
import { dirname, isAbsolute, join, relative } from './paths';
import { run } from './status';


const kNodeW = 150;
const kNodeH = 56;

/** The outcome shown under the graph: validation, then (live) the build's. */
type BuildState = 'none' | 'pending' | 'built' | 'failed';

export class DefinitionEditor {
  readonly model = new DefinitionModel();
  private selected: string | null = kRig;
  private selectedLink: string | null = null; // the child's id
  private buildTimer: number | null = null;
  private building: Promise<void> | null = null;
  private rebuildAgain = false;
  problems: Problem[] = [];
  /** Builds sent (live or by the button) and their outcome, for tests. */
  readonly builds: { ok: boolean; rig?: string; error?: string }[] = [];
  private valid: boolean | null = null;
  private buildState: BuildState = 'none';
  private buildError = '';

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
  private readonly detailsContext: DetailsContext;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
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
    this.detailsContext = {
      model: this.model,
      edited: (n, structural = false) => {
        this.refreshNode(n);
        if (structural) this.renderDetails();
        if (this.model.attached(n.id)) this.changed();
      },
      detach: (id) => this.detach(id),
      remove: (id) => this.removeNode(id),
      error: (text) => this.app.status.error(text),
    };

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
        else if (this.selected && this.selected !== kRig) this.removeNode(this.selected);
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
    const signals = app.store.signals;
    signals.nodesChanged.add(() => this.fillJoints());
    signals.rigsChanged.add(() => this.fillRigs());
    signals.sceneChanged.add(() => this.defaultGeometry());
    this.renderAll();
  }

  /** The model's nodes (for tests). */
  get nodes(): ReadonlyMap<string, GNode> {
    return this.model.nodes;
  }

  async loadSchemas(): Promise<void> {
    const a = await this.app.api.components();
    this.model.schemas = new Map(a.components.map((c) => [c.type, c]));
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
    const names = this.app.store.rigs.map((r) => r.name);
    const current = this.openSelect.value;
    if (JSON.stringify(names) === JSON.stringify([...this.openSelect.options].map((o) => o.value))) return;
    fill(
      this.openSelect,
      names.length ? names.map((n) => h('option', { value: n, selected: n === current }, n)) : h('option', { value: '' }, '(no rig)'),
    );
  }

  /** A new definition's geometry: the character the scene was opened from. */
  private defaultGeometry(): void {
    if (this.model.defaultGeometry(this.app.store.scene?.character) && this.selected === kRig) this.renderDetails();
  }

  /** True when no build or validation is waiting or running (for tests). */
  idle(): boolean {
    return this.buildTimer === null && this.building === null;
  }

  private fillJoints(): void {
    const joints = (this.app.store.nodes?.nodes ?? []).filter((n) => n.type === 'joint').map((n) => n.name);
    fill(
      this.jointList,
      joints.map((j) => h('option', { value: j })),
    );
  }

  // ------------------------------------------------------------------ edits

  reset(): void {
    this.model.reset();
    this.selected = kRig;
    this.selectedLink = null;
    this.problems = [];
    this.valid = null;
    this.buildState = 'none';
    this.defaultGeometry();
    this.renderAll();
    this.renderProblems();
  }

  /** Opens the definition rig `name` of the scene was built from. */
  async open(name: string): Promise<void> {
    const a = await this.app.api.definition(name);
    // The definition's relative files are relative to its folder.
    const root = this.app.store.scene?.root ?? '';
    const file = a.path ? (isAbsolute(a.path) || !root ? a.path : join(root, a.path)) : '';
    this.load(a.definition, file ? dirname(file) : root);
    if (file && root && file.startsWith(`${root.replace(/\/$/, '')}/`)) this.savePath.value = relative(root, file);
    this.app.status.info(`Opened the definition of ${a.rig}${a.path ? ` (${a.path})` : ''}`);
  }

  /** Replaces the graph with a `.rig.json` definition whose relative files are relative to `folder`. */
  load(def: RigJson, folder: string): void {
    this.model.load(def, folder);
    this.selected = kRig;
    this.selectedLink = null;
    this.problems = [];
    this.valid = null;
    this.buildState = 'none';
    this.renderAll();
    this.renderProblems();
  }

  /** Adds a component node (unattached); returns its id. */
  addComponent(type: string, x?: number, y?: number): string | null {
    const node = this.model.addComponent(type, x, y);
    if (!node) {
      this.app.status.error(`Unknown component type ${type}`);
      return null;
    }
    this.selected = node.id;
    this.selectedLink = null;
    this.renderAll();
    this.app.status.info(`Added a ${type} node; connect it to build it`);
    return node.id;
  }

  removeNode(id: string): void {
    if (id === kRig) return;
    const wasAttached = this.model.removeNode(id);
    if (this.selected === id) this.selected = kRig;
    this.renderAll();
    if (wasAttached) this.changed();
  }

  connect(parentId: string, childId: string): boolean {
    const problem = this.model.linkProblem(parentId, childId);
    const parent = this.model.nodes.get(parentId);
    const child = this.model.nodes.get(childId);
    if (problem || !parent || !child) {
      this.app.status.error(`Link refused: ${problem ?? 'unknown node'}`);
      return false;
    }
    if (child.parent === parentId) return true;
    this.model.connect(parentId, childId);
    this.selected = childId;
    this.selectedLink = null;
    this.renderAll();
    this.app.status.info(`${child.name} now hangs from ${parent.kind === 'rig' ? 'the Rig node' : parent.name}`);
    this.changed();
    return true;
  }

  detach(childId: string): void {
    const child = this.model.nodes.get(childId);
    if (!child || !child.parent) return;
    const was = this.model.detach(childId);
    this.selectedLink = null;
    this.renderAll();
    if (was) this.changed();
  }

  /** The definition in its `.rig.json` form, geometry relative to the folder Save writes to. */
  definition(): RigJson {
    const root = this.app.store.scene?.root;
    return this.model.toJson(root ? dirname(join(root, this.saveTarget())) : null);
  }

  /** The path Save writes to (relative to the server root). */
  private saveTarget(): string {
    return this.savePath.value.trim() || `${this.model.rig.name}.rig.xml`;
  }

  /** Test hooks: node ids by name. */
  idOf(name: string): string | null {
    return this.model.idOf(name);
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
    const a = await this.app.api.validateDefinition({ definition: this.definition() });
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
        if (!this.model.children(kRig).length) {
          this.app.status.info('Attach a component to the Rig node to build');
          return;
        }
        if (!(await this.buildOnce())) return;
      } while (this.rebuildAgain);
    })().finally(() => {
      this.building = null;
    });
    return this.building;
  }

  /** One validation and build; false when the definition is not valid. */
  private async buildOnce(): Promise<boolean> {
    this.buildState = 'pending';
    const ok = await this.validate();
    if (!ok) {
      this.buildState = 'none';
      this.renderProblems();
      this.builds.push({ ok: false, error: 'invalid' });
      this.app.status.error(`Definition not built: ${this.problems.length} problem${this.problems.length === 1 ? '' : 's'} (${this.problems[0]?.message ?? ''})`);
      return false;
    }
    await commands.runBuild(
      (c) => this.app.execute(c),
      commands.buildDefinition(this.definition()),
      (a) => {
        this.builds.push({ ok: true, rig: a.rig });
        this.buildState = 'built';
        this.renderProblems();
      },
      (message, reason) => {
        this.builds.push({ ok: false, error: message });
        // Valid is not enough: the panel says the build failed, and why.
        this.buildState = 'failed';
        this.buildError = this.app.status.rename(reason);
        this.renderProblems();
      },
    );
    return true;
  }

  async save(): Promise<void> {
    const rig = this.model.rig;
    const path = this.saveTarget();
    const command = commands.saveDefinition(this.definition(), path);
    await this.app.execute({
      ...command,
      apply: (a) => {
        if (a.version) rig.version = a.version;
        // The answer's path is absolute; the field keeps the root-relative one a request takes.
        this.savePath.value = path;
        if (this.selected === kRig) this.renderDetails();
      },
      message: (a) => `Saved ${a.path ?? path} (version ${a.version ?? rig.version})`,
    });
  }

  // -------------------------------------------------------------- rendering

  private renderAll(): void {
    this.renderGraph();
    this.renderDetails();
  }

  private renderDetails(): void {
    renderDetails(this.details, this.selected ? this.model.nodes.get(this.selected) : undefined, this.detailsContext);
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
    for (const id of this.model.order) {
      const n = this.model.nodes.get(id)!;
      maxX = Math.max(maxX, n.x + kNodeW + 40);
      maxY = Math.max(maxY, n.y + kNodeH + 40);
      const p = n.parent ? this.model.nodes.get(n.parent) : undefined;
      if (p) this.svg.append(this.linkElement(p, n));
      this.graph.append(this.nodeElement(n));
    }
    this.svg.setAttribute('width', String(maxX));
    this.svg.setAttribute('height', String(maxY));
  }

  private linkElement(p: GNode, n: GNode): SVGPathElement {
    const [x1, y1] = this.portPos(p, 'out');
    const [x2, y2] = this.portPos(n, 'in');
    const path = document.createElementNS('http://www.w3.org/2000/svg', 'path');
    path.setAttribute('d', curve(x1, y1, x2, y2));
    path.classList.add('link');
    if (this.model.attached(n.id)) path.classList.add('live');
    if (this.selectedLink === n.id) path.classList.add('selected');
    path.dataset.child = n.id;
    path.addEventListener('pointerdown', (e) => {
      e.stopPropagation();
      this.selectedLink = n.id;
      this.graph.focus();
      this.renderGraph();
    });
    return path;
  }

  private nodeElement(n: GNode): HTMLElement {
    const schema = this.model.schemas.get(n.type);
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
    el.classList.toggle('detached', n.kind === 'component' && !this.model.attached(n.id));
    el.classList.toggle('rig-node', n.kind === 'rig');
    el.addEventListener('pointerdown', (e) => {
      if (e.target === outPort || e.button !== 0) return;
      e.preventDefault();
      this.moveNode(n, el, e);
    });
    outPort.addEventListener('pointerdown', (e) => {
      e.preventDefault();
      e.stopPropagation();
      this.dragLink(n);
    });
    return el;
  }

  /** Moves a node by dragging its body; a click without motion selects it. */
  private moveNode(n: GNode, el: HTMLElement, e: PointerEvent): void {
    this.graph.focus();
    dragNode(n, e, {
      move: (x, y) => {
        n.x = Math.max(0, x);
        n.y = Math.max(0, y);
        el.style.left = `${n.x}px`;
        el.style.top = `${n.y}px`;
        this.redrawLinks();
      },
      done: (moved) => {
        if (moved) {
          this.renderGraph();
          return;
        }
        this.selected = n.id;
        this.selectedLink = null;
        this.renderAll();
      },
    });
  }

  /** Links by dragging from `n`'s output port onto another node (its new child). */
  private dragLink(n: GNode): void {
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
  }

  private redrawLinks(): void {
    for (const path of [...this.svg.querySelectorAll<SVGPathElement>('.link')]) {
      const n = this.model.nodes.get(path.dataset.child ?? '');
      const p = n?.parent ? this.model.nodes.get(n.parent) : undefined;
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
}

function curve(x1: number, y1: number, x2: number, y2: number): string {
  const dx = Math.max(40, Math.abs(x2 - x1) / 2);
  return `M${x1},${y1} C${x1 + dx},${y1} ${x2 - dx},${y2} ${x2},${y2}`;
}
