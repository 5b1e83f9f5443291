// The JSON API of `rigel serve` (docs/SERVER.md), one typed method per
// route with its request and answer types next to it (the animator views'
// types in apiviews.ts, re-exported here): no other file names a route or
// declares what an answer holds. Every request goes through one
// client (http.ts), so every error reaches the status bar and every change
// the tab makes is recorded as its own revision.

import { ApiError, Http } from './http';
import type { ApiEvents, RequestOptions } from './http';

export { ApiError };
export * from './apiviews';
import type {
  CurveKeysAnswer,
  CurveKeysRequest,
  CurvesAnswer,
  CurvesRequest,
  ExportAnswer,
  GhostsAnswer,
  NodeRef,
  PickerAnswer,
  PoseApplyRequest,
  PoseInfo,
  SelectionSetRequest,
  SelectionSetsAnswer,
  ShapeEditAnswer,
  ShapeEditRequest,
  ShapeInfo,
  SpacesAnswer,
  TrailsAnswer,
} from './apiviews';
export type { ApiEvents, RequestOptions };

export type Vec3 = [number, number, number];
export type Quat = [number, number, number, number];
/** Local (or world) TRS of a node: [tx, ty, tz, qx, qy, qz, qw, sx, sy, sz]. */
export type Trs = [number, number, number, number, number, number, number, number, number, number];

/** What every answer of a change carries: the scene's new revision. */
export interface Revised {
  revision: number;
}

// ------------------------------------------------------------------ the scene

export interface SceneInfo {
  revision: number;
  path: string | null;
  fps: number;
  frame: number;
  time: number;
  range: [number, number];
  /** The playback range the animator set (saved with the scene), or null. */
  playbackRange?: [number, number] | null;
  mode: string;
  modes: string[];
  autoKey: boolean;
  canUndo: boolean;
  canRedo: boolean;
  undo: string | null;
  redo: string | null;
  selection: string[];
  /** The served folder (absolute): request paths are relative to it. */
  root?: string;
  /** The character file the scene was opened from (absolute), or null. */
  character?: string | null;
  /** Keying scope per ephemeral rig. */
  keyScopes?: Record<string, string>;
}

export interface NodeInfo {
  uuid: string;
  name: string;
  type: string;
  parent: string | null;
}

export interface ControlShape {
  points: Vec3[];
  closed: boolean;
  color: Vec3;
}

export interface ControlInfo {
  uuid: string;
  name: string;
  joint: string | null;
  rig: string;
  ephemeral: boolean;
  /** What it is shown and hidden with: a built rig's component, an ephemeral rig's region ("face_ctrl"). */
  group: string;
  shape: ControlShape;
}

export interface NodesAnswer {
  revision: number;
  nodes: NodeInfo[];
  controls: ControlInfo[];
}

export interface PoseAnswer {
  revision: number;
  frame?: number;
  time?: number;
  space?: string;
  /** Every transform node (GET /api/pose), or only those a drag changed. */
  nodes: Record<string, Trs>;
}

// ---------------------------------------------------------- posing and time

export interface SelectRequest {
  /** Uuids (or names) of controls. */
  controls: string[];
  /** Add to the selection instead of replacing it. */
  add?: boolean;
}
export interface SelectAnswer extends Revised {
  selection: string[];
}

export interface ModeAnswer extends Revised {
  mode: string;
}

export interface OptionsRequest {
  autoKey?: boolean;
  magnetFraction?: number;
  magnetRadius?: number;
  maxChain?: number;
}
export interface OptionsAnswer {
  autoKey?: boolean;
  magnetFraction?: number;
  magnetRadius?: number;
  maxChain?: number;
}

export interface DragRequest {
  control: string;
  /** Where the grabbed control goes, in world space. */
  to: { t: Vec3; q: Quat };
}
/** The nodes whose local transform the drag changed. */
export interface DragAnswer extends PoseAnswer {
  notes?: string[];
}

export interface HistoryAnswer extends Revised {
  label: string;
}

export type TimeRequest = { frame: number } | { time: number };
export interface TimeAnswer extends Revised {
  frame: number;
  time: number;
}

export interface KeysAnswer {
  /** null when no controls were asked for and nothing is selected. */
  scope: string | null;
  frames: number[];
  times: number[];
}

export interface KeyRequest {
  /** Default: the selection. */
  controls?: string[];
  delete?: boolean;
}
export interface KeyAnswer extends Revised {
  frames: number[];
}

/** Where a channel has keys: at the current frame, at other frames only, or none. */
export type KeyedState = 'here' | 'elsewhere' | 'none';

