// The build-graph editor's plugin node kinds: the shipped Repeat (a flow
// kind, flow:rigel.repeat) from the palette runs an arm's node once per
// pass, each arm named from the pass's index by pure functions (Number as
// text, Join text) whose inputs are edited in the details panel; live, a
// new count builds or removes arms. A build function's output cannot feed
// the Repeat's count (it is made while building): refused visibly.

import { addNode, drawLeftArm, drawnLinks, link, panel } from './buildgraphhelpers';
import { expect, settle, test } from './fixtures';
import type { RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

/** The components of rig `rig` in the server's scene, as TYPE:NAME, sorted; null when it has none. */
async function componentsOf(server: RigelServer, rig: string): Promise<string[] | null> {
  const r = ((await server.get('/api/rigs')).rigs as any[]).find((x) => x.name === rig);
  return r ? r.components.map((c: any) => `${c.type}:${c.name}`).sort() : null;
}

/** Sets input `socket` of node `node` in the details panel (Enter commits it). */
async function setInput(page: Page, node: string, socket: string, value: string): Promise<void> {
  await page.getByTestId(`bg-title-${node}`).click();
  const field = panel(page).getByTestId(`bg-input-${socket}`);
  await field.fill(value);
  await field.press('Enter');
}

/** Links `from` to `to` after scrolling the graph to the output socket (the graph holds more nodes than it shows). */
async function near(page: Page, from: string, to: string): Promise<void> {
  await page.getByTestId(`bg-out-${from}`).scrollIntoViewIfNeeded();
  await page.getByTestId(`bg-in-${to}`).scrollIntoViewIfNeeded();
  await link(page, from, to);
}

test('build graph: a plugin node kind from the palette repeats an arm, named per pass; live, a new count rebuilds', async ({ app: page, server }) => {
  await page.getByTestId('tab-build').click();
  await panel(page).getByTestId('bg-rig-name').fill('flowrig');
  await panel(page).getByTestId('bg-rig-name').press('Enter');
  // The chain first (the nodes near Start), then the naming nodes beside the arm.
  const global = await addNode(page, 'glob', 'component:global');
  const repeat = await addNode(page, 'repeat', 'flow:rigel.repeat');
  await expect(page.getByTestId(`bg-out-${repeat}.body`)).toBeVisible();
  const limb = await addNode(page, 'limb', 'component:limb');
  await page.getByTestId('bg-search').fill('');
  await drawLeftArm(page, limb);
  await near(page, 'start.then', `${global}.exec`);
  await near(page, `${global}.then`, `${repeat}.exec`);
  await near(page, `${repeat}.body`, `${limb}.exec`);
  await near(page, `${global}.component`, `${limb}.parent`);
  await expect.poll(() => drawnLinks(page)).toHaveLength(4);
  const number = await addNode(page, 'number as', 'function:rigel.intText');
  const join = await addNode(page, 'join', 'function:rigel.joinText');
  const colour = await addNode(page, 'colour', 'function:rigel.setControlColor');
  await page.getByTestId('bg-search').fill('');
  await setInput(page, number, 'digits', '2');
  await setInput(page, join, 'a', 'arm');
  await setInput(page, join, 'separator', '_');
  await expect
    .poll(() => page.evaluate((id) => (window as any).rigel.buildGraph.model.nodes.get(id).values, join))
    .toMatchObject({ a: 'arm', separator: '_' });
  await near(page, `${repeat}.index`, `${number}.value`);
  await near(page, `${number}.text`, `${join}.b`);
  await near(page, `${join}.text`, `${limb}.name`);
  await expect.poll(() => drawnLinks(page)).toHaveLength(7);
  // A build function's output is made while building: the Repeat's count cannot read it.
  await near(page, `${colour}.count`, `${repeat}.count`);
  await expect.poll(() => page.evaluate(() => (window as any).rigel.buildGraph.lastRefusal?.to)).toBe(`${repeat}.count`);
  expect(await drawnLinks(page)).toHaveLength(7);
  // The unused function node is not on the chain: removed before building.
  await page.getByTestId(`bg-title-${colour}`).click();
  await page.keyboard.press('Delete');
  await expect(page.getByTestId(`bg-node-${colour}`)).toHaveCount(0);

  // Live: one arm per pass (count 2 by default), each named from its index.
  await page.getByTestId('bg-live').check();
  await expect.poll(() => componentsOf(server, 'flowrig')).toEqual(['global:global', 'limb:arm_00_L', 'limb:arm_01_L']);
  await expect(page.getByTestId('bg-problems')).toContainText('✔ valid and built');
  // A third pass: one more arm; back to one: the others go.
  await setInput(page, repeat, 'count', '3');
  await expect.poll(() => componentsOf(server, 'flowrig')).toEqual(['global:global', 'limb:arm_00_L', 'limb:arm_01_L', 'limb:arm_02_L']);
  await setInput(page, repeat, 'count', '1');
  await expect.poll(() => componentsOf(server, 'flowrig')).toEqual(['global:global', 'limb:arm_00_L']);
  // A count the Repeat refuses is shown on its node; the rig stays as it was.
  await setInput(page, repeat, 'count', '-1');
  await expect(page.getByTestId('bg-problems')).toContainText('count: -1');
  expect(await componentsOf(server, 'flowrig')).toEqual(['global:global', 'limb:arm_00_L']);
  await settle(page, server);
  expect(((await page.evaluate(() => (window as any).rigel.errors)) as string[]).filter((x) => /^(GET|POST) /.test(x))).toEqual([]);
});
