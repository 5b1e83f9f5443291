// The build graph's types (docs/BUILD_GRAPH.md, docs/SERVER.md "Build graphs"):
// a `.build.json` file's object, the palette, and the graph routes' answers
// (api.ts declares the routes and re-exports these).

import type { ComponentJson, Problem, Revised } from './api';

/** A data type of build graph sockets (GET /api/graph/palette). */
export interface GraphType {
  name: string;
  /** The socket's colour, "#rrggbb". */
  color: string;
  /** True when a constant or a variable can hold it. */
  value: boolean;
  /** True when a graph variable can hold it: the value types, their lists, and component (none until a Set gives it one). */
  variable?: boolean;
  /** A list type's element type ("list:number" -> "number"); "" for the others. */
  element?: string;
  help: string;
}

/** A socket of a node kind: `exec` orders nodes; `$variable` is the type of the node's variable. */
export interface GraphSocket {
  name: string;
  type: string;
  help: string;
  default?: unknown;
}

/** A node kind of the palette: start, component:TYPE, constant:TYPE, variable:get|set, branch, forEach:TYPE, graph:PATH, function:ID. */
export interface GraphKind {
  id: string;
  niceName: string;
  category: string;
  help: string;
  inputs: GraphSocket[];
  outputs: GraphSocket[];
}

export interface GraphPaletteAnswer {
  types: GraphType[];
  kinds: GraphKind[];
}

/** A node of a `.build.json` (docs/BUILD_GRAPH.md). */
export interface BuildGraphNodeJson {
  id: string;
  kind: string;
  position?: [number, number];
  component?: ComponentJson;
  value?: unknown;
  values?: Record<string, unknown>;
  variable?: string;
  rigId?: string;
  [k: string]: unknown;
}

/** The rig's settings in a `.build.json`: as in a `.rig.json`, without components. */
export interface GraphRigJson {
  name?: string;
  version?: string;
  geometry?: { file: string; name?: string }[];
  [k: string]: unknown;
}

/** A `.build.json` file's object: what the graph routes take and give. */
export interface BuildGraphJson {
  buildGraph: {
    format: number;
    rig: GraphRigJson;
    variables?: { name: string; type: string; value: unknown; [k: string]: unknown }[];
    nodes: BuildGraphNodeJson[];
    /** "NODE.OUTPUT" -> "NODE.INPUT" (a node id may hold dots, a socket name none). */
    links: { from: string; to: string }[];
    [k: string]: unknown;
  };
}

/** A problem of a graph, on its node (and socket) when it has one. */
export interface GraphProblem extends Problem {
  node?: string;
  socket?: string;
}

export interface GraphFilesAnswer {
  /** `.build.json` files under the root, relative to it. */
  files: string[];
}

export interface GraphOpenAnswer {
  /** The file (relative to the root, or absolute); '' when a rig's definition was converted. */
  path: string;
  graph: BuildGraphJson;
  /** True when the graph was made from a rig's definition (it had no graph file). */
  converted?: boolean;
}

export interface GraphValidateAnswer {
  ok: boolean;
  problems: GraphProblem[];
  warnings: GraphProblem[];
  /** The node ids the exec chain runs, in order. */
  order: string[];
  /** rigId -> the node it comes from (a for-each body's node has one per item, a sub-graph node one per component). */
  rigIds: Record<string, string>;
}

export interface GraphBuildAnswer extends Revised {
  rig: string;
  /** The rigIds (re)built. */
  rebuilt?: string[];
  rigIds?: Record<string, string>;
}

export interface GraphSaveAnswer {
  /** Absolute. */
  path: string;
  version: string;
  problems?: GraphProblem[];
}
