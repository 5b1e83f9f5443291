// The definition editor: build a two-component rig from the palette by
// linking nodes, see invalid links refused, build it live, save it, and
// check the saved file with `rigel validate`.

import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import type { Page } from '@playwright/test';
import { character, expect, rigelBin, settle, test } from './fixtures';

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
    })
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
  // The rig's geometry: the scene's character, relative to the saved file's folder.
  const geo = /<geo file="([^"]+)"/.exec(text);
  expect(geo, text).not.toBeNull();
  expect(resolve(dirname(saved), geo![1]!)).toBe(resolve(character));
  await shots.take('saved');
  const v = spawnSync(rigelBin, ['validate', saved], { encoding: 'utf8' });
  expect(v.status, `rigel validate: ${v.stdout}${v.stderr}`).toBe(0);
  // The refused links were reported; no request to the API failed.
  const errors = (await page.evaluate(() => (window as any).rigel.errors)) as string[];
  expect(errors.filter((e) => /^(GET|POST) /.test(e))).toEqual([]);
  expect(errors.filter((e) => e.startsWith('Link refused')).length).toBe(2);
});

/** The geo files of a saved .rig.xml, resolved against its folder. */
function geoFiles(file: string): string[] {
  const text = readFileSync(file, 'utf8');
  return [...text.matchAll(/<geo file="([^"]+)"/g)].map((m) => resolve(dirname(file), m[1]!));
}

test('definition editor: a live build that fails shows the build error, not "valid"', async ({ app: page, server }) => {
  await page.getByTestId('tab-def').click();
  await page.getByTestId('palette-global').click();
  const global = await nodeId(page, 'global');
  await page.getByTestId('palette-fkChain').click();
  const chain = await nodeId(page, 'fkChain');
  await page.getByTestId(`node-${chain}`).click();
  await page.getByTestId('def-guide-joint-0').fill('upper_arm.L');
  await page.getByTestId('def-guide-joint-0').press('Enter');
  await page.getByTestId('def-guide-add').click();
  // A joint the character does not have: the definition is valid, its build is not.
  await page.getByTestId('def-guide-joint-1').fill('no_such_joint');
  await page.getByTestId('def-guide-joint-1').press('Enter');
  // The global alone builds...
  const types = async (): Promise<string[]> => ((await server.get('/api/rigs')).rigs[0]?.components ?? []).map((c: any) => c.type).sort();
  await link(page, 'rig', global);
  await expect.poll(types).toEqual(['global']);
  const problems = page.getByTestId('def-problems');
  await expect(problems).toContainText('✔ valid and built');
  // ...the chain on the missing joint does not.
  await link(page, global, chain);
  await expect(problems).toHaveAttribute('data-state', 'build-failed');
  await expect(page.getByTestId('def-build-error')).toContainText('no_such_joint');
  await expect(problems).not.toContainText('✔');
  await settle(page, server);
  // The failed rebuild changed nothing: the rig has only what built before (global).
  expect(await types()).toEqual(['global']);

  // Fixed: valid and built.
  await page.getByTestId(`node-${chain}`).click();
  await page.getByTestId('def-guide-joint-1').fill('forearm.L');
  await page.getByTestId('def-guide-joint-1').press('Enter');
  await expect(problems).toHaveAttribute('data-state', 'valid');
  await expect(problems).toContainText('✔ valid and built');
  await expect.poll(types).toEqual(['fkChain', 'global']);
});

test('definition editor: open the definition of a built rig, save it elsewhere with its <geo>', async ({ app: page, server, shots }) => {
  await page.getByTestId('rig-add-path').fill('examples/biped.rig.xml');
  await page.getByTestId('rig-add').click();
  await expect(page.getByTestId('rig-hero')).toBeVisible();
  await settle(page, server);
  const built = (await server.get('/api/rigs')).rigs[0];

  // From the Rig Manager: the editor opens with every component of the rig.
  await page.getByTestId('rig-open-definition').click();
  await expect(page.locator('#def-panel')).toBeVisible();
  await expect.poll(() => page.evaluate(() => (window as any).rigel.editor.nodes.size - 1)).toBe(built.components.length);
  await expect(page.locator('svg.links path.link.live')).toHaveCount(built.components.length);
  await expect(page.getByTestId('def-save-path')).toHaveValue('examples/biped.rig.xml');
  await page.getByTestId('node-rig').click();
  await expect(page.getByTestId('def-rig-name')).toHaveValue('hero');
  await expect(page.getByTestId('def-geo-file-0')).toHaveValue(join(server.root, 'tests/data/gltf/rigify_human_metarig.glb'));
  await shots.take('opened');

  // Saved two folders down: the <geo> line still names the same character.
  await page.getByTestId('def-save-path').fill('rigs/sub/hero.rig.xml');
  await page.getByTestId('def-save').click();
  await expect(page.getByTestId('status-text')).toContainText('Saved');
  const saved = join(server.root, 'rigs/sub/hero.rig.xml');
  expect(readFileSync(saved, 'utf8')).toContain('<geo file="../../tests/data/gltf/rigify_human_metarig.glb"/>');
  expect(geoFiles(saved)).toEqual(geoFiles(join(server.root, 'examples/biped.rig.xml')));
  // The same rig as the original (rigel diff), and it builds on its own <geo>.
  // The editor adds node positions, and the geometry's text moved with the
  // file (the files it names are the same, checked above); nothing else differs.
  const diff = spawnSync(rigelBin, ['diff', join(server.root, 'examples/biped.rig.xml'), saved, '--json'], { encoding: 'utf8' });
  const differences = (JSON.parse(diff.stdout) as { differences: { kind: string; text: string }[] }).differences;
  const moved = new Set(['rigGuiLocation', 'componentGuiLocation', 'geometryRemoved', 'geometryAdded']);
  expect(differences.filter((d) => !moved.has(d.kind)).map((d) => d.text)).toEqual([]);
  const out = mkdtempSync(join(tmpdir(), 'rigel-e2e-build-'));
  try {
    const b = spawnSync(rigelBin, ['build', saved, '-o', join(out, 'hero.rigel')], { encoding: 'utf8' });
    expect(b.status, `rigel build: ${b.stdout}${b.stderr}`).toBe(0);
  } finally {
    rmSync(out, { recursive: true, force: true });
  }

  // The editor's own Open does the same.
  await page.getByTestId('def-new').click();
  await expect.poll(() => page.evaluate(() => (window as any).rigel.editor.nodes.size)).toBe(1);
  await page.getByTestId('def-open-rig').selectOption('hero');
  await page.getByTestId('def-open').click();
  await expect.poll(() => page.evaluate(() => (window as any).rigel.editor.nodes.size - 1)).toBe(built.components.length);
  const errors = (await page.evaluate(() => (window as any).rigel.errors)) as string[];
  expect(errors).toEqual([]);
});
