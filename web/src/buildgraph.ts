// The build-graph editor (docs/BUILD_GRAPH.md; Unreal's Blueprints, Luna's
// rig builder), its view: a palette of the node kinds of GET
// /api/graph/palette by category (a search box filters it), the model's
// nodes (buildgraphmodel.ts) as boxes with their exec and data sockets in
// their type's colour, links drawn by dragging from an output to an input
// (a link whose types do not fit is refused, the socket flashing red), a
// details panel for the selected node (a component node's component in the
// definition editor's fields, defdetails.ts), the graph's variables, and
// the problems validation and builds find, on their nodes.
//
// Every change is validated, or with "Live" on built into the scene (a
// command: the scene is read again), debounced, one request at a time.
// "Step" moves the rig's build a step back or forward (POST
// /api/rigs/step), the node of the last step built marked when the answer
// names its component. "Save" writes the `.build.json`; "Open" reads one of
// the root's or makes the graph of a scene rig. A new graph's geometry is
// the scene's character.

import type { App } from './app';
import type { BuildGraphJson, GraphProblem } from './api';
import { renderGraphDetails, renderVariables } from './buildgraphdetails';
import type { GraphDetailsContext } from './buildgraphdetails';
import { curve, dragLink, dragNode, graphPoint, socketPosition } from './buildgraphgestures';
import type { Dir } from './buildgraphgestures';
import { BuildGraphModel, kNodeW, kStart, kTitleH, linkKey, refText } from './buildgraphmodel';
import type { GraphLink, GraphNode, SocketRef } from './buildgraphmodel';
import { filterPalette, nodeElement, renderPalette } from './buildgraphnodes';
import * as commands from './commands';
import { h, fill, typingTarget } from './dom';
import { dirname, isAbsolute, join, relative } from './paths';
import { run } from './status';

const kSvg = 'http://www.w3.org/2000/svg';
/** The wait after a change before it is validated or built. */
const kDebounceMs = 300;

/** The outcome shown under the graph: validation, then the build's. */
type BuildState = 'none' | 'pending' | 'built' | 'failed';

export class BuildGraphEditor {
  readonly model = new BuildGraphModel();
  private selected: string | null = null;
  private selectedLink: string | null = null;
  problems: GraphProblem[] = [];
  warnings: GraphProblem[] = [];
  /** What the last validation or build said: the chain's order and the node of each rigId. */
  order: string[] = [];
  rigIds: Record<string, string> = {};
  /** Builds sent (live or by Run) and their outcome, for tests. */
  readonly builds: { ok: boolean; rig?: string; error?: string }[] = [];
  /** The last link refused, for tests. */
  lastRefusal: { from: string; to: string; message: string } | null = null;
  private valid: boolean | null = null;
  private buildState: BuildState = 'none';
  private buildError = '';
  /** The rig the graph built last (its name may have changed since). */
  private builtRig: string | null = null;
  /** The rigId of the component of the last step a step button built ('' none). */
  private stepOwner = '';
  private files: string[] = [];
  private shown = false;
  private palette: Promise<void> | null = null;

  // One request at a time: what is asked waits for the one running.
  private asked: 'validate' | 'build' | null = null;
  private timer: number | null = null;
  private working: Promise<void> | null = null;

  private readonly paletteEl: HTMLElement;
  private readonly search: HTMLInputElement;
  private readonly graph: HTMLElement;
  private readonly svg: SVGSVGElement;
  private readonly tempPath: SVGPathElement;
  private readonly details: HTMLElement;
  private readonly problemsEl: HTMLElement;
  private readonly variablesEl: HTMLElement;
  private readonly live: HTMLInputElement;
  private readonly savePath: HTMLInputElement;
  private readonly openSelect: HTMLSelectElement;
  private readonly stepEl: HTMLElement;
  private readonly detailsContext: GraphDetailsContext;

