// Entry point: lays out the page, makes the store, the app and the views
// that subscribe to the store, wires the keyboard to the app's commands, and
// exposes `window.rigel`, the hook the end-to-end tests use to find where
// controls are on screen and to read the frame rate.

import { Api } from './api';
import { userText } from './names';
import type { Vec3 } from './api';
import { App, kModeKeys } from './app';
import { installBoxSelect } from './boxselect';
import { ChannelBox } from './channelbox';
import { ContextMenu } from './contextmenu';
import { BuildGraphEditor } from './buildgraph';
import { DefinitionEditor } from './defeditor';
import { GraphEditor } from './grapheditor';
import { h, fill, typingTarget } from './dom';
import { Overlays } from './overlays';
import { Picker } from './picker';
import { RigManager } from './rigs';
import { StatusBar, run, setStatusBar } from './status';
import { Store } from './store';
import { Timeline } from './timeline';
import { AnimatorTools } from './tools';
import { Viewport } from './viewport';
import type { FrameStats } from './viewport';
import { kMeshDisplays } from './viewport';

function byId(id: string): HTMLElement {
  const el = document.getElementById(id);
  if (!el) throw new Error(`index.html lacks #${id}`);
  return el;
}

const statusBar = new StatusBar(byId('statusbar'));
setStatusBar(statusBar);
// Messages name channels and nodes as the page does (names.ts).
const store = new Store((e) => statusBar.caught(e));
statusBar.rename = (text) => userText(text, (u) => store.names.get(u));
window.addEventListener('error', (e) => statusBar.error(`script error: ${e.message}`));
window.addEventListener('unhandledrejection', (e) => statusBar.caught(e.reason));

const token = new URLSearchParams(location.search).get('token');
let app: App | null = null;
const api = new Api('', token, {
  error: (err) => statusBar.error(err.describe()),
  ownRevision: (r) => store.noteRevision(r),
  connection: (up, err) => app?.connection(up, err),
});

const viewport = new Viewport(byId('viewport'), store, {
  pick: (uuid, additive) => app && run(app.pick(uuid, additive)),
  gestureStart: () => app?.drag.start(),
  gestureMove: (control, t, q) => app?.drag.move(control, t, q),
  gestureEnd: () => app && run(app.drag.end()),
});
app = new App(api, store, statusBar);
const theApp = app;
installBoxSelect(byId('viewport'), viewport, theApp);

// ------------------------------------------------------------------ toolbar

const modeButtons = new Map<string, HTMLButtonElement>();
const modeBar = byId('modes');
for (const [mode, key, label] of kModeKeys) {
  const b = h(
    'button.mode',
    { title: `${label} mode (${key})`, testid: `mode-${mode}`, dataset: { mode }, onclick: () => run(theApp.setMode(mode)) },
    label,
    h('kbd', {}, key),
  );
  modeButtons.set(mode, b);
  modeBar.append(b);
}
const moveBtn = h('button', { title: 'Move gizmo (W)', testid: 'gizmo-translate', onclick: () => setGizmo('translate') }, 'Move', h('kbd', {}, 'W'));
const rotBtn = h('button', { title: 'Rotate gizmo (E)', testid: 'gizmo-rotate', onclick: () => setGizmo('rotate') }, 'Rotate', h('kbd', {}, 'E'));
fill(byId('gizmo'), moveBtn, rotBtn);
function setGizmo(mode: 'translate' | 'rotate'): void {
  viewport.setGizmoMode(mode);
  moveBtn.classList.toggle('active', mode === 'translate');
  rotBtn.classList.toggle('active', mode === 'rotate');
}
setGizmo('translate');

const undoBtn = h('button', { testid: 'undo', onclick: () => run(theApp.undo(false)) }, '↶ Undo');
const redoBtn = h('button', { testid: 'redo', onclick: () => run(theApp.undo(true)) }, '↷ Redo');
fill(byId('history'), undoBtn, redoBtn);