/** One row of the channel box (GET /api/channels). */
export interface ChannelRow {
  /** The node that has the channel: the control, or its component's switch. */
  node: string;
  /** What /api/channel-values takes ("translateX", "fkIk"). */
  attr: string;
  /** What /api/channel-keys keys ("translate", "fkIk"). */
  keyAttr: string;
  plug: string;
  value: number;
  keyed: KeyedState;
}

export interface ChannelsAnswer extends Revised {
  frame: number;
  controls: { control: string; channels: ChannelRow[] }[];
}

export interface ChannelValuesRequest {
  controls: string[];
  attrs: string[];
  value: number;
}

export interface ChannelValuesAnswer extends Revised {
  channels: { plug: string; value: number }[];
  keys: { plug: string; frames: number[] }[];
}

export interface MatchRequest {
  rig: string;
  component: string;
  to: 'fk' | 'ik';
  /** Bake over these frames (default: the current frame). */
  frames?: [number, number];
}

export interface MatchAnswer extends Revised {
  frames: number;
  keys: number;
  controls: string[];
  maxError: number;
}

export interface MirrorRequest {
  controls: string[];
  all?: boolean;
  flip?: boolean;
}

export interface ToolAnswer extends Revised {
  set?: string[];
  keys?: unknown;
}

export interface TweenRequest {
  controls: string[];
  fraction: number;
}

export interface ChannelKeysRequest {
  controls: string[];
  /** Without: the controls' keying group. */
  attrs?: string[];
  delete?: boolean;
  /** Move (or with `copy` copy) the keys at `from` (default: the current frame) to this frame. */
  moveTo?: number;
  from?: number;
  copy?: boolean;
}

export interface ChannelKeysAnswer extends Revised {
  keys: { plug: string; frames: number[] }[];
}

// ---------------------------------------------------------------------- rigs

export interface RigComponentInfo {
  name: string;
  type: string;
  version: string;
  rigId: string;
  parent?: string;
  nodes?: number;
  /** The component's version in the definition on disk (null: not in it, or no definition). */
  definitionVersion?: string | null;
  /** current, changed (its definition differs), removed (gone from the definition), added. */
  state?: 'current' | 'changed' | 'removed' | 'added';
  outOfDate?: boolean;
}

export interface RigFeature {
  feature: string;
  switch: string;
  enabled: boolean;
}

export interface RigInfo {
  name: string;
  version: string;
  definition: string;
  definitionVersion: string | null;
  outOfDate: boolean;
  editMode: boolean;
  buildPosition: number;
  steps: number;
  /** Features the rig's build steps name (seed 003), with their state. */
  features?: RigFeature[];
  components: RigComponentInfo[];
  /** Components the definition has and the rig has not built yet. */
  added?: RigComponentInfo[];
  /** False when the definition file cannot be read; `definitionProblem` says why. */
  definitionFound?: boolean;
  definitionProblem?: string | null;
}

export interface RigsAnswer {
  rigs: RigInfo[];
}

export interface RigAddRequest {
  /** A definition file, relative to the server root. */
  definition: string;
  editMode?: boolean;
}
export interface RigAddAnswer extends Revised {
  rig: string;
  version: string;
  steps?: number;
  components?: unknown[];
}

export interface RigUpdateRequest {
  rig: string;
  keepKeys?: 'local' | 'world';
  force?: boolean;
}
export interface RigUpdateAnswer extends Revised {
  from: string;
  to: string;
  rebuilt?: string[];
}

export interface RigRequest {
  rig: string;
}

export interface RigEditRequest {
  rig: string;
  /** Where the committed definition goes (default: the rig's own file). */
  definitionOut?: string;
  keepEditing?: boolean;
}
export interface RigEditAnswer {
  rig: string;
  version: string;
  changed?: unknown;
  ignored?: unknown;
  definition?: string;
  editMode?: boolean;
}

export interface RigEditModeRequest {
  rig: string;
  on: boolean;
}
export interface RigEditModeAnswer extends Revised {
  rig: string;
  editMode: boolean;
}

export interface RigFeatureRequest {
  rig: string;
  feature: string;
  enabled: boolean;
  switch?: string;
}
export interface RigFeatureAnswer extends Revised {
  rig: string;
  features?: RigFeature[];
  position?: number;
  steps?: number;
}