  constructor(
    el: HTMLElement,
    private readonly app: App,
  ) {
    this.search = h('input', { type: 'search', placeholder: 'Search nodes', testid: 'bg-search' });
    this.paletteEl = h('div.bg-palette-list', { testid: 'bg-palette' });
    this.graph = h('div.graph.bg-graph', { tabIndex: 0, testid: 'bg-graph' });
    this.svg = document.createElementNS(kSvg, 'svg');
    this.svg.classList.add('links');
    this.tempPath = document.createElementNS(kSvg, 'path');
    this.tempPath.classList.add('temp-link');
    this.details = h('div.def-details.bg-details', { testid: 'bg-details' });
    this.problemsEl = h('div.problems', { testid: 'bg-problems' });
    this.variablesEl = h('div.bg-variables', { testid: 'bg-variables' });
    this.live = h('input', { type: 'checkbox', testid: 'bg-live' });
    this.savePath = h('input', { type: 'text', placeholder: 'rig.build.json', testid: 'bg-save-path' });
    this.openSelect = h('select', { testid: 'bg-open-select', title: 'A .build.json under the root, or a rig of the scene' });
    this.stepEl = h('span.step-pos', { testid: 'bg-step' }, 'step – / –');

    this.detailsContext = {
      model: this.model,
      nodeEdited: (n, structural = false) => {
        this.refreshNode(n);
        if (structural) this.renderDetails();
        this.changed();
      },
      graphEdited: (build = true) => {
        this.renderAll();
        if (build) this.changed();
      },
      disconnect: (key) => this.disconnect(key),
      remove: (id) => this.removeNode(id),
      error: (text) => this.app.status.error(text),
    };

    this.search.addEventListener('input', () => this.filterPalette());
    this.live.addEventListener('change', () => {
      if (this.live.checked) this.schedule('build', 0);
    });
    this.wireGraph();
    fill(el, ...this.layout());
    this.graph.append(this.svg);
    this.svg.append(this.tempPath);

    const signals = app.store.signals;
    signals.rigsChanged.add(() => {
      this.renderOpenList();
      this.renderStep();
    });
    signals.sceneChanged.add(() => this.defaultGeometry());
    this.renderAll();
  }

  private layout(): (HTMLElement | null)[] {
    return [
      h(
        'div.panel-head',
        {},
        h('h2', {}, 'Build Graph'),
        h('button.small', { title: 'Start a new graph', testid: 'bg-new', onclick: () => this.reset() }, 'New'),
        this.openSelect,
        h('button.small', { title: 'Open the graph chosen', testid: 'bg-open', onclick: () => run(this.openChosen()) }, 'Open'),
        h('button.small', { title: "The rig's settings", testid: 'bg-rig', onclick: () => this.select(null) }, 'Rig'),
      ),
      h(
        'div.hint',
        {},
        'Click or drag a node kind into the graph; drag from an output socket to an input to link them (exec sockets order the build from Start). Delete removes the selected node or link.',
      ),
      h('div.bg-body', {}, h('div.bg-palette', {}, this.search, this.paletteEl), this.graph),
      h(
        'div.button-row',
        {},
        h('label.toggle', { title: 'Build the rig in the scene after every change' }, this.live, 'Live'),
        h('button', { testid: 'bg-validate', onclick: () => run(this.validate()) }, 'Validate'),
        h('button.primary', { testid: 'bg-run', title: 'Build the rig into the scene', onclick: () => run(this.build()) }, 'Run'),
        h(
          'span.stepper',
          {},
          h('button.icon', { title: 'One build step back', testid: 'bg-step-back', onclick: () => run(this.step(-1)) }, '◀'),
          this.stepEl,
          h('button.icon', { title: 'One build step forward', testid: 'bg-step-forward', onclick: () => run(this.step(1)) }, '▶'),
        ),
      ),
      h('div.form-row', {}, this.savePath, h('button', { testid: 'bg-save', onclick: () => run(this.save()) }, 'Save')),
      this.problemsEl,
      this.details,
      h('h3', {}, 'Variables'),
      this.variablesEl,
    ];
  }

