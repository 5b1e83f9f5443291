// Viewport tools on the body with its ephemeral controls: Ctrl+drag box
// select (Ctrl+Shift adds), frame selected (F) and frame all (A), isolate
// selection (I: only the selection drawn and picked, again: all back).

import { clickControl, expect, expectSelection, settle, test } from './fixtures';
import type { Page } from '@playwright/test';

async function selectedNames(page: Page): Promise<string[]> {
  return page.evaluate(() => {
    const w = (window as any).rigel;
    return w.app.scene.selection.map((u: string) => w.store.names.get(u));
  });
}

test('box select, frame selected, frame all, isolate', async ({ app: page, server, shots }) => {
  const at = (await page.evaluate(() => (window as any).rigel.project('hand.L_ctrl'))) as { x: number; y: number };
  expect(at).not.toBeNull();
  // A box around the left hand: the hand and its fingers, nothing of the head or the feet.
  await page.keyboard.down('Control');
  await page.mouse.move(at.x - 30, at.y - 30);
  await page.mouse.down();
  await page.mouse.move(at.x, at.y);
  await page.mouse.move(at.x + 45, at.y + 45);
  await expect(page.getByTestId('select-box')).toBeVisible();
  await page.mouse.up();
  await page.keyboard.up('Control');
  await expect.poll(async () => (await selectedNames(page)).includes('hand.L_ctrl')).toBe(true);
  const boxed = await selectedNames(page);
  expect(boxed.length).toBeGreaterThan(3);
  for (const n of boxed) expect(n, `${n} is of the left hand`).toMatch(/\.L/);
  expect((await server.get('/api/scene')).selection.length).toBe(boxed.length);
  await shots.take('box-selected');

  // Ctrl+Shift+drag adds: a box around the right foot's control adds it.
  const foot = (await page.evaluate(() => {
    const w = (window as any).rigel;
    return w.toScreen(w.viewport.worldPosition(w.uuidOf('foot.R_ctrl')));
  })) as { x: number; y: number };
  await page.keyboard.down('Control');
  await page.keyboard.down('Shift');
  await page.mouse.move(foot.x - 15, foot.y - 15);
  await page.mouse.down();
  await page.mouse.move(foot.x + 15, foot.y + 15);
  await page.mouse.up();
  await page.keyboard.up('Shift');
  await page.keyboard.up('Control');
  await expect.poll(async () => (await selectedNames(page)).includes('foot.R_ctrl')).toBe(true);
  expect(await selectedNames(page)).toEqual(expect.arrayContaining(boxed));

  // Frame selected: the hand comes to the middle of the view, larger.
  await clickControl(page, 'hand.L_ctrl', false, server);
  await expectSelection(page, server, ['hand.L_ctrl']);
  const box = (await page.locator('#viewport canvas').boundingBox())!;
  await page.keyboard.press('f');
  await expect
    .poll(async () => {
      const p = await page.evaluate(() => {
        const w = (window as any).rigel;
        return w.toScreen(w.viewport.worldPosition(w.uuidOf('hand.L_ctrl')));
      });
      return Math.hypot(p.x - (box.x + box.width / 2), p.y - (box.y + box.height / 2));
    })
    .toBeLessThan(20);
  await shots.take('frame-selected');

  // Isolate: only the hand; the foot cannot be picked; again: everything back.
  await page.keyboard.press('i');
  await expect(page.getByTestId('isolate')).toHaveClass(/active/);
  await page.keyboard.press('a');
  await settle(page, server);
  expect(await page.evaluate(() => (window as any).rigel.project('foot.R_ctrl'))).toBeNull();
  expect(await page.evaluate(() => (window as any).rigel.viewport.isolated)).toEqual([await page.evaluate(() => (window as any).rigel.uuidOf('hand.L_ctrl'))]);
  await shots.take('isolated');
  await page.keyboard.press('i');
  await expect(page.getByTestId('isolate')).not.toHaveClass(/active/);
  await expect.poll(() => page.evaluate(() => (window as any).rigel.project('foot.R_ctrl') !== null)).toBe(true);
});