export interface StepRequest {
  rig: string;
  /** Go to this step (0: nothing built). */
  to?: number;
  /** Or move by ±1. */
  by?: number;
}
export interface StepAnswer extends Revised {
  position: number;
  steps: number;
  step: string;
  /** The rigId of the component whose step was built last ("" at 0 or for the rig's own step; the build-graph editor marks its node). */
  rigId: string;
}

// --------------------------------------------------------------- definitions

export interface ParamSchema {
  name: string;
  type: 'bool' | 'int' | 'double' | 'string' | 'enum' | 'vec3';
  default: unknown;
  min?: number;
  max?: number;
  choices?: string[];
  help?: string;
}

export interface ComponentSchema {
  type: string;
  help: string;
  params: ParamSchema[];
  guides: { min: number; max: number; names: string[]; help: string };
  controls: { role: string; shape: string; color: string; size: number; help: string }[];
  hooks: string[];
  features: string[];
  rootOnly: boolean;
  needsParent: boolean;
}

export interface ComponentsAnswer {
  components: ComponentSchema[];
}

/** A component in the `.rig.json` form of a definition. */
export interface ComponentJson {
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

/** A definition in its `.rig.json` form (what the definition routes take and give). */
export interface RigJson {
  rig: {
    name?: string;
    version?: string;
    guiLocation?: [number, number];
    geometry?: { file: string; name?: string }[];
    components?: ComponentJson[];
    [k: string]: unknown;
  };
}

export interface DefinitionAnswer {
  rig: string;
  /** The definition's file, relative to the root (or absolute), '' when none. */
  path: string;
  definition: RigJson;
}

export interface Problem {
  where: string;
  message: string;
}

export interface DefinitionRequest {
  definition: RigJson;
}
export interface ValidateAnswer {
  ok: boolean;
  problems: Problem[];
}

export interface BuildAnswer extends Revised {
  rig: string;
  /** docs/SERVER.md says `components`; the server answers `rebuilt` (rigIds). */
  components?: unknown[];
  rebuilt?: string[];
}

export interface SaveDefinitionRequest {
  definition: RigJson;
  /** `.rig.xml` or `.rig.json`, relative to the root. */
  path: string;
}
export interface SaveDefinitionAnswer {
  /** Absolute. */
  path: string;
  version: string;
}

// --------------------------------------------------------------- build graphs
// The .build.json object and the graph routes' answers: graphtypes.ts.
export type * from './graphtypes';
import type { BuildGraphJson, GraphBuildAnswer, GraphFilesAnswer, GraphOpenAnswer } from './graphtypes';
import type { GraphPaletteAnswer, GraphSaveAnswer, GraphValidateAnswer } from './graphtypes';

// -------------------------------------------------------------------- routes

const q = encodeURIComponent;

/** The client: one method per route of docs/SERVER.md that the page uses. */
export class Api {
  private readonly http: Http;

  constructor(base: string, token: string | null, events: ApiEvents) {
    this.http = new Http(base, token, events);
  }

  /** Requests in flight but the background ones (the page is settled at 0). */
  get pending(): number {
    return this.http.pending;
  }

  /** POSTs in flight (the revision poller waits for them). */
  get pendingWrites(): number {
    return this.http.pendingWrites;
  }

  // the scene

  /** The revision poller's question: always in the background. */
  revision(): Promise<Revised> {
    return this.http.get('/api/revision', { background: true });
  }

  scene(): Promise<SceneInfo> {
    return this.http.get('/api/scene');
  }

  /** The scene as binary glTF (every node's `extras.uuid` names its rigel node). */
  characterGlb(): Promise<ArrayBuffer> {
    return this.http.bytes('/api/character.glb');
  }

  nodes(): Promise<NodesAnswer> {
    return this.http.get('/api/nodes');
  }

  /** The local pose of every transform node. */
  pose(): Promise<PoseAnswer> {
    return this.http.get('/api/pose');
  }

  // posing

  select(req: SelectRequest): Promise<SelectAnswer> {
    return this.http.post('/api/select', req);
  }

  mode(mode: string): Promise<ModeAnswer> {
    return this.http.post('/api/mode', { mode });
  }

  options(req: OptionsRequest): Promise<OptionsAnswer> {
    return this.http.post('/api/options', req);
  }

  drag(req: DragRequest): Promise<DragAnswer> {
    return this.http.post('/api/drag', req);
  }

  /** Ends the gesture: one undo step. */
  release(): Promise<Revised> {
    return this.http.post('/api/release', {});
  }

  /** 409 when there is nothing to undo (`options.expected` keeps it off the status bar). */
  undo(options: RequestOptions = {}): Promise<HistoryAnswer> {
    return this.http.post('/api/undo', {}, options);
  }

