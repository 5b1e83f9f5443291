// The channel box on the biped built on the body: a built rig's IK control
// picked in the viewport, a value typed and keyed, the limb's fkIk switch
// set and keyed from the same box, the keyed state per channel (here /
// elsewhere), a value dragged, several controls edited together, and undo.

import { clickControl, expect, expectSelection, goToFrame, settle, test, type RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });


/** A channel as the server has it now. */
async function channel(server: RigelServer, control: string, plug: string): Promise<{ value: number; keyed: string }> {
  const box = await server.get(`/api/channels?controls=${control}`);
  const row = box.controls[0].channels.find((r: any) => r.plug === plug);
  if (!row) throw new Error(`${plug} not in the channel box of ${control}`);
  return { value: row.value, keyed: row.keyed };
}

async function typeValue(page: Page, label: string, value: string): Promise<void> {
  const field = page.getByTestId(`channel-value-${label}`);
  await field.fill(value);
  await field.press('Enter');
}

test('channel box: type, key, a switch, keyed state, drag, several controls, undo', async ({ app: page, server, shots }) => {
  const added = await server.post('/api/rigs/add', { definition: 'examples/biped.rig.xml' });
  expect(added.status, JSON.stringify(added.body)).toBe(200);
  await settle(page, server);
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length))
    .toBeGreaterThan(10);
  await goToFrame(page, server, 0);
  await page.getByTestId('tab-channels').click();
  await expect(page.getByTestId('channel-head')).toContainText('Select a control');

  await clickControl(page, 'hero_arm_L_ik', false, server);
  await expectSelection(page, server, ['hero_arm_L_ik']);
  await expect(page.getByTestId('channel-controls')).toHaveText('hero_arm_L_ik');
  for (const label of ['translateX', 'rotateY', 'scaleZ', 'fkIkSwitch.fkIk', 'spaceSwitch.space'])
    await expect(page.getByTestId(`channel-${label}`)).toBeVisible();
  await expect(page.getByTestId('channel-translateY')).toHaveAttribute('data-keyed', 'none');

  // Type a value: the control moves, nothing keyed (auto-key is off); the
  // arm is in FK, so the hand stays.
  const wrist0 = (await server.worldPose()).get('hand.L')!;
  await typeValue(page, 'translateY', '0.1');
  await expect.poll(async () => (await channel(server, 'hero_arm_L_ik', 'hero_arm_L_ik.translateY')).value).toBe(0.1);
  // Not a number: refused in the page, the value put back.
  await typeValue(page, 'translateY', 'up');
  await expect(page.locator('#statusbar')).toContainText('not a number');
  await expect(page.getByTestId('channel-value-translateY')).toHaveValue('0.100');

  // Key it: marked keyed here.
  await page.getByTestId('channel-key-translateY').click();
  await expect(page.getByTestId('channel-translateY')).toHaveAttribute('data-keyed', 'here');
  await expect(page.getByTestId('channel-rotateX')).toHaveAttribute('data-keyed', 'none');

  // The limb's switch from the same box: set to IK and keyed.
  await typeValue(page, 'fkIkSwitch.fkIk', '1');
  await expect.poll(async () => (await channel(server, 'hero_arm_L_ik', 'hero_arm_L_fkIkSwitch.fkIk')).value).toBe(1);
  await expect.poll(async () => {
    const w = (await server.worldPose()).get('hand.L')!;
    return Math.hypot(w[0]! - wrist0[0]!, w[1]! - wrist0[1]!, w[2]! - wrist0[2]!) > 0.05;
  }, { message: 'in IK the moved IK control takes the hand' }).toBe(true);
  await page.getByTestId('channel-key-fkIkSwitch.fkIk').click();
  await expect(page.getByTestId('channel-fkIkSwitch.fkIk')).toHaveAttribute('data-keyed', 'here');
  const keys = await server.get('/api/channel-keys?controls=hero_arm_L_fkIkSwitch&attrs=fkIk');
  expect(keys.keys[0].frames).toEqual([0]);
  await shots.take('channel-box-keyed');

  // Another frame: keyed elsewhere; typing into a keyed channel keys it there.
  await goToFrame(page, server, 10);
  await expect(page.getByTestId('channel-translateY')).toHaveAttribute('data-keyed', 'elsewhere');
  await typeValue(page, 'translateY', '0.2');
  await expect(page.getByTestId('channel-translateY')).toHaveAttribute('data-keyed', 'here');
  const moved = await server.get('/api/channel-keys?controls=hero_arm_L_ik&attrs=translate');
  expect(moved.keys.find((k: any) => k.plug.endsWith('translateY')).frames).toEqual([0, 10]);

  // Drag the channel's name: one change when the button comes up.
  const name = page.getByTestId('channel-rotateZ').locator('.channel-name');
  const box = (await name.boundingBox())!;
  await page.mouse.move(box.x + 5, box.y + box.height / 2);
  await page.mouse.down();
  for (let i = 1; i <= 8; i++) await page.mouse.move(box.x + 5 + i * 5, box.y + box.height / 2);
  await page.mouse.up();
  await expect.poll(async () => (await channel(server, 'hero_arm_L_ik', 'hero_arm_L_ik.rotateZ')).value).toBeCloseTo(20, 6);
  await settle(page, server);

  // Undo takes the drag back, and only it.
  await page.getByTestId('undo').click();
  await expect.poll(async () => (await channel(server, 'hero_arm_L_ik', 'hero_arm_L_ik.rotateZ')).value).toBe(0);
  expect((await channel(server, 'hero_arm_L_ik', 'hero_arm_L_ik.translateY')).value).toBeCloseTo(0.2, 9);

  // Two controls: an edit goes to each one's channel, its own switch included.
  await clickControl(page, 'hero_arm_R_ik', true, server);
  await expectSelection(page, server, ['hero_arm_L_ik', 'hero_arm_R_ik']);
  await expect(page.getByTestId('channel-controls')).toContainText('+1');
  await typeValue(page, 'translateZ', '0.05');
  await expect.poll(async () => (await channel(server, 'hero_arm_R_ik', 'hero_arm_R_ik.translateZ')).value).toBe(0.05);
  expect((await channel(server, 'hero_arm_L_ik', 'hero_arm_L_ik.translateZ')).value).toBe(0.05);
  await typeValue(page, 'fkIkSwitch.fkIk', '0.5');
  await expect.poll(async () => (await channel(server, 'hero_arm_R_ik', 'hero_arm_R_fkIkSwitch.fkIk')).value).toBe(0.5);
  expect((await channel(server, 'hero_arm_L_ik', 'hero_arm_L_fkIkSwitch.fkIk')).value).toBe(0.5);
  await settle(page, server);
  await shots.take('channel-box-two-controls');
});
