// The answer and request types of the JSON API's animator views (the graph
// editor, the picker and selection sets, motion trails and ghosts, the pose
// library, spaces, transfer and export): declared here beside api.ts, which
// re-exports them with its methods for these routes, so every route's types
// are still read from './api'.

import type { Revised, Vec3 } from './api';

// ----------------------------------------------------------- animator tools

export interface PoseInfo {
  name: string;
  rig: string;
  entries: number;
  error?: string;
  /** A thumbnail (NAME.pose.svg) is beside it. */
  thumbnail?: boolean;
}

export interface PoseApplyRequest {
  library: string;
  name: string;
  controls?: string[];
  mirror?: boolean;
  fraction?: number;
  key?: boolean;
}

export interface SpacesAnswer extends Revised {
  control: string;
  spaces: { name: string; target: string | null }[];
  current: string | null;
}

export interface ExportAnswer {
  path: string;
  nodes: number;
  meshes: number;
  skins: number;
  animations: number;
  channels: number;
  baked: boolean;
}

// ------------------------------------------------------ picker and sets

export interface PickerGroup {
  rig: string;
  name: string;
  part: 'head' | 'arm' | 'hand' | 'torso' | 'leg' | 'tail' | 'root' | 'other';
  side: 'L' | 'R' | 'C';
  controls: { uuid: string; name: string; label: string }[];
}

export interface PickerAnswer extends Revised {
  groups: PickerGroup[];
}

export interface SelectionSetInfo {
  name: string;
  members: { uuid: string; name: string }[];
  missing: string[];
}

export interface SelectionSetsAnswer extends Revised {
  sets: SelectionSetInfo[];
  /** After a POST: the selection. */
  selection?: string[];
}

export interface SelectionSetRequest {
  op: 'save' | 'remove' | 'select';
  name: string;
  controls?: string[];
  add?: boolean;
}

// ------------------------------------------------- motion trails and ghosts

export interface TrailInfo {
  control: string;
  name: string;
  frames: number[];
  points: Vec3[];
  keys: number[];
}

export interface TrailsAnswer extends Revised {
  trails: TrailInfo[];
}

export interface GhostsAnswer extends Revised {
  joints: string[];
  /** Each joint's parent: an index into joints, -1 for a root. */
  parents: number[];
  frames: { frame: number; points: Vec3[] }[];
}

// -------------------------------------------------------------- graph editor

/** One curve of GET /api/curves: keys, tangents (curves only; slopes per frame) and samples. */
export interface CurveInfo {
  /** The channel plug it drives: what /api/curve-keys names it by. */
  plug: string;
  curve: string;
  kind: 'curve' | 'vectorTrack' | 'rotationTrack';
  component: number;
  label: string;
  /** Whether key values can be edited (not a glTF rotation track's). */
  editable: boolean;
  frames: number[];
  values: number[];
  inTangents?: string[];
  outTangents?: string[];
  inSlopes?: number[];
  outSlopes?: number[];
  samples: { frames: number[]; values: number[] };
}

export interface CurvesAnswer extends Revised {
  fps: number;
  curves: CurveInfo[];
}

export interface CurvesRequest {
  controls: string[];
  first?: number;
  last?: number;
  step?: number;
  euler?: boolean;
}

export interface CurveKeyEdit {
  curve: string;
  frame: number;
  toFrame?: number;
  value?: number;
  component?: number;
  tangent?: string;
  inTangent?: string;
  outTangent?: string;
  inSlope?: number;
  outSlope?: number;
}

export interface CurveKeysRequest {
  op: 'edit' | 'insert' | 'delete';
  keys: CurveKeyEdit[];
}

export interface CurveKeysAnswer extends Revised {
  changed: number;
}

/** GET /api/shape: a control's look (what Copy shape / Copy colour keep). */
export interface ShapeInfo {
  control: string;
  name: string;
  points: Vec3[];
  closed: boolean;
  color: Vec3;
}

export interface NodeRef {
  uuid: string;
  name: string;
}

/** POST /api/shape. */
export interface ShapeEditRequest {
  op: 'paste' | 'mirror' | 'flip' | 'opposite';
  controls?: string[];
  shape?: { points: Vec3[]; closed: boolean; color: Vec3 };
  parts?: ('shape' | 'color')[];
}

export interface ShapeEditAnswer extends Revised {
  controls: NodeRef[];
  pairs?: { from: string; to: string }[];
}