  redo(options: RequestOptions = {}): Promise<HistoryAnswer> {
    return this.http.post('/api/redo', {}, options);
  }

  // time and keys

  time(req: TimeRequest): Promise<TimeAnswer> {
    return this.http.post('/api/time', req);
  }

  /** The keys of the keying set of `controls` (uuids or names). */
  keys(controls: string[]): Promise<KeysAnswer> {
    return this.http.get(`/api/keys?controls=${controls.map(q).join(',')}`);
  }

  key(req: KeyRequest): Promise<KeyAnswer> {
    return this.http.post('/api/key', req);
  }

  /** The channel box of `controls` (names or uuids). */
  channels(controls: string[]): Promise<ChannelsAnswer> {
    return this.http.get(`/api/channels?controls=${controls.map(q).join(',')}`);
  }

  channelValues(req: ChannelValuesRequest): Promise<ChannelValuesAnswer> {
    return this.http.post('/api/channel-values', req);
  }

  channelKeys(req: ChannelKeysRequest): Promise<ChannelKeysAnswer> {
    return this.http.post('/api/channel-keys', req);
  }

  // scene settings

  playbackRange(req: { first: number; last: number }): Promise<Revised & { playbackRange: [number, number] }> {
    return this.http.post('/api/playback-range', req);
  }

  // picker and selection sets

  picker(): Promise<PickerAnswer> {
    return this.http.get('/api/picker');
  }

  selectionSets(): Promise<SelectionSetsAnswer> {
    return this.http.get('/api/selection-sets');
  }

  selectionSet(req: SelectionSetRequest): Promise<SelectionSetsAnswer> {
    return this.http.post('/api/selection-sets', req);
  }

  // motion trails and ghosts (background: they follow edits, never block one)

  trails(controls: string[], first: number, last: number, step = 1): Promise<TrailsAnswer> {
    return this.http.get(`/api/trails?controls=${controls.map(q).join(',')}&first=${first}&last=${last}&step=${step}`, { background: true });
  }

  /** Ghosts around the current frame, or (atKeys) at the selection's keys. */
  ghosts(before: number, after: number, step: number, atKeys = false): Promise<GhostsAnswer> {
    const query = atKeys ? 'keys=1' : `before=${before}&after=${after}&step=${step}`;
    return this.http.get(`/api/ghosts?${query}`, { background: true });
  }

  // graph editor

  curves(req: CurvesRequest): Promise<CurvesAnswer> {
    let target = `/api/curves?controls=${req.controls.map(q).join(',')}`;
    if (req.first !== undefined) target += `&first=${req.first}`;
    if (req.last !== undefined) target += `&last=${req.last}`;
    if (req.step !== undefined) target += `&step=${req.step}`;
    if (req.euler !== undefined) target += `&euler=${req.euler ? 1 : 0}`;
    return this.http.get(target);
  }

  curveKeys(req: CurveKeysRequest): Promise<CurveKeysAnswer> {
    return this.http.post('/api/curve-keys', req);
  }

  // animator tools

  match(req: MatchRequest): Promise<MatchAnswer> {
    return this.http.post('/api/match', req);
  }

  mirror(req: MirrorRequest): Promise<ToolAnswer> {
    return this.http.post('/api/mirror', req);
  }

  bindPose(controls: string[]): Promise<ToolAnswer> {
    return this.http.post('/api/bind-pose', { controls });
  }

  poses(library: string, options: RequestOptions = {}): Promise<Revised & { poses: PoseInfo[] }> {
    return this.http.get(`/api/poses?library=${q(library)}`, options);
  }

  /** A saved pose's SVG thumbnail (the skeleton in the pose, from the front). */
  poseThumbnail(library: string, name: string): Promise<ArrayBuffer> {
    return this.http.bytes(`/api/poses/thumbnail?library=${q(library)}&name=${q(name)}`);
  }

  savePose(req: { library: string; name: string; controls?: string[] }): Promise<Revised & { name: string; entries: number }> {
    return this.http.post('/api/poses/save', req);
  }

  applyPose(req: PoseApplyRequest): Promise<ToolAnswer> {
    return this.http.post('/api/poses/apply', req);
  }

  removePose(req: { library: string; name: string }): Promise<Revised> {
    return this.http.post('/api/poses/remove', req);
  }

  // Rigger actions (docs/SERVER.md "Rigger actions").
  shape(control: string): Promise<ShapeInfo> {
    return this.http.get(`/api/shape?control=${q(control)}`);
  }

