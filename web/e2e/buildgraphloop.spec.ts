// The build-graph editor's lists, for-each nodes and sub-graphs: one arm
// drawn on the left joints, in the body of a for-each over a list constant
// edited in the details panel, builds live one arm per item (the right one
// mirrored); removing an item removes its arm and keeps the other. A graph
// file under the root is a node of the palette's Graphs: used in a loop, it
// builds an arm per side, and the saved graph builds the same from the CLI.

import { spawnSync } from 'node:child_process';
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import type { Page } from '@playwright/test';
import { addNode, drawLeftArm, drawnLinks, link, panel } from './buildgraphhelpers';
import { character, expect, rigelBin, settle, test } from './fixtures';
import type { RigelServer } from './fixtures';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

/** The components of rig `rig` in the server's scene, as TYPE:NAME, sorted; null when it has none. */
async function componentsOf(server: RigelServer, rig: string): Promise<string[] | null> {
  const r = ((await server.get('/api/rigs')).rigs as any[]).find((x) => x.name === rig);
  return r ? r.components.map((c: any) => `${c.type}:${c.name}`).sort() : null;
}

/** Sets item `i` of the list field `testid` in the details panel. */
async function setItem(page: Page, testid: string, i: number, value: string): Promise<void> {
  const field = panel(page).getByTestId(`${testid}-${i}`);
  await field.fill(value);
  await field.press('Enter');
}

/**
 * Opens the Build Graph tab on a new rig `rig` and adds a global, a list:string constant of `items` (edited in the
 * details panel) and a for-each over strings; returns their ids.
 */
async function loopOverItems(page: Page, rig: string, items: string[]): Promise<{ global: string; sides: string; each: string }> {
  await page.getByTestId('tab-build').click();
  await panel(page).getByTestId('bg-rig-name').fill(rig);
  await panel(page).getByTestId('bg-rig-name').press('Enter');
  const global = await addNode(page, 'glob', 'component:global');
  const sides = await addNode(page, 'list:string', 'constant:list:string');
  const each = await addNode(page, 'for each', 'forEach:string');
  await page.getByTestId(`bg-title-${sides}`).click();
  for (const [i, item] of items.entries()) {
    await panel(page).getByTestId('bg-value-add').click();
    await setItem(page, 'bg-value', i, item);
  }
  await expect.poll(() => page.evaluate((id) => (window as any).rigel.buildGraph.model.nodes.get(id).value, sides)).toEqual(items);
  return { global, sides, each };
}

test('build graph: a for-each over a list builds one arm per item live; removing an item removes its arm', async ({ app: page, server, shots }) => {
  // The list constant's items, edited in the details panel.
  const { global, sides, each } = await loopOverItems(page, 'looprig', ['L', 'R']);
  await expect(page.getByTestId(`bg-node-${sides}`)).toContainText('("L", "R")');
  const limb = await addNode(page, 'limb', 'component:limb');
  await page.getByTestId('bg-search').fill('');

  // The arm, drawn on the left joints.
  await drawLeftArm(page, limb);

  await link(page, 'start.then', `${global}.exec`);
  await link(page, `${global}.then`, `${each}.exec`);
  await link(page, `${sides}.value`, `${each}.list`);
  await link(page, `${each}.body`, `${limb}.exec`);
  await link(page, `${each}.element`, `${limb}.side`);
  await link(page, `${global}.component`, `${limb}.parent`);
  await expect.poll(() => drawnLinks(page)).toHaveLength(6);
  // A list cannot feed a string input: refused.
  await link(page, `${sides}.value`, `${limb}.name`);
  await expect.poll(() => page.evaluate(() => (window as any).rigel.buildGraph.lastRefusal?.to)).toBe(`${limb}.name`);
  expect(await drawnLinks(page)).toHaveLength(6);

  // Live: both arms, the right one built from the left one's node.
  await page.getByTestId('bg-live').check();
  await expect.poll(() => componentsOf(server, 'looprig')).toEqual(['global:global', 'limb:arm_L', 'limb:arm_R']);
  await expect(page.getByTestId('bg-problems')).toContainText('✔ valid and built');
  await settle(page, server);
  const world = await server.worldPose();
  const controls = ((await server.get('/api/nodes')).controls as { name: string; rig: string }[]).filter((c) => c.rig === 'looprig').map((c) => c.name);
  const left = controls.filter((n) => n.includes('_arm_L_'));
  expect(controls.filter((n) => n.includes('_arm_R_'))).toHaveLength(left.length);
  expect(left.length).toBeGreaterThan(0);
  for (const name of left) {
    const a = world.get(name)!;
    const b = world.get(name.replace('arm_L', 'arm_R'));
    expect(b, `${name.replace('arm_L', 'arm_R')} in the scene`).toBeDefined();
    expect(Math.abs(a[0]! + b![0]!)).toBeLessThan(1e-6);
    expect(Math.abs(a[1]! - b![1]!)).toBeLessThan(1e-6);
  }
  await shots.take('both-arms');

  // One item removed: its arm goes, the other stays.
  await page.getByTestId(`bg-title-${sides}`).click();
  await panel(page).getByTestId('bg-value-remove-1').click();
  await expect.poll(() => componentsOf(server, 'looprig')).toEqual(['global:global', 'limb:arm_L']);
  await settle(page, server);
  expect(((await page.evaluate(() => (window as any).rigel.errors)) as string[]).filter((x) => /^(GET|POST) /.test(x))).toEqual([]);
});

