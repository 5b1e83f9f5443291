// The context menu's rigger mode on the body's ephemeral rig: the mode
// switched at the menu's top (and kept for the next menu), a control's
// shape copied and pasted onto another, mirrored onto the opposite
// control, undone; a locator created at a control; the hand matched onto
// the locator in inverse mode and a finger chain's joints mirrored to the
// other side, each the same as the JSON API's call and undone.

import { clickControl, expect, expectSelection, sameAsApi, setMode, settle, test, undoInPage, type RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

async function menu(page: Page, server: RigelServer, control: string): Promise<void> {
  await settle(page, server);
  const at = (await page.evaluate((c) => (window as any).rigel.project(c, true), control)) as { x: number; y: number } | null;
  expect(at, `${control} can be right-clicked`).not.toBeNull();
  await page.mouse.click(at!.x, at!.y, { button: 'right' });
  await expect(page.getByTestId('context-menu')).toBeVisible();
}

const shapeOf = async (server: RigelServer, control: string): Promise<number[][]> =>
  (await server.get(`/api/shape?control=${encodeURIComponent(control)}`)).points;
const pageShape = (page: Page, control: string): Promise<number[][] | undefined> =>
  page.evaluate((c) => (window as any).rigel.app.nodes.controls.find((x: any) => x.name === c)?.shape.points, control);

test('rigger mode: copy and paste a shape, mirror it to the other side, undo', async ({ app: page, server, shots }) => {
  await menu(page, server, 'hand.L_ctrl');
  await page.getByTestId('menu-mode-rigger').click();
  await expect(page.getByTestId('menu-copy-shape')).toBeVisible();
  await expect(page.getByTestId('menu-key')).toHaveCount(0);
  await shots.take('rigger-menu');
  await page.getByTestId('menu-copy-shape').click();
  await expect.poll(() => page.evaluate(() => (window as any).rigel.contextMenu.clipboard)).toBe('hand.L_ctrl');

  const hand = await shapeOf(server, 'hand.L_ctrl');
  const foot = await shapeOf(server, 'foot.L_ctrl');
  const footR = await shapeOf(server, 'foot.R_ctrl');
  expect(foot).not.toEqual(hand);
  await clickControl(page, 'foot.L_ctrl', false, server);
  await expectSelection(page, server, ['foot.L_ctrl']);
  await menu(page, server, 'foot.L_ctrl');
  await expect(page.getByTestId('menu-paste-shape')).toBeVisible(); // the mode is kept
  await page.getByTestId('menu-paste-shape').click();
  await expect.poll(() => shapeOf(server, 'foot.L_ctrl')).toEqual(hand);
  await expect.poll(() => pageShape(page, 'foot.L_ctrl')).toEqual(hand);

  await menu(page, server, 'foot.L_ctrl');
  await page.getByTestId('menu-opposite-shape').click();
  await expect.poll(async () => (await shapeOf(server, 'foot.R_ctrl')).length).toBe(hand.length);
  await expect.poll(async () => (await pageShape(page, 'foot.R_ctrl'))?.length).toBe(hand.length);
  await shots.take('shape-mirrored-to-the-right-foot');

  await undoInPage(page, server);
  expect(await shapeOf(server, 'foot.R_ctrl')).toEqual(footR);
  await undoInPage(page, server);
  expect(await shapeOf(server, 'foot.L_ctrl')).toEqual(foot);
  await expect.poll(() => pageShape(page, 'foot.L_ctrl')).toEqual(foot);
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});

test('rigger mode: a locator, match position in inverse mode, mirror joints', async ({ app: page, server }) => {
  await page.evaluate(() => localStorage.setItem('rigel.menuMode', 'rigger'));
  await page.reload();
  await page.waitForFunction(() => (window as any).rigel?.isReady?.() === true);
  await setMode(page, server, 'inverse');

  // A locator at the hand, then moved a little up and out.
  await menu(page, server, 'hand.L_ctrl');
  await page.getByTestId('menu-locator').click();
  await expect.poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.some((c: any) => c.name === 'hand.L_ctrl_loc'))).toBe(true);
  const hand = (await server.worldPose()).get('hand.L_ctrl')!;
  const loc = (await server.worldPose()).get('hand.L_ctrl_loc')!;
  for (let i = 0; i < 3; i++) expect(Math.abs(loc[i]! - hand[i]!)).toBeLessThan(1e-9);
  const r = await server.post('/api/channel-values', { controls: ['hand.L_ctrl_loc'], attrs: ['translateX', 'translateY'], value: [loc[0]! + 0.06, loc[1]! + 0.1] });
  expect(r.status, JSON.stringify(r.body)).toBe(200);

  // The locator first, then the hand: the hand matches the locator.
  await clickControl(page, 'hand.L_ctrl_loc', false, server);
  await clickControl(page, 'hand.L_ctrl', true, server);
  await expectSelection(page, server, ['hand.L_ctrl_loc', 'hand.L_ctrl']);
  await menu(page, server, 'hand.L_ctrl');
  await expect(page.getByTestId('menu-match-position')).toContainText('hand.L_ctrl_loc');
  await sameAsApi(page, server, 'menu-match-position', '/api/align', {
    nodes: ['hand.L_ctrl'],
    target: 'hand.L_ctrl_loc',
    position: true,
    rotation: false,
  });

  // A finger moved on the left; its joints mirrored onto the right.
  const bend = await server.post('/api/channel-values', { controls: ['f_index.01.L_ctrl'], attrs: ['translateX'], value: 0.012 });
  expect(bend.status, JSON.stringify(bend.body)).toBe(200);
  await clickControl(page, 'f_index.01.L_ctrl', false, server);
  await menu(page, server, 'f_index.01.L_ctrl');
  await sameAsApi(page, server, 'menu-mirror-joints-update', '/api/mirror-joints', { joints: ['f_index.01.L_ctrl'], update: true });
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
