// The definition editor: build a two-component rig from the palette by
// linking nodes, see invalid links refused, build it live, save it, and
// check the saved file with `rigel validate`.

import { spawnSync } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import type { Page } from '@playwright/test';
import { expect, rigelBin, test } from './fixtures';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

async function link(page: Page, fromId: string, toId: string): Promise<void> {
  const from = (await page.getByTestId(`port-out-${fromId}`).boundingBox())!;
  const to = (await page.getByTestId(`node-${toId}`).boundingBox())!;
  await page.mouse.move(from.x + from.width / 2, from.y + from.height / 2);
  await page.mouse.down();
  await page.mouse.move(from.x + 40, from.y + 20, { steps: 3 });
  await page.mouse.move(to.x + to.width / 2, to.y + to.height / 2, { steps: 6 });
  await page.mouse.up();
}

async function nodeId(page: Page, name: string): Promise<string> {
  const id = await page.evaluate((n) => (window as any).rigel.editor.idOf(n), name);
  expect(id, `a node named ${name}`).not.toBeNull();
  return id as string;
}

test('definition editor: build global + fkChain live, save, validate', async ({ app: page, server, shots }) => {
  await page.getByTestId('tab-def').click();
  await expect(page.getByTestId('palette-global')).toBeVisible();
  await shots.take('empty');

  // Rig node.
  await page.getByTestId('node-rig').click();
  await page.getByTestId('def-rig-name').fill('armrig');
  await page.getByTestId('def-rig-name').press('Enter');

  await page.getByTestId('palette-global').click();
  const global = await nodeId(page, 'global');
  await page.getByTestId('palette-fkChain').click();
  const chain = await nodeId(page, 'fkChain');
  await shots.take('two-nodes');

  // fkChain details: name, side, two guides on the left arm.
  await page.getByTestId(`node-${chain}`).click();
  await page.getByTestId('def-name').fill('arm');
  await page.getByTestId('def-name').press('Enter');
  await page.getByTestId('def-side').selectOption('L');
  await page.getByTestId('def-guide-joint-0').fill('upper_arm.L');
  await page.getByTestId('def-guide-joint-0').press('Enter');
  await page.getByTestId('def-guide-add').click();
  await page.getByTestId('def-guide-joint-1').fill('forearm.L');
  await page.getByTestId('def-guide-joint-1').press('Enter');

  // Links: Rig -> global -> arm.
  await link(page, 'rig', global);
  await link(page, global, chain);
  await expect(page.locator('svg.links path.link.live')).toHaveCount(2);
  await shots.take('linked');

  // Invalid links are refused: global is root-only, and arm -> global would be a cycle.
  const refusals = async (): Promise<string[]> =>
    ((await page.evaluate(() => (window as any).rigel.errors)) as string[]).filter((e) => e.startsWith('Link refused'));
  await link(page, chain, global);
  await expect.poll(refusals).toHaveLength(1);
  expect((await refusals())[0]).toContain('root-only');
  // Two loose nodes (not under the Rig node, so nothing is built) for the cycle.
  await page.getByTestId('palette-fkChain').click();
  const a = await nodeId(page, 'fkChain2');
  await page.getByTestId('palette-fkChain').click();
  const b = await nodeId(page, 'fkChain3');
  await link(page, a, b);
  await expect(page.locator(`svg.links path.link[data-child="${b}"]`)).toHaveCount(1);
  await link(page, b, a);
  await expect.poll(refusals).toHaveLength(2);
  expect((await refusals())[1]).toContain('cycle');
  await expect(page.locator(`svg.links path.link[data-child="${a}"]`)).toHaveCount(0);
  for (const id of [a, b]) {
    await page.getByTestId(`node-${id}`).click();
    await page.getByTestId('def-delete').click();
    await expect(page.getByTestId(`node-${id}`)).toHaveCount(0);
  }
  await shots.take('refused');

  // Live build: the rig is in the scene with both components.
  await expect
    .poll(async () => {
      const rigs = (await server.get('/api/rigs')).rigs as any[];
      const r = rigs.find((x) => x.name === 'armrig');
      return r ? r.components.map((c: any) => c.type).sort() : null;
    }, { timeout: 15_000 })
    .toEqual(['fkChain', 'global']);
  await page.getByTestId('tab-rigs').click();
  await expect(page.getByTestId('rig-armrig')).toBeVisible();
  await shots.take('built');
  await page.getByTestId('tab-def').click();

  // A parameter from the schema of another type: details are generated.
  await page.getByTestId('palette-limb').click();
  await expect(page.getByTestId('def-param-kind')).toBeVisible();
  await expect(page.getByTestId('def-param-kind').locator('option')).toHaveCount(2);
  await expect(page.getByTestId('def-param-maxStretch')).toHaveAttribute('min', '1');
  await page.getByTestId('def-delete').click();

  // Save and validate with the command line.
  await page.getByTestId('def-save-path').fill('rigs/armrig.rig.xml');
  await page.getByTestId('def-save').click();
  await expect(page.getByTestId('status-text')).toContainText('Saved');
  const saved = join(server.root, 'rigs/armrig.rig.xml');
  expect(existsSync(saved)).toBe(true);
  const text = readFileSync(saved, 'utf8');
  expect(text).toContain('type="fkChain"');
  expect(text).toContain('upper_arm.L');
  await shots.take('saved');
  const v = spawnSync(rigelBin, ['validate', saved], { encoding: 'utf8' });
  expect(v.status, `rigel validate: ${v.stdout}${v.stderr}`).toBe(0);
  // The refused links were reported; no request to the API failed.
  const errors = (await page.evaluate(() => (window as any).rigel.errors)) as string[];
  expect(errors.filter((e) => /^(GET|POST) /.test(e))).toEqual([]);
  expect(errors.filter((e) => e.startsWith('Link refused')).length).toBe(2);
});