  /** Shown (its tab): the palette and the files read again (a graph file saved is a sub-graph kind). */
  set visible(on: boolean) {
    this.shown = on;
    if (!on) return;
    run(this.reloadPalette());
    run(this.refreshFiles());
  }

  get visible(): boolean {
    return this.shown;
  }

  /** True when no validation or build is waiting or running (for tests). */
  idle(): boolean {
    return this.timer === null && this.working === null && this.asked === null;
  }

  /** Test hooks: a node's id by its id or title ("arm_L"); the links as "FROM->TO". */
  idOf(title: string): string | null {
    return this.model.idOf(title);
  }

  linkKeys(): string[] {
    return this.model.links.map(linkKey);
  }

  // ------------------------------------------------------------------ palette

  /** Reads the palette and the component types (once). */
  loadPalette(): Promise<void> {
    this.palette ??= (async () => {
      const [p, c] = await Promise.all([this.app.api.graphPalette(), this.app.api.components()]);
      this.model.setPalette(p);
      this.model.schemas = new Map(c.components.map((s) => [s.type, s]));
      this.renderPalette();
      this.renderAll();
    })().catch((e: unknown) => {
      this.palette = null;
      throw e;
    });
    return this.palette;
  }

  /** Reads the palette again: the root's graph files are its Graphs. */
  reloadPalette(): Promise<void> {
    if (this.palette)
      this.palette = this.palette.then(() => this.readPalette()).catch((e: unknown) => {
        this.palette = null;
        throw e;
      });
    return this.loadPalette();
  }

  private async readPalette(): Promise<void> {
    this.model.setPalette(await this.app.api.graphPalette());
    this.renderPalette();
    this.renderAll();
  }

  private renderPalette(): void {
    renderPalette(this.paletteEl, this.model.kinds.values(), (kind) => this.addNode(kind));
    this.filterPalette();
  }

  private filterPalette(): void {
    filterPalette(this.paletteEl, this.search.value);
  }

  // -------------------------------------------------------------------- files

  async refreshFiles(): Promise<void> {
    this.files = (await this.app.api.graphFiles()).files;
    this.renderOpenList();
  }

  /** The Open list: the root's graph files, then "from rig NAME" for each rig of the scene. */
  private renderOpenList(): void {
    const values = [...this.files.map((f) => `file:${f}`), ...this.app.store.rigs.map((r) => `rig:${r.name}`)];
    if (JSON.stringify(values) === JSON.stringify([...this.openSelect.options].map((o) => o.value))) return;
    const current = this.openSelect.value;
    fill(
      this.openSelect,
      values.length
        ? values.map((v) => h('option', { value: v, selected: v === current }, v.startsWith('file:') ? v.slice(5) : `from rig ${v.slice(4)}`))
        : h('option', { value: '' }, '(no graph)'),
    );
  }

  private async openChosen(): Promise<void> {
    const v = this.openSelect.value;
    if (v.startsWith('file:')) await this.openFile(v.slice(5));
    else if (v.startsWith('rig:')) await this.openRig(v.slice(4));
    else this.app.status.info('Open: no .build.json under the root and no rig in the scene');
  }

  /** An absolute path of one the server gave (relative to the root, or absolute). */
  private absolute(path: string): string {
    const root = this.app.store.scene?.root ?? '';
    return isAbsolute(path) || !root ? path : join(root, path);
  }

  /** The root-relative path of an absolute file under the root, or ''. */
  private underRoot(file: string): string {
    const root = (this.app.store.scene?.root ?? '').replace(/\/$/, '');
    return root && file.startsWith(`${root}/`) ? relative(root, file) : '';
  }

