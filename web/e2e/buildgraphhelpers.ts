// Gestures and reads shared by the build-graph editor's browser tests
// (buildgraph.spec.ts, buildgraphloop.spec.ts).

import type { Locator, Page } from '@playwright/test';
import { expect } from './fixtures';

export const panel = (page: Page): Locator => page.locator('#build-panel');

/** The ids of the graph's nodes, in order. */
export async function nodeIds(page: Page): Promise<string[]> {
  return page.evaluate(() => [...(window as any).rigel.buildGraph.model.nodes.keys()] as string[]);
}

/** Adds a node from the palette, found with the search box; returns its id. */
export async function addNode(page: Page, search: string, kind: string): Promise<string> {
  await page.getByTestId('bg-search').fill(search);
  const entry = page.getByTestId(`bg-palette-${kind}`);
  await expect(entry).toBeVisible();
  const before = await nodeIds(page);
  await entry.click();
  await expect.poll(async () => (await nodeIds(page)).length).toBe(before.length + 1);
  const id = (await nodeIds(page)).find((x) => !before.includes(x))!;
  await expect(page.getByTestId(`bg-node-${id}`)).toBeVisible();
  return id;
}

/** Drags from output socket `from` ("node.socket") to input socket `to`. */
export async function link(page: Page, from: string, to: string): Promise<void> {
  await page.getByTestId('bg-graph').scrollIntoViewIfNeeded();
  const a = (await page.getByTestId(`bg-out-${from}`).boundingBox())!;
  const b = (await page.getByTestId(`bg-in-${to}`).boundingBox())!;
  await page.mouse.move(a.x + a.width / 2, a.y + a.height / 2);
  await page.mouse.down();
  await page.mouse.move(a.x + 30, a.y + 15, { steps: 3 });
  await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2, { steps: 6 });
  await page.mouse.up();
}

/** The links the page draws, as "FROM->TO". */
export async function drawnLinks(page: Page): Promise<string[]> {
  return page.locator('path.bg-link').evaluateAll((ps) => ps.map((p) => `${(p as SVGElement).dataset.from}->${(p as SVGElement).dataset.to}`).sort());
}

/** The graph the editor holds: nodes (no geometry) and links. */
export async function graphOf(page: Page): Promise<{ rig: string; nodes: unknown[]; links: unknown[] }> {
  return page.evaluate(() => {
    const g = (window as any).rigel.buildGraph.model.toJson(null).buildGraph;
    return { rig: g.rig.name, nodes: g.nodes, links: g.links };
  });
}

/** Makes limb node `limb` the biped's left arm (examples/biped.rig.xml) in the details panel: name, side, joints, FK. */
export async function drawLeftArm(page: Page, limb: string): Promise<void> {
  await page.getByTestId(`bg-title-${limb}`).click();
  await panel(page).getByTestId('def-name').fill('arm');
  await panel(page).getByTestId('def-name').press('Enter');
  await panel(page).getByTestId('def-side').selectOption('L');
  for (const [i, joint] of ['upper_arm.L', 'forearm.L', 'hand.L'].entries()) {
    await panel(page).getByTestId(`def-guide-joint-${i}`).fill(joint);
    await panel(page).getByTestId(`def-guide-joint-${i}`).press('Enter');
  }
  await panel(page).getByTestId('def-param-kind').selectOption('arm');
  await panel(page).getByTestId('def-param-defaultMode').selectOption('fk');
}
