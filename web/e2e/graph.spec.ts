// The graph editor on the biped built on the body: the IK arm control's
// keyed translate and its limb's fkIk switch (its last key set from the
// channel box) shown as curves; a key
// selected and dragged in time and value, the pose at that frame
// changed, undone; a tangent type set from
// the menu; a tangent handle dragged (both sides follow); a key inserted
// at the current frame and deleted; box select; frame all.

import { clickControl, dist, expect, goToFrame, settle, test, type RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

interface Curve {
  plug: string;
  frames: number[];
  values: number[];
  inTangents: string[];
  outTangents: string[];
  inSlopes: number[];
  outSlopes: number[];
}

async function curve(server: RigelServer, plug: string): Promise<Curve | undefined> {
  const a = await server.get<{ curves: Curve[] }>('/api/curves?controls=hero_arm_L_ik');
  return a.curves.find((c) => c.plug === plug);
}

async function post(server: RigelServer, path: string, body: unknown): Promise<void> {
  const r = await server.post(path, body);
  expect(r.status, `${path}: ${JSON.stringify(r.body)}`).toBe(200);
}

/** Client pixels of a key (or its handle) as the editor draws it, once the page has settled. */
async function point(page: Page, server: RigelServer, plug: string, frame: number, handle?: 'in' | 'out'): Promise<{ x: number; y: number }> {
  await settle(page, server);
  const p = await page.evaluate(([c, f, hd]) => (window as any).rigel.graphEditor.point(c, f, hd ?? undefined), [plug, frame, handle ?? null] as const);
  expect(p, `${plug} key at ${frame} shown`).not.toBeNull();
  return p as { x: number; y: number };
}

async function selection(page: Page): Promise<[string, number][]> {
  return page.evaluate(() => (window as any).rigel.graphEditor.selection);
}

const kFkIk = 'hero_arm_L_fkIkSwitch.fkIk';
const kTy = 'hero_arm_L_ik.translateY';
const kTx = 'hero_arm_L_ik.translateX';

test('graph editor: curves, select and drag keys, undo, tangents, insert, delete, box select', async ({ app: page, server, shots }) => {
  await post(server, '/api/rigs/add', { definition: 'examples/biped.rig.xml' });
  for (const f of [0, 10]) {
    await post(server, '/api/time', { frame: f });
    await post(server, '/api/channel-values', { controls: ['hero_arm_L_ik'], attrs: ['translateY'], value: 0.05 + f * 0.01 });
    await post(server, '/api/channel-keys', { controls: ['hero_arm_L_ik'], attrs: ['translate'] });
  }
  for (const [f, v] of [[0, 0], [10, 1]] as const) {
    await post(server, '/api/time', { frame: f });
    await post(server, '/api/channel-keys', { controls: ['hero_arm_L_fkIkSwitch'], attrs: ['fkIk'], value: v });
  }
  await settle(page, server);
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length))
    .toBeGreaterThan(10);
  await clickControl(page, 'hero_arm_L_ik', false, server);
  await page.keyboard.press('g');
  await expect(page.getByTestId('curve-canvas')).toBeVisible();
  for (const plug of [kTx, kTy, kFkIk]) await expect(page.getByTestId(`curve-${plug}`)).toBeVisible();
  // The switch keyed at 20 from the channel box (a keyed channel typed is keyed): the curve shows it.
  await page.getByTestId('tab-channels').click();
  await goToFrame(page, server, 20);
  const field = page.getByTestId('channel-value-fkIkSwitch.fkIk');
  await field.fill('0.5');
  await field.press('Enter');
  await expect.poll(async () => (await curve(server, kFkIk))?.frames).toEqual([0, 10, 20]);
  await expect.poll(() => page.evaluate((p) => (window as any).rigel.graphEditor.curves.find((c: any) => c.plug === p)?.frames.length, kFkIk)).toBe(3);
  await shots.take('graph-editor');

  // The pose at frame 15 before the key moves (the arm blends FK and IK there; the IK hand is raised).
  await goToFrame(page, server, 15);
  const hand15 = (await server.worldPose()).get('hand.L')!;

  // Click fkIk's key at 10 and drag it right and up: it lands on a whole frame with a larger value.
  const k10 = await point(page, server, kFkIk, 10);
  await page.mouse.move(k10.x, k10.y);
  await page.mouse.down();
  const to = await page.evaluate(() => {
    const ge = (window as any).rigel.graphEditor;
    return ge.at(15.2, 1.25);
  });
  for (let i = 1; i <= 8; ++i) await page.mouse.move(k10.x + ((to.x - k10.x) * i) / 8, k10.y + ((to.y - k10.y) * i) / 8);
  await page.mouse.up();
  await expect.poll(async () => (await curve(server, kFkIk))?.frames).toEqual([0, 15, 20]);
  const movedValue = (await curve(server, kFkIk))!.values[1]!;
  expect(movedValue).toBeGreaterThan(1.15);
  expect(movedValue).toBeLessThan(1.35);
  await expect.poll(() => selection(page)).toEqual([[kFkIk, 15]]);
  // The pose at frame 15 follows the key (all IK there now).
  await expect.poll(async () => dist((await server.worldPose()).get('hand.L')!, hand15)).toBeGreaterThan(1e-3);
  await shots.take('graph-editor-moved');

  // One undo step: back to frame 10 and 1.
  await page.getByTestId('undo').click();
  await expect.poll(async () => (await curve(server, kFkIk))?.frames).toEqual([0, 10, 20]);
  expect((await curve(server, kFkIk))!.values[1]).toBe(1);

  // Tangent type from the menu, on the key selected by a click.
  const again = await point(page, server, kFkIk, 10);
  await page.mouse.click(again.x, again.y);
  await expect.poll(() => selection(page)).toEqual([[kFkIk, 10]]);
  await page.getByTestId('curve-tangent').selectOption('step');
  await expect.poll(async () => (await curve(server, kFkIk))?.outTangents[1]).toBe('step');
  expect((await curve(server, kFkIk))!.inTangents[1]).toBe('step');

  // A tangent handle dragged: translateY's key at 0, its out handle pulled down; both sides take the slope.
  // (fkIk and translateZ hidden: translateZ's keys lie on translateX's.)
  for (const plug of [kFkIk, 'hero_arm_L_ik.translateZ']) await page.getByTestId(`curve-${plug}`).locator('input').uncheck();
  await page.getByTestId('curve-frame-all').click();
  const ty0 = await point(page, server, kTy, 0);
  await page.mouse.click(ty0.x, ty0.y);
  await expect.poll(() => selection(page)).toEqual([[kTy, 0]]);
  const before = (await curve(server, kTy))!;
  const handle = await point(page, server, kTy, 0, 'out');
  await page.mouse.move(handle.x, handle.y);
  await page.mouse.down();
  for (let i = 1; i <= 6; ++i) await page.mouse.move(handle.x, handle.y + i * 8);
  await page.mouse.up();
  await expect.poll(async () => (await curve(server, kTy))?.outSlopes[0]).toBeLessThan(before.outSlopes[0]! - 1e-4);
  const after = (await curve(server, kTy))!;
  expect(after.inSlopes[0]).toBeCloseTo(after.outSlopes[0]!, 9);
  expect(after.outTangents[0]).toBe('fixed');

  // Insert at the current frame on the curve of the selected key (I), then delete it (Delete).
  await goToFrame(page, server, 5);
  const tx0 = await point(page, server, kTx, 0);
  await page.mouse.click(tx0.x, tx0.y);
  await expect.poll(() => selection(page)).toEqual([[kTx, 0]]);
  await page.keyboard.press('i');
  await expect.poll(async () => (await curve(server, kTx))?.frames).toEqual([0, 5, 10]);
  expect((await curve(server, kTy))?.frames).toEqual([0, 10]);
  const tx5 = await point(page, server, kTx, 5);
  await page.mouse.click(tx5.x, tx5.y);
  await expect.poll(() => selection(page)).toEqual([[kTx, 5]]);
  await page.keyboard.press('Delete');
  await expect.poll(async () => (await curve(server, kTx))?.frames).toEqual([0, 10]);

  // Box select over the whole plot: every key shown.
  await settle(page, server);
  const box = (await page.getByTestId('curve-canvas').boundingBox())!;
  await page.mouse.move(box.x + 2, box.y + 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.move(box.x + box.width - 2, box.y + box.height - 2);
  await page.mouse.up();
  const shown = await page.evaluate(() => {
    const ge = (window as any).rigel.graphEditor;
    return ge.curves.filter((c: any) => c.plug === 'hero_arm_L_ik.translateX' || c.plug === 'hero_arm_L_ik.translateY').reduce((n: number, c: any) => n + c.frames.length, 0);
  });
  await expect.poll(async () => (await selection(page)).length).toBe(shown);
  await expect(page.getByTestId('curve-stats')).toHaveText(`${shown} keys selected`);
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
