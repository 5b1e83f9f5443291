// The rest of the animator tools in the page on the biped built on the body:
// the pose library (save, apply as the API does, mirrored, blended, undo),
// a space switch at a frame (the world pose kept, the space changed, undo),
// transfer of keys onto the other arm with an offset, FK/IK match baked
// over the playback range, and a deform-only
// glTF export that the Khronos validator passes.

import { spawnSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { join } from 'node:path';
import { clickControl, expect, expectSelection, goToFrame, poseDifference, repoDir, sameAsApi, settle, test, undoInPage, type RigelServer } from './fixtures';

test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

async function post(server: RigelServer, path: string, body: unknown): Promise<any> {
  const r = await server.post(path, body);
  expect(r.status, `${path}: ${JSON.stringify(r.body)}`).toBe(200);
  return r.body;
}

test('pose library, space switch, transfer and deform-only export from the page', async ({ app: page, server, shots }) => {
  await post(server, '/api/rigs/add', { definition: 'examples/biped.rig.xml' });
  await settle(page, server);
  await goToFrame(page, server, 0);
  await page.getByTestId('tab-channels').click();

  // Save the whole rig's pose with the left IK hand raised.
  await post(server, '/api/channel-values', { controls: ['hero_arm_L_ik'], attrs: ['translateY'], value: 0.1 });
  await post(server, '/api/channel-values', { controls: ['hero_arm_L_fkIkSwitch'], attrs: ['fkIk'], value: 1 });
  await settle(page, server);
  await page.getByTestId('pose-name').fill('raised');
  await page.getByTestId('pose-save').click();
  await expect(page.getByTestId('pose-raised')).toBeVisible();
  expect(existsSync(join(server.root, 'poses', 'raised.pose.json'))).toBe(true);
  // Its thumbnail: the skeleton in the pose, drawn in the row.
  expect(existsSync(join(server.root, 'poses', 'raised.pose.svg'))).toBe(true);
  const thumb = page.getByTestId('pose-thumb-raised');
  await expect(thumb).toBeVisible();
  await expect.poll(() => thumb.evaluate((img: HTMLImageElement) => img.complete && img.naturalWidth)).toBe(96);
  await thumb.scrollIntoViewIfNeeded();
  await shots.take('pose-thumbnail');
  await post(server, '/api/bind-pose', { controls: ['hero:'] });
  await settle(page, server);

  // Apply it, as the API does; mirrored; blended at half.
  await sameAsApi(page, server, 'pose-apply-raised', '/api/poses/apply', { library: 'poses', name: 'raised', fraction: 1 });
  await sameAsApi(page, server, 'pose-mirror-raised', '/api/poses/apply', { library: 'poses', name: 'raised', mirror: true, fraction: 1 });
  await page.getByTestId('pose-fraction').fill('50');
  await sameAsApi(page, server, 'pose-apply-raised', '/api/poses/apply', { library: 'poses', name: 'raised', fraction: 0.5 });
  await shots.take('pose-library');

  // A space switch at this frame: the space changes, the pose does not; undo.
  await clickControl(page, 'hero_arm_L_ik', false, server);
  await expectSelection(page, server, ['hero_arm_L_ik']);
  await expect(page.getByTestId('tool-space').locator('option')).not.toHaveCount(0);
  await page.getByTestId('tool-space').selectOption('world');
  const before = await server.worldPose();
  await page.getByTestId('tool-space-switch').click();
  await expect.poll(async () => (await server.get('/api/spaces?control=hero_arm_L_ik')).current).toBe('world');
  expect(poseDifference(await server.worldPose(), before)).toBeLessThan(1e-9);
  await undoInPage(page, server);
  await expect.poll(async () => (await server.get('/api/spaces?control=hero_arm_L_ik')).current).not.toBe('world');

  // Transfer the left arm's switch keys onto the right arm, 5 frames later.
  for (const [f, v] of [[0, 0], [10, 1]] as const) {
    await post(server, '/api/time', { frame: f });
    await post(server, '/api/channel-keys', { controls: ['hero_arm_L_fkIkSwitch'], attrs: ['fkIk'], value: v });
  }
  await settle(page, server);
  await page.getByTestId('tool-transfer-from').fill('hero:arm_L');
  await page.getByTestId('tool-transfer-to').fill('hero:arm_R');
  await page.getByTestId('tool-transfer-offset').fill('5');
  await page.getByTestId('tool-transfer').click();
  await expect
    .poll(async () => (await server.get('/api/channel-keys?controls=hero_arm_R_fkIkSwitch&attrs=fkIk')).keys[0]?.frames)
    .toEqual([5, 15]);

  // A deform-only export into the served folder.
  await page.getByTestId('tool-export-path').fill('export/shot.glb');
  await page.getByTestId('tool-export').click();
  await expect(page.locator('#statusbar')).toContainText('Wrote');
  expect(existsSync(join(server.root, 'export', 'shot.glb'))).toBe(true);
  // The Khronos validator: no error.
  const v = spawnSync(process.execPath, [join(repoDir, 'tools/validate-gltf.mjs'), join(server.root, 'export', 'shot.glb')], { encoding: 'utf8' });
  expect(v.status, `${v.stdout}${v.stderr}`).toBe(0);

  // FK/IK match baked over the playback range: a key on every frame of it, none outside.
  await post(server, '/api/playback-range', { first: 2, last: 8 });
  await settle(page, server);
  await page.getByTestId('tool-over-range').check();
  await clickControl(page, 'hero_arm_L_ik', false, server);
  await page.getByTestId('tool-match-ik').click();
  await expect
    .poll(async () => (await server.get('/api/channel-keys?controls=hero_arm_L_ik&attrs=translate')).keys[0]?.frames)
    .toEqual([2, 3, 4, 5, 6, 7, 8]);
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