  /** Opens a `.build.json` of the root. */
  async openFile(path: string): Promise<void> {
    await this.loadPalette();
    const a = await this.app.api.graphFile(path);
    const file = this.absolute(a.path || path);
    this.load(a.graph, dirname(file));
    this.savePath.value = this.underRoot(file) || path;
    this.app.status.info(`Opened ${path}`);
  }

  /** Opens the graph a rig of the scene was built from, or its definition made a graph. */
  async openRig(name: string): Promise<void> {
    await this.loadPalette();
    const a = await this.app.api.graphOfRig(name);
    const file = a.path ? this.absolute(a.path) : '';
    // A converted definition's files are relative to the definition's folder.
    const definition = this.app.store.rigs.find((r) => r.name === name)?.definition ?? '';
    const folder = file ? dirname(file) : definition ? dirname(this.absolute(definition)) : (this.app.store.scene?.root ?? '');
    this.load(a.graph, folder);
    this.builtRig = name;
    this.savePath.value = file ? this.underRoot(file) : '';
    this.app.status.info(a.converted ? `Made the graph of ${name}'s definition` : `Opened the graph of ${name} (${a.path})`);
  }

  /** Replaces the graph with a `.build.json` object whose relative files are relative to `folder`. */
  load(graph: BuildGraphJson, folder: string): void {
    this.model.load(graph, folder);
    this.forget();
    this.renderAll();
    this.renderProblems();
    this.schedule('validate', 0);
  }

  /** Forgets what belonged to the graph shown before: selection, problems, outcome, the stepped node. */
  private forget(): void {
    this.selected = null;
    this.selectedLink = null;
    this.problems = [];
    this.warnings = [];
    this.valid = null;
    this.buildState = 'none';
    this.stepOwner = '';
  }

  // ------------------------------------------------------------------ edits

  reset(): void {
    this.model.reset();
    this.forget();
    this.builtRig = null;
    this.savePath.value = '';
    this.defaultGeometry();
    this.renderAll();
    this.renderProblems();
  }

  /** A new graph's geometry: the character the scene was opened from. */
  private defaultGeometry(): void {
    if (this.model.defaultGeometry(this.app.store.scene?.character) && this.selected === null) this.renderDetails();
  }

  /** Adds a node of `kind` at (x, y) (by default a free spot in view); returns its id. */
  addNode(kind: string, x?: number, y?: number): string | null {
    if (kind === kStart && this.model.nodes.has(kStart)) {
      this.app.status.info('The graph has its start node already');
      return null;
    }
    const columns = Math.max(1, Math.floor(this.graph.clientWidth / (kNodeW + 60)));
    const n = this.model.addNode(kind, x, y, columns);
    if (!n) {
      this.app.status.error(`Unknown node kind ${kind}`);
      return null;
    }
    this.selected = n.id;
    this.selectedLink = null;
    this.renderAll();
    this.graph.querySelector(`.bgnode[data-node="${CSS.escape(n.id)}"]`)?.scrollIntoView({ block: 'nearest', inline: 'nearest' });
    this.app.status.info(`Added ${this.model.title(n)} (${kind})${this.model.kindOf(n)?.inputs.some((s) => s.type === 'exec') ? '; link its exec input to run it' : ''}`);
    this.changed();
    return n.id;
  }

  removeNode(id: string): void {
    if (id === kStart) {
      this.app.status.info('The start node stays: the build begins there');
      return;
    }
    if (!this.model.removeNode(id)) return;
    if (this.selected === id) this.selected = null;
    this.selectedLink = null;
    this.renderAll();
    this.changed();
  }

  select(id: string | null): void {
    this.selected = id;
    this.selectedLink = null;
    this.renderAll();
  }

