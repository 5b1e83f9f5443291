// The build-graph editor: draw the left arm's rig (global, then a limb) from
// the palette, see a link of the wrong type refused, build it live, step its
// build, save it, open it again after a reload, and check that `rigel graph
// run` builds the same rig from the saved file; and problems shown on their
// nodes.

import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import type { Page } from '@playwright/test';
import { addNode, drawLeftArm, drawnLinks, graphOf, link, nodeIds, panel } from './buildgraphhelpers';
import { character, expect, rigelBin, settle, test } from './fixtures';
import type { RigelServer } from './fixtures';

// The limb drives the joints itself: no ephemeral controls on this character.
test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

const errors = (page: Page): Promise<string[]> => page.evaluate(() => (window as any).rigel.errors as string[]);

/** A world TRS [t(3), q(4), s(3)] as its 3x4 matrix (rows), so that q and -q agree. */
function matrix(t: number[], q: number[], s: number[]): number[] {
  const [x, y, z, w] = q as [number, number, number, number];
  const r = [
    [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
  ];
  return r.flatMap((row, i) => [row[0]! * s[0]!, row[1]! * s[1]!, row[2]! * s[2]!, t[i]!]);
}

/** The names of the controls of rig `rig` in the server's scene. */
async function controlsOf(server: RigelServer, rig: string): Promise<string[]> {
  const a = await server.get<{ controls: { name: string; rig: string }[] }>('/api/nodes');
  return a.controls.filter((c) => c.rig === rig).map((c) => c.name).sort();
}

test('build graph: draw the left arm, refuse a wrong link, build live, step, save, reopen, and the CLI builds the same rig', async ({ app: page, server, shots }) => {
  await page.getByTestId('tab-build').click();
  await expect(page.getByTestId('bg-palette-component:global')).toBeVisible();
  // A new graph starts with its start node, on the scene's character.
  expect(await nodeIds(page)).toEqual(['start']);
  await expect.poll(() => page.evaluate(() => (window as any).rigel.buildGraph.model.rig.geometry.map((g: any) => g.file))).toEqual([character]);
  await panel(page).getByTestId('bg-rig-name').fill('armrig');
  await panel(page).getByTestId('bg-rig-name').press('Enter');

  // The search box filters the palette.
  const global = await addNode(page, 'glob', 'component:global');
  await expect(page.getByTestId('bg-palette-component:limb')).toBeHidden();
  const limb = await addNode(page, 'limb', 'component:limb');
  await expect(page.getByTestId('bg-palette-component:global')).toBeHidden();
  await page.getByTestId('bg-search').fill('');
  expect([global, limb]).toEqual(['global', 'limb']);
  await shots.take('two-nodes');

  // The biped's left arm (examples/biped.rig.xml), set in the details panel.
  await drawLeftArm(page, limb);
  await expect(page.getByTestId(`bg-title-${limb}`)).toContainText('arm_L');
  expect(await page.evaluate(() => (window as any).rigel.buildGraph.idOf('arm_L'))).toBe(limb);

  // Links: the exec chain start -> global -> limb, and the limb hangs from the global.
  await link(page, 'start.then', 'global.exec');
  await link(page, 'global.then', 'limb.exec');
  await link(page, 'global.component', 'limb.parent');
  await expect.poll(() => drawnLinks(page)).toEqual(['global.component->limb.parent', 'global.then->limb.exec', 'start.then->global.exec']);
  // The parent linked: the attach field names the global's hooks.
  await expect(panel(page).getByTestId('def-attach')).toBeVisible();

  // A component output into a string input is refused, visibly.
  const refusals = async (): Promise<string[]> => (await errors(page)).filter((e) => e.startsWith('Link refused'));
  await link(page, 'global.component', 'limb.name');
  await expect.poll(refusals).toHaveLength(1);
  expect((await refusals())[0]).toContain('a component output cannot feed a string input');
  await expect(page.getByTestId('status-text')).toContainText('Link refused');
  expect(await page.evaluate(() => (window as any).rigel.buildGraph.lastRefusal)).toMatchObject({ from: 'global.component', to: 'limb.name' });
  expect(await drawnLinks(page)).toHaveLength(3);
  await shots.take('linked');

  // Live: the rig is built, its controls in the scene and in the page.
  await page.getByTestId('bg-live').check();
  await expect
    .poll(async () => {
      const r = ((await server.get('/api/rigs')).rigs as any[]).find((x) => x.name === 'armrig');
      return r ? r.components.map((c: any) => `${c.type}:${c.name}`).sort() : null;
    })
    .toEqual(['global:global', 'limb:arm_L']);
  await expect(page.getByTestId('bg-problems')).toContainText('✔ valid and built');
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'armrig').length))
    .toBeGreaterThan(2);
  await settle(page, server);
  const controls = await controlsOf(server, 'armrig');
  expect(controls.length).toBeGreaterThan(2);
  await shots.take('built');

  // Build stepping: one step back, one forward.
  const steps: number = ((await server.get('/api/rigs')).rigs as any[]).find((x) => x.name === 'armrig').steps;
  await expect(page.getByTestId('bg-step')).toHaveText(`step ${steps} / ${steps}`);
  await page.getByTestId('bg-step-back').click();
  await expect(page.getByTestId('bg-step')).toHaveText(`step ${steps - 1} / ${steps}`);
  await expect.poll(async () => ((await server.get('/api/rigs')).rigs as any[])[0].buildPosition).toBe(steps - 1);
  // The node whose component built the step the VCR stands on is marked.
  await expect(page.getByTestId(`bg-node-${limb}`)).toHaveClass(/\bstepped\b/);
  await expect(page.getByTestId(`bg-node-${global}`)).not.toHaveClass(/\bstepped\b/);
  await shots.take('stepped-back');
  await page.getByTestId('bg-step-forward').click();
  await expect(page.getByTestId('bg-step')).toHaveText(`step ${steps} / ${steps}`);
  await expect.poll(async () => ((await server.get('/api/rigs')).rigs as any[])[0].buildPosition).toBe(steps);
  await settle(page, server);

  // Save.
  await page.getByTestId('bg-save-path').fill('arm.build.json');
  await page.getByTestId('bg-save').click();
  await expect(page.getByTestId('status-text')).toContainText('Saved');
  const saved = join(server.root, 'arm.build.json');
  expect(existsSync(saved)).toBe(true);
  const drawn = await graphOf(page);
  const links = await drawnLinks(page);

  // Reload the page and open the file: the same nodes and links.
  await page.reload();
  await page.waitForFunction(() => (window as any).rigel?.isReady?.() === true, null, { timeout: 60_000 });
  await settle(page, server);
  await page.getByTestId('tab-build').click();
  expect(await nodeIds(page)).toEqual(['start']);
  await page.getByTestId('bg-open-select').selectOption({ label: 'arm.build.json' });
  await page.getByTestId('bg-open').click();
  await expect.poll(() => nodeIds(page)).toEqual(['start', global, limb]);
  expect(await graphOf(page)).toEqual(drawn);
  await expect.poll(() => drawnLinks(page)).toEqual(links);
  await expect(page.getByTestId(`bg-title-${limb}`)).toContainText('arm_L');
  await expect(page.getByTestId('bg-save-path')).toHaveValue('arm.build.json');
  await settle(page, server);
  await shots.take('reopened');

  // The command line builds the same rig from the saved file.
  const out = mkdtempSync(join(tmpdir(), 'rigel-e2e-graph-'));
  try {
    const v = spawnSync(rigelBin, ['graph', 'validate', saved], { encoding: 'utf8' });
    expect(v.status, `rigel graph validate: ${v.stdout}${v.stderr}`).toBe(0);
    const scene = join(out, 'arm.rigel');
    const r = spawnSync(rigelBin, ['graph', 'run', saved, '--character', character, '-o', scene, '--json'], { encoding: 'utf8' });
    expect(r.status, `rigel graph run: ${r.stdout}${r.stderr}`).toBe(0);
    const report = JSON.parse(r.stdout) as { rig: string; steps: number; components: { name: string; side: string; type: string }[] };
    expect(report.rig).toBe('armrig');
    expect(report.steps).toBe(steps);
    const served = ((await server.get('/api/rigs')).rigs as any[]).find((x) => x.name === 'armrig');
    expect(report.components.length).toBe(served.components.length);
    expect(report.components.map((c) => `${c.type}:${c.name}${c.side === 'C' ? '' : `_${c.side}`}`).sort()).toEqual(
      served.components.map((c: any) => `${c.type}:${c.name}`).sort(),
    );
    // Every control where the server's scene has it.
    const e = spawnSync(rigelBin, ['eval', scene, '--json'], { encoding: 'utf8', maxBuffer: 64 << 20 });
    expect(e.status, `rigel eval: ${e.stderr}`).toBe(0);
    const cli = (JSON.parse(e.stdout) as { nodes: Record<string, { t: number[]; q: number[]; s: number[] }> }).nodes;
    const world = await server.worldPose();
    let worst = 0;
    for (const name of controls) {
      const a = cli[name];
      const b = world.get(name);
      expect(a, `${name} in the CLI's scene`).toBeDefined();
      expect(b, `${name} in the server's scene`).toBeDefined();
      const ma = matrix(a!.t, a!.q, a!.s);
      const mb = matrix(b!.slice(0, 3), b!.slice(3, 7), b!.slice(7, 10));
      for (let i = 0; i < 12; i++) worst = Math.max(worst, Math.abs(ma[i]! - mb[i]!));
    }
    expect(worst).toBeLessThan(1e-6);
  } finally {
    rmSync(out, { recursive: true, force: true });
  }
  // "from rig": the graph of a scene rig's definition (converted: the rig was built from a graph sent, not a file).
  await page.getByTestId('bg-open-select').selectOption({ label: 'from rig armrig' });
  await page.getByTestId('bg-open').click();
  await expect.poll(() => nodeIds(page)).toEqual(['start', 'global', 'arm_L']);
  await expect.poll(() => drawnLinks(page)).toEqual(['global.component->arm_L.parent', 'global.then->arm_L.exec', 'start.then->global.exec']);
  await expect(page.getByTestId('bg-problems')).toHaveAttribute('data-state', 'valid');

  // The refused link was reported; no request to the API failed.
  const all = await errors(page);
  expect(all.filter((x) => /^(GET|POST) /.test(x))).toEqual([]);
});