/** An arm drawn on the left joints, hanging from its `parent` variable, of side `side`. */
const kArmGraph = {
  buildGraph: {
    format: 1,
    rig: { name: 'arm', version: '1.0' },
    variables: [
      { name: 'side', type: 'string', value: 'L' },
      { name: 'parent', type: 'component', value: null },
    ],
    nodes: [
      { id: 'start', kind: 'start' },
      {
        id: 'arm',
        kind: 'component:fkChain',
        component: { type: 'fkChain', name: 'arm', side: 'L', version: '1.0', guides: ['upper_arm.L', 'forearm.L', 'hand.L'].map((joint) => ({ joint })) },
      },
      { id: 'side', kind: 'variable:get', variable: 'side' },
      { id: 'parent', kind: 'variable:get', variable: 'parent' },
    ],
    links: [
      { from: 'start.then', to: 'arm.exec' },
      { from: 'side.value', to: 'arm.side' },
      { from: 'parent.value', to: 'arm.parent' },
    ],
  },
};

test('build graph: a graph file under the root is a sub-graph node; used per side, it builds both arms, and the CLI the same', async ({ app: page, server }) => {
  mkdirSync(join(server.root, 'lib'), { recursive: true });
  writeFileSync(join(server.root, 'lib', 'arm.build.json'), JSON.stringify(kArmGraph, null, 2));
  const { global, sides, each } = await loopOverItems(page, 'subrig', ['L', 'R']);
  const arm = await addNode(page, 'arm.build', 'graph:lib/arm.build.json');
  await page.getByTestId('bg-search').fill('');
  // The sub-graph's variables are the node's sockets.
  await expect(page.getByTestId(`bg-in-${arm}.side`)).toBeVisible();
  await expect(page.getByTestId(`bg-in-${arm}.parent`)).toBeVisible();
  await expect(page.getByTestId(`bg-out-${arm}.parent`)).toBeVisible();

  await link(page, 'start.then', `${global}.exec`);
  await link(page, `${global}.then`, `${each}.exec`);
  await link(page, `${sides}.value`, `${each}.list`);
  await link(page, `${each}.body`, `${arm}.exec`);
  await link(page, `${each}.element`, `${arm}.side`);
  await link(page, `${global}.component`, `${arm}.parent`);
  await expect.poll(() => drawnLinks(page)).toHaveLength(6);

  await page.getByTestId('bg-live').check();
  await expect.poll(() => componentsOf(server, 'subrig')).toEqual(['fkChain:arm_L', 'fkChain:arm_R', 'global:global']);
  await expect(page.getByTestId('bg-problems')).toContainText('✔ valid and built');
  await settle(page, server);

  // Saved beside lib/, the file builds the same rig from the command line.
  await page.getByTestId('bg-save-path').fill('hero.build.json');
  await page.getByTestId('bg-save').click();
  await expect(page.getByTestId('status-text')).toContainText('Saved');
  const r = spawnSync(rigelBin, ['graph', 'run', join(server.root, 'hero.build.json'), '--character', character, '-o', join(server.root, 'hero.rigel'), '--json'], {
    encoding: 'utf8',
  });
  expect(r.status, `rigel graph run: ${r.stdout}${r.stderr}`).toBe(0);
  const report = JSON.parse(r.stdout) as { components: { name: string; side: string; type: string }[] };
  expect(report.components.map((c) => `${c.type}:${c.name}${c.side === 'C' ? '' : `_${c.side}`}`).sort()).toEqual(['fkChain:arm_L', 'fkChain:arm_R', 'global:global']);
  expect(((await page.evaluate(() => (window as any).rigel.errors)) as string[]).filter((x) => /^(GET|POST) /.test(x))).toEqual([]);
});