  /** Links output `from` to input `to`, or says why not (the input's socket flashing red). */
  connect(from: SocketRef, to: SocketRef): boolean {
    const r = this.model.connect(from, to);
    if ('problem' in r) {
      this.refuse(from, to, r.problem.replace(/^link /, ''));
      return false;
    }
    this.selectedLink = null;
    this.renderAll();
    const replaced = r.replaced.length ? ` (replacing ${r.replaced.map((l) => `${refText(l.from)} → ${refText(l.to)}`).join(', ')})` : '';
    this.app.status.info(`Linked ${refText(from)} → ${refText(to)}${replaced}`);
    this.changed();
    return true;
  }

  private refuse(from: SocketRef, to: SocketRef, message: string): void {
    this.lastRefusal = { from: refText(from), to: refText(to), message };
    this.app.status.error(`Link refused: ${message}`);
    for (const [ref, dir] of [[to, 'in'], [from, 'out']] as const) {
      const s = this.socketElement(ref, dir);
      if (!s) continue;
      s.classList.remove('refused');
      void s.offsetWidth; // restarts the flash
      s.classList.add('refused');
    }
  }

  disconnect(key: string): void {
    if (!this.model.disconnect(key)) return;
    if (this.selectedLink === key) this.selectedLink = null;
    this.renderAll();
    this.changed();
  }

  /** The graph in its `.build.json` form, geometry relative to the folder Save writes to. */
  graphJson(): BuildGraphJson {
    const root = this.app.store.scene?.root;
    return this.model.toJson(root ? dirname(join(root, this.saveTarget())) : null);
  }

  /** The path Save writes to (relative to the server root). */
  private saveTarget(): string {
    return this.savePath.value.trim() || `${this.model.rig.name}.build.json`;
  }

  // ----------------------------------------------------------- server work

  /** A change to the graph: validated, or built when live. */
  private changed(): void {
    this.schedule(this.live.checked ? 'build' : 'validate', kDebounceMs);
  }

  /** Asks for a validation or a build after `delay` ms (a build covers a validation). */
  private schedule(what: 'validate' | 'build', delay: number): void {
    if (what === 'build' || this.asked === null) this.asked = what;
    if (this.timer !== null) window.clearTimeout(this.timer);
    this.timer = window.setTimeout(() => {
      this.timer = null;
      run(this.drain());
    }, delay);
  }

  /** Runs what is asked, one request at a time, until nothing is. */
  private drain(): Promise<void> {
    this.working ??= (async () => {
      while (this.asked) {
        const what = this.asked;
        this.asked = null;
        try {
          if (what === 'build') await this.buildOnce();
          else await this.validateOnce();
        } catch (e) {
          this.app.status.caught(e);
        }
      }
    })().finally(() => {
      this.working = null;
    });
    return this.working;
  }

  /** Validates now (after what runs); true when the graph compiles. */
  async validate(): Promise<boolean> {
    this.asked ??= 'validate';
    await this.drain();
    return this.valid === true;
  }

  /** Validates and builds the rig into the scene now (after what runs). */
  async build(): Promise<void> {
    this.asked = 'build';
    await this.drain();
  }

  private async validateOnce(): Promise<boolean> {
    const a = await this.app.api.validateGraph(this.graphJson());
    this.problems = a.problems ?? [];
    this.warnings = a.warnings ?? [];
    this.order = a.order ?? [];
    this.rigIds = a.rigIds ?? {};
    this.valid = a.ok;
    this.renderProblems();
    this.applyMarks();
    return a.ok;
  }