test('build graph: a problem shows on its node in red; linked inputs are read-only; Delete removes links and nodes', async ({ app: page, server, shots }) => {
  await page.getByTestId('tab-build').click();
  const global = await addNode(page, 'global', 'component:global');

  // Not on the exec chain from start: the node is outlined red with the message.
  await page.getByTestId('bg-validate').click();
  const node = page.getByTestId(`bg-node-${global}`);
  await expect(node).toHaveClass(/problem/);
  await expect(page.getByTestId('bg-problems')).toHaveAttribute('data-state', 'invalid');
  const problem = page.locator(`[data-testid="bg-problem"][data-node="${global}"]`);
  await expect(problem).toContainText('not on the exec chain');
  await expect(page.getByTestId(`bg-title-${global}`)).toHaveAttribute('title', /not on the exec chain/);
  await shots.take('problem');
  // Clicking the problem selects its node.
  await page.getByTestId('bg-rig').click();
  await expect(node).not.toHaveClass(/selected/);
  await problem.click();
  await expect(node).toHaveClass(/selected/);
  await expect(panel(page).getByTestId('bg-node-id')).toHaveText(global);

  // Linked: valid, the outline gone.
  await link(page, 'start.then', `${global}.exec`);
  await expect(page.getByTestId('bg-problems')).toHaveAttribute('data-state', 'valid');
  await expect(node).not.toHaveClass(/problem/);

  // A string constant feeds the global's name: its field shows the link, read-only.
  const name = await addNode(page, 'string', 'constant:string');
  await panel(page).getByTestId('bg-value').fill('root');
  await panel(page).getByTestId('bg-value').press('Enter');
  await link(page, `${name}.value`, `${global}.name`);
  await page.getByTestId(`bg-title-${global}`).click();
  await expect(panel(page).getByTestId('def-name')).toBeDisabled();
  await expect(panel(page).getByTestId('bg-linked-name')).toHaveText(`← ${name}.value`);
  await expect(page.getByTestId('bg-problems')).toHaveAttribute('data-state', 'valid');

  // A variable read by a Get node: its output takes the variable's type.
  await page.getByTestId('bg-var-new-name').fill('label');
  await page.getByTestId('bg-var-new-type').selectOption('string');
  await page.getByTestId('bg-var-new-value').fill('L');
  await page.getByTestId('bg-var-add').click();
  await expect(page.getByTestId('bg-var-label')).toBeVisible();
  expect(await page.evaluate(() => (window as any).rigel.buildGraph.model.variables.map((v: any) => [v.name, v.type, v.value]))).toEqual([['label', 'string', 'L']]);
  const get = await addNode(page, 'get', 'variable:get');
  await expect(panel(page).getByTestId('bg-variable')).toHaveValue('label');
  await link(page, `${get}.value`, `${global}.attach`);
  await expect.poll(() => drawnLinks(page)).toContain(`${get}.value->${global}.attach`);
  await shots.take('linked-inputs');

  // A node dragged by its title keeps its new place in the file.
  const title = page.getByTestId(`bg-title-${name}`);
  const at = (await title.boundingBox())!;
  const before = await page.evaluate((id) => (window as any).rigel.buildGraph.model.nodes.get(id).y, name);
  await page.mouse.move(at.x + 20, at.y + 10);
  await page.mouse.down();
  await page.mouse.move(at.x + 30, at.y + 60, { steps: 5 });
  await page.mouse.move(at.x + 40, at.y + 110, { steps: 5 });
  await page.mouse.up();
  const position = (): Promise<number[]> =>
    page.evaluate((id) => (window as any).rigel.buildGraph.model.toJson(null).buildGraph.nodes.find((n: any) => n.id === id).position, name);
  await expect.poll(async () => (await position())[1]).toBe(before + 100);
  // A palette entry dragged into the graph is added where it is dropped.
  await page.getByTestId('bg-search').fill('bool');
  await page.getByTestId('bg-palette-constant:bool').dragTo(page.getByTestId('bg-graph'), { targetPosition: { x: 500, y: 400 } });
  await expect.poll(() => nodeIds(page)).toContain('bool');

  // Delete: the selected link, then the selected node (never start).
  await page.locator(`path.bg-link[data-to="${global}.name"]`).dispatchEvent('pointerdown');
  await page.getByTestId('bg-graph').press('Delete');
  await expect.poll(() => drawnLinks(page)).not.toContain(`${name}.value->${global}.name`);
  await page.getByTestId(`bg-title-${get}`).click();
  await page.getByTestId('bg-graph').press('Delete');
  await expect(page.getByTestId(`bg-node-${get}`)).toHaveCount(0);
  await page.getByTestId('bg-title-start').click();
  await page.getByTestId('bg-graph').press('Delete');
  await expect(page.getByTestId('bg-node-start')).toHaveCount(1);
  await settle(page, server);
  expect((await errors(page)).filter((x) => /^(GET|POST) /.test(x))).toEqual([]);
});
