// The transport under api.ts: plain fetches against `rigel serve`, every
// failure reported once (to the status bar) before the promise rejects, and
// counters of what is in flight (for the revision poller and the tests).

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
 * GETs and POSTs are plain fetches; every POST carries `Content-Type:
 * application/json` (the server refuses writes without it) and the token
 * of the page's `?token=` as a bearer token. `pendingWrites` counts POSTs
 * in flight so that the revision poller never mistakes this tab's own
 * change (whose answer has not arrived yet) for another tab's; `pending`
 * counts every request but the background ones (for tests: the page is
 * settled when it is 0).
 *
 * A request that gets no answer at all (network error: the server is gone)
 * is reported through `connection(false)`, not as an error: the app shows
 * one "connection lost" state, not one error per request.
 */
export class Http {
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

  /** A binary answer (the scene's glTF). */
  async bytes(path: string): Promise<ArrayBuffer> {
    const route = `GET ${path}`;
    this.pending++;
    try {
      let res: Response;
      try {
        res = await fetch(this.base + path, { cache: 'no-store' });
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