  /** One validation and build; a graph that does not compile is not sent. */
  private async buildOnce(): Promise<void> {
    this.buildState = 'pending';
    this.renderProblems();
    if (!(await this.validateOnce())) {
      this.buildState = 'none';
      this.renderProblems();
      this.builds.push({ ok: false, error: 'invalid' });
      const n = this.problems.length;
      this.app.status.error(`Graph not built: ${n} problem${n === 1 ? '' : 's'} (${this.problems[0]?.message ?? ''})`);
      return;
    }
    await commands.runBuild(
      (c) => this.app.execute(c),
      commands.buildGraph(this.graphJson()),
      (a) => {
        this.builds.push({ ok: true, rig: a.rig });
        this.builtRig = a.rig;
        if (a.rigIds) this.rigIds = a.rigIds;
        this.stepOwner = '';
        this.buildState = 'built';
        this.renderProblems();
        this.applyMarks();
      },
      (message, reason) => {
        this.builds.push({ ok: false, error: message });
        this.buildState = 'failed';
        this.buildError = this.app.status.rename(reason);
        this.renderProblems();
      },
    );
  }

  /** The rig the step buttons move: the one built last, else the graph's. */
  private stepRig(): string {
    return this.builtRig ?? this.model.rig.name;
  }

  /** One build step of the graph's rig back (-1) or forward (1). */
  async step(by: -1 | 1): Promise<void> {
    const rig = this.stepRig();
    if (!this.app.store.rigs.some((r) => r.name === rig)) {
      this.app.status.info(`Step: the scene has no rig ${rig}; run the graph first`);
      return;
    }
    await this.app.execute(
      commands.also(commands.step(rig, { by }), (a) => {
        this.stepOwner = a.position > 0 ? (a.rigId ?? '') : '';
        this.stepEl.textContent = `step ${a.position} / ${a.steps}`;
        this.applyMarks();
      }),
    );
  }

  /** The node whose component (or call) built the last step a step button went to (the step's rigId); null when none. */
  private steppedNode(): string | null {
    const rigId = this.stepOwner;
    if (!rigId) return null;
    const id = this.rigIds[rigId];
    if (id !== undefined && this.model.nodes.has(id)) return id;
    for (const n of this.model.nodes.values()) if ((n.component?.rigId ?? n.rigId) === rigId) return n.id;
    return null;
  }

  async save(): Promise<void> {
    const path = this.saveTarget();
    const rig = this.model.rig;
    await this.app.execute({
      ...commands.saveGraph(this.graphJson(), path),
      apply: (a) => {
        if (a.version) rig.version = a.version;
        this.savePath.value = path;
        this.problems = a.problems ?? [];
        this.valid = this.problems.length === 0;
        this.renderProblems();
        this.applyMarks();
        if (this.selected === null) this.renderDetails();
      },
      message: (a) => `Saved ${a.path || path} (version ${a.version || rig.version})${a.problems?.length ? `; ${a.problems.length} problem(s)` : ''}`,
    });
    await Promise.all([this.refreshFiles(), this.reloadPalette()]);
  }

  // -------------------------------------------------------------- rendering

  private renderDetails(): void {
    renderGraphDetails(this.details, this.selected ? this.model.nodes.get(this.selected) : undefined, this.detailsContext);
  }

  private renderVariables(): void {
    renderVariables(this.variablesEl, this.detailsContext);
  }

  private renderAll(): void {
    this.renderGraph();
    this.renderDetails();
    this.renderVariables();
    this.renderStep();
    this.savePath.placeholder = `${this.model.rig.name}.build.json`;
  }

  private renderStep(): void {
    const r = this.app.store.rigs.find((x) => x.name === this.stepRig());
    this.stepEl.textContent = r ? `step ${r.buildPosition} / ${r.steps}` : 'step – / –';
    this.stepEl.title = r ? `The build steps of ${r.name}` : 'Run the graph to build its rig';
  }

  private renderProblems(): void {
    this.problemsEl.dataset.state = this.valid === false ? 'invalid' : this.buildState === 'failed' ? 'build-failed' : this.valid ? 'valid' : 'none';
    const rows: HTMLElement[] = [];
    if (this.valid === false) rows.push(...this.problems.map((p) => this.problemRow(p, 'problem')));
    else if (this.valid) rows.push(this.stateRow());
    rows.push(...this.warnings.map((p) => this.problemRow(p, 'warning')));
    fill(this.problemsEl, rows);
  }

