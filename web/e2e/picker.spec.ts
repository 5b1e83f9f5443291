// The picker and selection sets on the biped built on the body: controls
// picked by their buttons (Shift adds), a whole component by its title, a
// selection saved as a named set (saved with the scene), selected again,
// removed and brought back by undo.

import { expect, expectSelection, settle, test, type RigelServer } from './fixtures';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

async function sets(server: RigelServer): Promise<{ name: string; members: { name: string }[] }[]> {
  return (await server.get('/api/selection-sets')).sets;
}

test('picker: pick controls and components, save, select and remove a selection set, undo', async ({ app: page, server, shots }) => {
  const added = await server.post('/api/rigs/add', { definition: 'examples/biped.rig.xml' });
  expect(added.status, JSON.stringify(added.body)).toBe(200);
  await settle(page, server);
  await page.getByTestId('tab-picker').click();
  await expect(page.getByTestId('pick-hero_arm_L_ik')).toBeVisible();

  // The layout: the left arm in the left column (the character's left, on the viewer's right).
  const left = await page.getByTestId('picker-group-arm_L').boundingBox();
  const right = await page.getByTestId('picker-group-arm_R').boundingBox();
  expect(left!.x).toBeGreaterThan(right!.x);
  await shots.take('picker');

  // Pick, Shift-pick: the selection the server has.
  await page.getByTestId('pick-hero_arm_L_ik').click();
  await expectSelection(page, server, ['hero_arm_L_ik']);
  await expect(page.getByTestId('pick-hero_arm_L_ik')).toHaveClass(/active/);
  await page.getByTestId('pick-hero_arm_L_fk0').click({ modifiers: ['Shift'] });
  await expectSelection(page, server, ['hero_arm_L_ik', 'hero_arm_L_fk0']);

  // Save it as a set.
  await page.getByTestId('set-name').fill('left_arm');
  await page.getByTestId('set-save').click();
  await expect.poll(async () => (await sets(server)).map((s) => [s.name, s.members.map((m) => m.name)])).toEqual([
    ['left_arm', ['hero_arm_L_ik', 'hero_arm_L_fk0']],
  ]);
  await expect(page.getByTestId('set-left_arm')).toBeVisible();

  // A component's title selects all of its controls.
  const picker = await server.get('/api/picker');
  const legR = picker.groups.find((g: any) => g.name === 'leg_R');
  await page.getByTestId('picker-group-leg_R').click();
  await expectSelection(page, server, legR.controls.map((c: any) => c.name));

  // The set selects its members again; Shift adds them.
  await page.getByTestId('set-left_arm').locator('.set-select').click();
  await expectSelection(page, server, ['hero_arm_L_ik', 'hero_arm_L_fk0']);
  await page.getByTestId('picker-group-leg_R').click();
  await page.getByTestId('set-left_arm').locator('.set-select').click({ modifiers: ['Shift'] });
  await expectSelection(page, server, [...legR.controls.map((c: any) => c.name), 'hero_arm_L_ik', 'hero_arm_L_fk0']);
  await shots.take('picker-set-selected');

  // Remove it; undo brings it back.
  await page.getByTestId('set-remove-left_arm').click();
  await expect.poll(async () => (await sets(server)).length).toBe(0);
  await expect(page.getByTestId('set-left_arm')).toHaveCount(0);
  await page.getByTestId('undo').click();
  await expect.poll(async () => (await sets(server)).length).toBe(1);
  await expect(page.getByTestId('set-left_arm')).toBeVisible();
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