// Display: the mesh shaded, see-through or hidden (M); control groups shown or hidden.
const kMeshLabels = { shaded: 'Shaded', xray: 'X-ray', hidden: 'Hidden' } as const;
const meshBtn = h('button', { title: 'Mesh: shaded, x-ray, hidden (M)', testid: 'mesh-display', onclick: () => cycleMesh() });
function renderMeshButton(): void {
  fill(meshBtn, `Mesh: ${kMeshLabels[viewport.meshDisplay]}`, h('kbd', {}, 'M'));
}
function cycleMesh(): void {
  const i = kMeshDisplays.indexOf(viewport.meshDisplay);
  viewport.setMeshDisplay(kMeshDisplays[(i + 1) % kMeshDisplays.length]!);
  renderMeshButton();
}
renderMeshButton();
const groupsMenu = h('div.groups-menu', { testid: 'groups-menu', hidden: true });
const groupsBtn = h('button', { title: 'Show or hide groups of controls', testid: 'groups', onclick: () => toggleGroups() }, 'Groups ▾');
function renderGroups(): void {
  fill(
    groupsMenu,
    ...viewport.groups().map((g) => {
      const box = h('input', { type: 'checkbox', checked: g.visible, testid: `group-${g.group}` });
      box.addEventListener('change', () => {
        viewport.setGroupVisible(g.group, box.checked);
        renderGroups();
      });
      return h('label.toggle', {}, box, `${g.group} (${g.controls})`);
    }),
    h('div.form-row', {},
      h('button.small', { testid: 'groups-all', onclick: () => { for (const g of viewport.groups()) viewport.setGroupVisible(g.group, true); renderGroups(); } }, 'Show all'),
      h('button.small', { testid: 'groups-none', onclick: () => { for (const g of viewport.groups()) viewport.setGroupVisible(g.group, false); renderGroups(); } }, 'Hide all')),
  );
}
function toggleGroups(): void {
  groupsMenu.hidden = !groupsMenu.hidden;
  if (!groupsMenu.hidden) renderGroups();
}
store.signals.characterChanged.add(() => {
  if (!groupsMenu.hidden) renderGroups();
});
const graphEditor = new GraphEditor(byId('graph-editor'), theApp);
const graphBtn = h('button', { title: 'Graph editor: the curves of the selection (G)', testid: 'toggle-graph', onclick: () => toggleGraph() }, 'Graph', h('kbd', {}, 'G'));
function toggleGraph(): void {
  graphEditor.visible = !graphEditor.visible;
  graphBtn.classList.toggle('active', graphEditor.visible);
}
// Motion trails of the selection (T) and ghosts of the skeleton (O); the timeline gives the range.
let overlaysRange: () => [number, number] = () => [0, 100];
const overlays = new Overlays(viewport, theApp, () => overlaysRange());
const trailBtn = h('button', { title: 'Motion trails of the selected controls over the playback range (T)', testid: 'toggle-trails', onclick: () => toggleTrails() }, 'Trail', h('kbd', {}, 'T'));
const ghostBtn = h('button', { title: 'Ghosts: the skeleton 2, 4 and 6 frames before (red) and after (green); again: at the keys; again: off (O)', testid: 'toggle-ghosts', onclick: () => toggleGhosts() }, 'Ghosts', h('kbd', {}, 'O'));
function toggleTrails(): void {
  overlays.setTrails(!overlays.showTrails);
  trailBtn.classList.toggle('active', overlays.showTrails);
}
// O cycles the ghosts: around the current frame, at the selection's keys, off.
function toggleGhosts(): void {
  const mode = overlays.ghostMode;
  overlays.setGhosts(mode !== 'keys', mode === 'off' ? false : mode === 'around');
  ghostBtn.classList.toggle('active', overlays.showGhosts);
  fill(ghostBtn, overlays.ghostMode === 'keys' ? 'Ghosts: keys' : 'Ghosts', h('kbd', {}, 'O'));
}
// Isolate selection (I): only the selected controls drawn and picked, until pressed again.
const isolateBtn = h('button', { title: 'Isolate the selected controls (I)', testid: 'isolate', onclick: () => toggleIsolate() }, 'Isolate', h('kbd', {}, 'I'));
function toggleIsolate(): void {
  if (viewport.isolated) viewport.setIsolated(null);
  else if (store.selection.length) viewport.setIsolated(store.selection);
  else statusBar.error('Isolate: select the controls to keep first');
  isolateBtn.classList.toggle('active', viewport.isolated !== null);
}
fill(byId('display'), meshBtn, h('span.menu-anchor', {}, groupsBtn, groupsMenu), isolateBtn, graphBtn, trailBtn, ghostBtn);
const contextMenu = new ContextMenu(byId('viewport'), viewport, theApp, () => toggleIsolate());
byId('viewport').append(h('div.grid-label', { title: 'The ground grid: 10 by 10 scene units' }, 'grid square: 0.5 units'));

