// Display on the body's ephemeral rig: the mesh shaded, see-through or
// hidden (M), and control groups (the face, each hand, the chest, the hips)
// hidden and shown, so the face's many small controls can be picked alone
// and a finger control picked by clicking.

import { clickControl, expect, expectSelection, settle, test } from './fixtures';
import type { Page } from '@playwright/test';

type MeshState = { meshes: number; visible: number; opacity: number[] };

function meshState(page: Page): Promise<MeshState> {
  return page.evaluate(() => (window as any).rigel.viewport.meshState() as MeshState);
}

test('mesh shaded, x-ray and hidden; groups of controls hidden, shown and picked', async ({ app: page, server, shots }) => {
  const shaded = await meshState(page);
  expect(shaded.meshes).toBeGreaterThan(0);
  expect(shaded.visible).toBe(shaded.meshes);
  await expect(page.getByTestId('mesh-display')).toContainText('Shaded');

  await page.keyboard.press('m');
  await expect(page.getByTestId('mesh-display')).toContainText('X-ray');
  const xray = await meshState(page);
  expect(xray.visible).toBe(xray.meshes);
  expect(Math.max(...xray.opacity)).toBeLessThanOrEqual(0.3);
  await shots.take('mesh-xray');
  await page.getByTestId('mesh-display').click();
  await expect(page.getByTestId('mesh-display')).toContainText('Hidden');
  expect((await meshState(page)).visible).toBe(0);
  await shots.take('mesh-hidden');
  await page.keyboard.press('m');
  await expect(page.getByTestId('mesh-display')).toContainText('Shaded');
  expect(await meshState(page)).toEqual(shaded);

  // The groups: the face's controls in one, each hand's in another.
  const controls = (await page.evaluate(() => (window as any).rigel.app.nodes.controls)) as { name: string; group: string }[];
  const face = controls.filter((c) => c.group === 'face_ctrl').map((c) => c.name);
  expect(face.length).toBeGreaterThan(50);
  expect(controls.filter((c) => c.group === 'hand.L_ctrl').map((c) => c.name)).toContain('f_index.01.L_ctrl');
  await page.getByTestId('groups').click();
  await expect(page.getByTestId('group-face_ctrl')).toBeChecked();

  // A finger control picked by clicking, everything shown.
  await page.getByTestId('groups').click(); // closes the menu
  await clickControl(page, 'f_index.02.L_ctrl', false, server);
  await expectSelection(page, server, ['f_index.02.L_ctrl']);

  // Every control shape is drawn in one call: the frame's draw calls stay
  // far below the number of controls (the mesh, joints, gizmo, grid and the
  // merged shapes), and the shapes' segments follow what is shown.
  const stats = () => page.evaluate(() => (window as any).rigel.stats() as { drawCalls: number; controlSegments: number });
  await expect.poll(async () => (await stats()).drawCalls).toBeGreaterThan(0);
  const all = await stats();
  expect(controls.length).toBeGreaterThan(100);
  expect(all.drawCalls).toBeLessThan(30);
  expect(all.controlSegments).toBeGreaterThan(controls.length);

  // Only the face shown: a face control picked by clicking; the rest cannot be.
  await page.getByTestId('groups').click();
  await page.getByTestId('groups-none').click();
  await expect.poll(async () => (await stats()).controlSegments).toBe(0);
  await page.getByTestId('group-face_ctrl').check();
  await page.getByTestId('groups').click();
  await expect.poll(async () => (await stats()).controlSegments).toBeGreaterThan(0);
  expect((await stats()).controlSegments).toBeLessThan(all.controlSegments);
  expect(await page.evaluate(() => (window as any).rigel.project('f_index.02.L_ctrl'))).toBeNull();
  const target = face.find((n) => n.startsWith('lip.T.L')) ?? face[0]!;
  await clickControl(page, target, false, server);
  await expectSelection(page, server, [target]);
  await shots.take('face-only');

  // Everything back.
  await page.getByTestId('groups').click();
  await page.getByTestId('groups-all').click();
  await expect(page.getByTestId('group-spine_ctrl')).toBeChecked();
  expect(await page.evaluate(() => (window as any).rigel.project('f_index.02.L_ctrl'))).not.toBeNull();
  await settle(page, server);
});

test('? shows every shortcut and Esc closes it', async ({ app: page }) => {
  await expect(page.getByTestId('help')).toBeHidden();
  await page.keyboard.press('?');
  const help = page.getByTestId('help');
  await expect(help).toBeVisible();
  for (const text of ['Forward mode', 'Set key / delete key', 'Mesh: shaded, x-ray, hidden', 'Undo / redo']) await expect(help).toContainText(text);
  await page.keyboard.press('Escape');
  await expect(help).toBeHidden();
});
