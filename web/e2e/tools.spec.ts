// The animator tools in the page on the biped built on the body: FK/IK
// match, mirror, bind pose and tween each change the pose as the same call
// through the API does, and undo returns each.

import { clickControl, expect, expectSelection, sameAsApi, settle, test, undoInPage } from './fixtures';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

test('animator tools: match, mirror, bind pose and tween as the API does them, each undone', async ({ app: page, server, shots }) => {
  expect((await server.post('/api/rigs/add', { definition: 'examples/biped.rig.xml' })).status).toBe(200);
  await settle(page, server);
  await page.getByTestId('tab-channels').click();
  // An FK arm bent at the elbow, the IK control where it was built.
  const set = async (controls: string[], attrs: string[], value: number) =>
    expect((await server.post('/api/channel-values', { controls, attrs, value })).status).toBe(200);
  await set(['hero_arm_L_ik'], ['fkIk'], 0);
  await set(['hero_arm_L_fk1'], ['rotateZ'], 35);
  await set(['hero_arm_L_fk0'], ['rotateX'], 20);
  await settle(page, server);

  await clickControl(page, 'hero_arm_L_ik', false, server);
  await expectSelection(page, server, ['hero_arm_L_ik']);
  await expect(page.getByTestId('tool-target')).toHaveText('hero:arm_L');
  await shots.take('tools');

  // IK onto the FK pose, keyed: the switch goes to IK and the hand stays.
  const handBefore = (await server.worldPose()).get('hand.L')!;
  await page.getByTestId('tool-match-ik').click();
  await expect.poll(async () => (await server.get('/api/channels?controls=hero_arm_L_fkIkSwitch')).controls[0].channels[0].value).toBe(1);
  await settle(page, server);
  const handAfter = (await server.worldPose()).get('hand.L')!;
  for (let i = 0; i < 3; i++) expect(Math.abs(handAfter[i]! - handBefore[i]!)).toBeLessThan(1e-6);
  await undoInPage(page, server);
  await expect.poll(async () => (await server.get('/api/channels?controls=hero_arm_L_fkIkSwitch')).controls[0].channels[0].value).toBe(0);

  // Mirror the FK arm onto the right one (the FK controls selected), bind pose, tween.
  await clickControl(page, 'hero_arm_L_fk1', false, server);
  await clickControl(page, 'hero_arm_L_fk0', true, server);
  await expectSelection(page, server, ['hero_arm_L_fk1', 'hero_arm_L_fk0']);
  await set(['hero_arm_R_ik'], ['fkIk'], 0);
  await sameAsApi(page, server, 'tool-mirror', '/api/mirror', { controls: ['hero_arm_L_fk1', 'hero_arm_L_fk0'] });
  await sameAsApi(page, server, 'tool-bind-pose', '/api/bind-pose', { controls: ['hero_arm_L_fk1', 'hero_arm_L_fk0'] });

  // Tween: keys at 0 (bent) and 10 (bind pose), the slider at 50% at frame 5.
  expect((await server.post('/api/channel-keys', { controls: ['hero_arm_L_fk1'], attrs: ['rotate'] })).status).toBe(200);
  expect((await server.post('/api/time', { frame: 10 })).status).toBe(200);
  await set(['hero_arm_L_fk1'], ['rotateZ'], 0);
  expect((await server.post('/api/time', { frame: 5 })).status).toBe(200);
  await set(['hero_arm_L_fk1'], ['rotateZ'], 90); // off the curve: the tween puts it back between the keys
  await settle(page, server);
  await page.getByTestId('tool-tween-fraction').fill('50');
  await sameAsApi(page, server, 'tool-tween', '/api/tween', { controls: ['hero_arm_L_fk1', 'hero_arm_L_fk0'], fraction: 0.5 });
});
