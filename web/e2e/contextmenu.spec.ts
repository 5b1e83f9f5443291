// The viewport's context menu on the biped built on the body: right-click
// a built limb's IK control for its actions: FK/IK match, a space switch,
// the component's bind pose, select the component; Escape closes it.

import { expect, expectSelection, settle, test, type RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

async function menu(page: Page, server: RigelServer, control: string): Promise<void> {
  await settle(page, server);
  const at = (await page.evaluate((c) => (window as any).rigel.project(c, true), control)) as { x: number; y: number } | null;
  expect(at, `${control} can be right-clicked`).not.toBeNull();
  await page.mouse.click(at!.x, at!.y, { button: 'right' });
  await expect(page.getByTestId('context-menu')).toBeVisible();
}

async function post(server: RigelServer, path: string, body: unknown): Promise<void> {
  const r = await server.post(path, body);
  expect(r.status, `${path}: ${JSON.stringify(r.body)}`).toBe(200);
}

test('context menu: match, space, bind pose of the component, select the component', async ({ app: page, server, shots }) => {
  await post(server, '/api/rigs/add', { definition: 'examples/biped.rig.xml' });
  await post(server, '/api/channel-values', { controls: ['hero_arm_L_ik'], attrs: ['fkIk'], value: 0 });
  await post(server, '/api/channel-values', { controls: ['hero_arm_L_fk1'], attrs: ['rotateZ'], value: 35 });
  await settle(page, server);

  // IK onto the FK pose: the switch goes to IK.
  await menu(page, server, 'hero_arm_L_ik');
  await expectSelection(page, server, ['hero_arm_L_ik']);
  await expect(page.getByTestId('menu-match-ik')).toBeVisible();
  await shots.take('context-menu');
  await page.getByTestId('menu-match-ik').click();
  await expect(page.getByTestId('context-menu')).toBeHidden();
  await expect.poll(async () => (await server.get('/api/channels?controls=hero_arm_L_fkIkSwitch')).controls[0].channels[0].value).toBe(1);

  // A space from the menu, at this frame.
  await menu(page, server, 'hero_arm_L_ik');
  await page.getByTestId('menu-space-world').click();
  await expect.poll(async () => (await server.get('/api/spaces?control=hero_arm_L_ik')).current).toBe('world');

  // The component's bind pose: the elbow straight again.
  await menu(page, server, 'hero_arm_L_ik');
  await page.getByTestId('menu-bind-component').click();
  await expect
    .poll(async () => {
      const box = await server.get('/api/channels?controls=hero_arm_L_fk1');
      return box.controls[0].channels.find((r: any) => r.plug === 'hero_arm_L_fk1.rotateZ').value;
    })
    .toBe(0);

  // Select the component; Escape closes an open menu.
  await menu(page, server, 'hero_arm_L_ik');
  await page.getByTestId('menu-select-component').click();
  const arm = (await server.get('/api/picker')).groups.find((g: any) => g.name === 'arm_L');
  await expectSelection(page, server, arm.controls.map((c: any) => c.name));
  await menu(page, server, 'hero_arm_L_ik');
  await page.keyboard.press('Escape');
  await expect(page.getByTestId('context-menu')).toBeHidden();
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