const info = byId('info');
function renderToolbar(): void {
  const s = store.scene;
  for (const [mode, b] of modeButtons) {
    b.classList.toggle('active', s?.mode === mode);
    b.hidden = !!s?.modes?.length && !s.modes.includes(mode);
  }
  undoBtn.disabled = !s?.canUndo;
  redoBtn.disabled = !s?.canRedo;
  undoBtn.title = s?.canUndo ? `Undo ${statusBar.rename(s.undo ?? '')} (Ctrl+Z)` : 'Nothing to undo';
  redoBtn.title = s?.canRedo ? `Redo ${statusBar.rename(s.redo ?? '')} (Ctrl+Shift+Z)` : 'Nothing to redo';
  const label = kModeKeys.find((m) => m[0] === s?.mode)?.[2] ?? s?.mode ?? '—';
  const sel = s?.selection ?? [];
  const names = sel.map((u) => store.names.get(u) ?? u);
  const scope = store.shownScope();
  fill(
    info,
    h('span.pill', { testid: 'current-mode' }, 'Mode: ', h('b', {}, label)),
    h('span.pill', { testid: 'current-scope' }, 'Keying: ', h('b', {}, scope || '—')),
    h('span.pill', { testid: 'selection', title: names.join(', ') }, `Selected: ${names.length > 2 ? `${names.slice(0, 2).join(', ')} +${names.length - 2}` : names.join(', ') || 'none'}`),
    h('span.pill.dim', { testid: 'revision' }, `rev ${store.knownRevision}`),
  );
}
store.signals.sceneChanged.add(renderToolbar);
store.signals.selectionChanged.add(renderToolbar);
store.signals.timeChanged.add(renderToolbar);
store.signals.keysChanged.add(renderToolbar);

// -------------------------------------------------------------------- panels

const timeline = new Timeline(byId('timeline'), theApp);
overlaysRange = () => timeline.range();
const rigPanel = byId('rigs-panel');
const defPanel = byId('def-panel');
const channelPanel = byId('channel-panel');
const rigManager = new RigManager(rigPanel, theApp);
const editor = new DefinitionEditor(defPanel, theApp);
const buildPanel = byId('build-panel');
const buildGraph = new BuildGraphEditor(buildPanel, theApp);
const channelBox = new ChannelBox(channelPanel, theApp);
const toolsPanel = byId('tools-panel');
const animatorTools = new AnimatorTools(toolsPanel, theApp, () => timeline.range());
const pickerPanel = byId('picker-panel');
const picker = new Picker(pickerPanel, theApp);