  private stateRow(): HTMLElement {
    switch (this.buildState) {
      case 'failed':
        return h('div.problem', { testid: 'bg-build-error' }, h('b', {}, 'build failed'), ': ', this.buildError);
      case 'pending':
        return h('div.ok', {}, 'valid; building…');
      case 'built':
        return h('div.ok', {}, '✔ valid and built');
      default:
        return h('div.ok', {}, '✔ valid');
    }
  }

  /** A problem (or warning) under the graph; clicking one on a node selects the node. */
  private problemRow(p: GraphProblem, kind: 'problem' | 'warning'): HTMLElement {
    const node = p.node && this.model.nodes.has(p.node) ? p.node : '';
    return h(
      `div.${kind}-row`,
      {
        testid: `bg-${kind}`,
        dataset: { node },
        title: p.where,
        onclick: () => {
          if (!node) return;
          this.select(node);
          this.graph.querySelector(`.bgnode[data-node="${CSS.escape(node)}"]`)?.scrollIntoView({ block: 'nearest', inline: 'nearest' });
        },
      },
      h('b', {}, p.node ? `${p.node}${p.socket ? `.${p.socket}` : ''}` : 'graph'),
      ': ',
      this.app.status.rename(p.message),
    );
  }

  private renderGraph(): void {
    for (const el of [...this.graph.querySelectorAll('.bgnode')]) el.remove();
    for (const el of [...this.svg.querySelectorAll('.link')]) el.remove();
    let maxX = 600;
    let maxY = 300;
    for (const n of this.model.nodes.values()) {
      maxX = Math.max(maxX, n.x + kNodeW + 60);
      maxY = Math.max(maxY, n.y + this.model.nodeHeight(n) + 60);
      this.graph.append(this.nodeElement(n));
    }
    for (const l of this.model.links) {
      const path = this.linkElement(l);
      if (path) this.svg.append(path);
    }
    this.svg.setAttribute('width', String(maxX));
    this.svg.setAttribute('height', String(maxY));
    this.applyMarks();
  }

  /** Problems on their nodes and sockets (red, the messages as tooltips), the node of the last step. */
  private applyMarks(): void {
    const byNode = new Map<string, GraphProblem[]>();
    for (const p of this.valid === false ? this.problems : []) {
      if (p.node) byNode.set(p.node, [...(byNode.get(p.node) ?? []), p]);
    }
    const stepped = this.steppedNode();
    for (const el of this.graph.querySelectorAll<HTMLElement>('.bgnode')) {
      const id = el.dataset.node ?? '';
      const mine = byNode.get(id) ?? [];
      el.classList.toggle('problem', mine.length > 0);
      el.classList.toggle('stepped', id === stepped);
      const title = el.querySelector<HTMLElement>('.bgnode-title');
      const n = this.model.nodes.get(id);
      const help = n ? (this.model.kindOf(n)?.help ?? '') : '';
      if (title) title.title = mine.length ? mine.map((p) => this.app.status.rename(p.message)).join('\n') : help;
      el.dataset.problem = mine.map((p) => p.message).join('\n');
      for (const s of el.querySelectorAll<HTMLElement>('.bg-sock')) s.classList.toggle('problem', mine.some((p) => p.socket === s.dataset.socket));
    }
  }

  /** Where a socket's centre is, in graph coordinates. */
  private socketPos(ref: SocketRef, dir: Dir): [number, number] | null {
    return socketPosition(this.model, ref, dir);
  }

  private socketElement(ref: SocketRef, dir: Dir): HTMLElement | null {
    return this.graph.querySelector<HTMLElement>(`[data-testid="${CSS.escape(`bg-${dir}-${refText(ref)}`)}"]`);
  }

