// Fixtures of the end-to-end tests: a fresh `rigel serve` per test (so tests
// never see each other's poses, keys or rigs), the page opened on it and
// ready, and helpers that read the scene through the JSON API.
//
// The server is started here rather than by the config's webServer because
// every test gets its own scene: one process per test, on a port the
// server picks (--port 0 --json prints it), in a temp --root holding copies
// of the files the test needs.

import { test as base, expect as baseExpect, type Page, type TestInfo } from '@playwright/test';
import { spawn, type ChildProcess } from 'node:child_process';
import { copyFileSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
export const webDir = resolve(here, '..');
export const repoDir = resolve(webDir, '..');
export const rigelBin = resolve(webDir, process.env.RIGEL_BIN ?? '../build/release/apps/cli/rigel');
// The default character: Rigify's metarig (159 joints) with its skinned
// 10,037-vertex body, as scripts/demo serves it.
export const character = join(repoDir, 'tests/data/gltf/rigify_human_body.glb');
// The character the bundled biped definition names in its <geo>.
const bipedGeo = 'tests/data/gltf/rigify_human_metarig.glb';

export type Vec3 = [number, number, number];

export interface ServerOptions {
  /** Give every joint an ephemeral control (`--setup-ephemeral`). */
  ephemeral: boolean;
  /** Require this token on writes (the page gets it as ?token=). */
  token: string | null;
  /** The character file to serve (tests/data/gltf/...; the body by default). */
  character?: string;
}

export class RigelServer {
  log = '';
  constructor(
    readonly url: string,
    readonly root: string,
    readonly token: string | null,
    private proc: ChildProcess,
    private readonly args: string[],
  ) {}

  get port(): number {
    return Number(new URL(this.url).port);
  }

  pageUrl(): string {
    return this.url.includes('?') || !this.token ? this.url : `${this.url}?token=${this.token}`;
  }

  async get<T = any>(path: string): Promise<T> {
    const res = await fetch(new URL(path, this.url));
    const text = await res.text();
    if (!res.ok) throw new Error(`GET ${path}: ${res.status} ${text}`);
    return JSON.parse(text) as T;
  }

  async post<T = any>(path: string, body: unknown = {}): Promise<{ status: number; body: T }> {
    const headers: Record<string, string> = { 'Content-Type': 'application/json' };
    if (this.token) headers.Authorization = `Bearer ${this.token}`;
    const res = await fetch(new URL(path, this.url), { method: 'POST', headers, body: JSON.stringify(body) });
    const text = await res.text();
    return { status: res.status, body: (text ? JSON.parse(text) : {}) as T };
  }

  /** name -> uuid of every node. */
  async uuids(): Promise<Map<string, string>> {
    const a = await this.get<{ nodes: { uuid: string; name: string }[] }>('/api/nodes');
    return new Map(a.nodes.map((n) => [n.name, n.uuid]));
  }

  /** name -> world TRS ([t(3), q(4), s(3)]) of every transform node. */
  async worldPose(): Promise<Map<string, number[]>> {
    const [nodes, pose] = await Promise.all([
      this.get<{ nodes: { uuid: string; name: string }[] }>('/api/nodes'),
      this.get<{ nodes: Record<string, number[]> }>('/api/pose?space=world'),
    ]);
    const out = new Map<string, number[]>();
    for (const n of nodes.nodes) {
      const v = pose.nodes[n.uuid];
      if (v) out.set(n.name, v);
    }
    return out;
  }

  alive(): boolean {
    return this.proc.exitCode === null && this.proc.signalCode === null;
  }

  /** Kills the server as a crash would (SIGKILL), keeping its folder. */
  async kill(): Promise<void> {
    if (!this.alive()) return;
    const exited = new Promise<void>((r) => this.proc.once('exit', () => r()));
    this.proc.kill('SIGKILL');
    await exited;
  }

  /** Starts the server again on the same port and folder (a fresh scene). */
  async restart(): Promise<void> {
    await this.kill();
    const args = this.args.map((a, i) => (this.args[i - 1] === '--port' ? String(this.port) : a));
    const { proc, log } = await spawnServer(args);
    this.proc = proc;
    this.log += log;
    proc.stderr!.on('data', (d: Buffer) => (this.log += d.toString()));
    await waitListening(this);
  }

  async stop(): Promise<void> {
    if (this.alive()) {
      const exited = new Promise<void>((r) => this.proc.once('exit', () => r()));
      this.proc.kill('SIGTERM');
      // The exit, or SIGKILL when SIGTERM is not enough (a wedged server).
      const timer = setTimeout(() => this.proc.kill('SIGKILL'), 5000);
      await exited;
      clearTimeout(timer);
    }
    rmSync(this.root, { recursive: true, force: true });
  }
}

/** Spawns `rigel serve ARGS` and resolves with its URL once it prints it. */
async function spawnServer(args: string[]): Promise<{ proc: ChildProcess; url: string; log: string }> {
  const proc = spawn(rigelBin, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  let log = `$ ${rigelBin} ${args.join(' ')}\n`;
  proc.stderr!.on('data', (d: Buffer) => (log += d.toString()));
  const url = await new Promise<string>((resolvePromise, reject) => {
    let out = '';
    // Generous: the first start on a loaded machine imports the character.
    const timer = setTimeout(() => reject(new Error(`rigel serve printed no URL in 60 s:\n${log}${out}`)), 60_000);
    proc.on('error', (e) => {
      clearTimeout(timer);
      reject(new Error(`cannot start ${rigelBin}: ${e.message} (set RIGEL_BIN)`));
    });
    proc.on('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`rigel serve exited with ${code}:\n${log}${out}`));
    });
    proc.stdout!.on('data', (d: Buffer) => {
      out += d.toString();
      log += d.toString();
      const line = out.split('\n').find((l) => l.trim().startsWith('{'));
      if (!line) return;
      try {
        const j = JSON.parse(line) as { url: string; port: number };
        clearTimeout(timer);
        resolvePromise(j.url ?? `http://127.0.0.1:${j.port}/`);
      } catch {
        // not the whole line yet
      }
    });
  });
  return { proc, url, log };
}

/** Waits until the server answers its API (it prints its URL once listening; this is the check). */
async function waitListening(server: RigelServer): Promise<void> {
  await baseExpect
    .poll(
      async () => {
        try {
          await server.get('/api/revision');
          return true;
        } catch {
          return false;
        }
      },
      { timeout: 30_000, intervals: [50, 100, 250] },
    )
    .toBe(true);
}

/** Starts `rigel serve` on the demo character in a temp root with copies of the examples. */
export async function startServer(opts: ServerOptions): Promise<RigelServer> {
  const root = mkdtempSync(join(tmpdir(), 'rigel-e2e-'));
  // The examples as the definitions reference them (biped's <geo> is ../tests/data/gltf/...).
  mkdirSync(join(root, 'examples'), { recursive: true });
  mkdirSync(join(root, 'tests/data/gltf'), { recursive: true });
  mkdirSync(join(root, 'rigs'), { recursive: true });
  copyFileSync(join(repoDir, 'examples/biped.rig.xml'), join(root, 'examples/biped.rig.xml'));
  copyFileSync(join(repoDir, bipedGeo), join(root, bipedGeo));

  const args = ['serve', opts.character ? join(repoDir, opts.character) : character, '--port', '0', '--json', '--root', root, '--web', join(webDir, 'dist')];
  if (opts.ephemeral) args.push('--setup-ephemeral');
  if (opts.token) args.push('--token', opts.token);
  const { proc, url, log } = await spawnServer(args);
  const server = new RigelServer(url.split('?')[0]!, root, opts.token, proc, args);
  server.log = log;
  proc.stderr!.on('data', (d: Buffer) => (server.log += d.toString()));
  await waitListening(server);
  return server;
}

/** Screenshots, numbered in order, into the test's output folder. */
export class Shots {
  private n = 0;
  constructor(
    private readonly page: Page,
    private readonly info: TestInfo,
  ) {}

  async take(name: string): Promise<void> {
    this.n++;
    const file = this.info.outputPath(`${String(this.n).padStart(2, '0')}-${name}.png`);
    await this.page.screenshot({ path: file });
  }
}

export const test = base.extend<
  { server: RigelServer; app: Page; shots: Shots },
  { serverOptions: ServerOptions }
>({
  serverOptions: [{ ephemeral: true, token: 'e2e-token' }, { option: true, scope: 'worker' }],
  server: async ({ serverOptions }, use, testInfo) => {
    const server = await startServer(serverOptions);
    await use(server);
    await testInfo.attach('rigel-serve.log', { body: server.log, contentType: 'text/plain' });
    await server.stop();
  },
  app: async ({ page, server }, use, testInfo) => {
    const console: string[] = [];
    page.on('console', (m) => console.push(`${m.type()}: ${m.text()}`));
    page.on('pageerror', (e) => console.push(`pageerror: ${e.message}`));
    await page.goto(server.pageUrl());
    await page.waitForFunction(() => (window as any).rigel?.isReady?.() === true, null, { timeout: 60_000 });
    await settle(page, server);
    await use(page);
    await testInfo.attach('console.log', { body: console.join('\n'), contentType: 'text/plain' });
  },
  shots: async ({ page }, use, testInfo) => {
    await use(new Shots(page, testInfo));
  },
});

/** Playwright's expect, with polls that retry every 50-250 ms (not up to 1 s). */
export const expect = new Proxy(baseExpect, {
  get(target, prop, receiver) {
    if (prop === 'poll') {
      return (fn: () => unknown, options: Record<string, unknown> = {}) =>
        target.poll(fn, { intervals: [50, 100, 150, 250], ...options });
    }
    return Reflect.get(target, prop, receiver);
  },
}) as typeof baseExpect;

// ------------------------------------------------------------------ helpers

export function dist(a: number[], b: number[]): number {
  return Math.hypot(a[0]! - b[0]!, a[1]! - b[1]!, a[2]! - b[2]!);
}

export function sub(a: number[], b: number[]): Vec3 {
  return [a[0]! - b[0]!, a[1]! - b[1]!, a[2]! - b[2]!];
}

/** How far each named node moved between two world poses. */
export function moved(before: Map<string, number[]>, after: Map<string, number[]>, names: string[]): Record<string, number> {
  const out: Record<string, number> = {};
  for (const n of names) {
    const a = before.get(n);
    const b = after.get(n);
    if (!a || !b) throw new Error(`no world pose for ${n}`);
    out[n] = dist(a, b);
  }
  return out;
}

/** Largest difference between two world poses over every node and number. */
export function poseDifference(a: Map<string, number[]>, b: Map<string, number[]>): number {
  let worst = 0;
  for (const [name, va] of a) {
    const vb = b.get(name);
    if (!vb) return Infinity;
    for (let i = 0; i < va.length; i++) worst = Math.max(worst, Math.abs(va[i]! - vb[i]!));
  }
  return a.size === b.size ? worst : Infinity;
}

/**
 * Waits until the page has caught up with the server: no request, refresh,
 * gesture or build in flight, and the newest revision the server has is one
 * the page has seen. What is on screen is then what the server holds, so a
 * click lands where the page says a control is.
 */
export async function settle(page: Page, server: RigelServer): Promise<void> {
  const revision = (await server.get<{ revision: number }>('/api/revision')).revision;
  await expect
    .poll(
      () =>
        page.evaluate((r) => {
          const w = window as any;
          return w.rigel.settled() && w.rigel.app.knownRevision >= r;
        }, revision),
      { message: `the page settles at revision ${revision} or later` },
    )
    .toBe(true);
}

/** Clicks a control where the app says it is on screen (Shift to add), once the page has settled. */
export async function clickControl(page: Page, name: string, shift = false, server?: RigelServer): Promise<void> {
  if (server) await settle(page, server);
  else await expect.poll(() => page.evaluate(() => (window as any).rigel.settled())).toBe(true);
  const at = await page.evaluate((n) => (window as any).rigel.project(n), name);
  expect(at, `${name} should be visible and pickable in the viewport`).not.toBeNull();
  if (shift) await page.keyboard.down('Shift');
  await page.mouse.click(at.x, at.y);
  if (shift) await page.keyboard.up('Shift');
}

/** Waits until the app's selection (from the server) is exactly `names`. */
export async function expectSelection(page: Page, server: RigelServer, names: string[]): Promise<void> {
  const uuids = await server.uuids();
  const want = names.map((n) => uuids.get(n));
  await expect
    .poll(async () => (await server.get<{ selection: string[] }>('/api/scene')).selection.slice().sort())
    .toEqual(want.slice().sort());
  await expect.poll(() => page.evaluate(() => (window as any).rigel.app.scene.selection.length)).toBe(names.length);
}

/**
 * Drags the gizmo's translate arrow of `axis` by `pixels` along the arrow on
 * screen, in `steps` mouse moves, and waits for the gesture to be released.
 */
export async function dragGizmo(page: Page, axis: 'x' | 'y' | 'z', pixels: number, steps = 12): Promise<void> {
  await expect.poll(() => page.evaluate(() => (window as any).rigel.settled())).toBe(true);
  await expect.poll(() => page.evaluate((a) => (window as any).rigel.gizmoHandle(a) !== null, axis)).toBe(true);
  const gestures = await page.evaluate(() => (window as any).rigel.app.drag.stats.gestures as number);
  const hnd = await page.evaluate((a) => (window as any).rigel.gizmoHandle(a), axis);
  await page.mouse.move(hnd.x, hnd.y);
  await page.mouse.down();
  for (let i = 1; i <= steps; i++) {
    await page.mouse.move(hnd.x + (hnd.dx * pixels * i) / steps, hnd.y + (hnd.dy * pixels * i) / steps);
  }
  await page.mouse.up();
  await expect
    .poll(() => page.evaluate(() => ({ g: (window as any).rigel.app.drag.stats.gestures, active: (window as any).rigel.app.drag.active })))
    .toEqual({ g: gestures + 1, active: false });
}

export async function setMode(page: Page, server: RigelServer, mode: string): Promise<void> {
  await page.getByTestId(`mode-${mode}`).click();
  await expect.poll(async () => (await server.get<{ mode: string }>('/api/scene')).mode).toBe(mode);
  await expect(page.getByTestId(`mode-${mode}`)).toHaveClass(/active/);
}

/** Types a frame into the timeline's field, waits for the server to be there, and gives the focus back. */
export async function goToFrame(page: Page, server: RigelServer, frame: number): Promise<void> {
  const field = page.getByTestId('frame');
  await field.fill(String(frame));
  await field.press('Enter');
  await expect.poll(async () => (await server.get('/api/scene')).frame).toBe(frame);
  // Back to the viewport so that shortcuts reach the app, not the field.
  await field.blur();
}

/** Undo through the page's button, waiting for the page to settle before and after. */
export async function undoInPage(page: Page, server: RigelServer): Promise<void> {
  await settle(page, server);
  await page.getByTestId('undo').click();
  await settle(page, server);
}

/**
 * Clicks `testid` in the page, then checks: the pose changed, undo gives the
 * pose before, and the same request through the API (`route`, `body`) gives
 * the page's pose (then is undone too).
 */
export async function sameAsApi(page: Page, server: RigelServer, testid: string, route: string, body: unknown): Promise<void> {
  await settle(page, server);
  const before = await server.worldPose();
  const revision = (await server.get('/api/revision')).revision;
  await page.getByTestId(testid).click();
  await expect.poll(async () => (await server.get('/api/revision')).revision).toBeGreaterThan(revision);
  await settle(page, server);
  const byPage = await server.worldPose();
  expect(poseDifference(byPage, before), `${testid} changes the pose`).toBeGreaterThan(1e-4);
  await undoInPage(page, server);
  expect(poseDifference(await server.worldPose(), before), `undo takes ${testid} back`).toBeLessThan(1e-9);
  const r = await server.post(route, body);
  expect(r.status, JSON.stringify(r.body)).toBe(200);
  expect(poseDifference(await server.worldPose(), byPage), `${testid}: the page and the API agree`).toBeLessThan(1e-9);
  const u = await server.post('/api/undo');
  expect(u.status).toBe(200);
}