  shapeEdit(req: ShapeEditRequest): Promise<ShapeEditAnswer> {
    return this.http.post('/api/shape', req);
  }

  align(req: { nodes?: string[]; target: string; position?: boolean; rotation?: boolean }): Promise<Revised & { moved: NodeRef[] }> {
    return this.http.post('/api/align', req);
  }

  locators(req: { nodes?: string[]; size?: number }): Promise<Revised & { locators: NodeRef[] }> {
    return this.http.post('/api/locators', req);
  }

  mirrorJoints(req: { joints?: string[]; update?: boolean }): Promise<Revised & { created: NodeRef[]; updated: NodeRef[] }> {
    return this.http.post('/api/mirror-joints', req);
  }

  spaces(control: string): Promise<SpacesAnswer> {
    return this.http.get(`/api/spaces?control=${q(control)}`);
  }

  switchSpace(req: { control: string; switch: string; frame?: number; frames?: [number, number] }): Promise<ToolAnswer & { from: string; to: string; maxError: number }> {
    return this.http.post('/api/space', req);
  }

  transfer(req: { from: string; to: string; offset?: number }): Promise<ToolAnswer & { channels: number }> {
    return this.http.post('/api/transfer', req);
  }

  exportGltf(req: { path: string; deformOnly?: boolean; bake?: boolean }): Promise<ExportAnswer> {
    return this.http.post('/api/export', req);
  }

  tween(req: TweenRequest): Promise<ToolAnswer> {
    return this.http.post('/api/tween', req);
  }

  // rigs

  rigs(options: RequestOptions = {}): Promise<RigsAnswer> {
    return this.http.get('/api/rigs', options);
  }

  rigAdd(req: RigAddRequest): Promise<RigAddAnswer> {
    return this.http.post('/api/rigs/add', req);
  }

  rigUpdate(req: RigUpdateRequest): Promise<RigUpdateAnswer> {
    return this.http.post('/api/rigs/update', req);
  }

  rigRemove(req: RigRequest): Promise<Revised> {
    return this.http.post('/api/rigs/remove', req);
  }

  /** Commits rig edit mode (moved controls become guides). */
  rigEdit(req: RigEditRequest): Promise<RigEditAnswer> {
    return this.http.post('/api/rigs/edit', req);
  }

  rigEditMode(req: RigEditModeRequest): Promise<RigEditModeAnswer> {
    return this.http.post('/api/rigs/edit-mode', req);
  }

  rigFeature(req: RigFeatureRequest): Promise<RigFeatureAnswer> {
    return this.http.post('/api/rigs/feature', req);
  }

  rigStep(req: StepRequest): Promise<StepAnswer> {
    return this.http.post('/api/rigs/step', req);
  }

  // definitions

  components(): Promise<ComponentsAnswer> {
    return this.http.get('/api/components');
  }

  /** The definition rig `rig` was built from. */
  definition(rig: string): Promise<DefinitionAnswer> {
    return this.http.get(`/api/definition?rig=${q(rig)}`);
  }

  validateDefinition(req: DefinitionRequest): Promise<ValidateAnswer> {
    return this.http.post('/api/definition/validate', req);
  }

  buildDefinition(req: DefinitionRequest): Promise<BuildAnswer> {
    return this.http.post('/api/definition/build', req);
  }

  saveDefinition(req: SaveDefinitionRequest): Promise<SaveDefinitionAnswer> {
    return this.http.post('/api/definition/save', req);
  }

  // build graphs

  graphPalette(): Promise<GraphPaletteAnswer> {
    return this.http.get('/api/graph/palette');
  }

  graphFiles(): Promise<GraphFilesAnswer> {
    return this.http.get('/api/graph/files');
  }

  /** A `.build.json` file (relative to the root). */
  graphFile(path: string): Promise<GraphOpenAnswer> {
    return this.http.get(`/api/graph?path=${q(path)}`);
  }

  /** The graph of a scene's rig: its graph file, or its definition converted. */
  graphOfRig(rig: string): Promise<GraphOpenAnswer> {
    return this.http.get(`/api/graph?rig=${q(rig)}`);
  }

  validateGraph(graph: BuildGraphJson): Promise<GraphValidateAnswer> {
    return this.http.post('/api/graph/validate', { graph });
  }

  buildGraph(graph: BuildGraphJson): Promise<GraphBuildAnswer> {
    return this.http.post('/api/graph/build', { graph });
  }

  saveGraph(graph: BuildGraphJson, path: string): Promise<GraphSaveAnswer> {
    return this.http.post('/api/graph/save', { graph, path });
  }
}