const tabs = byId('tabs');
function showTab(which: 'channels' | 'picker' | 'rigs' | 'def' | 'build'): void {
  channelPanel.hidden = which !== 'channels';
  pickerPanel.hidden = which !== 'picker';
  picker.visible = which === 'picker';
  toolsPanel.hidden = which !== 'channels';
  rigPanel.hidden = which !== 'rigs';
  defPanel.hidden = which !== 'def';
  buildPanel.hidden = which !== 'build';
  buildGraph.visible = which === 'build';
  rigManager.visible = which === 'rigs';
  channelBox.visible = which === 'channels';
  if (which === 'channels') run(animatorTools.poses.refresh());
  byId('side').classList.toggle('wide', which === 'def');
  byId('side').classList.toggle('wider', which === 'build');
  for (const b of tabs.querySelectorAll<HTMLButtonElement>('button')) b.classList.toggle('active', b.dataset.tab === which);
}
fill(
  tabs,
  h('button', { dataset: { tab: 'channels' }, testid: 'tab-channels', onclick: () => showTab('channels') }, 'Channels'),
  h('button', { dataset: { tab: 'picker' }, testid: 'tab-picker', onclick: () => showTab('picker') }, 'Picker'),
  h('button', { dataset: { tab: 'rigs' }, testid: 'tab-rigs', onclick: () => showTab('rigs') }, 'Rig Manager'),
  h('button', { dataset: { tab: 'def' }, testid: 'tab-def', onclick: () => showTab('def') }, 'Definition Editor'),
  h('button', { dataset: { tab: 'build' }, testid: 'tab-build', onclick: () => showTab('build') }, 'Build Graph'),
);
showTab('rigs');
rigManager.openDefinition = (rig) => {
  showTab('def');
  run(editor.open(rig));
};

// ------------------------------------------------------------------ keyboard

// A button clicked with the mouse gives the focus back, so that Space and the
// other shortcuts reach the app instead of pressing that button again.
document.addEventListener('pointerup', (e) => {
  const b = (e.target as HTMLElement | null)?.closest?.('button');
  if (b) window.setTimeout(() => b.blur(), 0);
});

// The help overlay (?): every shortcut, from the one list the keyboard handler follows.
const kShortcuts: [string, string][] = [
  ...kModeKeys.map(([, key, label]): [string, string] => [key, `${label} mode`]),
  ['W / E', 'Move / rotate gizmo'],
  ['S / Shift+S', 'Set key / delete key'],
  ['K', 'Auto-key on / off'],
  ['Space', 'Play / stop'],
  ['← / →', 'Previous / next frame'],
  ['F / A', 'Frame the selection / frame all'],
  ['I', 'Isolate the selection (again: show all)'],
  ['Ctrl+drag / Ctrl+Shift+drag', 'Box select / add to the selection'],
  ['M', 'Mesh: shaded, x-ray, hidden'],
  ['T / O', 'Motion trails on or off / ghosts around the frame, at the keys, off'],
  ['G', 'Graph editor (in it: A frame all, F frame selected, I insert key, Delete delete keys)'],
  ['Esc', 'Clear the selection (or close this)'],
  ['Ctrl+Z / Ctrl+Shift+Z', 'Undo / redo'],
  ['Click / Shift+click', 'Select a control / add or remove it'],
  ['Right-click a control', 'Its actions: key, bind pose, match, spaces, mirror, frame, isolate'],
  ['?', 'This help'],
];
const help = h(
  'div.help-overlay',
  { testid: 'help', hidden: true, onclick: () => (help.hidden = true) },
  h('div.help-box', {}, h('h2', {}, 'Shortcuts'),
    h('table', {}, ...kShortcuts.map(([k, what]) => h('tr', {}, h('td', {}, h('kbd', {}, k)), h('td', {}, what))))),
);
document.body.append(help);

