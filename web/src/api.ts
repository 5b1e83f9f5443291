// The JSON API of `rigel serve` (docs/SERVER.md): typed answers and one
// client that every panel goes through, so that every error reaches the
// status bar and every change the tab makes is recorded as its own revision.

export type Vec3 = [number, number, number];
export type Quat = [number, number, number, number];
/** Local (or world) TRS of a node: [tx, ty, tz, qx, qy, qz, qw, sx, sy, sz]. */
export type Trs = [number, number, number, number, number, number, number, number, number, number];

export interface SceneInfo {
  revision: number;
  path: string | null;
  fps: number;
  frame: number;
  time: number;
  range: [number, number];
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
  nodes: Record<string, Trs>;
}

export interface KeysAnswer {
  /** null when no controls were asked for and nothing is selected. */
  scope: string | null;
  frames: number[];
  times: number[];
}

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

export interface RigFeature {
  feature: string;
  switch: string;
  enabled: boolean;
}

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

export interface StepAnswer {
  revision: number;
  position: number;
  steps: number;
  step: string;
}

/** An answer of the API with a 4xx/5xx status, or a request that never got one. */
export class ApiError extends Error {
  constructor(
    readonly route: string,
    readonly status: number,
    message: string,
    readonly field: string | null,
  ) {
    super(message);
    this.name = 'ApiError';
  }

  /**
   * The text the status bar shows: route, status, message and field, with
   * the message in the user's words (`rename`, e.g. names.ts's userText).
   */
  describe(rename: (text: string) => string = (t) => t): string {
    const field = this.field ? ` (field ${this.field})` : '';
    const status = this.status > 0 ? ` ${this.status}` : '';
    return `${this.route}${status}: ${rename(this.message)}${field}`;
  }
}

export interface ApiEvents {
  /** Every failed request, reported once here (callers may ignore the rejection). */
  error(err: ApiError): void;
  /** A revision this tab caused (the answer of a POST). */
  ownRevision(revision: number): void;
  /** A request reached the server (true) or could not (false: network error). */
  connection(up: boolean, err?: ApiError): void;
}

export interface RequestOptions {
  /** Not counted in `pending` (the revision poller, periodic refetches). */
  background?: boolean;
  /** Statuses the caller handles itself: rejected, but not reported as errors. */
  expected?: number[];
}

/**
 * The client. GETs and POSTs are plain fetches; every POST carries
 * `Content-Type: application/json` (the server refuses writes without it)
 * and the token of the page's `?token=` as a bearer token. `pendingWrites`
 * counts POSTs in flight so that the revision poller never mistakes this
 * tab's own change (whose answer has not arrived yet) for another tab's;
 * `pending` counts every request but the background ones (for tests: the
 * page is settled when it is 0).
 *
 * A request that gets no answer at all (network error: the server is gone)
 * is reported through `connection(false)`, not as an error: the app shows
 * one "connection lost" state, not one error per request.
 */
export class Api {
  pendingWrites = 0;
  pending = 0;

  constructor(
    private readonly base: string,
    private readonly token: string | null,
    private readonly events: ApiEvents,
  ) {}

  async get<T>(path: string, options: RequestOptions = {}): Promise<T> {
    return this.request<T>('GET', path, undefined, options);
  }

  async post<T>(path: string, body: unknown = {}, options: RequestOptions = {}): Promise<T> {
    this.pendingWrites++;
    try {
      const answer = await this.request<T>('POST', path, body, options);
      const revision = (answer as { revision?: unknown } | null)?.revision;
      if (typeof revision === 'number') this.events.ownRevision(revision);
      return answer;
    } finally {
      this.pendingWrites--;
    }
  }

  /** The scene as binary glTF. */
  async glb(): Promise<ArrayBuffer> {
    const route = 'GET /api/character.glb';
    this.pending++;
    try {
      let res: Response;
      try {
        res = await fetch(this.base + '/api/character.glb', { cache: 'no-store' });
      } catch (e) {
        throw this.lost(new ApiError(route, 0, `network error: ${String(e)}`, null));
      }
      this.events.connection(true);
      if (!res.ok) throw this.fail(await this.errorOf(route, res), {});
      return await res.arrayBuffer();
    } finally {
      this.pending--;
    }
  }

  private async request<T>(method: 'GET' | 'POST', path: string, body: unknown, options: RequestOptions): Promise<T> {
    const route = `${method} ${path.split('?')[0]}`;
    const headers: Record<string, string> = {};
    if (method === 'POST') {
      headers['Content-Type'] = 'application/json';
      if (this.token) headers['Authorization'] = `Bearer ${this.token}`;
    }
    if (!options.background) this.pending++;
    try {
      let res: Response;
      try {
        res = await fetch(this.base + path, {
          method,
          headers,
          body: method === 'POST' ? JSON.stringify(body ?? {}) : undefined,
          cache: 'no-store',
        });
      } catch (e) {
        throw this.lost(new ApiError(route, 0, `network error: ${String(e)}`, null));
      }
      this.events.connection(true);
      if (!res.ok) throw this.fail(await this.errorOf(route, res), options);
      const text = await res.text();
      try {
        return (text.length ? JSON.parse(text) : {}) as T;
      } catch {
        throw this.fail(new ApiError(route, res.status, `answer is not JSON: ${text.slice(0, 120)}`, null), options);
      }
    } finally {
      if (!options.background) this.pending--;
    }
  }

  private async errorOf(route: string, res: Response): Promise<ApiError> {
    const text = await res.text().catch(() => '');
    try {
      const body = JSON.parse(text) as { error?: unknown; field?: unknown };
      const message = typeof body.error === 'string' ? body.error : text || res.statusText;
      const field = typeof body.field === 'string' && body.field.length ? body.field : null;
      return new ApiError(route, res.status, message, field);
    } catch {
      return new ApiError(route, res.status, text.slice(0, 200) || res.statusText, null);
    }
  }

  private fail(err: ApiError, options: RequestOptions): ApiError {
    if (!options.expected?.includes(err.status)) this.events.error(err);
    return err;
  }

  private lost(err: ApiError): ApiError {
    this.events.connection(false, err);
    return err;
  }
}