  private linkElement(l: GraphLink): SVGPathElement | null {
    const a = this.socketPos(l.from, 'out');
    const b = this.socketPos(l.to, 'in');
    if (!a || !b) return null;
    const type = this.model.socketType(l.from, 'out');
    const path = document.createElementNS(kSvg, 'path');
    const key = linkKey(l);
    path.setAttribute('d', curve(a[0], a[1], b[0], b[1]));
    path.classList.add('link', 'bg-link');
    path.classList.toggle('exec', type === 'exec');
    path.classList.toggle('selected', this.selectedLink === key);
    path.style.stroke = this.model.colorOf(type);
    path.dataset.key = key;
    path.dataset.from = refText(l.from);
    path.dataset.to = refText(l.to);
    path.addEventListener('pointerdown', (e) => {
      e.stopPropagation();
      this.selectedLink = key;
      this.graph.focus();
      this.renderGraph();
    });
    return path;
  }

  private nodeElement(n: GraphNode): HTMLElement {
    return nodeElement(this.model, n, this.selected === n.id, {
      grab: (el, e) => this.moveNode(n, el, e),
      press: () => {
        this.graph.focus();
        if (this.selected !== n.id) this.select(n.id);
      },
      link: (ref, dir) => this.dragLink(ref, dir),
    });
  }

  /** Moves a node by dragging its title (its position is saved in the file); a click without motion selects it. */
  private moveNode(n: GraphNode, el: HTMLElement, e: PointerEvent): void {
    this.graph.focus();
    dragNode(n, e, {
      move: (x, y) => {
        this.model.moveNode(n.id, x, y);
        el.style.left = `${n.x}px`;
        el.style.top = `${n.y}px`;
        this.redrawLinks();
      },
      done: (moved) => (moved ? this.renderGraph() : this.select(n.id)),
    });
  }

  /** Links by dragging from a socket to a socket of the other direction (an output to an input, or back). */
  private dragLink(start: SocketRef, dir: Dir): void {
    const p = this.socketPos(start, dir);
    if (!p) return;
    dragLink(this.graph, this.tempPath, start, dir, p, {
      connect: (from, to) => this.connect(from, to),
      refuse: (from, to, message) => this.refuse(from, to, message),
    });
  }

  private redrawLinks(): void {
    for (const path of [...this.svg.querySelectorAll<SVGPathElement>('.bg-link')]) {
      const l = this.model.links.find((x) => linkKey(x) === path.dataset.key);
      const a = l && this.socketPos(l.from, 'out');
      const b = l && this.socketPos(l.to, 'in');
      if (a && b) path.setAttribute('d', curve(a[0], a[1], b[0], b[1]));
    }
  }

  /** Draws a node's box again (after a field edit) without touching the details. */
  private refreshNode(n: GraphNode): void {
    const old = this.graph.querySelector(`.bgnode[data-node="${CSS.escape(n.id)}"]`);
    if (old) old.replaceWith(this.nodeElement(n));
    this.applyMarks();
  }

  private wireGraph(): void {
    this.graph.addEventListener('dragover', (e) => e.preventDefault());
    this.graph.addEventListener('drop', (e) => {
      e.preventDefault();
      const kind = e.dataTransfer?.getData('text/x-rigel-kind');
      if (!kind) return;
      const [x, y] = graphPoint(this.graph, e);
      this.addNode(kind, x - kNodeW / 2, y - kTitleH / 2);
    });
    this.graph.addEventListener('pointerdown', (e) => {
      if (e.target === this.graph || e.target === this.svg) {
        this.graph.focus();
        if (this.selected !== null || this.selectedLink !== null) this.select(null);
      }
    });
    this.graph.addEventListener('keydown', (e) => {
      if (typingTarget(e.target) || (e.key !== 'Delete' && e.key !== 'Backspace')) return;
      e.preventDefault();
      e.stopPropagation();
      if (this.selectedLink) this.disconnect(this.selectedLink);
      else if (this.selected) this.removeNode(this.selected);
    });
  }
}