window.addEventListener('keydown', (e) => {
  if (typingTarget(e.target)) return;
  if (e.key === '?') {
    e.preventDefault();
    help.hidden = !help.hidden;
    return;
  }
  if (!help.hidden && e.key === 'Escape') {
    e.preventDefault();
    help.hidden = true;
    return;
  }
  const ctrl = e.ctrlKey || e.metaKey;
  const k = e.key.toLowerCase();
  if (ctrl && k === 'z') {
    e.preventDefault();
    run(theApp.undo(e.shiftKey));
    return;
  }
  if (ctrl && k === 'y') {
    e.preventDefault();
    run(theApp.undo(true));
    return;
  }
  if (ctrl || e.altKey) return;
  const mode = kModeKeys.find((m) => m[1] === e.key);
  if (mode) {
    e.preventDefault();
    run(theApp.setMode(mode[0]));
    return;
  }
  switch (k) {
    case 'w':
      setGizmo('translate');
      break;
    case 'm':
      cycleMesh();
      break;
    case 'g':
      toggleGraph();
      break;
    case 't':
      toggleTrails();
      break;
    case 'o':
      toggleGhosts();
      break;
    case 'e':
      setGizmo('rotate');
      break;
    case 's':
      run(theApp.key(e.shiftKey));
      break;
    case 'k':
      run(theApp.setAutoKey(!store.scene?.autoKey));
      break;
    case ' ':
      if ((e.target as HTMLElement | null)?.closest?.('#def-panel, #build-panel')) return;
      timeline.toggle();
      break;
    case 'arrowleft':
      timeline.stepFrame(-1);
      break;
    case 'arrowright':
      timeline.stepFrame(1);
      break;
    case 'f':
      viewport.frameSelected();
      break;
    case 'a':
      viewport.frameAll();
      break;
    case 'i':
      toggleIsolate();
      break;
    case 'escape':
      run(theApp.select([], false));
      break;
    default:
      return;
  }
  e.preventDefault();
});

// ------------------------------------------------------------------ test hook

interface RigelHook {
  ready: Promise<void>;
  isReady: () => boolean;
  /** True when no request, refresh, gesture, definition or graph build is in flight. */
  settled: () => boolean;
  app: App;
  store: Store;
  viewport: Viewport;
  timeline: Timeline;
  editor: DefinitionEditor;
  /** The build-graph editor (its model, idOf(title), builds, problems). */
  buildGraph: BuildGraphEditor;
  channelBox: ChannelBox;
  graphEditor: GraphEditor;
  overlays: Overlays;
  contextMenu: ContextMenu;
  /** Client pixels where clicking picks the control (by uuid or name), or null. */
  project: (control: string, rightClick?: boolean) => { x: number; y: number } | null;
  /** Client pixels of a world point. */
  toScreen: (p: Vec3) => { x: number; y: number; visible: boolean };
  gizmoHandle: (axis: 'x' | 'y' | 'z') => { x: number; y: number; dx: number; dy: number } | null;
  uuidOf: (name: string) => string | null;
  stats: () => FrameStats & { drag: App['drag']['stats'] };
  errors: string[];
}

declare global {
  interface Window {
    rigel: RigelHook;
  }
}

const uuidOf = (name: string): string | null => store.byName.get(name) ?? (store.names.has(name) ? name : null);
window.rigel = {
  ready: theApp.ready,
  isReady: () => theApp.isReady,
  settled: () => theApp.settled() && editor.idle() && buildGraph.idle() && !timeline.busy() && !channelBox.busy && !graphEditor.busy && !picker.busy && !overlays.busy,
  app: theApp,
  store,
  viewport,
  timeline,
  editor,
  buildGraph,
  channelBox,
  graphEditor,
  overlays,
  contextMenu,
  project: (control, rightClick = false) => {
    const u = uuidOf(control);
    return u ? viewport.project(u, rightClick) : null;
  },
  toScreen: (p) => viewport.toScreen(p),
  gizmoHandle: (axis) => viewport.gizmoHandle(axis),
  uuidOf,
  stats: () => ({ ...viewport.stats(), drag: { ...theApp.drag.stats } }),
  errors: statusBar.errors,
};

async function boot(): Promise<void> {
  statusBar.info('Loading the scene…');
  await theApp.start(() => viewport.frameAll());
  await editor.loadSchemas();
}
boot().catch((e: unknown) => {
  statusBar.caught(e);
  statusBar.error(`The app could not start: ${e instanceof Error ? e.message : String(e)}`);
});
